#!/usr/bin/env bash
# Per-pass costs of the hybrid (issue 16): for each scene, resolution and shadow kind, sm / srt / frt
# frame totals, every pass's GPU time (median frame), the time no pass accounts for, PIP %, rays and
# wrong pixels against the Embree reference, and srt's model bound: the sm frame plus the PIP share
# of frt's trace (hard; soft: the penumbra-mask share). With BEFORE=path/to/penumbra (a build of an
# earlier commit) each configuration runs on both binaries, alternating, in the same session.
# Scenes: the built-in courtyard (default view) and real models (bench/fetch_scenes.sh) in a view the
# model fills (the camera at 35% of real_scenes.sh's distance). Hard: point-like light; soft: light
# 0.1 of the scene radius, 16 samples per pixel. --tracer bvh (the paper's setting); TRACERS adds
# rows for other tracers on the courtyard at 1024^2, and hard-shadow rows with the map fitted to the
# view (--light-fit view) follow. Release build, warm-up 1, median of REPEAT.
# Writes bench/results/passes.{csv,md} and passes.machine.txt.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh
REPEAT=${REPEAT:-5}
TRACERS=${TRACERS:-rq embree}
[ -x build/bin/penumbra ] || bash scripts/build.sh
runs=$(mktemp -d)
trap 'rm -rf "$runs"' EXIT
G=bench/scenes/generated

n=0
# run BUILD SCENE_LABEL KIND RES TRACER [bench options...]
run() {
  local build=$1 label=$2 kind=$3 res=$4 tracer=$5 bin out methods extra=()
  shift 5
  bin=build/bin/penumbra
  [ "$build" = before ] && bin=$BEFORE
  n=$((n + 1))
  out="$runs/$(printf %03d $n)"
  methods=sm,srt,frt
  [ "$kind" = soft ] && extra=(--light-sizes 0.1 --spp 16)
  echo "== [$build] $label $kind $res $tracer"
  "$bin" bench --res "$res" --methods "$methods" --tracer "${tracer%%,*}" --warmup 1 --repeat "$REPEAT" --temporal-frames 0 \
    --no-images --no-report --out "$out" "${extra[@]}" "$@" >/dev/null
  printf '%s\n' "$build" "$label" "$kind" "$tracer" >"$out/case"
}

# builds BUILDS LABEL KIND RES TRACER [bench options...]: run on each build of the list, back to
# back, so that drift of this shared machine over the sweep hits them alike.
builds() {
  local list=$1 b
  shift
  for b in $list; do run "$b" "$@"; done
}

# scenes BUILDS KIND RES TRACER [bench options...]: the courtyard and the real models.
scenes() {
  local b=$1 kind=$2 res=$3 tracer=$4
  shift 4
  builds "$b" courtyard "$kind" "$res" "$tracer" --scenes builtin:courtyard "$@"
  if [ -f "$G/bunny_stage.gltf" ]; then
    builds "$b" "Stanford Bunny (close)" "$kind" "$res" "$tracer" --scenes "$G/bunny_stage.gltf" \
      --camera 1.201,2.106,1.715:0,0.991,0 --light disk:-2.668,6.326,1.601:0.378,0.236,-0.227 "$@"
    builds "$b" "FZK-Haus (close)" "$kind" "$res" "$tracer" --scenes "$G/fzk-haus_stage.gltf" \
      --camera 1.118,1.444,1.596:0,0.407,0 --light disk:-2.483,5.372,1.490:0.153,0.100,-0.092 "$@"
    builds "$b" "wrought-iron fence (close)" "$kind" "$res" "$tracer" --scenes "$G/fence_stage.gltf" \
      --camera 1.136,1.639,1.623:0,0.584,0 --light disk:-1.5,3.5,-4:0,0.5,0 "$@"
  fi
}

for res in 512x512 1024x1024; do
  for kind in hard soft; do scenes "${BEFORE:+before }after" "$kind" "$res" bvh; done
done
# The map fitted to the view (--light-fit view, hard shadows: area lights keep the whole-scene map).
for res in 512x512 1024x1024; do scenes after hard "$res" "bvh, view fit" --light-fit view; done
for tracer in $TRACERS; do
  for kind in hard soft; do run after courtyard "$kind" 1024x1024 "$tracer" --scenes builtin:courtyard; done
