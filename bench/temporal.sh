#!/usr/bin/env bash
# Temporal stability (issue 8): under a slowly moving light (circling 0.25 degrees per frame about
# the scene's vertical axis), the mean |change| of the visibility buffer between consecutive
# frames, for every method and for the Embree reference; a method above the reference's value
# flickers (shadow-map texels swimming, sample noise that is not shared between frames).
# `penumbra bench --temporal-frames`, Release build, 512^2, hard light and a 0.05 R area light, on
# the static courtyard and the one with the moving drone (posed at t = 0; the light moves, not it).
# Writes bench/results/temporal.{csv,md,machine.txt} and temporal_report/ (report.html).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh
[ -x build/bin/penumbra ] || bash scripts/build.sh
RES=${RES:-512x512}
FRAMES=${FRAMES:-8}
out=bench/results/temporal_report
rm -rf "$out"
./build/bin/penumbra bench --methods sm,pcf,pcss,msm,srt,frt,ls --scenes builtin:courtyard,builtin:courtyard-moving \
  --light-sizes 0,0.05 --res "$RES" --warmup 1 --repeat 3 --temporal-frames "$FRAMES" --no-images --out "$out"
mv "$out/bench.csv" bench/results/temporal.csv
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(uname -m)" |
  tee bench/results/temporal.machine.txt
/usr/bin/python3 - "$RES" "$FRAMES" <<'PY' > bench/results/temporal.md
import csv, sys
rows = list(csv.DictReader(open("bench/results/temporal.csv")))
res, frames = sys.argv[1], sys.argv[2]
first = rows[0]
print("# Temporal stability under a slowly moving light\n")
print(f"`bench/temporal.sh`: {res}, {frames} frames per method with the light circling 0.25 degrees per frame about the "
      "scene's vertical axis; the value is the mean |visibility change| between consecutive frames over pixels covered in "
      "both, and 'vs ref' divides it by the Embree reference's (same light samples): 1.00x = no flicker beyond the true "
      "change of the shadows. Errors are of the first (timed) frame against the reference.\n")
print(f"Machine: {first['machine']}; device {first['device']}, driver {first['driver']}.\n")
print("| scene | light | method | temporal change | vs ref | wrong % | time ms (median) |")
print("|---|---|---|---|---|---|---|")
for r in rows:
    t, ref = r["temporal_change"], r["ref_temporal_change"]
    ratio = f"{float(t) / float(ref):.2f}x" if t and ref and float(ref) > 0 else "n/a"
    wrong = f"{100 * float(r['wrong_pixel_fraction']):.3f}" if r["wrong_pixel_fraction"] else "-"
    print(f"| {r['scene']} | {r['light_size']} | {r['label']} | {float(t):.5f} | {ratio} | {wrong} | {float(r['time_ms']):.0f} |")
PY
echo "wrote bench/results/temporal.{csv,md} and $out/report.html"
