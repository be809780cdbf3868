#!/usr/bin/env bash
# Proves that the bundle (scripts/bundle.sh) runs where none of Debian's packages are installed.
# It unpacks the tarball into a root that holds glibc alone (the files of Debian's libc6) and dash
# as /bin/sh, and runs, chrooted there in a private mount namespace (/dev, /proc, /sys bound in):
#   1. glibc's loader lists every program and library of the bundle: none may need a missing library;
#   2. ./penumbra device --validate, ./penumbra compare --scene builtin:courtyard --methods sm,srt,frt
#      (validation on) and render_tests' CLI tests, on lavapipe carried into /lavapipe for the check
#      alone (Mesa's CPU driver and the libraries it loads; on a GPU machine the vendor's driver
#      takes its place);
# then, outside the root, the unpacked bundle's gpu_check.sh --cpu (here's lavapipe). Usage:
#   bash scripts/bundle_check.sh [TARBALL]    (default: a fresh bash scripts/bundle.sh)
# Root, or unprivileged user namespaces (unshare -r), for the chroot. Writes out/bundle_check/.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
tarball=${1:-$(bash scripts/bundle.sh | tail -n1)}
out=out/bundle_check
rm -rf "$out"
mkdir -p "$out"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
root=$work/root

# glibc: libc6's files (ld.so, libc, libm, ...) in Debian 12's merged-/usr layout, and dash as sh.
mkdir -p "$root"/{usr/bin,usr/lib/x86_64-linux-gnu,usr/lib64,dev,proc,sys,tmp,lavapipe}
ln -s usr/bin "$root/bin"
ln -s usr/lib "$root/lib"
ln -s usr/lib64 "$root/lib64"
chmod 1777 "$root/tmp"
while read -r f; do
  case $f in */x86_64-linux-gnu/*.so* | /lib64/ld-linux-x86-64.so.2)
    [ -e "$f" ] || continue
    mkdir -p "$(dirname "$root/usr${f#/usr}")"
    cp -a "$f" "$root/usr${f#/usr}" ;;
  esac
done < <(dpkg -L libc6)
cp /usr/bin/dash "$root/usr/bin/sh"
tar -C "$root" -xzf "$tarball"
bundle=/$(basename "$tarball" .tar.gz)
[ -x "$root$bundle/penumbra" ] || { echo "bundle_check: $tarball holds no ${bundle#/}/penumbra" >&2; exit 1; }

# lavapipe for the check: its ICD and what it loads, apart from glibc.
lvp=$(sed -n 's/.*"library_path": *"\([^"]*\)".*/\1/p' /usr/share/vulkan/icd.d/lvp_icd.json)
[[ $lvp == /* ]] || lvp=/usr/lib/x86_64-linux-gnu/$lvp  # a bare name: the loader's search path
cp -L "$lvp" "$root/lavapipe/"
ldd "$lvp" | sed -n 's/^[[:space:]]*\([^ ]*\) => \(\/[^ ]*\) .*/\1 \2/p' | while read -r soname path; do
  case $soname in libc.so.* | libm.so.* | libpthread.so.* | libdl.so.* | librt.so.* | ld-linux*) continue ;; esac
  cp -L "$path" "$root/lavapipe/$soname"
done
sed "s|\"library_path\": *\"[^\"]*\"|\"library_path\": \"/lavapipe/${lvp##*/}\"|" /usr/share/vulkan/icd.d/lvp_icd.json \
  >"$root/lavapipe/lvp_icd.json"

cat >"$root/check.sh" <<EOF
set -e
cd $bundle
echo "== 1. every program and library's dependencies, bundle alone"
missing=0
for f in bin/* lib/*; do
  if LD_LIBRARY_PATH=$bundle/lib /lib64/ld-linux-x86-64.so.2 --list "\$f" >/tmp/deps 2>&1; then
    while read -r line; do
      case \$line in *"not found"*) echo "\$f: \$line"; missing=1 ;; esac
    done </tmp/deps
  else
    echo "\$f: the loader cannot list it"; cat /tmp/deps; missing=1
  fi
done
[ \$missing = 0 ] || { echo "bundle_check: libraries missing from the bundle"; exit 1; }
echo "all found"
export VK_DRIVER_FILES=/lavapipe/lvp_icd.json VK_ICD_FILENAMES=/lavapipe/lvp_icd.json LD_LIBRARY_PATH=/lavapipe
export XDG_RUNTIME_DIR=/tmp HOME=/tmp
echo "== 2. on lavapipe carried in /lavapipe"
./penumbra device --validate --out /tmp/device.json >/dev/null
./penumbra compare --scene builtin:courtyard --methods sm,srt,frt --res 256x256 --validate --no-report --out /tmp/compare
./run render_tests --gtest_brief=1 --gtest_filter='Cli.*'
EOF
if [ "$(id -u)" -eq 0 ]; then ns=(unshare --mount); else ns=(unshare --map-root-user --mount); fi
if ! "${ns[@]}" bash -c '
  set -e
  root=$1
  mount --make-rprivate /
  for d in dev proc sys; do mount --rbind "/$d" "$root/$d"; done
  exec chroot "$root" /bin/sh /check.sh
' sh "$root" 2>&1 | tee "$out/clean_root.txt"; then
  echo "bundle_check: failed in the clean root (see $out/clean_root.txt)" >&2
  exit 1
fi
cp "$root/tmp/device.json" "$root/tmp/compare/metrics.json" "$out/"

echo "== 3. gpu_check.sh --cpu from the unpacked bundle"
mkdir -p "$work/unpacked"
tar -C "$work/unpacked" -xzf "$tarball"
"$work/unpacked$bundle/gpu_check.sh" --cpu "$out/gpu_check"
echo "bundle_check: passed ($tarball, $(du -m "$tarball" | cut -f1) MiB)"
