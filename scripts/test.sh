#!/usr/bin/env bash
# Set up, build, and run the whole test suite (GoogleTest through ctest).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
source scripts/env.sh
ctest --test-dir build --output-on-failure -j2
