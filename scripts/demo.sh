#!/usr/bin/env bash
# The main job: set up, build, and compare sm, pcf, srt and frt against the Embree reference on the
# built-in courtyard. Writes out/ (images, visibility buffers, heatmaps, stats, metrics.json).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
source scripts/env.sh
./build/bin/penumbra compare --scene builtin:courtyard --methods sm,pcf,srt,frt --res 512x512 --out out "$@"
