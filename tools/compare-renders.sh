#!/usr/bin/env bash
# Byte-for-byte comparison of tools/render-matrix.sh between a base commit and the working tree:
# the proof that a refactor changed no pixel.
#
#   tools/compare-renders.sh BASE_REV
#
# BASE_REV is built in a temporary git worktree with its own target folder (the first run takes
# a few minutes), the working tree's binary with `cargo build`; both render the matrix, and every
# PNG (alpha kept) must be byte-identical, every refused case refused by both with the same message.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."

base=${1:?usage: tools/compare-renders.sh BASE_REV}
work=${COMPARE_DIR:-target/compare-renders}
base_tree="$work/base-tree"
mkdir -p "$work"

base_commit=$(git rev-parse --verify "$base^{commit}")
if [ ! -d "$base_tree" ] || [ "$(git -C "$base_tree" rev-parse HEAD)" != "$base_commit" ]; then
  git worktree remove --force "$base_tree" 2>/dev/null || rm -rf "$base_tree"
  git worktree add --detach "$base_tree" "$base_commit" >/dev/null
fi
# The base tree sits inside this workspace's folder: a base from before the workspace declares
# none, and cargo would take it for a member of this one. An empty table makes it its own.
if ! grep -q '^\[workspace\]' "$base_tree/Cargo.toml"; then
  printf '\n[workspace]\n' >> "$base_tree/Cargo.toml"
fi
# The shader compiler archive is prepared by tools/setup-debian.sh, not committed.
mkdir -p "$base_tree/tools/shaderc-lib"
cp -u tools/shaderc-lib/* "$base_tree/tools/shaderc-lib/" 2>/dev/null || true
(cd "$base_tree" && CARGO_TARGET_DIR="$PWD/../base-target" cargo build --quiet --bin nostencil)
cargo build --quiet --bin nostencil

rm -rf "$work/base" "$work/head"
tools/render-matrix.sh "$work/base" "$work/base-target/debug/nostencil"
tools/render-matrix.sh "$work/head" target/debug/nostencil

same=0
differ=0
for file in "$work/base"/*; do
  name=$(basename "$file")
  if [ ! -e "$work/head/$name" ]; then
    echo "differs: $name (only at $base)"
    differ=$((differ + 1))
  elif cmp -s "$file" "$work/head/$name"; then
    same=$((same + 1))
  else
    echo "differs: $name"
    differ=$((differ + 1))
  fi
done
for file in "$work/head"/*; do
  [ -e "$work/base/$(basename "$file")" ] || { echo "differs: $(basename "$file") (only in the working tree)"; differ=$((differ + 1)); }
done
echo "compare-renders: $same identical, $differ different (base $base_commit)"
[ "$differ" -eq 0 ]
