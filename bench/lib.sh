# Sourced by the bench/*.sh sweeps: Release build, Vulkan environment, and one `compare` per
# configuration appended to the sweep's CSV (warm-up 1, median of REPEAT frames).
# Usage: source bench/lib.sh NAME; bench_compare LABEL [penumbra compare options...]; bench_done
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh
REPEAT=${REPEAT:-3}
RES=${RES:-1024x1024}
bench_name=$1
csv=bench/results/$bench_name.csv
rm -f "$csv"
[ -x build/bin/penumbra ] || bash scripts/build.sh

bench_compare() {
  local label=$1 out
  shift
  out=$(mktemp -d)
  echo "== $label"
  ./build/bin/penumbra compare --res "$RES" --warmup 1 --repeat "$REPEAT" --csv "$csv" --out "$out" "$@" | tail -n 6
  rm -rf "$out"
}

# bench_real_views FN: FN LABEL VIEW [compare options...] for each real model of issue 39's suite
# (bench/fetch_scenes.sh), in its default and close views; none where they are not fetched.
bench_real_views() {
  local fn=$1 g=bench/scenes/generated
  if [ ! -d "$g" ]; then
    echo "$bench_name: no real models (bash bench/fetch_scenes.sh): the courtyard only"
    return 0
  fi
  local bunny=(--scene "$g/bunny_stage.gltf" --light disk:-2.668,6.326,1.601:0.378,0.236,-0.227)
  "$fn" "Stanford Bunny" default "${bunny[@]}" --camera 3.431,4.177,4.901:0,0.991,0
  "$fn" "Stanford Bunny" close "${bunny[@]}" --camera 1.201,2.106,1.715:0,0.991,0
  local fzk=(--scene "$g/fzk-haus_stage.gltf" --light disk:-2.483,5.372,1.490:0.153,0.100,-0.092)
  "$fn" "FZK-Haus" default "${fzk[@]}" --camera 3.193,3.371,4.561:0,0.407,0
  "$fn" "FZK-Haus" close "${fzk[@]}" --camera 1.118,1.444,1.596:0,0.407,0
  "$fn" "Japanese maple" default --scene "$g/maple.gltf"
  "$fn" "Japanese maple" close --scene "$g/maple.gltf" --camera 0.778,1.608,1.112:0,0.886,0
  "$fn" "USS Truman" default --scene "$g/truman.gltf"
  "$fn" "USS Truman" close --scene "$g/truman.gltf" --camera 0.512,0.678,0.731:0,0.203,0
  "$fn" "oasago2 (OpenArena)" default --scene "$g/oasago2.gltf"
  "$fn" "oasago2 (OpenArena)" close --scene "$g/oasago2.gltf" --camera 0.692,0.900,0.988:0,0.258,0
}

# bench_kind_options KIND: sets the caller's array `extra` to the compare options of tiles.sh's kinds
# of shadows: hard (none), soft (16 spp, light 0.1) and temporal (1 spp, light 0.1, --denoise temporal).
bench_kind_options() {
  case $1 in
    soft) extra=(--light-size 0.1 --spp 16) ;;
    temporal) extra=(--light-size 0.1 --spp 1 --denoise temporal) ;;
    *) extra=() ;;
  esac
}

bench_done() {
  echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(uname -m)" |
    tee "bench/results/$bench_name.machine.txt"
  # Charts (speed vs accuracy per scene, scalability) and report.html from the rows (bench/report/report.py).
  /usr/bin/python3 bench/report/report.py csv "$csv" "bench/results/${bench_name}_report"
  echo "wrote $csv and bench/results/${bench_name}_report/report.html"
}
