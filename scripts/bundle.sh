#!/usr/bin/env bash
# Packs Penumbra for another x86-64 Linux machine that has none of Debian's packages, e.g. a GPU
# machine with its vendor's Vulkan driver: dist/penumbra-<version>-linux-x86_64.tar.gz holds
#   penumbra           the CLI's launcher (./penumbra compare ..., as build/bin/penumbra)
#   run PROGRAM ...    runs any program of bin/ with the bundle's libraries and validation layer
#   gpu_check.sh       bench/gpu_check.sh: device, correctness and timing in one go (see its header)
#   bin/               penumbra, vulkaninfo and the test programs that exercise the GPU passes
#   lib/               every shared library they load except the C library (glibc >= 2.36 is needed,
#                      Debian 12's), the Vulkan loader and the Khronos validation layer
#   share/vulkan/explicit_layer.d/   the validation layer's manifest
#   MANIFEST.txt       version, and each library with the Debian package it came from
# The machine's own Vulkan driver (its ICD manifest under /usr/share/vulkan/icd.d or /etc/vulkan/icd.d)
# is what the bundled loader finds. Builds Release first (scripts/build.sh). Usage:
#   bash scripts/bundle.sh [OUTDIR]     (default dist/); prints the tarball's path last.
set -euo pipefail
cd "$(dirname "$0")/.."
out_dir=${1:-dist}
bash scripts/build.sh >&2

version=$(git describe --always --dirty --abbrev=7 2>/dev/null || echo unknown)
name=penumbra-$version-linux-x86_64
stage=$(mktemp -d)
trap 'rm -rf "$stage"' EXIT
root=$stage/$name
mkdir -p "$root/bin" "$root/lib" "$root/share/vulkan/explicit_layer.d"

read -ra programs <<<"$(bash bench/gpu_check.sh --programs)"  # the CLI and the test programs the check runs
for p in "${programs[@]}"; do strip --strip-unneeded -o "$root/bin/$p" "build/bin/$p"; done
cp "$(command -v vulkaninfo)" "$root/bin/"

multiarch=/usr/lib/x86_64-linux-gnu
loader=$multiarch/libvulkan.so.1  # opened at run time (vk::raii::Context), so no program lists it
layer=$multiarch/libVkLayer_khronos_validation.so
# glibc's own libraries stay the machine's: they must match its dynamic loader.
is_glibc() {
  case "$1" in
    ld-linux-x86-64.so.* | libc.so.* | libm.so.* | libmvec.so.* | libpthread.so.* | libdl.so.* | librt.so.* | \
      libresolv.so.* | libutil.so.* | libanl.so.* | libnsl.so.* | libBrokenLocale.so.* | linux-vdso.so.*) return 0 ;;
  esac
  return 1
}
declare -A seen=()
add_deps_of() {  # copies what $1 needs (ldd resolves the whole tree) under its soname
  local line soname path
  while read -r line; do
    soname=${line%% *}
    path=$(sed -n 's/.*=> \(\/[^ ]*\) .*/\1/p' <<<"$line")
    if [[ $line == *"not found"* ]]; then echo "bundle: $1 needs $soname, which is not installed" >&2; exit 1; fi
    [ -n "$path" ] || continue
    is_glibc "$soname" && continue
    [ -n "${seen[$soname]:-}" ] && continue
    seen[$soname]=$path
    cp -L "$path" "$root/lib/$soname"
  done < <(ldd "$1")
}
for p in "${programs[@]}"; do add_deps_of "build/bin/$p"; done
add_deps_of "$(command -v vulkaninfo)"
for so in "$loader" "$layer"; do
  cp -L "$so" "$root/lib/${so##*/}"
  seen[${so##*/}]=$so
  add_deps_of "$so"
done
# The layer's manifest names its library relative to itself, so no search path can pick another one.
sed 's|"library_path": *"[^"]*"|"library_path": "../../../lib/libVkLayer_khronos_validation.so"|' \
  /usr/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json >"$root/share/vulkan/explicit_layer.d/VkLayer_khronos_validation.json"

cat >"$root/run" <<'EOF'
#!/bin/sh
# Runs bin/PROGRAM with the bundle's libraries (lib/, ahead of the system's) and its validation layer.
# Plain sh without external commands, so it runs on any Linux (glibc >= 2.36).
case $0 in */*) here=${0%/*} ;; *) here=. ;; esac
here=$(cd "$here" && pwd -P)
[ $# -ge 1 ] || { echo "usage: $0 PROGRAM [ARGS...] (PROGRAM in $here/bin)" >&2; exit 2; }
program=$1
shift
LD_LIBRARY_PATH="$here/lib${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}"
VK_LAYER_PATH="$here/share/vulkan/explicit_layer.d"
XDG_RUNTIME_DIR="${XDG_RUNTIME_DIR:-${TMPDIR:-/tmp}}"
PENUMBRA_CLI="$here/bin/penumbra"  # the CLI the test programs run
export LD_LIBRARY_PATH VK_LAYER_PATH XDG_RUNTIME_DIR PENUMBRA_CLI
exec "$here/bin/$program" "$@"
EOF
cat >"$root/penumbra" <<'EOF'
#!/bin/sh
# The penumbra CLI with the bundle's libraries: ./penumbra compare --scene builtin:courtyard --methods sm,srt,frt
case $0 in */*) here=${0%/*} ;; *) here=. ;; esac
exec "$here/run" penumbra "$@"
EOF
cp bench/gpu_check.sh "$root/gpu_check.sh"
chmod 755 "$root/run" "$root/penumbra" "$root/gpu_check.sh"

{
  echo "penumbra $version, built $(date -u +%Y-%m-%dT%H:%MZ) on $(. /etc/os-release && echo "$PRETTY_NAME"), glibc $(ldd --version | head -n1 | awk '{print $NF}')"
  echo "needs: x86-64 Linux with glibc >= $(ldd --version | head -n1 | awk '{print $NF}') and a Vulkan 1.3 driver"
  echo
  echo "library -> Debian package version"
  for soname in $(printf '%s\n' "${!seen[@]}" | sort); do
    real=$(readlink -f "${seen[$soname]}")
    package=$(dpkg-query -S "*/${real##*/}" 2>/dev/null | cut -d: -f1 | head -n1 || true)  # /lib or /usr/lib
    echo "$soname -> ${package:-?} $([ -n "$package" ] && dpkg-query -W -f='${Version}' "$package" 2>/dev/null)"
  done
} >"$root/MANIFEST.txt"

mkdir -p "$out_dir"
tarball=$out_dir/$name.tar.gz
tar -C "$stage" -cf - "$name" | gzip -9 >"$tarball.partial"
mv "$tarball.partial" "$tarball"
size=$(du -m "$tarball" | cut -f1)
echo "bundle: $tarball, ${size} MiB, ${#seen[@]} libraries" >&2
[ "$size" -le 60 ] || echo "bundle: warning: over the 60 MiB the device's carry and the issue allow" >&2
echo "$tarball"
