#!/usr/bin/env bash
# The main job on a sample the project generates: make the samples, then simplify one into a
# multiresolution glTF with three levels, printing the statistics.
set -euo pipefail
cd "$(dirname "$0")/.."
mkdir -p out
build/bin/make-samples out/samples
build/bin/simplify -i out/samples/seamball.glb -o out/seamball.mr.glb --ratio 0.5,0.1,0.02 --report out/seamball.mr.json -v
echo "wrote out/seamball.mr.glb and out/seamball.mr.json"
