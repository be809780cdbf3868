#!/usr/bin/env bash
# Which rule puts each pixel in srt's penumbra mask, and what the Embree reference with the same
# samples says there (`compare --explain-misses`, metrics.json's mask_rules): in penumbra (the mask's
# job), fully lit or fully dark (16 rays each, traced for nothing with these samples). The courtyard
# and, where bench/fetch_scenes.sh ran, five real models, 16-spp soft (light 0.1), srt's paper path
# (--srt-choice off). Writes bench/results/mask_rules.{md,csv} and mask_rules.machine.txt.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh
RES=${RES:-512x512}
[ -x build/bin/penumbra ] || bash scripts/build.sh
G=bench/scenes/generated
runs=$(mktemp -d)
trap 'rm -rf "$runs"' EXIT
n=0
# one LABEL VIEW [compare options...]
one() {
  local label=$1 view=$2 out
  shift 2
  n=$((n + 1))
  out="$runs/$(printf %02d $n)"
  echo "== $label $view"
  ./build/bin/penumbra compare --methods srt --srt-choice off --tracer bvh --res "$RES" --light-size 0.1 --spp 16 \
    --warmup 0 --no-report --explain-misses --out "$out" "$@" >/dev/null
  # the same without the thin-triangle mask, whose texels are edges to the splat search too
  ./build/bin/penumbra compare --methods srt --srt-choice off --tracer bvh --res "$RES" --light-size 0.1 --spp 16 \
    --warmup 0 --no-report --no-thin --out "$out/no_thin" "$@" >/dev/null
  # the reference's penumbra with these 16 samples and with 256 (nearly the continuous light's)
  PYTHONPATH=build/python /usr/bin/python3 - "$out/penumbra.json" "$RES" "$@" >/dev/null <<'PY'
import json, sys
import penumbra
w, h = map(int, sys.argv[2].split("x"))
args = sys.argv[3:]
options = dict(zip([a[2:].replace("-", "_") for a in args[0::2]], args[1::2]))
scene = penumbra.Scene(options.pop("scene"))
share = {}
for spp in (16, 256):
    f = penumbra.Renderer(scene, res=(w, h), light_size=0.1, spp=spp, **options).render("ref")
    covered = f.covered.astype(bool)
    share[spp] = float((covered & (f.visibility > 0) & (f.visibility < 1)).sum() / covered.sum())
json.dump(share, open(sys.argv[1], "w"))
PY
  printf '%s\n' "$label" "$view" >"$out/case"
}
one courtyard default --scene builtin:courtyard
if [ -d "$G" ]; then
  one "Stanford Bunny" close --scene "$G/bunny_stage.gltf" --light disk:-2.668,6.326,1.601:0.378,0.236,-0.227 \
    --camera 1.201,2.106,1.715:0,0.991,0
  one "FZK-Haus" close --scene "$G/fzk-haus_stage.gltf" --light disk:-2.483,5.372,1.490:0.153,0.100,-0.092 \
    --camera 1.118,1.444,1.596:0,0.407,0
  one "Japanese maple" default --scene "$G/maple.gltf"
  one "USS Truman" close --scene "$G/truman.gltf" --camera 0.512,0.678,0.731:0,0.203,0
  one "oasago2 (OpenArena)" default --scene "$G/oasago2.gltf"
fi
/usr/bin/python3 - "$runs" bench/results/mask_rules "$RES" <<'PY'
import glob, json, os, sys
order = ["edge_doubt", "thin_doubt", "contact_doubt", "tangent_plane", "own_depth", "edge_splat", "surface_over",
         "corner_map", "outside_map", "unexplained"]
rows = []
for d in sorted(glob.glob(os.path.join(sys.argv[1], "*"))):
    label, view = open(os.path.join(d, "case")).read().split("\n")[:2]
    m = json.load(open(os.path.join(d, "metrics.json")))
    srt = next(x for x in m["methods"] if x["method"] == "srt")
    n = srt["error"]["pixels"]
    by = srt["mask_rules"] or {}
    pct = lambda v: "%.1f" % (100.0 * v / n)
    ref = json.load(open(os.path.join(d, "penumbra.json")))
    row = {"scene": label, "view": view, "mask_pct": pct(srt["pip_pixels"]),
           "penumbra_16spp_pct": "%.1f" % (100.0 * ref["16"]), "penumbra_256spp_pct": "%.1f" % (100.0 * ref["256"]),
           "penumbra_miss": "%.4f" % (srt["penumbra_miss_fraction"] or 0.0)}
    for name in order:
        r = by.get(name)
        row[name] = "" if r is None else "%s / %s (%s)" % (pct(r["holds"]["pixels"]), pct(r["alone"]["pixels"]),
                                                           pct(r["alone"]["penumbra"]))
    nt = next(x for x in json.load(open(os.path.join(d, "no_thin", "metrics.json")))["methods"] if x["method"] == "srt")
    row["no_thin: mask_pct"] = "%.1f" % (100.0 * nt["pip_fraction"])
    row["no_thin: penumbra_miss"] = "%.4f" % (nt["penumbra_miss_fraction"] or 0.0)
    row["no_thin: wrong_pct"] = "%.4f" % (100.0 * nt["error"]["wrong_pixel_fraction"])
    rows.append(row)
sys.path.insert(0, "bench/report")
import table  # noqa: E402
text = ("%s, 16-spp soft (light 0.1 of the scene radius), srt `--srt-choice off`, `compare --explain-misses` "
        "(metrics.json's mask_rules). Shares of the covered pixels. mask: srt's penumbra mask; penumbra_16spp/256spp: "
        "the Embree reference's pixels strictly between 0 and 1 with these 16 samples and with 256 (close to the "
        "continuous light's penumbra, which a mask sound for every sample must hold); penumbra_miss: the "
        "reference's penumbra pixels (0 < v < 1, the Embree reference with the same samples) left out. Per rule: "
        "the pixels where it holds / where it alone holds (the mask would lose them without it) (of those, the "
        "reference's penumbra: a rule whose alone-penumbra is 0 here could go without a miss on this view, if it "
        "is not needed for soundness elsewhere). no_thin: the same view with `--no-thin` (no thin-triangle mask, "
        "whose texels the splat search also takes for edges): its mask, penumbra_miss and wrong pixels "
        "(|d| > 0.05, %%)." % sys.argv[3])
table.write(sys.argv[2], "Which rules put each pixel in srt's penumbra mask (bench/mask_rules.sh)", text, rows,
            [k for k in rows[0] if any(r[k] for r in rows)])
PY
echo "machine: $(nproc) cores, $(lscpu | sed -n 's/^Model name: *//p'), $(uname -m)" | tee bench/results/mask_rules.machine.txt
