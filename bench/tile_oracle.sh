#!/usr/bin/env bash
# What per-tile decisions (issue 39: a conservative tile test, a per-tile choice between classifying
# and tracing outright) could save at most on this device, priced from its own frames: see
# bench/tile_oracle.py. The courtyard and, where bench/fetch_scenes.sh ran, five real models at
# 512^2 and 1024^2, hard and 16-spp soft (light 0.1); REPEAT frames each (default 3).
# Writes bench/results/tile_oracle.{md,csv} and tile_oracle.machine.txt.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh
[ -x build/bin/penumbra ] && [ -d build/python/penumbra ] || bash scripts/build.sh
PYTHONPATH=build/python /usr/bin/python3 bench/tile_oracle.py bench/results/tile_oracle
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(uname -m); $(./build/bin/penumbra device 2>/dev/null | /usr/bin/python3 -c 'import json,sys; d=json.load(sys.stdin); u=d["device"]; print(u.get("name", ""), u["driver"])' 2>/dev/null || true)" |
  tee bench/results/tile_oracle.machine.txt
