#!/usr/bin/env bash
# Renders every technique, in both stencil modes, on every built-in scene (plus the variants a
# refactor could break: each shadow-volume normalisation, each silhouette method), at 160x120,
# into OUT_DIR, one PNG per case named technique--variant--stencil--scene.png.
#
#   [TECHNIQUES="lit ..."] tools/render-matrix.sh OUT_DIR [NOSTENCIL_BINARY]
#
# The binary defaults to target/debug/nostencil (build it first). A case the binary refuses
# (for example a scene with no shadow caster for planar) is recorded as OUT_DIR/NAME.err with
# the binary's message, so two runs can be compared case for case by tools/compare-renders.sh.
set -euo pipefail

out=${1:?usage: tools/render-matrix.sh OUT_DIR [NOSTENCIL_BINARY]}
bin=${2:-target/debug/nostencil}
size=160x120
mkdir -p "$out"

# Every technique and built-in scene the binary lists (`nostencil info`), so that one added to
# the registry joins the matrix; plus the walking character, under a sun and a point light.
listed() { "$bin" info 2>/dev/null | sed -n "s/^$1: *//p" | tr -d ','; }
read -r -a scenes <<<"$(listed scenes) character character-point"
# TECHNIQUES="lit shadow-volume" restricts the run (the default is every technique).
read -r -a techniques <<<"${TECHNIQUES:-$(listed techniques)}"
if [ "${#scenes[@]}" -le 2 ] || [ "${#techniques[@]}" -eq 0 ]; then
  echo "render-matrix: '$bin info' listed no scenes or techniques" >&2
  exit 1
fi

variants_of() {
  case "$1" in
    shadow-volume) echo "seed max subpass" ;;
    silhouette | toon) echo "edges shader hull" ;;
    *) echo "default" ;;
  esac
}

variant_args() {
  case "$1:$2" in
    shadow-volume:*) echo "--normalize $2" ;;
    silhouette:* | toon:*) echo "--silhouette $2" ;;
    *) echo "" ;;
  esac
}

count=0
for scene in "${scenes[@]}"; do
  for technique in "${techniques[@]}"; do
    for variant in $(variants_of "$technique"); do
      for stencil in emulated reference; do
        name="$technique--$variant--$stencil--$scene"
        # shellcheck disable=SC2046
        if ! "$bin" render --size "$size" --technique "$technique" --stencil "$stencil" --scene "$scene" \
          $(variant_args "$technique" "$variant") --keep-alpha --out "$out/$name.png" 2>"$out/$name.log"; then
          mv "$out/$name.log" "$out/$name.err"
        else
          rm -f "$out/$name.log"
        fi
        count=$((count + 1))
      done
    done
  done
done
echo "render-matrix: $count cases in $out"
