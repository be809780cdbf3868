#!/bin/bash
# tiles.md's rows where srt auto came out over 1.05x min(frt, srt off), each rerun as ROUNDS (3)
# alternating rounds of srt auto, frt and srt off, one method per process (warm-up 1, median of
# REPEAT frames), so that this machine's run-to-run noise is told apart from a cost of the method.
# Reads bench/results/tiles.csv (bash bench/tiles.sh first); writes bench/results/tiles_recheck.{md,csv}.
name=tiles_recheck
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh" "$name"
ROUNDS=${ROUNDS:-3}
over=$(/usr/bin/python3 -c '
import csv
for r in csv.DictReader(open("bench/results/tiles.csv")):
    if float(r["auto/min(frt,off)"]) > 1.05:
        print("|".join((r["scene"], r["view"], r["res"], r["shadows"], r["auto/min(frt,off)"])))')
runs=$(mktemp -d)
n=0

# scene LABEL VIEW [compare options...]: the rounds of each of its rows over 1.05.
scene() {
  local label=$1 view=$2 l v res kind ratio extra round cfg methods choice out
  shift 2
  while IFS='|' read -r l v res kind ratio; do
    [ "$l|$v" = "$label|$view" ] || continue
    bench_kind_options "$kind"
    for round in $(seq "$ROUNDS"); do
      for cfg in auto frt off; do
        n=$((n + 1))
        out="$runs/$(printf %03d $n)"
        methods=srt choice=$cfg
        [ "$cfg" = frt ] && methods=frt choice=off
        echo "== $label $view $res $kind round $round $cfg"
        ./build/bin/penumbra compare --methods "$methods" --tracer bvh --srt-choice "$choice" \
          --tile-choice "$([ "$choice" = off ] && echo off || echo on)" --res "$res" --warmup 1 \
          --repeat "$REPEAT" --no-report --out "$out" "${extra[@]}" "$@" >/dev/null
        printf '%s\n' "$label" "$view" "$res" "$kind" "$ratio" "$cfg" >"$out/case"
      done
    done
  done <<<"$over"
}

scene courtyard default --scene builtin:courtyard
scene courtyard:64 default --scene builtin:courtyard:64
bench_real_views scene

/usr/bin/python3 - "$runs" "bench/results/$name" <<'PY'
import glob, json, os, statistics, sys
times = {}
for d in sorted(glob.glob(os.path.join(sys.argv[1], "*"))):
    label, view, res, kind, ratio, cfg = open(os.path.join(d, "case")).read().split("\n")[:6]
    m = json.load(open(os.path.join(d, "metrics.json")))
    total = [x for x in m["methods"] if x["method"] in ("srt", "frt")][0]["time_ms"]["total"]
    times.setdefault((label, view, res, kind, ratio), {}).setdefault(cfg, []).append(total)
    machine = "%s, %s" % (m["scene"].get("device", ""), m["scene"].get("driver", ""))
rows = []
for (label, view, res, kind, ratio), by in times.items():
    med = {cfg: statistics.median(ts) for cfg, ts in by.items()}
    spread = lambda cfg: "%.1f-%.1f" % (min(by[cfg]), max(by[cfg]))
    rows.append({"scene": label, "view": view, "res": res, "shadows": kind, "tiles.md auto/min(frt,off)": ratio,
                 "srt_auto_ms": "%.1f" % med["auto"], "frt_ms": "%.1f" % med["frt"], "srt_off_ms": "%.1f" % med["off"],
                 "auto/min(frt,off)": "%.2f" % (med["auto"] / min(med["frt"], med["off"])),
                 "auto spread": spread("auto"), "frt spread": spread("frt"), "off spread": spread("off")})
sys.path.insert(0, "bench/report")
import table  # noqa: E402
text = ("Device: %s. tiles.md's rows over 1.05, each as alternating rounds of srt auto, frt and srt off, one "
        "method per `compare` process, warm-up 1; medians of the rounds' frame totals (ms), and their spread." % machine
        if rows else "No row of tiles.md was over 1.05.")
table.write(sys.argv[2], "tiles.md's rows over 1.05, rerun (bench/tiles_recheck.sh, tracer bvh)", text,
            rows or [{"scene": ""}])
PY
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(uname -m)" | tee "bench/results/$name.machine.txt"
rm -rf "$runs"
