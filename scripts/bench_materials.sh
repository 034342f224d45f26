#!/usr/bin/env bash
# Every material channel against base colour only: the chain of each input packed twice (every
# channel; --base-color-only), both at LOD0's texel density so every level can be judged close up,
# and compare's lit PBR render (docs/compare.md) of each level against the original. Also the
# normal maps' own share on coarse levels (--normal-maps never) and pack's time for both.
#
#   bash scripts/bench_materials.sh [BIN] [WORK]      BIN defaults to build/bin
#
# Inputs: the generated pbrscene sample and, when ../shared/assets exists, Avocado and
# CesiumMilkTruck. Prints one row per input and level: PBR PSNR (dB) with every channel, base
# colour only and without normal maps, and the base-colour PSNR of the full chain.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN="$(cd "${1:-build/bin}" && pwd)"
WORK="${2:-$(mktemp -d /tmp/lodbake-materials.XXXXXX)}"
SHARED="${LODBAKE_SHARED:-../shared}"
mkdir -p "$WORK"
"$BIN/make-samples" "$WORK/samples" >/dev/null
inputs=("pbrscene=$WORK/samples/pbrscene.glb")
if [ -d "$SHARED/assets" ]; then
  inputs+=("Avocado=$SHARED/assets/Avocado/Avocado.gltf" "CesiumMilkTruck=$SHARED/assets/CesiumMilkTruck/CesiumMilkTruck.glb")
fi
pbr() {  # $1 original, $2 chain, $3 level, $4 key (pbr or baseColor)
  "$BIN/compare" "$1" "$2" --lod "$3" --json --no-geometry --views 8 |
    python3 -c "import json,sys; print('%.2f' % json.load(sys.stdin)['images']['$4']['psnr'])"
}
printf '%-16s %4s %9s  %9s %9s %9s  %9s\n' input lod triangles full base-only no-normal full-base
for entry in "${inputs[@]}"; do
  name="${entry%%=*}" src="${entry#*=}" o="$WORK/$name"
  "$BIN/simplify" -i "$src" -o "$o.mr.glb" --ratio 0.5,0.1,0.02 --quiet
  "$BIN/parameterize" -i "$o.mr.glb" -o "$o.uv.glb" --quiet
  t0=$(date +%s.%N)
  "$BIN/pack" -i "$o.uv.glb" -o "$o.full.glb" --lod0-density --report "$o.full.json" --quiet
  t1=$(date +%s.%N)
  "$BIN/pack" -i "$o.uv.glb" -o "$o.bc.glb" --lod0-density --base-color-only --quiet
  t2=$(date +%s.%N)
  "$BIN/pack" -i "$o.uv.glb" -o "$o.nonm.glb" --lod0-density --normal-maps never --quiet
  levels=$(python3 -c "import json; print(len(json.load(open('$o.full.json'))['levels']))")
  for ((k = 0; k < levels; ++k)); do
    tris=$(python3 -c "import json; print(json.load(open('$o.full.json'))['levels'][$k]['triangles'])")
    printf '%-16s %4d %9d  %9s %9s %9s  %9s\n' "$name" "$k" "$tris" "$(pbr "$src" "$o.full.glb" "$k" pbr)" \
      "$(pbr "$src" "$o.bc.glb" "$k" pbr)" "$(pbr "$src" "$o.nonm.glb" "$k" pbr)" "$(pbr "$src" "$o.full.glb" "$k" baseColor)"
  done
  python3 -c "print('%-16s pack: every channel %.1f s, base colour only %.1f s' % ('$name', $t1 - $t0, $t2 - $t1))"
done
