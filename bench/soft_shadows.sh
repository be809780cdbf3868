#!/usr/bin/env bash
# Soft shadows (Lauterbach et al. 3.2, Fig. 8 soft): msm, pcss, srt and frt on builtin:courtyard
# at ~50K, ~300K and >=1.7M triangles (tessellation levels 11, 27, 64), 1024^2, 16 light samples
# per pixel, light sizes 0.02 / 0.1 / 0.3 of the scene radius, on each tracer; then 64 samples on
# the middle case. Release build; one warm-up frame, then the median of REPEAT frames. The
# reference (ref) uses the same samples, so frt matches it exactly and srt's error is method error.
# Writes bench/results/soft_shadows.csv (one row per method and run, with machine, driver, device).
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
REPEAT=${REPEAT:-3}
RES=${RES:-1024x1024}
csv=bench/results/soft_shadows.csv
rm -f "$csv"
[ -x build/bin/penumbra ] || bash scripts/build.sh
run() {  # level light-size tracer spp methods
  out=$(mktemp -d)
  echo "== courtyard:$1 light-size=$2 tracer=$3 spp=$4"
  ./build/bin/penumbra compare --scene "builtin:courtyard:$1" --light-size "$2" --tracer "$3" --spp "$4" --methods "$5" \
    --res "$RES" --warmup 1 --repeat "$REPEAT" --csv "$csv" --out "$out" | tail -n 6
  rm -rf "$out"
}
for level in 11 27 64; do
  for size in 0.02 0.1 0.3; do
    run "$level" "$size" bvh 16 msm,pcss,srt,frt
    run "$level" "$size" embree 16 srt,frt
  done
done
run 27 0.1 bvh 64 msm,pcss,srt,frt
run 27 0.1 embree 64 srt,frt
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(uname -m)" | tee bench/results/soft_shadows.machine.txt
echo "wrote $csv"
