#!/usr/bin/env bash
# Benchmark (not a test): the whole chain at scale (issue 22). Makes textured >= 1M and ~4M
# triangle inputs itself (a shared asset subdivided with its UVs, normals, material and images,
# scripts/subdivide_textured.py; cached in $WORK), runs simplify -> parameterize ->
# texture-refine -> pack with default flags on each, and prints per stage wall time, CPU time
# (user + sys) and peak RSS (/usr/bin/time), GB of peak per million input triangles, beside
# Debian gltfpack's time on the same input (-si at the finest ratio), in one run. pack also runs
# on parameterize's output directly (simplify -> parameterize -> pack, "pack (no refine)").
# Then the whole chain (the `lodbake` tool, one process) on the small shared assets.
# Goals: big inputs <= 60 s wall on 2 cores and < 1 GB peak per M input triangles, every
# stage; small assets (<= 20k triangles) <= 3 s wall for the whole chain.
# Wall times depend on the machine's load: CPU time and peak memory are the steadier figures.
#
# Usage: scripts/bench_chain.sh
#   BIN=build-dir/bin WORK=dir (cached inputs and intermediates; default out/chain)
#   BIG="duck-1M duck-4M" (inputs: duck-1M, duck-4M = Duck x 4^4, 4^5; avocado-3M = Avocado x 4^6;
#        "" = none)
#   SMALL="Avocado Duck BoxTextured CesiumMilkTruck ChrKnight" ("" = none)
#   STAGES="simplify parameterize texture-refine pack pack-norefine lodbake" (stages of the big
#        inputs to run; a stage left out reuses its cached output in $WORK, e.g. STAGES=pack to
#        work on pack; "lodbake" is the whole chain in one process, as users run it)
#   RATIO=0.1,0.02,0.004 (simplify's levels)  PARAM_FLAGS="" (extra parameterize flags, e.g.
#        "--iterations 0" for a quick layout; its outputs are then cached under another name)
#   GLTFPACK=1 (0: skip gltfpack)  THREADS=0 (--threads of every stage; 0 = all cores)
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=${BIN:-build/bin}
WORK=${WORK:-out/chain}
BIG=${BIG-duck-1M duck-4M}
SMALL=${SMALL-Avocado Duck BoxTextured CesiumMilkTruck ChrKnight}
STAGES=${STAGES:-simplify parameterize texture-refine pack pack-norefine lodbake}
RATIO=${RATIO:-0.1,0.02,0.004}
PARAM_FLAGS=${PARAM_FLAGS:-}
GLTFPACK=${GLTFPACK:-1}
THREADS=${THREADS:-0}
ASSETS=../shared/assets
mkdir -p "$WORK"

if [ ! -d "$ASSETS" ]; then echo "bench_chain.sh: $ASSETS is absent (the shared assets): nothing to measure" >&2; exit 1; fi

# Input name -> shared asset and subdivision count.
source_of() {
  case "$1" in
    duck-1M) echo "$ASSETS/Duck/Duck.glb 4" ;;
    duck-4M) echo "$ASSETS/Duck/Duck.glb 5" ;;
    avocado-3M) echo "$ASSETS/Avocado/Avocado.gltf 6" ;;
    *) echo "bench_chain.sh: unknown input $1 (duck-1M, duck-4M, avocado-3M)" >&2; return 1 ;;
  esac
}
small_file() {
  case "$1" in
    Avocado) echo "$ASSETS/Avocado/Avocado.gltf" ;;
    ChrKnight) echo "$ASSETS/ChrKnight/chr_knight.glb" ;;
    *) echo "$ASSETS/$1/$1.glb" ;;
  esac
}
triangles() {
  python3 -c "import sys; sys.path.insert(0,'tests/cli'); from lodbake_test import Gltf; g=Gltf('$1'); print(sum(g.mesh_triangle_count(i) for i in range(len(g.json['meshes']))))"
}
has_stage() { case " $STAGES " in *" $1 "*) return 0 ;; *) return 1 ;; esac; }

# measure TRIS LABEL STAGE command...: runs the command under /usr/bin/time and prints a table row.
measure() {
  local tris=$1 label=$2 stage=$3; shift 3
  local log; log=$(mktemp)
  if ! /usr/bin/time -f "TIME %e %U %S %M" "$@" >/dev/null 2>"$log"; then
    echo "| $label | $stage | failed: $(grep -v '^TIME' "$log" | grep -v 'Command exited' | tail -1) |||||"
    rm -f "$log"; return 1
  fi
  grep '^TIME' "$log" | tail -1 | awk -v l="$label" -v s="$stage" -v t="$tris" '{
    printf "| %s | %s | %.1f | %.1f | %.0f | %.2f |\n", l, s, $2, $3 + $4, $5 / 1024, $5 / 1024 / 1024 / (t / 1e6) }'
  rm -f "$log"
}

