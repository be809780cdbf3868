#!/usr/bin/env bash
# Soft shadows (Lauterbach et al. 3.2, Fig. 8 soft): msm, pcss, srt and frt on builtin:courtyard
# at ~50K, ~300K and >=1.7M triangles (tessellation levels 11, 27, 64), 1024^2, 16 light samples
# per pixel, light sizes 0.02 / 0.1 / 0.3 of the scene radius, on each tracer; then 64 samples on
# the middle case. Release build; one warm-up frame, then the median of REPEAT frames. The
# reference (ref) uses the same samples, so frt matches it exactly and srt's error is method error.
# Writes bench/results/soft_shadows.csv (one row per method and run, with machine, driver, device).
source "$(dirname "$0")/lib.sh" soft_shadows
run() {  # level light-size tracer spp methods
  bench_compare "courtyard:$1 light-size=$2 tracer=$3 spp=$4" --scene "builtin:courtyard:$1" --light-size "$2" \
    --tracer "$3" --spp "$4" --methods "$5"
}
for level in 11 27 64; do
  for size in 0.02 0.1 0.3; do
    run "$level" "$size" bvh 16 msm,pcss,srt,frt
    run "$level" "$size" embree 16 srt,frt
  done
done
run 27 0.1 bvh 64 msm,pcss,srt,frt
run 27 0.1 embree 64 srt,frt
bench_done
