#!/usr/bin/env bash
# The main job on a sample the project generates: make the samples, then run the whole chain
# (simplify -> parameterize -> texture-refine -> pack) on one of them, writing a LOD chain
# out/seamball.lod.glb (MSFT_lod, one mesh, one material and one draw call per level) and a JSON
# report per stage.
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p out
build/bin/make-samples out/samples
build/bin/simplify -i out/samples/seamball.glb -o out/seamball.mr.glb --ratio 0.5,0.1,0.02 --report out/seamball.mr.json
build/bin/parameterize -i out/seamball.mr.glb -o out/seamball.uv.glb --report out/seamball.uv.json
build/bin/texture-refine -i out/seamball.uv.glb -o out/seamball.tex.glb --report out/seamball.tex.json
build/bin/pack -i out/seamball.tex.glb -o out/seamball.lod.glb --report out/seamball.lod.json -v
echo "wrote out/seamball.lod.glb (open it in any glTF viewer) and a report per stage in out/*.json"