echo "lodbake chain benchmark: $(nproc) cores, load average $(cut -d' ' -f1-3 /proc/loadavg), ratio $RATIO, threads $THREADS"
if [ -n "$BIG" ]; then
  echo
  echo "| input | stage | wall s | CPU s | peak MB | peak GB per M input triangles |"
  echo "|---|---|---|---|---|---|"
fi
for name in $BIG; do
  read -r src n < <(source_of "$name")
  in=$WORK/$name.glb
  [ -f "$in" ] || /usr/bin/python3 scripts/subdivide_textured.py "$src" "$in" "$n" >/dev/null
  tris=$(triangles "$in")
  label="$name ($tris tris)"
  uvname=$name${PARAM_FLAGS:+.$(echo "$PARAM_FLAGS" | tr -c 'a-zA-Z0-9' '_')}
  common=(--threads "$THREADS" --quiet)
  if has_stage simplify; then
    measure "$tris" "$label" simplify "$BIN/simplify" -i "$in" -o "$WORK/$name.mr.glb" --ratio "$RATIO" "${common[@]}" || continue
  fi
  if has_stage parameterize; then
    # shellcheck disable=SC2086
    measure "$tris" "$label" "parameterize $PARAM_FLAGS" "$BIN/parameterize" -i "$WORK/$name.mr.glb" -o "$WORK/$uvname.uv.glb" \
      $PARAM_FLAGS "${common[@]}" || continue
  fi
  if has_stage texture-refine; then
    measure "$tris" "$label" texture-refine "$BIN/texture-refine" -i "$WORK/$uvname.uv.glb" -o "$WORK/$uvname.tex.glb" "${common[@]}" || continue
  fi
  if has_stage pack; then
    measure "$tris" "$label" pack "$BIN/pack" -i "$WORK/$uvname.tex.glb" -o "$WORK/$uvname.lod.glb" "${common[@]}" \
      --report "$WORK/$uvname.lod.json" || true
  fi
  if has_stage pack-norefine; then
    measure "$tris" "$label" "pack (no refine)" "$BIN/pack" -i "$WORK/$uvname.uv.glb" -o "$WORK/$uvname.norefine.lod.glb" "${common[@]}" \
      --report "$WORK/$uvname.norefine.lod.json" || true
  fi
  if has_stage lodbake; then
    # shellcheck disable=SC2086
    measure "$tris" "$label" "whole chain (lodbake)" "$BIN/lodbake" -i "$in" -o "$WORK/$uvname.chain.lod.glb" --ratio "$RATIO" \
      $PARAM_FLAGS "${common[@]}" --report "$WORK/$uvname.chain.lod.json" || true
  fi
  if [ "$GLTFPACK" = 1 ]; then
    measure "$tris" "$label" "gltfpack -si ${RATIO%%,*} (Debian)" gltfpack -i "$in" -o "$WORK/$name.gltfpack.glb" -si "${RATIO%%,*}" || true
  fi
done

if [ -n "$SMALL" ]; then
  echo
  echo "whole chain (lodbake -i IN -o OUT --ratio $RATIO), goal <= 3 s wall up to 20k triangles:"
  echo
  echo "| asset | triangles | wall s | CPU s | peak MB |"
  echo "|---|---|---|---|---|"
fi
for a in $SMALL; do
  f=$(small_file "$a")
  tris=$(triangles "$f")
  log=$(mktemp)
  if /usr/bin/time -f "TIME %e %U %S %M" "$BIN/lodbake" -i "$f" -o "$WORK/$a.lod.glb" --ratio "$RATIO" --threads "$THREADS" --quiet \
      --report "$WORK/$a.lod.json" >/dev/null 2>"$log"; then
    grep '^TIME' "$log" | awk -v a="$a" -v t="$tris" '{ printf "| %s | %d | %.1f | %.1f | %.0f |\n", a, t, $2, $3 + $4, $5 / 1024 }'
    python3 - "$WORK/$a.lod.json" <<'PY'
import json, sys
r = json.load(open(sys.argv[1]))
parts = []
for s in r["stages"]:
    t = s.get("time", {})
    # pack's "measure" lies inside its "pack"; "...Cpu" figures are CPU time, not wall.
    work = sum(v for k, v in t.items() if k not in ("load", "write", "measure") and not k.endswith("Cpu"))
    parts.append("%s %.1f" % (s.get("tool"), work))
print("|   stages (s of work, wall) | " + ", ".join(parts) + " ||||")
PY
  else
    echo "| $a | $tris | failed: $(grep -v '^TIME' "$log" | tail -1) |||"
  fi
  rm -f "$log"
done
