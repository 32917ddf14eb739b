#!/usr/bin/env bash
# Prepares a fresh Debian 12 / Ubuntu 22.04+ machine to build and test nostencil:
# - the Vulkan loader, lavapipe (Mesa's software Vulkan) and the Khronos validation layer;
# - shaderc, glslang and SPIRV-Tools as static libraries, merged into one archive that the
#   shaderc crate links (see "Shader compilation" in README.md for why).
# Safe to run again: packages already present are kept, the archive is rebuilt.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

packages=(
  libvulkan1 libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  libshaderc-dev glslang-dev spirv-tools
  binutils pkg-config
)

as_root=()
if [ "$(id -u)" -ne 0 ]; then as_root=(sudo); fi

export DEBIAN_FRONTEND=noninteractive
"${as_root[@]}" apt-get update -q
"${as_root[@]}" apt-get install -y -q --no-install-recommends "${packages[@]}"

"$here/merge-shaderc.sh"

if ! command -v cargo >/dev/null 2>&1; then
  echo "setup: cargo is not on PATH; install Rust with rustup, then run this again" >&2
  exit 1
fi
echo "setup: done"
