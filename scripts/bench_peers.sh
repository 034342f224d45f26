#!/usr/bin/env bash
# Peer comparison: lodbake's chain (simplify -> parameterize -> pack) against Debian's
# gltfpack -si R, npm gltfpack -si R -sp -se 1 (permissive: may cross attribute seams, no error
# limit) and Blender's Decimate modifier (collapse, headless), at 10% and 2% of the triangles, on
# Duck, Avocado, CesiumMilkTruck and 2CylinderEngine (ASSETS may also name BoxTextured, ChrKnight,
# ShapeCollection and StanfordBunny). Every output is measured against the
# original with `compare ORIGINAL OUT [--lod K] --json` (lit PBR and base-colour PSNR, triangles, draw calls)
# and a Markdown table is printed (docs/benchmarks.md, "Against the peers").
# Usage: scripts/bench_peers.sh [BIN] [WORKDIR]
# Environment: ASSETS="Duck Avocado" (a subset), PACK_FLAGS (default --lod0-density: compare renders
# every level close up at 256 px, so every level is textured at LOD0's texel density, as the peers
# keep the original textures for every level; PACK_FLAGS= measures the shipping default, where a
# coarse level only carries the texels it can show at its switch distance), REUSE_PEERS=1 (keep
# peer outputs already in WORKDIR), COMPARE_FLAGS.
# Peers that are not installed are skipped (blender: apt-get install blender python3-numpy;
# Blender's glTF importer needs numpy).
set -u
HERE=$(cd "$(dirname "$0")/.." && pwd)
BIN=${1:-$HERE/build/bin}
WORK=${2:-/tmp/lodbake-bench-peers}
SHARED=${LODBAKE_SHARED:-$HERE/../shared}
NPM_GLTFPACK=$HERE/scripts/node/node_modules/.bin/gltfpack
COMPARE_FLAGS=${COMPARE_FLAGS:---views 8 --resolution 256 --samples 100000}
PACK_FLAGS=${PACK_FLAGS---lod0-density}
ASSETS=${ASSETS:-Duck Avocado CesiumMilkTruck 2CylinderEngine}
REUSE_PEERS=${REUSE_PEERS:-0}
fresh() { [ "$REUSE_PEERS" != 1 ] || [ ! -s "$1" ]; }
mkdir -p "$WORK"
declare -A FILES=([Duck]=Duck/Duck.glb [Avocado]=Avocado/Avocado.gltf [CesiumMilkTruck]=CesiumMilkTruck/CesiumMilkTruck.glb
                  [2CylinderEngine]=2CylinderEngine/2CylinderEngine.glb [BoxTextured]=BoxTextured/BoxTextured.glb
                  [ChrKnight]=ChrKnight/chr_knight.glb [ShapeCollection]=ShapeCollection/ShapeCollection.glb
                  [StanfordBunny]=StanfordBunny/StanfordBunny.glb)
ROWS="["
sep=""
row() { ROWS="$ROWS$sep{\"asset\":\"$1\",\"ratio\":\"$2\",\"tool\":\"$3\",\"original\":\"$4\",\"file\":\"$5\",\"lod\":$6}"; sep=","; }
for name in $ASSETS; do
    src=$SHARED/assets/${FILES[$name]}
    [ -f "$src" ] || { echo "bench_peers: $src missing, skipped" >&2; continue; }
    # Ours: one chain with LOD1 = 10%, LOD2 = 2%.
    rm -f "$WORK/$name.lod.glb"
    "$BIN/simplify" -i "$src" -o "$WORK/$name.mr.glb" --ratio 0.1,0.02 --quiet &&
    "$BIN/parameterize" -i "$WORK/$name.mr.glb" -o "$WORK/$name.uv.glb" --quiet &&
    "$BIN/pack" -i "$WORK/$name.uv.glb" -o "$WORK/$name.lod.glb" --quiet --report "$WORK/$name.lod.json" $PACK_FLAGS ||
        echo "bench_peers: lodbake failed on $name" >&2
    lod=1
    for r in 0.1 0.02; do
        row "$name" "$r" lodbake "$src" "$WORK/$name.lod.glb" $lod
        lod=$((lod + 1))
        if command -v gltfpack >/dev/null; then
            fresh "$WORK/$name.gltfpack-deb.$r.glb" && gltfpack -i "$src" -o "$WORK/$name.gltfpack-deb.$r.glb" -si $r >/dev/null 2>&1
            row "$name" "$r" "gltfpack (Debian) -si $r" "$src" "$WORK/$name.gltfpack-deb.$r.glb" 0
        fi
        if [ -x "$NPM_GLTFPACK" ]; then
            fresh "$WORK/$name.gltfpack-npm.$r.glb" &&
                "$NPM_GLTFPACK" -i "$src" -o "$WORK/$name.gltfpack-npm.$r.glb" -si $r -sp -se 1 >/dev/null 2>&1
            row "$name" "$r" "gltfpack (npm) -si $r -sp -se 1" "$src" "$WORK/$name.gltfpack-npm.$r.glb" 0
        fi
        if command -v blender >/dev/null; then
            fresh "$WORK/$name.blender.$r.glb" && blender -b --factory-startup --python "$HERE/scripts/blender_decimate.py" -- "$src" "$WORK/$name.blender.$r.glb" $r \
                >"$WORK/$name.blender.$r.log" 2>&1
            row "$name" "$r" "Blender Decimate $r" "$src" "$WORK/$name.blender.$r.glb" 0
        fi
    done
done
ROWS="$ROWS]"
echo "$ROWS" | BENCH_JSON="$WORK/results.json" python3 "$HERE/scripts/bench_peers.py" "$BIN/compare" $COMPARE_FLAGS
