#!/usr/bin/env bash
# Many lights (issue 42): builtin:street with 1, 4, 16 and 64 lamps (point lights of range 7 whose
# ranges barely overlap, the same camera for every count), sm / srt / frt against the Embree
# reference of every lamp, 512^2, --tracer bvh. Per row: the frame's time and its passes summed over
# the lamps, the lamps the view reaches (the others are culled), rays, PIP, the worst lamp's wrong
# pixels and pip_miss against the reference's same lamp, the shaded image's rmse, the maps' texels,
# and the frame's cost over the same street lit by its first lamp alone; the largest street again with
# a trace dispatch per lamp (--lights-trace each), and with each lamp keeping its own maps
# (--reuse-light-passes on), and with --light-error 0.01; then its first 16 lamps without a range by
# --light-error. Release build, warm-up 1, median of REPEAT.
# Writes bench/results/lights.{csv,md} and lights.machine.txt.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh
REPEAT=${REPEAT:-3}
RES=${RES:-512x512}
LAMPS=${LAMPS:-1 4 16 64}
[ -x build/bin/penumbra ] || bash scripts/build.sh
runs=$(mktemp -d)
trap 'rm -rf "$runs"' EXIT

for n in $LAMPS; do
  echo "== builtin:street:$n"
  ./build/bin/penumbra compare --scene "builtin:street:$n" --methods sm,srt,frt --tracer bvh --res "$RES" --warmup 1 \
    --repeat "$REPEAT" --no-report --out "$runs/$n" | tail -n 5
  # the same street lit by its first lamp alone (a lights file of it, from the scene's saved view)
  ./build/bin/penumbra render --scene "builtin:street:$n" --method sm --res 16x16 --save-view "$runs/view$n.json" \
    --out "$runs/view$n" > /dev/null
  /usr/bin/python3 -c 'import json, sys; json.dump(json.load(open(sys.argv[1]))["lights"][:1], open(sys.argv[2], "w"))' \
    "$runs/view$n.json" "$runs/one$n.json"
  ./build/bin/penumbra compare --scene "builtin:street:$n" --lights "$runs/one$n.json" --methods sm,srt,frt --tracer bvh \
    --res "$RES" --warmup 1 --repeat "$REPEAT" --no-report --out "$runs/one$n" | tail -n 4
