#!/usr/bin/env bash
# Bitmask visibility sampling against the tracers (Eisemann & Décoret 2007, the shape of Fig. 10):
# time and error of `bitmask`, `srt` and `frt` with the same light samples (--shared-samples), on
# builtin:courtyard at three tessellation levels (~4K, ~28K, ~280K triangles; the ground is the
# receiver), against light size (0.05 .. 1.0 of the scene radius, 64 samples) and against the
# sample count (32 .. 1024, light 0.2, ~28K triangles). bitmask's own pass (table, map fit,
# casters' influence regions, resolve) is reported apart from the fallback (srt: the classification
# answers the pixels off the ground, its doubtful ones traced), with its fill (influence-region
# texels per map texel).
# Writes bench/results/bitmask.csv (compare's rows), bitmask.md (the tables) and bitmask.machine.txt.
# RES (default 256x256), REPEAT (default 1), MAP (--bitmask-res, default 512).
RES=${RES:-256x256}
REPEAT=${REPEAT:-1}
source "$(dirname "$0")/lib.sh" bitmask
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
MAP=${MAP:-512}

one() {  # name level size spp
  local out="$work/$1"
  echo "== $1"
  ./build/bin/penumbra compare --res "$RES" --warmup 1 --repeat "$REPEAT" --csv "$csv" --out "$out" --no-report \
    --scene "builtin:courtyard:$2" --light-size "$3" --spp "$4" --shared-samples --bitmask-res "$MAP" \
    --methods bitmask,srt,frt | tail -n 4
  printf '%s\n' "$2" "$3" "$4" >"$out/case"
}

for level in 3 8 26; do
  for size in 0.05 0.1 0.2 0.5 1.0; do one "L${level}_s${size}_n64" "$level" "$size" 64; done
done
for spp in 32 128 256 1024; do one "L8_s0.2_n${spp}" 8 0.2 "$spp"; done

bench_done
python3 - "$work" "$RES" "$MAP" >bench/results/bitmask.md <<'PY'
import glob, json, os, sys
work, res, res_map = sys.argv[1], sys.argv[2], sys.argv[3]
rows = []
for d in sorted(glob.glob(os.path.join(work, "*"))):
    level, size, spp = open(os.path.join(d, "case")).read().split()
    m = json.load(open(os.path.join(d, "metrics.json")))
    by = {x["method"]: x for x in m["methods"]}
    rows.append((int(level), float(size), int(spp), m["scene"]["triangles"], by))
rows.sort(key=lambda r: (r[3], r[1], r[2]))
machine = open("bench/results/bitmask.machine.txt").read().strip()
print("# Bitmask visibility sampling vs the tracers (bench/bitmask.sh)\n")
print(f"builtin:courtyard at three tessellation levels, {res}, default camera and disk light; `bitmask` with a {res_map}² map on")
print("the ground (the only planar mesh), every other covered pixel answered by `srt` (its fallback); `srt` and `frt` on the GPU BVH.")
print("All with the same light samples (`--shared-samples`), against the Embree reference with them: rmse and wrong %")
print("(|error| > 0.05) of the visibility over covered pixels. ms: the median frame (one warm-up frame); for bitmask")
print("also its own pass (Hough table when the samples change, map fit, influence regions, resolve) and the fallback's")
print("trace; traced %: the covered pixels the fallback traced. Fill: influence-region texels drawn per map texel. Device: lavapipe (llvmpipe, CPU), a machine shared")
print("with other jobs: times are indicative, ratios from one run.\n")
def table(title, keep):
    print(f"## {title}\n")
    print("| triangles | light | samples | bitmask ms | its pass ms | fallback trace ms | fill | traced % | bitmask rmse | bitmask wrong % | srt ms | frt ms | bitmask / frt |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for level, size, spp, tris, by in rows:
        if not keep(level, size, spp): continue
        b, s, f = by["bitmask"], by["srt"], by["frt"]
        counts = b.get("counts") or {}
        fill = counts.get("bitmask_fill_texels", 0) / max(counts.get("bitmask_map_texels", 1), 1)
        traced = 100.0 * (b["pip_fraction"] or 0.0)
        t = lambda x: x["time_ms"]["total"]
        print(f"| {tris} | {size} | {spp} | {t(b):.0f} | {b['time_ms'].get('bitmask', 0):.0f} | {b['time_ms'].get('trace', 0):.0f} | "
              f"{fill:.1f} | {traced:.1f} | {b['error']['rmse']:.4f} | {100 * b['error']['wrong_pixel_fraction']:.2f} | "
              f"{t(s):.0f} | {t(f):.0f} | {t(b) / t(f):.2f} |")
    print()
table("Against light size (64 samples)", lambda l, s, n: n == 64)
table("Against the sample count (light 0.2, ~28K triangles)", lambda l, s, n: l == 8 and abs(s - 0.2) < 1e-6)
print(machine)
PY
