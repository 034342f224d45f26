#!/usr/bin/env bash
# Coarse levels' geometry: simplify's levels at 10% and 2% against the original, with the cost and
# part pruning of issue 24 on and off, beside Blender's Decimate at the same ratio. Each output is
# measured by `compare ORIGINAL OUT [--lod K] --json` (8 views, 256², 100k samples): relative
# Hausdorff and silhouette IoU (shaded mode), which depend on the geometry only, so simplify's
# .mr.glb levels are measured directly. Prints a Markdown table (docs/benchmarks.md, "Coarse
# levels: two-sided cost and parts by visual weight").
# Usage: scripts/bench_coarse.sh [BIN] [WORKDIR]
# Environment: ASSETS="drum Duck" (a subset; drum is make-samples' drum.glb).
set -u
HERE=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$HERE/build/bin}
WORK=${2:-/tmp/lodbake-bench-coarse}
SHARED=${LODBAKE_SHARED:-$HERE/../shared}
ASSETS=${ASSETS:-drum Avocado BoxTextured CesiumMilkTruck ChrKnight Duck ShapeCollection}
mkdir -p "$WORK"
"$BIN/make-samples" "$WORK/samples" || exit 1
declare -A FILES=([drum]=$WORK/samples/drum.glb [Duck]=$SHARED/assets/Duck/Duck.glb
                  [Avocado]=$SHARED/assets/Avocado/Avocado.gltf [BoxTextured]=$SHARED/assets/BoxTextured/BoxTextured.glb
                  [CesiumMilkTruck]=$SHARED/assets/CesiumMilkTruck/CesiumMilkTruck.glb
                  [ChrKnight]=$SHARED/assets/ChrKnight/chr_knight.glb
                  [ShapeCollection]=$SHARED/assets/ShapeCollection/ShapeCollection.glb)
declare -A VARIANTS=([before]="--no-visual-weight" [two-sided]="--two-sided-cost --no-visual-weight"
                     [visual-weight]="" [both]="--two-sided-cost")
ORDER="before two-sided visual-weight both"
measure() {  # ORIGINAL OUT LOD -> "tris, hausdorff%, IoU"
    "$BIN/compare" "$1" "$2" --lod "$3" --json --views 8 --resolution 256 --samples 100000 2>/dev/null |
        python3 -c 'import json,sys; r=json.load(sys.stdin); c=r["counts"]["b"]
print("%d, %.2f%%, %.3f" % (c["triangles"], 100*r["geometry"]["relHausdorff"], r["images"]["shaded"]["iou"]))' ||
        echo failed
}
echo "| asset | ratio | before | two-sided | visual weight (default) | both | Blender Decimate |"
echo "|---|---|---|---|---|---|---|"
for name in $ASSETS; do
    src=${FILES[$name]}
    [ -f "$src" ] || { echo "bench_coarse: $src missing, skipped" >&2; continue; }
    for v in $ORDER; do
        "$BIN/simplify" -i "$src" -o "$WORK/$name.$v.mr.glb" --ratio 0.1,0.02 --quiet ${VARIANTS[$v]} ||
            echo "bench_coarse: simplify $v failed on $name" >&2
    done
    lod=1
    for r in 0.1 0.02; do
        line="| $name | $r"
        for v in $ORDER; do line="$line | $(measure "$src" "$WORK/$name.$v.mr.glb" $lod)"; done
        if command -v blender >/dev/null; then
            [ -s "$WORK/$name.blender.$r.glb" ] ||
                blender -b --factory-startup --python "$HERE/scripts/blender_decimate.py" -- "$src" \
                    "$WORK/$name.blender.$r.glb" $r >"$WORK/$name.blender.$r.log" 2>&1
            line="$line | $(measure "$src" "$WORK/$name.blender.$r.glb" 0)"
        else
            line="$line | (no blender)"
        fi
        echo "$line |"
        lod=$((lod + 1))
    done
done
