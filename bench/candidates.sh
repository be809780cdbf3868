#!/usr/bin/env bash
# The candidate line space against exact structures for indirect rays (Keul et al. 2018, Table 1's
# shape): method `indirect` (one bounce, K cosine-weighted rays per pixel, a shadow ray from each
# hit) on the exact BVH, the BVH with candidate line spaces at two depths, the exact N-tree (6,3)
# and (10,3), and each N-tree with line spaces at level 1 and at its second-to-last level (LS(2), the
# paper's; refused where it exceeds one storage binding), on a ~70K scan
# (the Stanford bunny on a stage), a ~1M one (the bunny subdivided twice) and builtin:courtyard.
# Error: against the Embree reference with the same rays (rmse and wrong % = |diff| > 0.05 of the
# indirect term, over covered pixels). Build: the structure's setup (BVH + line spaces, or N-tree +
# line spaces), CPU; MB: what it uploads; ms: the median frame and the indirect pass alone.
# Writes bench/results/candidates.csv (compare's rows), candidates.md and candidates.machine.txt.
# RES (default 1280x720, the paper's 720p), REPEAT (default 3), RAYS (default 4), SCENES.
RES=${RES:-1280x720}
REPEAT=${REPEAT:-3}
source "$(dirname "$0")/lib.sh" candidates
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
RAYS=${RAYS:-4}
GEN=bench/scenes/generated
SCENES=${SCENES:-"$GEN/bunny_stage.gltf $GEN/bunny_sub2.gltf builtin:courtyard"}
for s in $SCENES; do
  case $s in builtin:*) ;; *) [ -f "$s" ] || { echo "missing $s: run bash bench/fetch_scenes.sh" >&2; exit 1; } ;; esac
done

one() {  # scene label options...
  local scene=$1 label=$2 out="$work/$(basename "$1" .gltf)_$2"
  shift 2
  echo "== $scene $label"
  if ./build/bin/penumbra compare --res "$RES" --warmup 1 --repeat "$REPEAT" --csv "$csv" --out "$out" --no-report \
    --scene "$scene" --methods indirect --indirect-rays "$RAYS" "$@" >"$work/log" 2>&1; then
    tail -n 3 "$work/log"
  else  # refused (over a memory limit): the row says so
    mkdir -p "$out"
    tail -n 1 "$work/log" | tee "$out/refused"
  fi
  printf '%s\n%s\n' "$scene" "$label" >"$out/case"
}

for scene in $SCENES; do
  one "$scene" "BVH" --tracer bvh
  one "$scene" "BVH+LS(9)" --tracer bvh-ls --bvh-ls-depth 9 --linespace-n 4
  one "$scene" "BVH+LS(12)" --tracer bvh-ls --bvh-ls-depth 12 --linespace-n 4
  for n in 6 10; do
    one "$scene" "NT($n,3)" --tracer ntree --linespace-n "$n" --linespace-depth 3
    for d in 1 2; do
      one "$scene" "NT($n,3)+LS($d)" --tracer ntree-ls --linespace-n "$n" --linespace-depth 3 --ntree-ls-depth "$d"
    done
  done
done

