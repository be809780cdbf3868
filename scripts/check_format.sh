#!/usr/bin/env bash
# The format (.clang-format) of every C++ line changed since the commit the check began at (GLSL is
# formatted by hand): `git clang-format` reformats only changed lines, so the tree converges without
# one sweeping reformat. Prints the fix and fails when a changed line is not formatted. Run from anywhere in the
# repository; PENUMBRA_FORMAT_BASE picks another base commit.
set -euo pipefail
cd "$(dirname "$0")/.."
base=${PENUMBRA_FORMAT_BASE:-121bf8c}
command -v git-clang-format >/dev/null || { echo "check_format: git-clang-format missing; run scripts/setup.sh" >&2; exit 1; }
git rev-parse -q --verify "$base^{commit}" >/dev/null || {
  echo "check_format: base commit $base is not in this clone (a shallow clone?); fetch the history" >&2
  exit 1
}
out=$(git clang-format --diff --extensions cpp,h "$base" -- . 2>&1) || true
case "$out" in
  "no modified files to format"* | "clang-format did not modify any files"*) echo "check_format: changed lines formatted"; exit 0 ;;
esac
echo "$out"
echo "check_format: lines changed since $base are not formatted; fix with: git clang-format $base" >&2
exit 1
