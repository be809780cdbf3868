#!/bin/bash
# The penumbra mask's tile test (--tile-test, issue 39): soft srt (16 spp, light 0.1, --srt-choice
# off, --tracer bvh) with the test off and on, in alternating `render` runs (ROUNDS of each, warm-up
# 1, median of REPEAT frames per run), on the courtyard and the real models (bench/fetch_scenes.sh)
# in the views of bench/tiles.sh, 512^2 and 1024^2; one `compare` of sm, srt and frt per view for
# srt's wrong pixels and its model bound (the sm frame plus the PIP share of frt's trace). Reports
# the medians over the rounds of srt's frame, classify and tile-test passes, the share of the tiles
# with receivers that the test cleared, and whether the mask stayed the same (PIP in every run).
# ONLY=regex keeps the scenes whose label it matches.
# Results: bench/results/mask_tiles.{md,csv}.
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh" mask_tiles
ROUNDS=${ROUNDS:-3}
runs=$(mktemp -d)
n=0
SOFT=(--light-size 0.1 --spp 16 --tracer bvh --srt-choice off --warmup 1 --repeat "$REPEAT")

# view LABEL VIEW [compare options...]: both resolutions.
view() {
  local label=$1 name=$2 res round test
  shift 2
  [[ "$label" =~ ${ONLY:-.} ]] || return 0
  for res in 512x512 1024x1024; do
    n=$((n + 1))
    local dir="$runs/$(printf %03d $n)"
    mkdir -p "$dir"
    printf '%s\n' "$label" "$name" "$res" >"$dir/case"
    echo "== $label $name $res"
    ./build/bin/penumbra compare --methods sm,srt,frt --no-report --out "$dir/base" --res "$res" "${SOFT[@]}" "$@" >/dev/null
    for round in $(seq "$ROUNDS"); do
      for test in off on; do
        ./build/bin/penumbra render --method srt --out "$dir/$test$round" --res "$res" --tile-test "$test" "${SOFT[@]}" \
          "$@" >/dev/null
      done
    done
  done
}

view courtyard default --scene builtin:courtyard
bench_real_views view

/usr/bin/python3 - "$runs" bench/results/mask_tiles <<'PY'
import glob, json, os, statistics, sys
rows = []
for d in sorted(glob.glob(os.path.join(sys.argv[1], "*"))):
    label, view, res = open(os.path.join(d, "case")).read().split("\n")[:3]
    base = {x["method"]: x for x in json.load(open(os.path.join(d, "base", "metrics.json")))["methods"]}
    sm, srt, frt = base["sm"], base["srt"], base["frt"]
    machine = json.load(open(os.path.join(d, "base", "metrics.json")))["scene"]
    by = {t: [json.load(open(os.path.join(d, r, "srt.stats.json"))) for r in sorted(os.listdir(d)) if r.startswith(t)]
          for t in ("off", "on")}
    med = lambda t, f: statistics.median(f(x) for x in by[t])
    total = lambda x: x["time_ms"]["total"]
    classify = lambda x: x["time_ms"].get("classify", 0.0)
    tiletest = lambda x: x["time_ms"].get("mask_tiles", 0.0)
    counts = by["on"][0].get("counts", {})
    tiles, clear = counts.get("mask_tiles", 0), counts.get("mask_tiles_clear", 0)
    same = all(x["pip_fraction"] == srt["pip_fraction"] for x in by["off"] + by["on"])
    bound = total(sm) + srt["pip_fraction"] * frt["time_ms"].get("trace", 0.0)
    on, off = med("on", total), med("off", total)
    rows.append({
        "scene": label, "view": view, "res": res,
        "srt_off_ms": "%.1f" % off, "srt_on_ms": "%.1f" % on, "on/off": "%.2f" % (on / off),
        "classify_off_ms": "%.1f" % med("off", classify), "classify_on_ms": "%.1f" % med("on", classify),
        "mask_tiles_ms": "%.1f" % med("on", tiletest),
        "tiles_clear_pct": "%.1f" % (100.0 * clear / tiles if tiles else 0.0),
        "frt_ms": "%.1f" % total(frt), "bound_ms": "%.1f" % bound,
        "frt/srt_off": "%.2f" % (total(frt) / off), "frt/srt_on": "%.2f" % (total(frt) / on),
        "on/bound": "%.2f" % (on / bound), "pip_pct": "%.3f" % (100 * srt["pip_fraction"]),
        "mask_same": "yes" if same else "NO",
        "srt_wrong_pct": "%.4f" % (100 * srt["error"]["wrong_pixel_fraction"]),
    })
if not rows:
    sys.exit("mask_tiles: no views (ONLY=%s?)" % os.environ.get("ONLY", ""))
sys.path.insert(0, "bench/report")
import table  # noqa: E402
table.write(sys.argv[2], "The penumbra mask's tile test (bench/mask_tiles.sh)",
            ("Device: %s, %s. " % (machine.get("device", ""), machine.get("driver", ""))) + "Soft srt (16 spp, light 0.1, `--srt-choice off`, `--tracer bvh`) with `--tile-test off` "
            "and `on` in alternating `render` runs: medians over the rounds of each run's median frame (warm-up 1); "
            "classify and mask_tiles (the test's own pass) likewise. tiles_clear: of the 8x8 tiles with receivers, "
            "those the test cleared (no pixel searched). sm, frt and srt's wrong pixels (against the Embree reference "
            "with the same samples) from one `compare` (the test on); bound: the sm frame plus the PIP share of frt's "
            "trace. mask_same: every run's PIP fraction equal (the test must not change the mask).", rows)
PY
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(uname -m)" | tee bench/results/mask_tiles.machine.txt
rm -rf "$runs"
