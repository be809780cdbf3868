#!/usr/bin/env bash
# Runs Penumbra on Debian 12's stock Mesa 22.3 lavapipe next to the installed (backports) Mesa, with
# the same binary: downloads the stock mesa-vulkan-drivers package without installing it, unpacks it
# into a cache folder that git ignores (build-stock-mesa/, or $PENUMBRA_MESA_CACHE), and points the
# Vulkan loader at its lavapipe ICD (VK_DRIVER_FILES; VK_ICD_FILENAMES for older loaders).
#
#   bench/stock_mesa.sh -- build/bin/penumbra compare ...   # run one command on the stock driver
#   eval "$(bench/stock_mesa.sh)"                           # export the variables into this shell
#   source bench/stock_mesa.sh                              # the same, when sourced
#
# PENUMBRA_MESA_VERSION picks another Debian package version (default 22.3.6-1+deb12u2, Debian 12's).
# Needs apt-get (no root: `apt-get download` writes to the current folder) on the first run only.
_stock_mesa_main() {
  local version=${PENUMBRA_MESA_VERSION:-22.3.6-1+deb12u2}
  local repo
  repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
  local cache=${PENUMBRA_MESA_CACHE:-$repo/build-stock-mesa}/mesa-$version
  local icd=$cache/lvp_icd.json
  if [ ! -f "$icd" ]; then
    local tmp
    tmp=$(mktemp -d) || return 1
    if ! (cd "$tmp" && apt-get download "mesa-vulkan-drivers=$version" >&2); then
      echo "stock_mesa.sh: 'apt-get download mesa-vulkan-drivers=$version' failed;" \
        "check the version with 'apt-cache policy mesa-vulkan-drivers' (and run apt-get update)" >&2
      rm -rf "$tmp"
      return 1
    fi
    mkdir -p "$cache"
    dpkg -x "$tmp"/mesa-vulkan-drivers_*.deb "$cache/root" || { rm -rf "$tmp"; return 1; }
    rm -rf "$tmp"
    local lib json
    lib=$(find "$cache/root" -name libvulkan_lvp.so | head -n 1)
    json=$(find "$cache/root" -name 'lvp_icd*.json' | head -n 1)
    if [ -z "$lib" ] || [ -z "$json" ]; then
      echo "stock_mesa.sh: the package has no lavapipe (libvulkan_lvp.so and lvp_icd*.json) under $cache/root" >&2
      return 1
    fi
    # The package's ICD names the system path; point it at the unpacked library instead.
    sed -E "s#\"library_path\"[[:space:]]*:[[:space:]]*\"[^\"]*\"#\"library_path\": \"$lib\"#" "$json" > "$icd.tmp" &&
      mv "$icd.tmp" "$icd"
  fi
  STOCK_MESA_ICD=$icd
}

if [ "${BASH_SOURCE[0]}" != "$0" ]; then  # sourced: export into the caller's shell
  if _stock_mesa_main; then
    export VK_DRIVER_FILES=$STOCK_MESA_ICD VK_ICD_FILENAMES=$STOCK_MESA_ICD
  else
    return 1
  fi
else
  set -euo pipefail
  _stock_mesa_main
  if [ "${1:-}" = "--" ]; then
    shift
    VK_DRIVER_FILES=$STOCK_MESA_ICD VK_ICD_FILENAMES=$STOCK_MESA_ICD exec "$@"
  elif [ $# -gt 0 ]; then
    echo "usage: bench/stock_mesa.sh [-- command args...]" >&2
    exit 2
  else
    printf 'export VK_DRIVER_FILES=%q VK_ICD_FILENAMES=%q\n' "$STOCK_MESA_ICD" "$STOCK_MESA_ICD"
  fi
fi
