#!/usr/bin/env bash
# Installs every dependency of Penumbra from Debian 12 packages. Idempotent: installs only what is missing.
# Mesa's Vulkan driver (lavapipe) comes from bookworm-backports (Mesa 25: ray queries, per-pass timers
# that hold); everything else stays on stable. PENUMBRA_STOCK_MESA=1 keeps Debian 12's Mesa 22.3,
# which runs everything except the ray-query tracer.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  libvulkan-dev vulkan-validationlayers vulkan-tools glslang-tools
  libglm-dev libembree-dev libtinygltf-dev libtinyobjloader-dev libstb-dev libtinyexr-dev
  gltfpack libmeshoptimizer-dev  # glTF as gltfpack writes it (EXT_meshopt_compression); its tests run gltfpack
  libdraco-dev draco  # KHR_draco_mesh_compression; its tests write Draco files with draco_transcoder
  libassimp-dev  # the other model formats (.ply, .stl, .dae, .fbx, ...)
  nlohmann-json3-dev libcli11-dev libgtest-dev
  pybind11-dev python3-dev python3-numpy python3-pytest  # the Python module (python/) and its tests
  parallel slurm-wlm munge  # sharded sweeps on GNU parallel and Slurm; their test starts a one-node cluster
  clang-format  # git clang-format: the format check of changed lines (scripts/check_format.sh)
  python3-matplotlib chromium  # report.html charts (bench/report/report.py); the report test renders the page
  libglfw3-dev libimgui-dev libgl-dev xvfb xauth  # penumbra-demo (GLFW + OpenGL + Dear ImGui); its tests run it under Xvfb
)
sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"

# Adds bookworm-backports to apt by copying this machine's own Debian entry (same URIs, components and
# keyring, Suites: bookworm-backports): the project names no mirror. Does nothing when the suite is there.
add_backports() {
  grep -Eqs '(^|[[:space:]])bookworm-backports([[:space:]]|$)' /etc/apt/sources.list /etc/apt/sources.list.d/*.list \
    /etc/apt/sources.list.d/*.sources && return 1
  local entry=""
  for f in /etc/apt/sources.list.d/*.sources; do  # deb822: the stanza whose Suites has "bookworm"
    [ -f "$f" ] || continue
    entry=$(awk 'BEGIN { RS = ""; ORS = "\n\n" }
      /(^|\n)Types:[^\n]*(^|[[:space:]])deb([[:space:]]|\n|$)/ && /(^|\n)Suites:[^\n]*[[:space:]]bookworm([[:space:]]|\n|$)/ {
        n = split($0, lines, "\n"); out = ""
        for (i = 1; i <= n; i++) {
          if (lines[i] ~ /^#/) continue
          if (lines[i] ~ /^Suites:/) lines[i] = "Suites: bookworm-backports"
          if (lines[i] ~ /^Types:/) lines[i] = "Types: deb"
          out = out lines[i] "\n"
        }
        print out; exit
      }' "$f")
    [ -n "$entry" ] && { printf '%s' "$entry" | $sudo_cmd tee /etc/apt/sources.list.d/penumbra-backports.sources >/dev/null; break; }
  done
  if [ -z "$entry" ] && [ -f /etc/apt/sources.list ]; then  # one-line form: "deb [opts] URI bookworm components"
    entry=$(grep -E '^deb[[:space:]]+(\[[^]]*\][[:space:]]+)?[^[:space:]]+[[:space:]]+bookworm[[:space:]]' /etc/apt/sources.list |
      head -n1 | sed -E 's/[[:space:]]bookworm[[:space:]]/ bookworm-backports /')
    [ -n "$entry" ] && echo "$entry" | $sudo_cmd tee /etc/apt/sources.list.d/penumbra-backports.list >/dev/null
  fi
  [ -n "$entry" ] || { echo "setup: no Debian bookworm entry in /etc/apt to copy for bookworm-backports" >&2; exit 1; }
  echo "setup: added bookworm-backports (copied from this machine's Debian entry)"
}

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
missing=()
for p in "${packages[@]}"; do installed "$p" || missing+=("$p"); done
mesa_version=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
backported=()  # packages taken from bookworm-backports
if [ "${PENUMBRA_STOCK_MESA:-0}" = 1 ]; then
  installed mesa-vulkan-drivers || missing+=(mesa-vulkan-drivers)
elif [ -z "$mesa_version" ] || dpkg --compare-versions "$mesa_version" lt 25; then
  backported+=(mesa-vulkan-drivers/bookworm-backports)
fi
# `pip install .` (pyproject.toml): scikit-build-core, which needs backports' python3-packaging 25
installed python3-scikit-build-core ||
  backported+=(python3-scikit-build-core/bookworm-backports python3-packaging/bookworm-backports)
if [ ${#missing[@]} -gt 0 ] || [ ${#backported[@]} -gt 0 ]; then
  [ ${#backported[@]} -gt 0 ] && { add_backports || true; }
  echo "setup: installing ${missing[*]} ${backported[*]}"
  $sudo_cmd apt-get update -qq
  # Mesa from backports brings the libdrm and Mesa GL drivers of its own suite (apt resolves them).
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}" "${backported[@]}"
else
  echo "setup: all dependencies present (mesa-vulkan-drivers $mesa_version)"
fi
