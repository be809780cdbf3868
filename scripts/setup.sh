#!/usr/bin/env bash
# Installs every dependency of Penumbra from Debian 12 packages. Idempotent: installs only what is missing.
set -euo pipefail
packages=(
  build-essential cmake ninja-build pkg-config
  mesa-vulkan-drivers libvulkan-dev vulkan-validationlayers vulkan-tools glslang-tools
  libglm-dev libembree-dev libtinygltf-dev libtinyobjloader-dev libstb-dev libtinyexr-dev
  nlohmann-json3-dev libcli11-dev libgtest-dev
  python3-matplotlib chromium  # report.html charts (bench/report/report.py); the report test renders the page
  libglfw3-dev libimgui-dev libgl-dev xvfb xauth  # penumbra-demo (GLFW + OpenGL + Dear ImGui); its tests run it under Xvfb
)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -gt 0 ]; then
  sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  echo "setup: installing ${missing[*]}"
  $sudo_cmd apt-get update -qq
  DEBIAN_FRONTEND=noninteractive $sudo_cmd apt-get install -y -qq --no-install-recommends "${missing[@]}"
else
  echo "setup: all dependencies present"
fi
