#!/usr/bin/env bash
# Hard shadows, the shape of Lauterbach et al.'s Fig. 8: sm, srt and frt on builtin:courtyard at
# ~50K, ~300K and >=1.7M triangles (tessellation levels 11, 27, 64 of the same scene), 1024^2,
# on each tracer. Release build; each method warms up once, then the median of REPEAT frames.
# Writes bench/results/hard_shadows.csv (one row per method and run, with machine, driver and
# device) and prints where the per-run outputs are.
REPEAT=${REPEAT:-5}
source "$(dirname "$0")/lib.sh" hard_shadows
for level in 11 27 64; do
  for tracer in bvh embree; do
    bench_compare "courtyard:$level tracer=$tracer" --scene "builtin:courtyard:$level" --methods sm,srt,frt --tracer "$tracer"
  done
done
bench_done
