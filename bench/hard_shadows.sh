#!/usr/bin/env bash
# Hard shadows, the shape of Lauterbach et al.'s Fig. 8: sm, srt and frt on builtin:courtyard at
# ~50K, ~300K and >=1.7M triangles (tessellation levels 11, 27, 64 of the same scene), 1024^2,
# on each tracer. Release build; each method warms up once, then the median of REPEAT frames.
# Writes bench/results/hard_shadows.csv (one row per method and run, with machine, driver and
# device) and prints where the per-run outputs are.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh
REPEAT=${REPEAT:-5}
RES=${RES:-1024x1024}
csv=bench/results/hard_shadows.csv
rm -f "$csv"
[ -x build/bin/penumbra ] || bash scripts/build.sh
for level in 11 27 64; do
  for tracer in bvh embree; do
    out=$(mktemp -d)
    echo "== courtyard:$level tracer=$tracer"
    ./build/bin/penumbra compare --scene "builtin:courtyard:$level" --methods sm,srt,frt --tracer "$tracer" \
      --res "$RES" --warmup 1 --repeat "$REPEAT" --csv "$csv" --out "$out" | tail -n 5
    rm -rf "$out"
  done
done
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(uname -m)" | tee bench/results/hard_shadows.machine.txt
echo "wrote $csv"
