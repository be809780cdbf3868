#!/bin/bash
# Whether the hybrid pays (issue 39): sm, srt with its choices off (the paper's: classify, trace
# the doubtful pixels) and on (--srt-choice auto: per frame the cheaper of that and tracing every
# covered pixel, by its own measurements; --tile-choice on: per tile of an area light's frame), frt, and srt's model bound (the sm frame plus the PIP share
# of frt's trace), on the courtyard and the real models (bench/fetch_scenes.sh), default and close
# views, 512^2 and 1024^2, hard and 16-spp soft (light 0.1), and 1-spp srt with the temporal
# denoiser; --tracer bvh (TRACER=rq|embree for the others). Warm-up 1, median of REPEAT frames; ratios
# come from one run each. ONLY=regex keeps the scenes whose label it matches. Results:
# bench/results/tiles.{md,csv} (bvh), tiles_rq.*, tiles_embree.*.
TRACER=${TRACER:-bvh}
name=tiles
[ "$TRACER" = bvh ] || name=tiles_$TRACER
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh" "$name"
runs=$(mktemp -d)
n=0

# one LABEL VIEW RES KIND [compare options...]: the paper's srt beside sm and frt, then srt auto.
one() {
  local label=$1 view=$2 res=$3 kind=$4 extra=() choice
  shift 4
  bench_kind_options "$kind"
  for choice in off auto; do
    n=$((n + 1))
    local out="$runs/$(printf %03d $n)" methods=srt
    [ "$choice" = off ] && methods=sm,srt,frt
    echo "== $label $view $res $kind srt-choice $choice"
    ./build/bin/penumbra compare --methods "$methods" --tracer "$TRACER" --srt-choice "$choice" \
      --tile-choice "$([ "$choice" = off ] && echo off || echo on)" --res "$res" \
      --warmup 1 --repeat "$REPEAT" --no-report --out "$out" "${extra[@]}" "$@" >/dev/null
    printf '%s\n' "$label" "$view" "$kind" "$res" "$choice" >"$out/case"
  done
}

# scene LABEL VIEW [compare options...]: both resolutions, hard and soft (KINDS).
scene() {
  local label=$1 view=$2 res kind
  shift 2
  [[ "$label" =~ ${ONLY:-.} ]] || return 0
  for res in 512x512 1024x1024; do
    for kind in ${KINDS:-hard soft}; do one "$label" "$view" "$res" "$kind" "$@"; done
  done
}

scene courtyard default --scene builtin:courtyard
if [[ "courtyard" =~ ${ONLY:-.} ]]; then
  one courtyard default 1024x1024 temporal --scene builtin:courtyard
  one courtyard:64 default 1024x1024 soft --scene builtin:courtyard:64
  one courtyard:64 default 1024x1024 hard --scene builtin:courtyard:64
fi
bench_real_views scene

/usr/bin/python3 - "$runs" "bench/results/$name" "$TRACER" <<'PY'
import glob, json, os, sys
cases = {}
for d in sorted(glob.glob(os.path.join(sys.argv[1], "*"))):
    label, view, kind, res, choice = open(os.path.join(d, "case")).read().split("\n")[:5]
    m = json.load(open(os.path.join(d, "metrics.json")))
    cases.setdefault((label, view, kind, res), {})[choice] = {x["method"]: x for x in m["methods"]}
    machine = "%s, %s" % (m["scene"].get("device", ""), m["scene"].get("driver", ""))
rows = []
for (label, view, kind, res), by in cases.items():
    off, auto = by["off"], by["auto"]
    sm, srt, frt, srta = off["sm"], off["srt"], off["frt"], auto["srt"]
    t = lambda r: r["time_ms"]["total"]
    frt_trace = frt["time_ms"].get("trace", 0.0)
    bound = t(sm) + srt["pip_fraction"] * frt_trace
    # The same bound by traversal steps (GPU BVH): srt's node visits at frt's cost per visit. Penumbra
    # rays take more steps than frt's average ray, which the pixel share does not count.
    visits = lambda r: (r.get("traversal") or {}).get("node_visits")
    step_bound = t(sm) + visits(srt) / visits(frt) * frt_trace if visits(srt) and visits(frt) else None
    counts = srta.get("counts") or {}
    whole, classified = counts.get("tiles_traced_whole"), counts.get("tiles_classified")
    pct = lambda v: "" if v is None else "%.3f" % (100 * v)
    rows.append({
        "scene": label, "view": view, "res": res, "shadows": kind,
        "sm_ms": "%.1f" % t(sm), "srt_off_ms": "%.1f" % t(srt), "srt_auto_ms": "%.1f" % t(srta),
        "srt_auto_path": srta.get("srt_path") or "",
        "tiles_whole_pct": "%.1f" % (100.0 * whole / (whole + classified)) if whole is not None and whole + classified else "",
        "frt_ms": "%.1f" % t(frt), "bound_ms": "%.1f" % bound,
        "frt/srt_off": "%.2f" % (t(frt) / t(srt)), "frt/srt_auto": "%.2f" % (t(frt) / t(srta)),
        "auto/min(frt,off)": "%.2f" % (t(srta) / min(t(frt), t(srt))), "off/bound": "%.2f" % (t(srt) / bound),
        "step_bound_ms": "" if step_bound is None else "%.1f" % step_bound,
        "off/step_bound": "" if step_bound is None else "%.2f" % (t(srt) / step_bound),
        "pip_pct": pct(srt["pip_fraction"]), "srt_off_wrong_pct": pct(srt["error"]["wrong_pixel_fraction"]),
        "srt_auto_wrong_pct": pct(srta["error"]["wrong_pixel_fraction"]), "pip_miss_pct": pct(srt["pip_miss_fraction"]),
    })
sys.path.insert(0, "bench/report")
import table  # noqa: E402
table.write(sys.argv[2], "Does the hybrid pay? srt's path choice (bench/tiles.sh, tracer %s)" % sys.argv[3],
            ("Device: %s. " % machine) + "Frame totals in ms, warm-up 1, median of the repeats, each configuration's methods in one "
            "`compare` run (srt auto in a second one). srt off: the paper's path every frame (`--srt-choice off --tile-choice off`); srt auto: "
            "`--srt-choice auto` (its path in the measured frames: classify or trace_all) with `--tile-choice on` (tiles_whole: of the tiles with covered pixels, those it traced whole); both with the penumbra mask's default `--tile-test auto`. bound: srt's model bound, "
            "the sm frame plus the PIP share of frt's trace; step_bound: the sm frame plus srt's share of frt's BVH node visits times frt's trace (what srt's own rays cost at frt's cost per step; bvh only). Wrong: |d| > 0.5 hard, > 0.05 soft against the Embree "
            "reference with the same samples; pip_miss: of sm's wrong pixels, those srt off left untraced. "
            "temporal: 1 spp with `--denoise temporal` (wrong against the 1-spp reference).", rows)
PY
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(uname -m)" | tee "bench/results/$name.machine.txt"
rm -rf "$runs"