# Where the candidates fail: heatmaps of |indirect - reference| (white at 0.25) and the images, at
# the courtyard's default view and close up on the bunny (its curved surface fills the frame).
maps=bench/results/candidates_heatmaps
rm -rf "$maps"
mkdir -p "$maps"
heat() {  # name scene options...
  local name=$1 scene=$2 out="$work/heat_$1"
  shift 2
  echo "== heatmaps $name"
  ./build/bin/penumbra compare --res 512x512 --out "$out" --no-report --scene "$scene" --methods ao,indirect \
    --indirect-rays "$RAYS" --tracer bvh-ls,ntree-ls --linespace-n 4 --ntree-ls-depth 2 "$@" | tail -n 5 >"$maps/$name.txt" || true
  for f in "$out"/*-ls.heatmap.png "$out"/*-ls.png "$out"/*-embree.png; do [ -f "$f" ] && cp "$f" "$maps/${name}_$(basename "$f")"; done
}
heat courtyard builtin:courtyard
heat bunny_close "$GEN/bunny_stage.gltf" --camera 1.201,2.106,1.715:0,0.991,0 --light disk:-2.668,6.326,1.601:0.378,0.236,-0.227

bench_done
python3 - "$work" "$RES" "$RAYS" >bench/results/candidates.md <<'PY'
import glob, json, os, sys
work, res, rays = sys.argv[1], sys.argv[2], sys.argv[3]
rows = {}
order = []
for d in sorted(glob.glob(os.path.join(work, "*"))):
    if not os.path.isdir(d) or os.path.basename(d).startswith("heat_"): continue
    scene, label = open(os.path.join(d, "case")).read().split("\n")[:2]
    if scene not in order: order.append(scene)
    if os.path.exists(os.path.join(d, "refused")):
        rows[(scene, label)] = {"refused": open(os.path.join(d, "refused")).read().strip()}
        continue
    m = json.load(open(os.path.join(d, "metrics.json")))
    rows[(scene, label)] = {"scene": m["scene"], "m": m["methods"][0]}
machine = open("bench/results/candidates.machine.txt").read().strip()
labels = ["BVH", "BVH+LS(9)", "BVH+LS(12)", "NT(6,3)", "NT(6,3)+LS(1)", "NT(6,3)+LS(2)", "NT(10,3)", "NT(10,3)+LS(1)",
          "NT(10,3)+LS(2)"]
base = {l: ("BVH" if l.startswith("BVH") else l.split("+")[0]) for l in labels if "+" in l}
print("# Candidate line space vs exact structures, indirect rays (bench/candidates.sh)\n")
print(f"Keul et al. 2018, Table 1's shape on this machine: method `indirect` at {res}, {rays} cosine-weighted rays per")
print("pixel and a shadow ray from each hit (exact on the BVH and the exact N-tree; the binary line space's test on")
print("NT+LS, as the paper does). LS(D): candidate line spaces (N = 4 on the BVH, the tree's N on the N-tree) at the")
print("BVH's depth D, or at the N-tree's level D (and shallower nodes with fewer than 8 triangles). Build: the structure's CPU setup")
print("(seconds); MB: uploaded; ms: median frame (warm-up 1) and the indirect pass; speed-up: the exact structure's")
print("indirect pass over this one's; Mrays/s: indirect and shadow rays over the indirect pass; visits and tests")
print("(triangles, or candidate planes) per ray, indirect and shadow")
print("rays together; filled: shafts with a candidate; error of the indirect term against Embree on the same rays. Device: lavapipe")
print("(llvmpipe, CPU), a machine shared with other jobs: times are indicative, ratios from one run.\n")
print("| scene | triangles | structure | build s | MB | filled % | frame ms | indirect ms | Mrays/s | speed-up | visits / ray | tests / ray | rmse | wrong % |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
def setup_s(m):
    return sum(v for k, v in (m.get("setup_ms") or {}).items() if k != "embree_build") / 1000.0
def mem(m):
    keep = ("bvh", "bvh_ls", "linespace", "ntree", "ntree_ls", "candidates")
    return sum(v for k, v in (m.get("memory_bytes") or {}).items() if any(k.startswith(p) for p in keep)) / 1e6
for scene in order:
    for label in labels:
        r = rows.get((scene, label))
        if r is None: continue
        name = os.path.basename(scene).replace(".gltf", "")
        if "refused" in r:
            print(f"| {name} | | {label} | refused: {r['refused'].replace('|', '/')} | | | | | | | | | | |")
            continue
        m = r["m"]
        t = m["time_ms"]
        speed = ""
        b = rows.get((scene, base.get(label, "")))
        if b and "m" in b and t.get("indirect"):
            speed = f"{b['m']['time_ms']['indirect'] / t['indirect']:.2f}x"
        tr = m.get("traversal") or {}
        rays = (m.get("rays_traced") or 0) + (m.get("counts") or {}).get("shadow_rays", 0)
        per = lambda k: f"{tr[k] / rays:.1f}" if tr.get(k) is not None and rays else ""
        fill = next((n.split("% of shafts filled")[0].split(", ")[-1] for n in m.get("notes", []) if "% of shafts filled" in n), "")
        print(f"| {name} | {r['scene']['triangles']} | {label} | {setup_s(m):.2f} | {mem(m):.1f} | {fill} | {t['total']:.0f} | "
              f"{t.get('indirect', 0):.0f} | {rays / t['indirect'] / 1e3 if t.get('indirect') else 0:.2f} | {speed} | {per('node_visits')} | {per('triangle_tests')} | {m['error']['rmse']:.4f} | "
              f"{100 * m['error']['wrong_pixel_fraction']:.2f} |")
print()
print("## Where the candidates fail\n")
print("`bench/results/candidates_heatmaps/`: |indirect - reference| and |ao - reference| (white at 0.25) of `bvh-ls` (D = 9, N = 4)")
print("and `ntree-ls` (N = 4, d = 3, LS(2)) at 512x512, beside the Embree images, on the courtyard and close up on the bunny.")
print("Their summaries:\n")
for name in ("courtyard", "bunny_close"):
    path = os.path.join("bench/results/candidates_heatmaps", name + ".txt")
    if os.path.exists(path):
        print(f"{name}:\n```\n{open(path).read().strip()}\n```\n")
device = next((r["scene"] for r in rows.values() if "scene" in r), {})
print(f"{machine}; device: {device.get('device', '?')}, driver: {device.get('driver', '?')}")
PY
echo "wrote bench/results/candidates.md"
