#!/usr/bin/env bash
# libFuzzer over the ways a scene enters (issue 20): builds core/ and the harnesses in fuzz/ with
# clang (AddressSanitizer and UndefinedBehaviorSanitizer on) in build-fuzz/, then runs each harness
# (glTF, GLB, OBJ, builtin: specs) for FUZZ_SECONDS seconds (default 60) from its seeds and every
# input kept in fuzz/corpus/<name>/; inputs that reach new code are saved in build-fuzz/corpus/<name>/.
# A finding stops the run with the input in build-fuzz/; once fixed, keep it in fuzz/corpus/<name>/
# so that every later run replays it first.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
if ! command -v clang++ >/dev/null || ! dpkg -s libclang-rt-14-dev >/dev/null 2>&1; then
  sudo_cmd=""; [ "$(id -u)" -ne 0 ] && sudo_cmd="sudo"
  $sudo_cmd apt-get install -y --no-install-recommends clang libclang-rt-14-dev
fi
cmake -S . -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=RelWithDebInfo -DPENUMBRA_FUZZ=ON
cmake --build build-fuzz -j"$(nproc)"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
for name in gltf glb obj builtin; do
  mkdir -p "build-fuzz/corpus/$name"
  echo "== fuzz_$name, ${FUZZ_SECONDS:-60} s"
  "build-fuzz/bin/fuzz_$name" -max_total_time="${FUZZ_SECONDS:-60}" -timeout=20 -rss_limit_mb=4096 -print_final_stats=1 \
    -artifact_prefix="build-fuzz/fuzz_$name-" "build-fuzz/corpus/$name" "fuzz/corpus/$name"
done
