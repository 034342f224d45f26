#!/usr/bin/env bash
# The main job on a sample the project generates: make the samples, then bake seamball's LOD chain
# with the one-command `lodbake` (simplify -> parameterize -> texture-refine -> pack in one
# process, default levels 0.5, 0.1, 0.02): out/seamball.lod.glb (MSFT_lod, one mesh, one material and one draw call per level)
# and its report out/seamball.lod.json.
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p out
build/bin/make-samples out/samples
build/bin/lodbake -i out/samples/seamball.glb -o out/seamball.lod.glb --report out/seamball.lod.json -v
echo "wrote out/seamball.lod.glb: open it in the three.js editor (https://threejs.org/editor/, File > Import)"
echo "or the Babylon.js sandbox (https://sandbox.babylonjs.com/, drop the file), which switches its levels by screen size"
