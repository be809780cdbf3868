#!/usr/bin/env bash
# Models the project did not make (issues 20 and 22): every file of Debian's assimp-testmodels
# (fetched by bench/fetch_scenes.sh into bench/models/; valid and deliberately broken models in
# some 40 formats) through `penumbra render --method sm` at 32x32. Each must render (exit 0) or be
# refused with a message (exit 2); a crash (exit >= 128) or a hang (60 s, exit 124) is a finding.
# Writes bench/results/model_corpus.{csv,md}.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh
[ -x build/bin/penumbra ] || bash scripts/build.sh
root=bench/models/assimp-testmodels
[ -d "$root" ] || { echo "model_corpus: run bench/fetch_scenes.sh first" >&2; exit 1; }
csv=bench/results/model_corpus.csv
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
echo "exit,ms,file,message" >"$csv"
# Image, text and material files are what models refer to, not models.
find "$root" -type f | grep -viE '\.(png|jpe?g|bmp|tga|dds|txt|md|mtl|bin|xml|tiff?|gif|pcx|rgb|psd|hdr)$' | sort |
  while read -r file; do
    start=$(date +%s%N)
    rc=0
    timeout 60 build/bin/penumbra render --scene "$file" --method sm --res 32x32 --shadow-map-res 256 --out "$out/r" \
      >"$out/log" 2>&1 || rc=$?
    ms=$(( ($(date +%s%N) - start) / 1000000 ))
    message=$(grep '^penumbra: ' "$out/log" | tail -n 1 | cut -c1-200 | tr ',"' ';'"'" || true)
    echo "$rc,$ms,${file#"$root"/},\"$message\"" >>"$csv"
  done
/usr/bin/python3 - "$csv" "$(git rev-parse --short HEAD)" <<'EOF'
import csv, collections, sys
rows = list(csv.DictReader(open(sys.argv[1])))
codes = collections.Counter(int(r["exit"]) for r in rows)
bad = [r for r in rows if int(r["exit"]) not in (0, 2)]
ext = collections.Counter(r["file"].rsplit(".", 1)[-1].lower() for r in rows if int(r["exit"]) == 0)
md = ["# Models the project did not make: Debian's assimp-testmodels (bench/model_corpus.sh)", "",
      f"{len(rows)} files through `penumbra render --method sm --res 32x32` (commit {sys.argv[2]}): "
      f"{codes[0]} rendered, {codes[2]} refused with a message (exit 2), {len(bad)} crashed or hung.", "",
      "Rendered, by extension: " + ", ".join(f"{e} {n}" for e, n in ext.most_common()) + ".", ""]
if bad:
    md += ["| exit | file |", "|---:|---|"] + [f"| {r['exit']} | {r['file']} |" for r in bad]
open(sys.argv[1].replace(".csv", ".md"), "w").write("\n".join(md) + "\n")
print("\n".join(md))
EOF
