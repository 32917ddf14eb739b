#!/usr/bin/env bash
# Debian's libshaderc_combined.a is not combined: it lacks glslang and SPIRV-Tools, and its
# libshaderc.so.1 leaves glslang symbols undefined. The shaderc crate links one static archive,
# so merge the pieces into tools/shaderc-lib/libshaderc_combined.a (.cargo/config.toml points
# SHADERC_LIB_DIR there). This avoids building shaderc from source (10+ minutes on 2 cores).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
out_dir="$here/shaderc-lib"
multiarch=$(gcc -print-multiarch 2>/dev/null || dpkg-architecture -qDEB_HOST_MULTIARCH)
lib_dir="/usr/lib/$multiarch"
parts=(shaderc_combined glslang MachineIndependent GenericCodeGen OSDependent OGLCompiler
       SPIRV SPIRV-Tools-opt SPIRV-Tools)

mkdir -p "$out_dir"
script="CREATE $out_dir/libshaderc_combined.a.tmp"$'\n'
for part in "${parts[@]}"; do
  lib="$lib_dir/lib$part.a"
  # Newer glslang releases fold some of these into libglslang.a; skip what is not there.
  if [ -f "$lib" ]; then script+="ADDLIB $lib"$'\n'; fi
done
[ -f "$lib_dir/libshaderc_combined.a" ] || { echo "merge-shaderc: $lib_dir/libshaderc_combined.a not found (install libshaderc-dev)" >&2; exit 1; }
script+=$'SAVE\nEND\n'
printf '%s' "$script" | ar -M
mv "$out_dir/libshaderc_combined.a.tmp" "$out_dir/libshaderc_combined.a"
echo "merge-shaderc: wrote $out_dir/libshaderc_combined.a"
