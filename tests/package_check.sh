#!/usr/bin/env bash
# The installed package, as a user outside the source tree meets it: `cmake --install` the build
# into a temporary prefix, build examples/cpp against it with find_package(Penumbra), run it, and
# check what it printed: srt's traced pixels, and metrics JSON in which srt matches the reference on
# builtin:square and sm does not do better; bad input is one clear line and exit code 2.
#   tests/package_check.sh BUILD_DIR
set -euo pipefail
build=$(cd "$1" && pwd)
src=$(cd "$(dirname "$0")/.." && pwd)
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake --install "$build" --prefix "$tmp/prefix" >/dev/null
headers=$(cd "$tmp/prefix/include" && find . -type f | sort)
[ "$headers" = "./penumbra/penumbra.h" ] || { echo "installed headers are not the API alone: $headers" >&2; exit 1; }
cmake -S "$src/examples/cpp" -B "$tmp/example" -G Ninja -DCMAKE_PREFIX_PATH="$tmp/prefix" >/dev/null
cmake --build "$tmp/example" >/dev/null
# The library's own symbols are the API's only (the internal libraries are hidden).
leaked=$(nm -DC --defined-only "$tmp"/prefix/lib*/libpenumbra.so | grep -c " penumbra::" | tr -d ' ' || true)
api=$(nm -DC --defined-only "$tmp"/prefix/lib*/libpenumbra.so | grep -c " penumbra::api::" | tr -d ' ' || true)
[ "$leaked" = "$api" ] || { echo "libpenumbra.so exports $((leaked - api)) internal penumbra:: symbols" >&2; exit 1; }
out=$("$tmp/example/shadow_report" builtin:square 64x64)
echo "$out" | head -1
grep -q "srt traced [1-9][0-9]* of [1-9][0-9]* covered pixels" <<<"$out"
sed -n 2p <<<"$out" | /usr/bin/python3 -c '
import json, sys
m = json.load(sys.stdin)
wrong = {r["method"]: r["error"]["wrong_pixel_fraction"] for r in m["methods"]}
assert set(wrong) == {"sm", "srt"}, wrong
assert wrong["srt"] <= 0.0005 and wrong["srt"] <= wrong["sm"], wrong
assert m["scene"]["resolution"] == [64, 64], m["scene"]["resolution"]
print("metrics: wrong", wrong)'
set +e
err=$("$tmp/example/shadow_report" builtin:nosuch 2>&1 >/dev/null)
code=$?
set -e
[ "$code" = 2 ] && grep -q "nosuch" <<<"$err" || { echo "bad scene: exit $code, '$err'" >&2; exit 1; }
echo "package_check: installed, example built and run"
