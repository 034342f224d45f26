#!/usr/bin/env bash
# Benchmark (not a test): the whole chain (`lodbake`) of two builds on every shared asset, side by
# side, in one run: wall and CPU time, peak memory, and compare's figures at 10% and 2% (lit PBR
# PSNR, relative Hausdorff, silhouette IoU). Issue 22 asks that the speed work leaves the shared
# assets' chains as good or better; this prints the table for docs/benchmarks.md.
#
# Usage: scripts/bench_before_after.sh BEFORE_BIN AFTER_BIN [WORKDIR]
#   ASSETS="Duck Avocado ..." (default: every shared asset but the malformed-on-purpose ones)
#   CHAIN_FLAGS="--lod0-density" (extra lodbake flags for both builds; default none: the shipping
#   chain)  COMPARE_FLAGS (default --views 8 --resolution 256 --samples 100000)
set -euo pipefail
HERE=$(cd "$(dirname "$0")/.." && pwd)
BEFORE=${1:?usage: bench_before_after.sh BEFORE_BIN AFTER_BIN [WORKDIR]}
AFTER=${2:?usage: bench_before_after.sh BEFORE_BIN AFTER_BIN [WORKDIR]}
WORK=${3:-/tmp/lodbake-before-after}
SHARED=${LODBAKE_SHARED:-$HERE/../shared}
ASSETS=${ASSETS:-Avocado BoxTextured CesiumMilkTruck ChrKnight Duck ShapeCollection 2CylinderEngine StanfordBunny}
CHAIN_FLAGS=${CHAIN_FLAGS:-}
COMPARE_FLAGS=${COMPARE_FLAGS:---views 8 --resolution 256 --samples 100000}
[ -d "$SHARED/assets" ] || { echo "bench_before_after.sh: $SHARED/assets is absent: nothing to measure" >&2; exit 1; }
mkdir -p "$WORK"

file_of() {
  case "$1" in
    Avocado) echo "$SHARED/assets/Avocado/Avocado.gltf" ;;
    ChrKnight) echo "$SHARED/assets/ChrKnight/chr_knight.glb" ;;
    *) echo "$SHARED/assets/$1/$1.glb" ;;
  esac
}

# run BUILD_LABEL BIN ASSET: the chain under /usr/bin/time; prints "wall cpu peakMB" or "failed".
run() {
  local label=$1 bin=$2 asset=$3 src log
  src=$(file_of "$asset")
  log=$(mktemp)
  # shellcheck disable=SC2086
  if /usr/bin/time -f "TIME %e %U %S %M" "$bin/lodbake" -i "$src" -o "$WORK/$asset.$label.lod.glb" --ratio 0.1,0.02 \
       --quiet $CHAIN_FLAGS >/dev/null 2>"$log"; then
    grep '^TIME' "$log" | tail -1 | awk '{ printf "%.1f %.1f %.0f\n", $2, $3 + $4, $5 / 1024 }'
  else
    echo "failed"
  fi
  rm -f "$log"
}

# figures ASSET LABEL LOD: "pbr hausdorff iou" of that level against the original.
figures() {
  local src out=$WORK/$1.$2.lod.glb
  src=$(file_of "$1")
  [ -f "$out" ] || { echo "- - -"; return; }
  # shellcheck disable=SC2086
  "$AFTER/compare" "$src" "$out" --lod "$3" --json $COMPARE_FLAGS 2>/dev/null | python3 -c '
import json, sys
j = json.load(sys.stdin)
print("%.2f %.4f %.4f" % (j["images"]["pbr"]["psnr"], j["geometry"]["relHausdorff"], j["images"]["baseColor"]["iou"]))' ||
    echo "- - -"
}

echo "lodbake before/after: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg); before $BEFORE, after $AFTER${CHAIN_FLAGS:+, flags $CHAIN_FLAGS}"
echo
echo "| asset | before: wall s / CPU s / MB | after: wall s / CPU s / MB | level | PBR PSNR dB before → after | rel. Hausdorff before → after | silhouette IoU before → after |"
echo "|---|---|---|---|---|---|---|"
for a in $ASSETS; do
  [ -f "$(file_of "$a")" ] || { echo "bench_before_after.sh: $a missing, skipped" >&2; continue; }
  read -r bw bc bm < <(run before "$BEFORE" "$a"; echo)
  read -r aw ac am < <(run after "$AFTER" "$a"; echo)
  for lod in 1 2; do
    read -r bp bh bi < <(figures "$a" before $lod)
    read -r ap ah ai < <(figures "$a" after $lod)
    ratio=$([ $lod = 1 ] && echo "10%" || echo "2%")
    if [ $lod = 1 ]; then
      echo "| $a | $bw / ${bc:-} / ${bm:-} | $aw / ${ac:-} / ${am:-} | $ratio | $bp → $ap | $bh → $ah | $bi → $ai |"
    else
      echo "| | | | $ratio | $bp → $ap | $bh → $ah | $bi → $ai |"
    fi
  done
done
