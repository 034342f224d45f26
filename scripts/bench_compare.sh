#!/bin/sh
# Benchmark of `compare` with default options (200k samples per side, 16 views, 256x256) on the
# shared StanfordBunny (69,451 triangles) against gltfpack -si 0.5 of it (~34.7k): a ~104k-triangle
# pair. Prints wall time and peak memory (GNU time -v).
# Usage: scripts/bench_compare.sh [BIN] [WORKDIR]      target: < 30 s on 2 cores
set -eu
HERE=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$HERE/build/bin}
WORK=${2:-/tmp/lodbake-bench-compare}
SHARED=${LODBAKE_SHARED:-$HERE/../shared}
mkdir -p "$WORK"
[ -x /usr/bin/time ] || { echo "bench_compare: needs GNU time (apt-get install time)" >&2; exit 1; }
BUNNY=$SHARED/assets/StanfordBunny/StanfordBunny.glb
if [ -f "$BUNNY" ] && command -v gltfpack >/dev/null; then
    A=$BUNNY
    B=$WORK/bunny_half.glb
    gltfpack -i "$A" -o "$B" -si 0.5 >/dev/null
else
    echo "bench_compare: $BUNNY or gltfpack missing" >&2
    exit 1
fi
echo "A: $A"
echo "B: $B"
/usr/bin/time -v "$BIN/compare" "$A" "$B" --report "$WORK/report.json" 2> "$WORK/time.txt" | sed -n '3,9p'
grep -E "Elapsed \(wall clock\)|Maximum resident set size" "$WORK/time.txt"
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); print('triangles A/B:', j['counts']['a']['triangles'], j['counts']['b']['triangles'])" "$WORK/report.json"
