#!/usr/bin/env bash
# Benchmark (not a test): parameterize on a ~50k-triangle textured asset the project generates
# (make-samples --scale 2.3: hemisphere9 with 50,508 triangles and 9 textured materials), after
# simplify --ratio 0.5,0.1,0.02; prints wall time, peak memory and parameterize's own split for
# --threads 1 and for all cores, and checks that both outputs are byte-identical.
# Target: under 30 s on 2 cores.
# Usage: scripts/bench_parameterize.sh [INPUT.glb]    BIN=build-dir/bin OUT=dir SCALE=s
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-build/bin}
OUT=${OUT:-out/bench}
SCALE=${SCALE:-2.3}
mkdir -p "$OUT"
IN=${1:-}
if [ -z "$IN" ]; then
  "$BIN/make-samples" "$OUT/samples-x$SCALE" --scale "$SCALE"
  IN=$OUT/samples-x$SCALE/hemisphere9.glb
fi
NAME=$(basename "${IN%.*}")
"$BIN/simplify" -i "$IN" -o "$OUT/$NAME.mr.glb" --ratio 0.5,0.1,0.02 --quiet
TRIS=$(python3 -c "import sys; sys.path.insert(0,'tests/cli'); from lodbake_test import Gltf; g=Gltf('$IN'); print(sum(g.mesh_triangle_count(i) for i in range(len(g.json['meshes']))))")
echo "input: $IN ($TRIS triangles), $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg)"
for threads in 1 0; do
  log=$(mktemp)
  /usr/bin/time -v "$BIN/parameterize" -i "$OUT/$NAME.mr.glb" -o "$OUT/$NAME.t$threads.uv.glb" --threads "$threads" \
    --quiet --report "$OUT/$NAME.t$threads.uv.json" 2>"$log" >/dev/null || { cat "$log"; exit 1; }
  wall=$(grep "Elapsed (wall clock)" "$log" | awk '{print $NF}' | awk -F: '{ if (NF==3) print $1*3600+$2*60+$3; else print $1*60+$2 }')
  rss=$(grep "Maximum resident set size" "$log" | awk '{print $NF}')
  rm -f "$log"
  python3 - "$OUT/$NAME.t$threads.uv.json" "$threads" "$wall" "$rss" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
t = r["time"]
threads = "all cores" if sys.argv[2] == "0" else sys.argv[2] + " thread"
folds = sum(l["flips"] + l["overlaps"] for l in r["levels"])
print("parameterize --threads %-9s %7.2f s wall %8.1f MB peak   (load %.2f, charts %.2f, bake %.2f, checks %.2f s; %d charts; %d folded level triangles)  target < 30 s: %s" % (
    threads, float(sys.argv[3]), int(sys.argv[4]) / 1024, t["load"], t["parameterize"], t["bake"], t["checks"],
    len(r["charts"]), folds, "yes" if float(sys.argv[3]) < 30 else "NO"))
PY
done
if cmp -s "$OUT/$NAME.t1.uv.glb" "$OUT/$NAME.t0.uv.glb"; then echo "outputs identical for --threads 1 and all cores"; else echo "OUTPUTS DIFFER between thread counts"; exit 1; fi
