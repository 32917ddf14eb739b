#!/usr/bin/env bash
# Prepares a fresh Debian 12 / Ubuntu 22.04+ machine to build and test nostencil:
# - the Vulkan loader, lavapipe (Mesa's software Vulkan) and the Khronos validation layer;
# - Xvfb and the X11 client libraries, for the windowed viewer and its test;
# - shaderc, glslang and SPIRV-Tools as static libraries, merged into one archive that the
#   shaderc crate links (see docs/shader-compilation.md for why).
# Safe to run again: packages already present are kept, the archive is rebuilt.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

packages=(
  libvulkan1 libvulkan-dev mesa-vulkan-drivers vulkan-validationlayers vulkan-tools
  libshaderc-dev glslang-dev spirv-tools
  binutils pkg-config
  # `nostencil view` and tests/inside/viewer.rs: an X server without a screen, and the libraries
  # winit opens at run time for X11 (Xlib, XCB, Xcursor, XRandR, XInput2, xkbcommon); the test
  # presses keys and closes the window with xdotool.
  xvfb xauth xdotool
  libx11-6 libx11-xcb1 libxcursor1 libxrandr2 libxi6 libxkbcommon0 libxkbcommon-x11-0
  # tests/real_programs.rs: programs nobody here wrote, run under the fill-rate layer
  # (vkd3d-gears, vkd3d-triangle: Direct3D 12 through vkd3d; vkcube comes with vulkan-tools;
  # mpv with Vulkan output and ffmpeg's libplacebo filter: compute and transfers).
  vkd3d-demos mpv ffmpeg
  # tests/real_programs.rs and tests/profile_app_gl.rs: OpenGL and GLES programs run on Vulkan
  # through Mesa's zink (libgl1-mesa-dri holds zink; glxgears and es2gears come with mesa-utils).
  libgl1 libgl1-mesa-dri libegl1 mesa-utils
  # tests/html_report.rs: the HTML pages opened in a real browser, JUnit XML checked against
  # its schema.
  chromium libxml2-utils
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