done
# the largest street again with a trace dispatch per lamp (--lights-trace each): one trace for the lamps, or each its own
last=${LAMPS##* }
./build/bin/penumbra compare --scene "builtin:street:$last" --methods srt,frt --tracer bvh --res "$RES" --warmup 1 \
  --repeat "$REPEAT" --lights-trace each --no-report --out "$runs/each$last" | tail -n 3

# and with each still lamp keeping maps of its own (--reuse-light-passes on, the demo's default): the
# warm-up frame renders them, the repeated frames none
./build/bin/penumbra compare --scene "builtin:street:$last" --methods sm,srt --tracer bvh --res "$RES" --warmup 1 \
  --repeat "$REPEAT" --reuse-light-passes on --no-report --out "$runs/keep$last" | tail -n 3

# and with --light-error 0.01: where a lamp's shadow changes a pixel's shade by less than 1% of white,
# srt keeps its map's answer and frt the lamp unshadowed, tracing no ray there
./build/bin/penumbra compare --scene "builtin:street:$last" --methods srt,frt --tracer bvh --res "$RES" --warmup 1 \
  --repeat "$REPEAT" --light-error 0.01 --no-report --out "$runs/eps$last" | tail -n 3

# the largest street's first 16 lamps without a range (glTF's default: each lights every pixel, fading
# with the inverse square), at --light-error 0, 0.01 and 0.03
/usr/bin/python3 -c 'import json, sys; l = json.load(open(sys.argv[1]))["lights"][:16]; [x.pop("range", None) for x in l]
json.dump(l, open(sys.argv[2], "w"))' "$runs/view$last.json" "$runs/unbounded.json"
for eps in 0 0.01 0.03; do
  ./build/bin/penumbra compare --scene "builtin:street:$last" --lights "$runs/unbounded.json" --methods srt,frt --tracer bvh \
    --res "$RES" --warmup 1 --repeat "$REPEAT" --light-error $eps --no-report --out "$runs/unbounded$eps" | tail -n 3
done

echo "$(nproc) cores, $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(./build/bin/penumbra device 2>/dev/null | grep -m1 '"driver"' | cut -d'"' -f4)" |
  tee bench/results/lights.machine.txt
/usr/bin/python3 - "$runs" "$LAMPS" "$RES" <<'EOF'
import csv, json, os, sys
runs, counts, res = sys.argv[1], sys.argv[2].split(), sys.argv[3]
rows, alone = [], {}
for n in counts:
    runs_of = [(n, "all"), ("one" + n, "first")] + (
        [("each" + n, "each"), ("keep" + n, "keep"), ("eps" + n, "eps")] if n == counts[-1] else [])
    for run, lit in runs_of:
        m = json.load(open(os.path.join(runs, run, "metrics.json")))
        for s in ([m["reference"]] if lit in ("all", "first") else []) + m["methods"]:
            lights = s.get("lights") or [s]
            t = s["time_ms"]
            if lit == "first":
                alone[(int(n), s["method"])] = t["total"]
                continue
            reached = sum(1 for l in lights if not any(note.startswith("culled") for note in l["notes"]))
            def worst(key):
                v = [l[key] for l in lights if l.get(key) is not None]
                return max(v) if v else None
            wrong = [l["error"]["wrong_pixel_fraction"] for l in lights if l.get("error")]
            mapped = [l for l in lights if (l.get("counts") or {}).get("shadow_map_texels")]
            rows.append({
                "lamps": int(n),
                "method": s["method"] + {"each": " (each)", "keep": " (kept maps)", "eps": " (ε 0.01)"}.get(lit, ""),
                "reached": reached, "total_ms": t["total"],
                "shadow_map_ms": t.get("shadow_map", 0.0), "lookup_ms": t.get("lookup", 0.0),
                "classify_ms": t.get("classify", 0.0) + t.get("thin_pass", 0.0), "trace_ms": t.get("trace", 0.0),
                "gbuffer_ms": t.get("gbuffer", 0.0), "shade_ms": t.get("shade", 0.0),
                "rays": s.get("rays_traced") or 0, "pip_fraction": s.get("pip_fraction"),
                "worst_wrong": max(wrong) if wrong else None, "worst_pip_miss": worst("pip_miss_fraction"),
                "image_rmse": (s.get("image_error") or {}).get("rmse"), "light_error_max": s.get("light_error_max"),
                "map_texels": (s.get("counts") or {}).get("shadow_map_texels", 0),
                "maps_rendered": sum(1 for l in mapped if "shadow_map" not in l.get("reused_passes", [])),
                "maps_mib": max([(l.get("memory_bytes") or {}).get("light_maps", 0) for l in lights] + [0]) / 2**20})
for r in rows:
    r["first_lamp_alone_ms"] = alone[(r["lamps"], r["method"].split(" ")[0])]
out = "bench/results/lights.csv"
with open(out, "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0]))
    w.writeheader()
    w.writerows(rows)
fmt = lambda v, p="{:.3f}": "–" if v is None else p.format(v)
with open("bench/results/lights.md", "w") as f:
    f.write("# Many lights: builtin:street (bench/lights.sh)\n\n")
    f.write(f"{res}, `--tracer bvh`, median of the repeated frames; times in ms summed over the lamps the view reaches "
            "(the others are culled: nothing runs for them). Worst lamp: the largest wrong-pixel fraction and pip_miss "
            "of any lamp against the reference's same lamp. Map Mtexels: every lamp's shadow map summed (each lamp's "
            "resolution follows its range's footprint, `--light-map-res footprint`). First lamp alone: the same "
            "method's frame of the same street lit by its first lamp only (a lights file of it); × alone: the frame's "
            "time over it. A frame of several lamps on a GPU tracer traces the lamps that trace every covered pixel (frt, and srt "
            "where `--srt-choice auto` takes that path) in one dispatch per batch of lamps (`--lights-trace one`, the "
            "default); rows `(each)`: a dispatch per lamp, in the same run. Rows `(kept maps)`: each still lamp keeps "
            "maps of its own (`--reuse-light-passes on`, the demo's default, within `--light-maps-memory`), rendered by the "
            "warm-up frame. Maps rendered: the lamps that rendered their map in the frame; maps MiB: what every lamp's maps, "
            "thin masks and edge pyramids hold. Rows `(ε 0.01)`: `--light-error 0.01`, where a lamp's shadow can change a "
            "pixel's shaded value by less than 0.01 (linear, of white) srt keeps its map's answer and frt takes the lamp "
            "unshadowed, tracing no ray there; shade error: the most the lamps' visibility errors changed a pixel's shaded "
            "value against the reference (linear, summed over the lamps).\n\n")
    f.write("| lamps | method | reached | total | shadow map | lookup | classify | trace | G-buffer | shade | rays | PIP % | "
            "worst lamp wrong % | worst pip_miss % | image rmse | shade error | map Mtexels | maps rendered | maps MiB | "
            "first lamp alone | × alone |\n")
    f.write("|" + "---|" * 21 + "\n")
    for r in rows:
        pip = None if r["pip_fraction"] is None else 100 * r["pip_fraction"]
        f.write(f"| {r['lamps']} | {r['method']} | {r['reached']} | {r['total_ms']:.1f} | {r['shadow_map_ms']:.1f} | "
                f"{r['lookup_ms']:.1f} | {r['classify_ms']:.1f} | {r['trace_ms']:.1f} | {r['gbuffer_ms']:.1f} | "
                f"{r['shade_ms']:.1f} | {r['rays']:,} | {fmt(pip, '{:.2f}')} | "
                f"{fmt(None if r['worst_wrong'] is None else 100 * r['worst_wrong'])} | "
                f"{fmt(None if r['worst_pip_miss'] is None else 100 * r['worst_pip_miss'])} | {fmt(r['image_rmse'], '{:.4f}')} | {fmt(r['light_error_max'], '{:.4f}')} | "
                f"{r['map_texels'] / 1e6:.1f} | {r['maps_rendered']} | {r['maps_mib']:.0f} | {r['first_lamp_alone_ms']:.1f} | {r['total_ms'] / r['first_lamp_alone_ms']:.2f} |\n")
    f.write("\n## Lamps without a range\n\nThe largest street's first 16 lamps with no `range` (glTF's default: each "
            "lights every pixel, fading with the inverse square, so no lamp is culled anywhere), by `--light-error`. "
            "Below ε pixels: covered pixels of every lamp where its shadow weighs less than ε (an approximate answer "
            "stands there); worst lamp wrong %: visibility, which those pixels may get wrong; shade error: the most "
            "the lamps' visibility errors changed a pixel's shaded value against the reference (linear, summed over "
            "the lamps; per lamp it stays below ε); image rmse and FLIP: the shaded sRGB image against the "
            "reference's.\n\n")
    f.write("| ε | method | total | trace | shade | rays | below ε pixels | worst lamp wrong % | shade error | "
            "worst lamp shade error | image rmse | image FLIP |\n")
    f.write("|" + "---|" * 12 + "\n")
    for eps in ("0", "0.01", "0.03"):
        m = json.load(open(os.path.join(runs, "unbounded" + eps, "metrics.json")))
        for s in m["methods"]:
            lights, t, img = s["lights"], s["time_ms"], s.get("image_error") or {}
            lamp_error = [l["light_error_max"] for l in lights if l.get("light_error_max") is not None]
            f.write(f"| {eps} | {s['method']} | {t['total']:.1f} | {t.get('trace', 0.0):.1f} | {t.get('shade', 0.0):.1f} | "
                    f"{s['rays_traced'] or 0:,} | {sum((l.get('counts') or {}).get('light_error_pixels', 0) for l in lights):,} | "
                    f"{fmt(100 * max(l['error']['wrong_pixel_fraction'] for l in lights))} | "
                    f"{fmt(s.get('light_error_max'), '{:.4f}')} | {fmt(max(lamp_error) if lamp_error else None, '{:.4f}')} | "
                    f"{fmt(img.get('rmse'), '{:.4f}')} | {fmt(img.get('flip_mean'), '{:.4f}')} |\n")
    f.write(f"\nMachine: {open('bench/results/lights.machine.txt').read().strip()}\n")
print("wrote", out, "and bench/results/lights.md")
EOF
