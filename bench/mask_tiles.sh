#!/bin/bash
# The penumbra mask's tile test (--tile-test, issue 39): soft srt (16 spp, light 0.1, --srt-choice
# off, --tracer bvh) with the test off and on, in alternating runs (ROUNDS of each, warm-up 1,
# median of REPEAT frames per run), on the courtyard and the real models (bench/fetch_scenes.sh) in
# the views of bench/tiles.sh, 512^2 and 1024^2; sm and frt once per view, for srt's model bound
# (the sm frame plus the PIP share of frt's trace). Reports the medians over the rounds of srt's
# frame and classify pass, the share of the tiles with receivers that the test cleared, and whether
# the mask stayed the same (PIP, wrong %). ONLY=regex keeps the scenes whose label it matches.
# Results: bench/results/mask_tiles.{md,csv}.
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh" mask_tiles
ROUNDS=${ROUNDS:-3}
G=bench/scenes/generated
runs=$(mktemp -d)
n=0
SOFT=(--light-size 0.1 --spp 16 --tracer bvh --srt-choice off --warmup 1 --repeat "$REPEAT" --no-report)

run() {  # run DIR METHODS [compare options...]
  local out=$1 methods=$2
  shift 2
  ./build/bin/penumbra compare --methods "$methods" --out "$out" "${SOFT[@]}" "$@" >/dev/null
}

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
    run "$dir/base" sm,frt --res "$res" "$@"
    for round in $(seq "$ROUNDS"); do
      for test in off on; do run "$dir/$test$round" srt --res "$res" --tile-test "$test" "$@"; done
    done
  done
}

view courtyard default --scene builtin:courtyard
if [ -d "$G" ]; then
  BUNNY=(--scene "$G/bunny_stage.gltf" --light disk:-2.668,6.326,1.601:0.378,0.236,-0.227)
  view "Stanford Bunny" default "${BUNNY[@]}" --camera 3.431,4.177,4.901:0,0.991,0
  view "Stanford Bunny" close "${BUNNY[@]}" --camera 1.201,2.106,1.715:0,0.991,0
  FZK=(--scene "$G/fzk-haus_stage.gltf" --light disk:-2.483,5.372,1.490:0.153,0.100,-0.092)
  view "FZK-Haus" default "${FZK[@]}" --camera 3.193,3.371,4.561:0,0.407,0
  view "FZK-Haus" close "${FZK[@]}" --camera 1.118,1.444,1.596:0,0.407,0
  close() { view "$1" default --scene "$G/$2.gltf"; view "$1" close --scene "$G/$2.gltf" --camera "$3"; }
  close "Japanese maple" maple 0.778,1.608,1.112:0,0.886,0
  close "USS Truman" truman 0.512,0.678,0.731:0,0.203,0
  close "oasago2 (OpenArena)" oasago2 0.692,0.900,0.988:0,0.258,0
else
  echo "mask_tiles: no real models (bash bench/fetch_scenes.sh): the courtyard only"
fi

/usr/bin/python3 - "$runs" bench/results/mask_tiles <<'PY'
import csv, glob, json, os, statistics, sys
rows = []
for d in sorted(glob.glob(os.path.join(sys.argv[1], "*"))):
    label, view, res = open(os.path.join(d, "case")).read().split("\n")[:3]
    method = lambda run, name: next(x for x in json.load(open(os.path.join(d, run, "metrics.json")))["methods"]
                                    if x["method"] == name)
    sm, frt = method("base", "sm"), method("base", "frt")
    machine = json.load(open(os.path.join(d, "base", "metrics.json")))["scene"]
    by = {t: [method(r, "srt") for r in sorted(os.listdir(d)) if r.startswith(t)] for t in ("off", "on")}
    med = lambda t, f: statistics.median(f(x) for x in by[t])
    total = lambda x: x["time_ms"]["total"]
    classify = lambda x: x["time_ms"].get("classify", 0.0)
    srt = by["on"][0]
    counts = srt.get("counts", {})
    tiles, clear = counts.get("mask_tiles", 0), counts.get("mask_tiles_clear", 0)
    same = all(x["pip_fraction"] == srt["pip_fraction"] for x in by["off"] + by["on"])
    bound = total(sm) + srt["pip_fraction"] * frt["time_ms"].get("trace", 0.0)
    on, off = med("on", total), med("off", total)
    rows.append({
        "scene": label, "view": view, "res": res,
        "srt_off_ms": "%.1f" % off, "srt_on_ms": "%.1f" % on, "on/off": "%.2f" % (on / off),
        "classify_off_ms": "%.1f" % med("off", classify), "classify_on_ms": "%.1f" % med("on", classify),
        "tiles_clear_pct": "%.1f" % (100.0 * clear / tiles if tiles else 0.0),
        "frt_ms": "%.1f" % total(frt), "bound_ms": "%.1f" % bound,
        "frt/srt_off": "%.2f" % (total(frt) / off), "frt/srt_on": "%.2f" % (total(frt) / on),
        "on/bound": "%.2f" % (on / bound), "pip_pct": "%.3f" % (100 * srt["pip_fraction"]),
        "mask_same": "yes" if same else "NO",
        "srt_wrong_pct": "%.4f" % (100 * srt["error"]["wrong_pixel_fraction"]),
    })
keys = list(rows[0].keys())
with open(sys.argv[2] + ".csv", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=keys)
    w.writeheader()
    w.writerows(rows)
with open(sys.argv[2] + ".md", "w") as f:
    f.write("# The penumbra mask's tile test (bench/mask_tiles.sh)\n\n")
    f.write("Device: %s, %s. Soft srt (16 spp, light 0.1, `--srt-choice off`, `--tracer bvh`) with `--tile-test off` "
            "and `on` in alternating runs: medians over the rounds of each run's median frame (warm-up 1). "
            "tiles_clear: of the 16x16 tiles with receivers, those the test cleared (no pixel searched). bound: the sm "
            "frame plus the PIP share of frt's trace (sm and frt run once). mask_same: every run's PIP fraction equal "
            "(the test must not change the mask).\n\n" % (machine.get("device", ""), machine.get("driver", "")))
    f.write("| " + " | ".join(keys) + " |\n|" + "---|" * len(keys) + "\n")
    for r in rows:
        f.write("| " + " | ".join(r[k] for k in keys) + " |\n")
print("wrote %s.md (%d rows)" % (sys.argv[2], len(rows)))
PY
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(uname -m)" | tee bench/results/mask_tiles.machine.txt
rm -rf "$runs"
