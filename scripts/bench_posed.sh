#!/bin/bash
# Skinned levels posed: for each rigged asset, simplify -> parameterize -> pack with the tools in
# BIN, then compare every level with the original posed at the start, middle and end of animation
# 0. Prints one line per level: triangles, pack's measured Hausdorff (model units), posed Hausdorff
# and silhouette IoU at the three times, and simplify's time.
# Usage: [SIMPLIFY_FLAGS="..."] scripts/bench_posed.sh BIN OUT [asset.glb ...]
# (without assets: the walker of BIN's make-samples, simple_skin and CesiumMilkTruck)
set -euo pipefail
BIN=$1 OUT=$2
shift 2
mkdir -p "$OUT"
ASSETS=("$@")
if [ ${#ASSETS[@]} -eq 0 ]; then
  "$BIN/make-samples" "$OUT/samples" >/dev/null
  ASSETS=("$OUT/samples/walker.glb" /usr/share/assimp/models/glTF2/simple_skin/simple_skin.gltf
          ../shared/assets/CesiumMilkTruck/CesiumMilkTruck.glb)
fi
printf "| asset | level | triangles | measured Hausdorff | posed Hausdorff start / middle / end | posed silhouette IoU start / middle / end | simplify s |\n"
printf "|---|---|---|---|---|---|---|\n"
for A in "${ASSETS[@]}"; do
  N=$(basename "${A%.*}")
  P="$OUT/$N"
  "$BIN/simplify" -q --threads 1 -i "$A" -o "$P.mr.glb" --ratio 0.5,0.1 --report "$P.s.json" ${SIMPLIFY_FLAGS:-}
  "$BIN/parameterize" -q --threads 1 -i "$P.mr.glb" -o "$P.uv.glb"
  "$BIN/pack" -q --threads 1 -i "$P.uv.glb" -o "$P.lod.glb" --report "$P.k.json"
  for k in 0 1 2; do
    H="" I=""
    for t in start middle end; do
      "$BIN/compare" "$A" "$P.lod.glb" --lod $k --animation 0 --time $t --json --views 6 --threads 1 > "$P.c$k$t.json"
      H="$H $(python3 -c "import json,sys; print('%.5g' % json.load(open(sys.argv[1]))['geometry']['hausdorff'])" "$P.c$k$t.json")"
      I="$I $(python3 -c "import json,sys; print('%.5f' % json.load(open(sys.argv[1]))['images']['baseColor']['iou'])" "$P.c$k$t.json")"
    done
    python3 - "$P" "$k" "$N" "$H" "$I" <<'PY'
import json, sys
p, k, n, h, i = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4].split(), sys.argv[5].split()
pack = json.load(open(p + ".k.json"))
s = json.load(open(p + ".s.json"))
L = pack["levels"][k]
print("| %s | %d | %s | %.5g | %s | %s | %.3f |" % (n, k, "{:,}".format(L["triangles"]), L["deviation"]["hausdorff"],
      " / ".join(h), " / ".join(i), s["time"]["simplify"]))
PY
  done
done
