#!/usr/bin/env bash
# Tracers (issue 15): shadow rays per second of the compute BVH (bvh), inline ray queries on the
# driver's acceleration structures (rq) and Embree on the CPU (embree), all tracing frt's rays (every
# covered pixel) on the courtyard at tessellation levels 8 / 32 / 64 and on the real models, hard
# (1024^2) and soft (light 0.1 of the radius, 16 samples per pixel, 512^2); build time and bytes of
# each tracer's structure; refit/update time of the moving meshes' structures over a loop of
# builtin:courtyard-moving (penumbra-demo under Xvfb); and sm / srt / frt frame totals on Debian 12's
# stock Mesa 22.3 lavapipe and on the installed Mesa 25 one (bench/stock_mesa.sh), same binary.
# Release build; one warm-up frame, then the median of REPEAT frames. Real models need
# bench/fetch_scenes.sh first (skipped otherwise). Writes bench/results/tracers.{csv,md} and
# tracers.machine.txt.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh
REPEAT=${REPEAT:-3}
FRAMES=${FRAMES:-120}
[ -x build/bin/penumbra ] || bash scripts/build.sh
runs=$(mktemp -d)
trap 'rm -rf "$runs"' EXIT

n=0
# run DRIVER LABEL [penumbra compare options...]: one compare, its stats kept under $runs/N-DRIVER.
run() {
  local driver=$1 label=$2 out
  shift 2
  n=$((n + 1))
  out="$runs/$(printf %03d $n)-$driver"
  echo "== [$driver] $label: $*"
  local cmd=(./build/bin/penumbra compare --warmup 1 --repeat "$REPEAT" --no-report --out "$out" "$@")
  if [ "$driver" = mesa22 ]; then bench/stock_mesa.sh -- "${cmd[@]}"; else "${cmd[@]}"; fi | tail -n 5
  echo "$label" >"$out/label"
}

G=bench/scenes/generated
# SCENES="a b ..." replaces the list (the default takes ~50 min).
scenes=(builtin:courtyard:8 builtin:courtyard:32 builtin:courtyard:64)
if [ -n "${SCENES:-}" ]; then
  read -r -a scenes <<<"$SCENES"
elif [ -f "$G/bunny_stage.gltf" ]; then
  scenes+=("$G/bunny_stage.gltf" "$G/armadillo_stage.gltf" "$G/fzk-haus_stage.gltf" "$G/fence_stage.gltf"
           "$G/bunny_sub2.gltf")
else
  echo "tracers: no real models (run bench/fetch_scenes.sh); courtyard only" >&2
fi
for scene in "${scenes[@]}"; do
  for tracer in bvh rq embree; do
    run mesa25 "$(basename "$scene") hard" --scene "$scene" --methods frt --tracer "$tracer" --res 1024x1024
    run mesa25 "$(basename "$scene") soft" --scene "$scene" --methods frt --tracer "$tracer" --res 512x512 \
      --light-size 0.1 --spp 16
  done
done

# Frame totals on both drivers: the default courtyard, 1024^2, hard; rq exists on Mesa 25 only.
for driver in mesa22 mesa25; do
  run "$driver" "frames" --scene builtin:courtyard --methods sm,srt,frt --tracer bvh --res 1024x1024
done
run mesa25 "frames" --scene builtin:courtyard --methods srt,frt --tracer rq --res 1024x1024

# Moving meshes: the drone's structure updated every frame (refit, or rebuilt past the SAH limit).
updates=$runs/updates
mkdir -p "$updates"
for tracer in bvh rq; do
  echo "== updates $tracer"
  xvfb-run -a -s "-screen 0 1024x768x24" ./build/bin/penumbra-demo --scene builtin:courtyard-moving --method frt \
    --tracer "$tracer" --res 256x256 --frames "$FRAMES" --hide-ui --stats-csv "$updates/$tracer.csv" | tail -n 1
done

machine="$(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(uname -m), $(lscpu | sed -n 's/^Model name: *//p')"
echo "machine: $machine" | tee bench/results/tracers.machine.txt
/usr/bin/python3 bench/report/tracers_table.py "$runs" "$updates" "$machine" "$REPEAT" bench/results/tracers.csv \
  >bench/results/tracers.md
echo "wrote bench/results/tracers.md and tracers.csv"