done

/usr/bin/python3 - "$runs" <<'EOF'
import csv, glob, json, os, sys
runs = sys.argv[1]
rows = []
for d in sorted(glob.glob(os.path.join(runs, "*"))):
    build, label, kind, tracer = open(os.path.join(d, "case")).read().split("\n")[:4]
    bench = json.load(open(os.path.join(d, "bench.json")))
    by = {r["method"]: r for r in bench["rows"]}
    for m in ("sm", "srt", "frt"):
        r = by[m]
        passes = r.get("passes") or {}
        rows.append(dict(build=build, scene=label, shadows=kind, res=f"{r['width']}x{r['height']}", tracer=tracer,
                         method=m, total_ms=r["time_ms"], min_ms=r["time_min_ms"], max_ms=r["time_max_ms"],
                         unaccounted_ms=r["time_ms"] - sum(passes.values()), pip=r.get("pip_fraction"),
                         rays=r.get("rays_traced"), wrong=(r.get("error") or {}).get("wrong_pixel_fraction"),
                         zoom=(r.get("stats") or {}).get("light_map_zoom"),
                         passes=json.dumps({k: round(v, 2) for k, v in passes.items()}),
                         device=bench.get("device", ""), driver=bench.get("driver", "")))
os.makedirs("bench/results", exist_ok=True)
with open("bench/results/passes.csv", "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=list(rows[0].keys()))
    w.writeheader()
    w.writerows(rows)

def key(r): return (r["build"], r["scene"], r["shadows"], r["res"], r["tracer"])
groups = {}
for r in rows: groups.setdefault(key(r), {})[r["method"]] = r
order = ["gbuffer", "light_fit", "shadow_map", "thin_pass", "classify", "depth_pyramid", "lookup", "compact", "trace", "shade"]
out = ["# Per-pass costs: sm, srt, frt (bench/passes.sh)", "",
       f"{rows[0]['device']}, {rows[0]['driver']}; median of the frames, ms. `other` = frame total minus the passes "
       "(submission, readbacks, host work). Bound = sm total + PIP share x frt's trace pass.", ""]
for build in ("before", "after"):
    keys = [k for k in groups if k[0] == build]
    if not keys: continue
    out += [f"## {build}", "",
            "| scene | shadows | res | tracer | sm | srt | frt | srt/sm | frt/srt | srt/bound | PIP % | map zoom | " +
            " | ".join(order) + " | other | sm: shadow_map | sm: lookup | frt: trace | srt wrong % | sm wrong % |",
            "|" + "---|" * (17 + len(order))]
    for k in keys:
        g = groups[k]
        sm, srt, frt = g["sm"], g["srt"], g["frt"]
        sp = json.loads(srt["passes"])
        bound = sm["total_ms"] + (srt["pip"] or 0) * json.loads(frt["passes"]).get("trace", 0)
        cells = [k[1], k[2], k[3], k[4], f"{sm['total_ms']:.0f}", f"{srt['total_ms']:.0f}", f"{frt['total_ms']:.0f}",
                 f"{srt['total_ms'] / sm['total_ms']:.2f}", f"{frt['total_ms'] / srt['total_ms']:.2f}",
                 f"{srt['total_ms'] / bound:.2f}", f"{100 * (srt['pip'] or 0):.1f}",
                 f"{srt['zoom']:.1f}" if srt["zoom"] else ""]
        cells += [f"{sp[p]:.1f}" if p in sp else "" for p in order]
        smp, frtp = json.loads(sm["passes"]), json.loads(frt["passes"])
        cells += [f"{srt['unaccounted_ms']:.1f}", f"{smp.get('shadow_map', 0):.1f}", f"{smp.get('lookup', 0):.1f}",
                  f"{frtp.get('trace', 0):.1f}", f"{100 * srt['wrong']:.4f}" if srt["wrong"] is not None else "",
                  f"{100 * sm['wrong']:.3f}" if sm["wrong"] is not None else ""]
        out.append("| " + " | ".join(cells) + " |")
    out.append("")
open("bench/results/passes.md", "w").write("\n".join(out) + "\n")
print("\n".join(out))
EOF
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(uname -m)" |
  tee bench/results/passes.machine.txt
