#!/usr/bin/env bash
# Set up, build, and run the whole test suite (GoogleTest through ctest), then check the bundle for
# other machines in a root without Debian's packages and run bench/gpu_check.sh --cpu from it.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
source scripts/env.sh
ctest --test-dir build --output-on-failure -j2
bash scripts/bundle_check.sh
