#!/usr/bin/env bash
# The main job: set up, build, and compare sm, pcf, srt and frt against the Embree reference on the
# built-in courtyard. Writes out/ (images, visibility buffers, heatmaps, stats, metrics.json) and
# out/report.html, the page that shows them side by side with the metrics and a speed-vs-accuracy chart.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
source scripts/env.sh
./build/bin/penumbra compare --scene builtin:courtyard --methods sm,pcf,srt,frt --res 512x512 --repeat 3 --out out "$@"
echo "open out/report.html"
