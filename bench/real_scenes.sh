#!/usr/bin/env bash
# Real scenes (the shape of Lauterbach et al. Fig. 8 on models made by others): for each real model
# set on a ground quad and for the scaled variants, hard shadows (sm, pcf, srt, frt) and soft
# shadows (msm, pcss, srt, frt; light 0.1 of the scene radius, 16 samples per pixel), 1024^2,
# GPU BVH tracer, one warm-up frame then the median of REPEAT frames. Scaling, stated per row:
# "scan" = the model itself, "subdiv xN" = midpoint subdivision of the scan (same surface, N times
# the triangles), "instanced xN" = N glTF nodes instancing one mesh. bunny_sub3 (4.46M triangles)
# exceeds lavapipe's 128 MiB storage-buffer binding for the GPU BVH, so its srt and frt trace with
# Embree (PIP classification and compaction stay on the GPU) and it runs at RES_4M (512x512).
# Needs bench/fetch_scenes.sh first. Writes bench/results/real_scenes.{csv,md}. ONLY=REGEX runs only
# the scenes whose "label scaling" matches (e.g. ONLY=fence).
REPEAT=${REPEAT:-3}
RES_4M=${RES_4M:-512x512}
# With ONLY, the other scenes' rows of the last run are kept (lib.sh starts a new CSV).
self=$(realpath "$0") previous=$(mktemp)
if [ -n "${ONLY:-}" ] && [ -f "$(dirname "$0")/results/real_scenes.csv" ]; then
  cp "$(dirname "$0")/results/real_scenes.csv" "$previous"
fi
source "$(dirname "$0")/lib.sh" real_scenes
G=bench/scenes/generated
[ -f "$G/bunny_stage.gltf" ] || { echo "real_scenes: run bench/fetch_scenes.sh first" >&2; exit 1; }
cases=$(mktemp)

# scene LABEL SCALING FILE TRACER [camera/light options...]: hard and soft runs of one scene.
scene() {
  local label=$1 scaling=$2 file=$3 tracer=$4 before after
  shift 4
  if [ -n "${ONLY:-}" ] && ! [[ "$label $scaling" =~ $ONLY ]]; then return 0; fi
  for kind in hard soft; do
    before=$( [ -f "$csv" ] && wc -l <"$csv" || echo 0)
    if [ "$kind" = hard ]; then
      bench_compare "$label hard" --scene "$G/$file" --tracer "$tracer" --methods sm,pcf,srt,frt "$@"
    else
      bench_compare "$label soft" --scene "$G/$file" --tracer "$tracer" --light-size 0.1 --spp 16 \
        --methods msm,pcss,srt,frt "$@"
    fi
    after=$(wc -l <"$csv")
    [ "$before" -eq 0 ] && before=1  # the header line
    echo "$label|$scaling|$kind|$before|$after|$RES|$*" >>"$cases"
  done
}

# Cameras and lights: the automatic three-quarter view and light (2.5 radii up and to the left)
# suit the single models, written out here so the table says what was rendered. The fences get a
# light from behind and above, so the bars' shadows fall across the ground in front of the camera.
BUNNY=(--camera 3.431,4.177,4.901:0,0.991,0 --light disk:-2.668,6.326,1.601:0.378,0.236,-0.227)
scene "Stanford Bunny" scan bunny_stage.gltf bvh "${BUNNY[@]}"
scene "Stanford Armadillo" scan armadillo_stage.gltf bvh \
  --camera 3.436,4.190,4.908:0,1,0 --light disk:-2.671,6.343,1.603:0.381,0.238,-0.229
scene "2-cylinder engine (CAD)" scan engine_stage.gltf bvh \
  --camera 3.184,3.324,4.548:0,0.367,0 --light disk:-2.475,5.318,1.485:0.138,0.091,-0.083
scene "FZK-Haus (IFC)" scan fzk-haus_stage.gltf bvh \
  --camera 3.193,3.371,4.561:0,0.407,0 --light disk:-2.483,5.372,1.490:0.153,0.100,-0.092
scene "wrought-iron fence" scan fence_stage.gltf bvh \
  --camera 3.245,3.597,4.636:0,0.584,0 --light disk:-1.5,3.5,-4:0,0.5,0
scene "Stanford Bunny" "subdiv x4" bunny_sub1.gltf bvh "${BUNNY[@]}"
scene "Stanford Bunny" "subdiv x16" bunny_sub2.gltf bvh "${BUNNY[@]}"
RES=$RES_4M scene "Stanford Bunny" "subdiv x64" bunny_sub3.gltf embree "${BUNNY[@]}"
scene "fence field" "instanced x64" fence_field.gltf bvh --light disk:-6,9,-12:0,0.5,0
scene "engine rows" "instanced x8" engine_row.gltf bvh \
  --camera 10.077,9.725,14.396:0,0.367,0 --light disk:-7.835,16.038,4.701:0.137,0.092,-0.082

# The paper-shaped table from the CSV rows of each run (kept scenes first sorted into script order).
order=$(grep -E '^(RES=\$RES_4M )?scene "' "$self" | sed -E 's/^(RES=\$RES_4M )?scene "([^"]*)" ("[^"]*"|[^ ]*).*/\2|\3/; s/"//g')
export ORDER="$order"
/usr/bin/python3 - "$csv" "$cases" "$previous" <<'EOF'
import csv, os, sys
path, cases_path, previous_path = sys.argv[1:4]
ORDER = [tuple(line.split("|", 1)) for line in os.environ["ORDER"].splitlines()]
rows = list(csv.DictReader(open(path)))
# Label this run's rows by case: scene_label, scaling, shadows, resolution, options.
labelled = []
for line in open(cases_path):
    label, scaling, kind, first, last, res, args = line.rstrip("\n").split("|", 6)
    for r in rows[int(first) - 1:int(last) - 1]:
        labelled.append(dict(scene_label=label, scaling=scaling, shadows=kind, options=args, **r))
