#!/usr/bin/env bash
# Benchmark (not a test): simplify a >= 1M-triangle mesh (the Stanford bunny subdivided twice,
# 1.1M triangles) to 1% with lodbake's simplify and with Debian's gltfpack -si, in the same run,
# and print wall time, input triangles per second and peak memory side by side.
# Target: simplify <= 2x gltfpack's time and < 1 GB peak memory per million input triangles.
# Usage: scripts/bench_simplify.sh [INPUT.glb] [RATIO]
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-build/bin}
OUT=${OUT:-out/bench}
RATIO=${2:-0.01}
mkdir -p "$OUT"
IN=${1:-$OUT/bunny-1M.glb}
if [ ! -f "$IN" ]; then
  python3 scripts/subdivide_glb.py ../shared/assets/StanfordBunny/StanfordBunny.glb "$IN" 2
fi
TRIS=$(python3 -c "import sys; sys.path.insert(0,'tests/cli'); from lodbake_test import Gltf; g=Gltf('$IN'); print(sum(g.mesh_triangle_count(i) for i in range(len(g.json['meshes']))))")

measure() {  # name, command...
  local name=$1; shift
  local log; log=$(mktemp)
  /usr/bin/time -v "$@" >/dev/null 2>"$log" || { echo "$name failed:"; cat "$log"; rm -f "$log"; return 1; }
  local wall rss
  wall=$(grep "Elapsed (wall clock)" "$log" | awk '{print $NF}' | awk -F: '{ if (NF==3) print $1*3600+$2*60+$3; else print $1*60+$2 }')
  rss=$(grep "Maximum resident set size" "$log" | awk '{print $NF}')
  rm -f "$log"
  awk -v n="$name" -v w="$wall" -v r="$rss" -v t="$TRIS" 'BEGIN {
    printf "%-22s %9.2f s %12.0f tri/s %9.1f MB peak %9.1f MB per M tris\n", n, w, t / (w > 0 ? w : 1e-9), r / 1024, r / 1024 / (t / 1e6) }'
}

echo "input: $IN ($TRIS triangles), target ratio $RATIO"
measure "lodbake simplify" "$BIN/simplify" -i "$IN" -o "$OUT/simplify.glb" --ratio "$RATIO" --quiet
measure "gltfpack -si (Debian)" gltfpack -i "$IN" -o "$OUT/gltfpack.glb" -si "$RATIO"
if [ -x scripts/node/node_modules/.bin/gltfpack ]; then
  measure "gltfpack -si (npm)" scripts/node/node_modules/.bin/gltfpack -i "$IN" -o "$OUT/gltfpack-npm.glb" -si "$RATIO"
fi
