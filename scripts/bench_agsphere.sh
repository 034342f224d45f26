#!/usr/bin/env bash
# Benchmark (not a test): agsphere-build's wall time and peak memory on the Stanford bunny (69k
# triangles) and on the bunny subdivided to 1.1M triangles (out/bench/bunny-1M.glb, made by
# scripts/subdivide_glb.py when absent), for view-independent levels and for one --view, with the
# stage split from the tool's --report (cells, depth statistics, selection, levels, write).
# Usage: scripts/bench_agsphere.sh [RATIOS]
#   BIN=build-dir/bin OUT=dir (default out/bench) RUNS=n (best of n)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-build/bin}
OUT=${OUT:-out/bench}
RATIOS=${1:-0.5,0.3}
RUNS=${RUNS:-1}
mkdir -p "$OUT"
BUNNY=../shared/assets/StanfordBunny/StanfordBunny.glb
BIG=$OUT/bunny-1M.glb
if [ ! -f "$BIG" ]; then
  python3 scripts/subdivide_glb.py "$BUNNY" "$BIG" 2
fi

measure() {  # name, input, extra flags... -> one row (best of RUNS) and the report's stage split
  local name=$1 in=$2; shift 2
  local log rep; log=$(mktemp); rep="$OUT/agsphere-$name.json"
  local best_wall="" best_rss=0
  for _ in $(seq "$RUNS"); do
    /usr/bin/time -v "$BIN/agsphere-build" -i "$in" -o "$OUT/agsphere-$name.glb" --ratio "$RATIOS" \
      --report "$rep" --quiet "$@" >/dev/null 2>"$log" || { echo "$name failed:"; cat "$log"; rm -f "$log"; return 1; }
    local wall rss
    wall=$(grep "Elapsed (wall clock)" "$log" | awk '{print $NF}' | awk -F: '{ if (NF==3) print $1*3600+$2*60+$3; else print $1*60+$2 }')
    rss=$(grep "Maximum resident set size" "$log" | awk '{print $NF}')
    if [ -z "$best_wall" ] || awk -v a="$wall" -v b="$best_wall" 'BEGIN { exit !(a < b) }'; then
      best_wall=$wall best_rss=$rss
    fi
  done
  rm -f "$log"
  python3 - "$name" "$best_wall" "$best_rss" "$rep" <<'PY'
import json, sys
name, wall, rss, rep = sys.argv[1], float(sys.argv[2]), float(sys.argv[3]), json.load(open(sys.argv[4]))
n = rep["input"]["triangles"]
t = rep["time"]
print("%-14s %9d tris %8.2f s %9.1f MB peak %7.1f MB per M tris" % (name, n, wall, rss / 1024, rss / 1024 / (n / 1e6)))
print("  stages: load %.2f s, cells %.2f s, depths %.2f s, select %.3f s, levels %.2f s, write %.2f s"
      % (t["load"], t["cells"], t["depths"], t["select"], t["levels"], t["write"]))
print("  levels: " + ", ".join("%d tris / %d regions" % (l["triangles"], l["regions"]) for l in rep["levels"]))
PY
}

echo "agsphere-build --ratio $RATIOS, best of $RUNS run(s), $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
measure bunny "$BUNNY"
measure bunny-view "$BUNNY" --view 1,0,0
measure bunny-1M "$BIG"
measure bunny-1M-view "$BIG" --view 1,0,0