rerun = {(r["scene_label"], r["scaling"]) for r in labelled}
kept = [r for r in csv.DictReader(open(previous_path)) if (r["scene_label"], r["scaling"]) not in rerun]
labelled = sorted(kept + labelled, key=lambda r: ORDER.index((r["scene_label"], r["scaling"])))
fields = ["scene_label", "scaling", "shadows", "options"] + (list(rows[0].keys()) if rows else [])
with open(path, "w", newline="") as f:
    w = csv.DictWriter(f, fieldnames=fields, extrasaction="ignore")
    w.writeheader()
    w.writerows(labelled)
hard, soft, views = {}, {}, {}
for r in labelled:
    key = (r["scene_label"], r["scaling"])
    views[key] = r["options"] or "default"
    table = hard if r["shadows"] == "hard" else soft
    table.setdefault(key, (f"{r['width']}x{r['height']}", {}))[1][r["method"]] = r
rows = labelled

def ms(by, m):
    return f"{float(by[m]['total_ms']):.0f}" if m in by else "–"
def wrong(by, m):
    v = by.get(m, {}).get("wrong_pixel_fraction", "")
    return f"{100 * float(v):.3f}" if v else "–"
def ratio(by, a, b):
    return f"{float(by[a]['total_ms']) / float(by[b]['total_ms']):.2f}" if a in by and b in by else "–"
def rays(by, m):
    v = by.get(m, {}).get("rays_traced", "")
    return ("–" if not v else f"{int(v) / 1e6:.2f}M" if int(v) >= 100000 else f"{int(v):,}")
def pip(by):
    v = by.get("srt", {}).get("pip_fraction", "")
    return f"{100 * float(v):.2f}" if v else "–"
def tris(by):
    return f"{int(next(iter(by.values()))['triangles']):,}" if by else "–"

out = ["## Hard shadows (point light): sm, pcf, srt, frt",
       "",
       "| scene | scaling | triangles | res | tracer | sm ms | pcf ms | srt ms | frt ms | PIP % | rays srt / frt | frt/srt | srt/sm | wrong % sm / pcf / srt / frt |",
       "|---|---|---:|---|---|---:|---:|---:|---:|---:|---|---:|---:|---|"]
for (label, scaling), (res, by) in hard.items():
    tracer = by.get("srt", {}).get("tracer", "")
    out.append(f"| {label} | {scaling} | {tris(by)} | {res} | {tracer} | {ms(by, 'sm')} | {ms(by, 'pcf')} | {ms(by, 'srt')} | "
               f"{ms(by, 'frt')} | {pip(by)} | {rays(by, 'srt')} / {rays(by, 'frt')} | {ratio(by, 'frt', 'srt')} | "
               f"{ratio(by, 'srt', 'sm')} | {wrong(by, 'sm')} / {wrong(by, 'pcf')} / {wrong(by, 'srt')} / {wrong(by, 'frt')} |")
out += ["", "## Soft shadows (disk light 0.1 of the scene radius, 16 samples per pixel): msm, pcss, srt, frt", "",
        "| scene | scaling | triangles | res | tracer | msm ms | pcss ms | srt ms | frt ms | PIP % | rays srt / frt | frt/srt | srt/msm | wrong % msm / pcss / srt / frt |",
        "|---|---|---:|---|---|---:|---:|---:|---:|---:|---|---:|---:|---|"]
for (label, scaling), (res, by) in soft.items():
    tracer = by.get("srt", {}).get("tracer", "")
    out.append(f"| {label} | {scaling} | {tris(by)} | {res} | {tracer} | {ms(by, 'msm')} | {ms(by, 'pcss')} | {ms(by, 'srt')} | "
               f"{ms(by, 'frt')} | {pip(by)} | {rays(by, 'srt')} / {rays(by, 'frt')} | {ratio(by, 'frt', 'srt')} | "
               f"{ratio(by, 'srt', 'msm')} | {wrong(by, 'msm')} / {wrong(by, 'pcss')} / {wrong(by, 'srt')} / {wrong(by, 'frt')} |")
device = rows[0]["device"] if rows else "?"
head = f"""# Real scenes: hard and soft shadows on models made by others (the shape of Lauterbach et al. Fig. 8)

`bash bench/real_scenes.sh` (after `bash bench/fetch_scenes.sh`). Device: {device}. Release build,
one warm-up frame, then the median of the REPEAT frames (min–max in `real_scenes.csv`). Every model
is normalised (2 units on its longest side, resting on y = 0) and set on a 2-triangle ground quad;
triangle counts are after dropping zero-area triangles. Scaling column: "scan" = the model as
published; "subdiv xN" = midpoint subdivision of the scan (the same surface with N times the
triangles); "instanced xN" = N glTF nodes instancing one mesh (flattened by the loader, so every
instance is traced). Wrong pixels against the Embree reference with the same light samples:
|d| > 0.5 for hard shadows, > 0.05 for soft ones. Times in ms (lavapipe: Vulkan on the CPU).

"""
out += ["", "## Cameras and lights (penumbra options; the soft runs add --light-size 0.1 --spp 16)", "",
        "| scene | scaling | options |", "|---|---|---|"]
out += [f"| {label} | {scaling} | `{opts}` |" for (label, scaling), opts in views.items()]
open(path.replace(".csv", ".md"), "w").write(head + "\n".join(out) + "\n")
print("\n".join(out))
EOF
rm -f "$cases" "$previous"
bench_done
