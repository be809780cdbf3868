#!/usr/bin/env bash
# One-off diagnosis of why the NVIDIA Vulkan ICD does not create an instance here.
set -u
b=$(ls -d /tmp/penumbra-*-linux-x86_64)
echo "== env"; env | grep -i -E 'nvidia|vk_|ld_library|display|xdg' ; id
echo "== dev"; ls -la /dev/nvidia* /dev/dri 2>&1 | head -20
echo "== nvidia libs"; for d in /usr/local/nvidia/lib64 /lib /usr/lib/x86_64-linux-gnu /lib/x86_64-linux-gnu; do ls $d 2>/dev/null | grep -i -E 'nvidia|cuda|GLX|EGL|vulkan' | sed "s|^|$d/|"; done | sort -u | head -80
echo "== manifests"; ls -la /usr/share/vulkan/* /etc/vulkan/* /usr/share/glvnd/egl_vendor.d 2>&1 | head -30
echo "== ldd GLX"; ldd /usr/local/nvidia/lib64/libGLX_nvidia.so.0 2>&1 | head -30
echo "== ldd GLX with bundle libs"; LD_LIBRARY_PATH=$b/lib ldd /usr/local/nvidia/lib64/libGLX_nvidia.so.0 2>&1 | grep -v nvidia | head -30
echo "== system loader?"; ls -la /usr/lib/x86_64-linux-gnu/libvulkan* /lib/x86_64-linux-gnu/libvulkan* 2>&1; which vulkaninfo
echo "== loader debug (bundle)"; VK_LOADER_DEBUG=error,warn,driver timeout 20 $b/run vulkaninfo --summary 2>&1 | grep -v -E '^\s*$' | head -60
egl=$(ldconfig -p | sed -n 's/.*libEGL_nvidia\.so\.0.*=> //p' | head -n1)
echo "== EGL ICD: $egl"
if [ -n "$egl" ]; then
  printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s", "api_version": "1.3.0"}}\n' "$egl" >/tmp/egl_icd.json
  VK_DRIVER_FILES=/tmp/egl_icd.json VK_LOADER_DEBUG=error,warn timeout 20 $b/run vulkaninfo --summary 2>&1 | head -40
  echo "== penumbra device with EGL ICD"
  VK_DRIVER_FILES=/tmp/egl_icd.json timeout 30 $b/penumbra device 2>&1 | head -40
fi
echo "== GLX ICD with full path, no bundle LD path for driver"
printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s", "api_version": "1.3.0"}}\n' /usr/local/nvidia/lib64/libGLX_nvidia.so.0 >/tmp/glx_icd.json
VK_DRIVER_FILES=/tmp/glx_icd.json VK_LOADER_DEBUG=error,warn timeout 20 $b/run vulkaninfo --summary 2>&1 | head -20
echo "== strace?"; which strace ltrace gdb 2>&1
