#!/usr/bin/env bash
# Benchmark (not a test): simplify the Stanford bunny subdivided twice (1.1M triangles) and three
# times (4.4M) to 1% with lodbake's simplify and with Debian's gltfpack -si, in the same run, and
# print wall time, CPU time, input triangles per second and peak memory side by side, simplify's
# own load / simplify / write split (from its --report), the time to read its output back
# (scripts/bench_mr_io.sh) and the ratios against the targets.
# Target: simplify <= 2x gltfpack's time and < 1 GB peak memory per million input triangles.
# Usage: scripts/bench_simplify.sh [INPUT.glb] [RATIO]   (no INPUT: both bunnies)
#   BIN=build-dir/bin OUT=dir THREADS=n (simplify's --threads; default: all cores) RUNS=n (best of n)
#   READBACK=0 skips the read-back timing (also skipped when BIN is not a build dir's bin/)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-build/bin}
OUT=${OUT:-out/bench}
RATIO=${2:-0.01}
RUNS=${RUNS:-1}
THREADS=${THREADS:-0}
READBACK=${READBACK:-1}
mkdir -p "$OUT"

WALL=0 RSS=0 CPU=0 TRIS=0
measure() {  # name, command...  -> prints a row, sets WALL (s), CPU (s) and RSS (KB) of the best run
  local name=$1; shift
  local log; log=$(mktemp)
  local best_wall="" best_rss=0 best_cpu=0
  for _ in $(seq "$RUNS"); do
    /usr/bin/time -v "$@" >/dev/null 2>"$log" || { echo "$name failed:"; cat "$log"; rm -f "$log"; return 1; }
    local wall rss cpu
    wall=$(grep "Elapsed (wall clock)" "$log" | awk '{print $NF}' | awk -F: '{ if (NF==3) print $1*3600+$2*60+$3; else print $1*60+$2 }')
    rss=$(grep "Maximum resident set size" "$log" | awk '{print $NF}')
    cpu=$(awk -F': ' '/User time|System time/ { s += $2 } END { print s }' "$log")
    if [ -z "$best_wall" ] || awk -v a="$wall" -v b="$best_wall" 'BEGIN { exit !(a < b) }'; then
      best_wall=$wall best_rss=$rss best_cpu=$cpu
    fi
  done
  rm -f "$log"
  WALL=$best_wall RSS=$best_rss CPU=$best_cpu
  awk -v n="$name" -v w="$WALL" -v r="$RSS" -v t="$TRIS" -v c="$CPU" 'BEGIN {
    printf "%-24s %8.2f s wall %8.2f s cpu %11.0f tri/s %8.1f MB peak %7.1f MB per M tris\n", n, w, c, t / (w > 0 ? w : 1e-9), r / 1024, r / 1024 / (t / 1e6) }'
}

bench() {  # input.glb
  local IN=$1 STEM; STEM=$(basename "$IN" .glb)
  TRIS=$(python3 -c "import sys; sys.path.insert(0,'tests/cli'); from lodbake_test import Gltf; g=Gltf('$IN'); print(sum(g.mesh_triangle_count(i) for i in range(len(g.json['meshes']))))")
  echo "input: $IN ($TRIS triangles), target ratio $RATIO, best of $RUNS run(s), $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
  measure "lodbake simplify" "$BIN/simplify" -i "$IN" -o "$OUT/$STEM.mr.glb" --ratio "$RATIO" --threads "$THREADS" \
    --report "$OUT/$STEM.simplify.json" --quiet
  local S_WALL=$WALL S_RSS=$RSS S_CPU=$CPU
  python3 -c "import json; t=json.load(open('$OUT/$STEM.simplify.json'))['time']; print('  simplify split: load %.2f s, simplify %.2f s, write %.2f s' % (t['load'], t['simplify'], t['write']))"
  if [ "$READBACK" = 1 ] && [ -f "$(dirname "$BIN")/liblodbake_gltf.a" ]; then
    printf '  read back: '
    BUILD=$(dirname "$BIN") RUNS=1 scripts/bench_mr_io.sh "$OUT/$STEM.mr.glb"
  fi
  measure "gltfpack -si (Debian)" gltfpack -i "$IN" -o "$OUT/$STEM.gltfpack.glb" -si "$RATIO"
  local G_WALL=$WALL G_CPU=$CPU
  if [ -x scripts/node/node_modules/.bin/gltfpack ]; then
    measure "gltfpack -si (npm)" scripts/node/node_modules/.bin/gltfpack -i "$IN" -o "$OUT/$STEM.gltfpack-npm.glb" -si "$RATIO"
  fi
  awk -v s="$S_WALL" -v g="$G_WALL" -v sc="$S_CPU" -v gc="$G_CPU" -v r="$S_RSS" -v t="$TRIS" 'BEGIN {
    ratio = s / (g > 0 ? g : 1e-9); mem = r / 1024 / 1024 / (t / 1e6)
    cpu = gc > 0 ? sprintf("%.2fx", sc / gc) : "n/a"
    printf "time ratio simplify / gltfpack (Debian): %.2fx wall, %s cpu (target <= 2x wall: %s)\n", ratio, cpu, ratio <= 2 ? "met" : "NOT met"
    printf "simplify peak memory: %.2f GB per M input triangles (target < 1: %s)\n", mem, mem < 1 ? "met" : "NOT met" }'
}

if [ $# -ge 1 ]; then
  bench "$1"
else
  for n in 2 3; do
    IN=$OUT/bunny-$([ $n = 2 ] && echo 1M || echo 4M).glb
    [ -f "$IN" ] || python3 scripts/subdivide_glb.py ../shared/assets/StanfordBunny/StanfordBunny.glb "$IN" $n
    bench "$IN"
  done
fi
