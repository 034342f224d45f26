#!/usr/bin/env bash
# Prints the sha256 of every output of every tool, run with the flag sets the tests use, on every
# generated sample and every asset of ../shared/assets (when present). Two builds that print the
# same list write the same bytes: run it before and after a change that must not alter output.
#
#   bash scripts/output_hashes.sh [BIN] > hashes.txt      BIN defaults to build/bin
#
# Reports are left out (they hold times). A run that fails prints its exit code instead of hashes.
set -uo pipefail
cd "$(dirname "$0")/.."
BIN="$(cd "${1:-build/bin}" && pwd)"
SHARED="${LODBAKE_SHARED:-../shared}"
WORK="$(mktemp -d /tmp/lodbake-hashes.XXXXXX)"
trap 'rm -rf "$WORK"' EXIT

# Runs one tool; on success prints "<sha256>  <tag>/<file>" for every file it wrote into its own
# output folder, otherwise "<tag> exit <code>".
run() {
  local tag="$1"; shift
  local out="$WORK/out/$tag"
  mkdir -p "$out"
  if "$@" >/dev/null 2>"$out.stderr"; then
    (cd "$out" && find . -type f | LC_ALL=C sort | while read -r f; do
      echo "$(sha256sum < "$f" | cut -c1-64)  $tag/${f#./}"
    done)
  else
    echo "$tag exit $?"
  fi
}

# The whole chain with defaults, plus agsphere-build, on one input. $1 tag, $2 input file.
chain() {
  local t="$1" in="$2" o="$WORK/out"
  run "$t.simplify" "$BIN/simplify" -i "$in" -o "$o/$t.simplify/$t.mr.glb" --ratio 0.5,0.1,0.02 --quiet
  run "$t.agsphere" "$BIN/agsphere-build" -i "$in" -o "$o/$t.agsphere/$t.ag.glb" --ratio 0.5,0.1,0.02 --quiet
  run "$t.agsphere-view" "$BIN/agsphere-build" -i "$in" -o "$o/$t.agsphere-view/$t.ag.glb" --ratio 0.1 --view 0,0,1 --light 1,1,0 --quiet
  local mr="$o/$t.simplify/$t.mr.glb"
  [ -f "$mr" ] || return 0
  run "$t.parameterize" "$BIN/parameterize" -i "$mr" -o "$o/$t.parameterize/$t.uv.glb" --quiet
  local uv="$o/$t.parameterize/$t.uv.glb"
  [ -f "$uv" ] || return 0
  run "$t.refine" "$BIN/texture-refine" -i "$uv" -o "$o/$t.refine/$t.tex.glb" --quiet
  local tex="$o/$t.refine/$t.tex.glb"
  run "$t.pack-uv" "$BIN/pack" -i "$uv" -o "$o/$t.pack-uv/$t.lod.glb" --quiet
  [ -f "$tex" ] && run "$t.pack" "$BIN/pack" -i "$tex" -o "$o/$t.pack/$t.lod.glb" --quiet
  return 0
}

run samples "$BIN/make-samples" "$WORK/out/samples"
S="$WORK/out/samples"
for f in "$S"/*.glb; do chain "$(basename "$f" .glb)" "$f"; done

# Flag sets the tests use beyond the defaults, on generated samples.
O="$WORK/out"
run seamball.simplify-tri "$BIN/simplify" -i "$S/seamball.glb" -o "$O/seamball.simplify-tri/s.glb" --triangles 2000,400 --quiet
run seamball.simplify-err "$BIN/simplify" -i "$S/seamball.glb" -o "$O/seamball.simplify-err/s.glb" --max-error 0.001,0.01 --quiet
run seamball.parameterize-256 "$BIN/parameterize" -i "$O/seamball.simplify/seamball.mr.glb" -o "$O/seamball.parameterize-256/s.glb" --size 256 --quiet
run seamball.refine-sizes "$BIN/texture-refine" -i "$O/seamball.parameterize/seamball.uv.glb" -o "$O/seamball.refine-sizes/s.glb" --sizes 64,256 --quiet
run seamball.pack-draco "$BIN/pack" -i "$O/seamball.refine/seamball.tex.glb" -o "$O/seamball.pack-draco/s.glb" --draco --qp 16 --quiet
run hemisphere9.pack-split "$BIN/pack" -i "$O/hemisphere9.refine/hemisphere9.tex.glb" -o "$O/hemisphere9.pack-split/h.glb" --split --quiet
run colors.pack-jpeg "$BIN/pack" -i "$O/colors.refine/colors.tex.glb" -o "$O/colors.pack-jpeg/c.gltf" --image-format jpeg --jpeg-quality 80 --pot --quiet
run seamball.pack-small "$BIN/pack" -i "$O/seamball.parameterize/seamball.uv.glb" -o "$O/seamball.pack-small/s.glb" --max-size 512 --samples 20000 --quiet

if [ -d "$SHARED/assets" ]; then
  for f in "$SHARED"/assets/*/*.glb "$SHARED"/assets/*/*.gltf; do
    [ -f "$f" ] || continue
    chain "asset-$(basename "$f" | sed 's/\.[a-z]*$//')" "$f"
  done
else
  echo "# ../shared/assets absent: generated samples only"
fi
