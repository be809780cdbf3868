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

bench_done() {
  echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(uname -m)" |
    tee "bench/results/$bench_name.machine.txt"
  # Charts (speed vs accuracy per scene, scalability) and report.html from the rows (bench/report/report.py).
  /usr/bin/python3 bench/report/report.py csv "$csv" "bench/results/${bench_name}_report"
  echo "wrote $csv and bench/results/${bench_name}_report/report.html"
}
