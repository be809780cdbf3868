#!/usr/bin/env bash
# Where srt's classification lets wrong pixels through (issue 17): for the built-in scenes, the
# stress scenes (foliage, level, knot) and the real models (bench/fetch_scenes.sh) in their default
# view and in a close view the model fills, at 512^2 and 1024^2, hard (point-like light) and soft
# (light 0.1, 16 samples): PIP %, sm and srt wrong %, pip_miss and penumbra_miss, and
# `compare --explain-misses`' causes of the misses. Accuracy only (one frame, no timing).
# With BEFORE=path/to/penumbra every configuration also runs on that binary (rows marked before);
# AFTER=path/to/penumbra replaces build/bin/penumbra (a copy keeps a long run apart from rebuilds).
# Writes bench/results/misses.{csv,md} and misses.machine.txt (RESULTS=path/prefix writes elsewhere).
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh
[ -x build/bin/penumbra ] || bash scripts/build.sh
G=bench/scenes/generated
[ -f "$G/bunny_stage.gltf" ] || { echo "misses: run bench/fetch_scenes.sh first" >&2; exit 1; }
runs=$(mktemp -d)
trap 'rm -rf "$runs"' EXIT
n=0

# one BUILD LABEL VIEW RES KIND [compare options...]
one() {
  local build=$1 label=$2 view=$3 res=$4 kind=$5 bin=${AFTER:-build/bin/penumbra} extra=()
  shift 5
  [ "$build" = before ] && bin=$BEFORE
  [ "$kind" = soft ] && extra=(--light-size 0.1 --spp 16)
  n=$((n + 1))
  local out="$runs/$(printf %03d $n)"
  echo "== [$build] $label $view $res $kind"
  "$bin" compare --methods sm,srt --res "$res" --warmup 0 --no-report --explain-misses --out "$out" "${extra[@]}" "$@" >/dev/null
  printf '%s\n' "$build" "$label" "$view" "$kind" "$res" >"$out/case"
}

# scene LABEL VIEW [compare options...]: every resolution, hard and soft (KINDS), on each build;
# ONLY=regex keeps the labels it matches (a partial run writes a partial table).
scene() {
  local label=$1 view=$2 res kind build
  shift 2
  [[ "$label" =~ ${ONLY:-.} ]] || return 0
  for res in 512x512 1024x1024; do
    for kind in ${KINDS:-hard soft}; do
      for build in after ${BEFORE:+before}; do one "$build" "$label" "$view" "$res" "$kind" "$@"; done
    done
  done
}

scene courtyard default --scene builtin:courtyard
KINDS=hard scene wires default --scene builtin:wires  # a directional light: no soft shadows
KINDS=hard scene room default --scene builtin:room  # a point light inside: no soft shadows
scene foliage default --scene builtin:foliage
scene level default --scene builtin:level
scene knot default --scene builtin:knot
BUNNY_LIGHT=(--light disk:-2.668,6.326,1.601:0.378,0.236,-0.227)
scene "Stanford Bunny" default --scene "$G/bunny_stage.gltf" --camera 3.431,4.177,4.901:0,0.991,0 "${BUNNY_LIGHT[@]}"
scene "Stanford Bunny" close --scene "$G/bunny_stage.gltf" --camera 1.201,2.106,1.715:0,0.991,0 "${BUNNY_LIGHT[@]}"
scene "2-cylinder engine" default --scene "$G/engine_stage.gltf" \
  --camera 3.184,3.324,4.548:0,0.367,0 --light disk:-2.475,5.318,1.485:0.138,0.091,-0.083
FZK_LIGHT=(--light disk:-2.483,5.372,1.490:0.153,0.100,-0.092)
scene "FZK-Haus" default --scene "$G/fzk-haus_stage.gltf" --camera 3.193,3.371,4.561:0,0.407,0 "${FZK_LIGHT[@]}"
scene "FZK-Haus" close --scene "$G/fzk-haus_stage.gltf" --camera 1.118,1.444,1.596:0,0.407,0 "${FZK_LIGHT[@]}"
FENCE_LIGHT=(--light disk:-1.5,3.5,-4:0,0.5,0)
scene "wrought-iron fence" default --scene "$G/fence_stage.gltf" --camera 3.245,3.597,4.636:0,0.584,0 "${FENCE_LIGHT[@]}"
scene "wrought-iron fence" close --scene "$G/fence_stage.gltf" --camera 1.136,1.639,1.623:0,0.584,0 "${FENCE_LIGHT[@]}"
# Real models of other kinds, as they are (no ground), in the default view and at 35% of its distance.
close() { scene "$1" default --scene "$G/$2.gltf"; scene "$1" close --scene "$G/$2.gltf" --camera "$3"; }
close "Japanese maple" maple 0.778,1.608,1.112:0,0.886,0
close "USS Truman" truman 0.512,0.678,0.731:0,0.203,0
close "sailing boat" sailboat 0.583,1.541,0.833:0,1,0
close "oasago2 (OpenArena)" oasago2 0.692,0.900,0.988:0,0.258,0
close "ctf_inyard (OpenArena)" ctf_inyard 0.556,0.918,0.794:0,0.402,0

python3 - "$runs" "${RESULTS:-bench/results/misses}" <<'PY'
import glob, json, os, sys
rows = []
for d in sorted(glob.glob(os.path.join(sys.argv[1], "*"))):
    build, label, view, kind, res = open(os.path.join(d, "case")).read().split("\n")[:5]
    m = json.load(open(os.path.join(d, "metrics.json")))
    by = {x["method"]: x for x in m["methods"]}
    sm, srt = by["sm"], by["srt"]
    pct = lambda v: "" if v is None else "%.4f" % (100 * v)
    causes = srt.get("miss_causes") or {}
    rows.append({
        "scene": label, "view": view, "res": res,
        "shadows": kind, "build": build, "pip_pct": pct(srt["pip_fraction"]),
        "sm_wrong_pct": pct(sm["error"]["wrong_pixel_fraction"]), "srt_wrong_pct": pct(srt["error"]["wrong_pixel_fraction"]),
        "pip_miss_pct": pct(srt["pip_miss_fraction"]), "penumbra_miss_pct": pct(srt["penumbra_miss_fraction"]),
        "miss_causes": " ".join("%s=%d" % (k, v) for k, v in sorted(causes.items()) if v),
    })
sys.path.insert(0, "bench/report")
import table  # noqa: E402
table.write(sys.argv[2], "Where srt misses (bench/misses.sh)",
            "Wrong pixels: |d| > 0.5 (hard), > 0.05 (soft) against the Embree reference with the same samples, over "
            "covered pixels. pip_miss: of the pixels sm gets wrong, those srt did not trace; penumbra_miss: of the "
            "reference's penumbra pixels, those not traced. Causes: compare --explain-misses (hard shadows).", rows)
PY
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(uname -m); $(vulkaninfo --summary 2>/dev/null | grep -m1 driverInfo | sed 's/^ *//')" \
  | tee "${RESULTS:-bench/results/misses}.machine.txt"
