#!/usr/bin/env bash
# One-off: the three tests the first GPU check failed, then srt's paper path on the GPU.
set -u
b=$(ls -d /tmp/penumbra-*-linux-x86_64)
printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s", "api_version": "1.3.0"}}\n' \
  "$(ldconfig -p | sed -n 's/.*libEGL_nvidia\.so\.0.*=> //p' | head -n1)" >/tmp/icd.json
export VK_DRIVER_FILES=/tmp/icd.json
cd /tmp
timeout 60 $b/run pass_tests --gtest_filter='PenumbraMask.SurfaceFits*' 2>&1 | tail -12
timeout 60 $b/run render_tests --gtest_filter='Cli.BadInput*' 2>&1 | tail -8
timeout 60 $b/run linespace_tests --gtest_filter='LineSpaceTracer.ExactShadows*' 2>&1 | tail -8
for args in "--scene builtin:courtyard:64 --res 1920x1080" "--scene builtin:courtyard:64 --res 1920x1080 --light-size 0.1 --spp 16" \
  "--scene builtin:courtyard --res 3840x2160"; do
  echo "### compare $args --methods sm,srt,frt --srt-choice off --repeat 5"
  timeout 90 $b/penumbra compare $args --methods sm,srt,frt --srt-choice off --tracer bvh --repeat 5 --no-report --out /tmp/c 2>&1 | tail -6
done
