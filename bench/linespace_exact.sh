#!/usr/bin/env bash
# The line-space tracer's two shadow modes (issue 19): binary (Keul et al. 2017: a set shaft bit at
# the second-to-last level means occluded) and exact (the set bits lead to the leaf cells, whose
# triangles are tested with the BVH's test), for method `ls` (every covered pixel traced) and
# `srt --tracer ls` (PIP rays only), against the GPU BVH (frt and srt on --tracer bvh), on
# builtin:courtyard and two real scenes (bench/fetch_scenes.sh), light 0.1 of the radius, 25
# samples per pixel, line space (N, d) = (LS_N, LS_D) (default the CLI's 6, 3). Error against the
# Embree reference with the same samples; trace ms median of REPEAT frames after a warm-up, with the
# frame's spread; node visits and triangle tests per ray from the kernels' counters; the exact
# pools' memory. Replaces the "Binary vs exact shadows" section of bench/results/linespace.md
# (the rest of the file, bench/linespace.sh's table, is kept) and writes linespace_exact.csv.
# RES (default 512x512), REPEAT (default 3), SCENES_DIR (default bench/scenes/generated).
RES=${RES:-512x512}
source "$(dirname "$0")/lib.sh" linespace_exact  # Release build, Vulkan environment, REPEAT, $csv
G=${SCENES_DIR:-bench/scenes/generated}
scenes=${SCENES:-"builtin:courtyard $G/fence_stage.gltf $G/maple.gltf"}
LS_N=${LS_N:-6} LS_D=${LS_D:-3}
for s in $scenes; do
  [[ $s == builtin:* || -f $s ]] || { echo "linespace_exact: $s missing; run bench/fetch_scenes.sh first" >&2; exit 1; }
done
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

one() {  # out-dir [options...]
  local out=$1
  shift
  echo "== $(basename "$out")"
  if ! ./build/bin/penumbra compare --res "$RES" --warmup 1 --repeat "$REPEAT" --csv "$csv" --out "$out" --no-report \
      --light-size 0.1 --spp 25 --linespace-n "$LS_N" --linespace-depth "$LS_D" "$@" >"$out.log" 2>"$out.err"; then
    cat "$out.err"
  else
    tail -n 4 "$out.log"
  fi
}

i=0
for s in $scenes; do
  one "$work/s${i}_bvh" --scene "$s" --methods frt,srt --tracer bvh
  for mode in binary exact; do
    one "$work/s${i}_$mode" --scene "$s" --methods ls,srt --tracer ls --ls-shadows "$mode"
  done
  i=$((i + 1))
done

section=$(mktemp)
python3 - "$work" "$RES" "$REPEAT" "$LS_N" "$LS_D" $scenes >"$section" <<'PY'
import json, os, sys
work, res, repeat, n, d, scenes = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4], sys.argv[5], sys.argv[6:]
def load(name, method):
    path = os.path.join(work, name, method + ".stats.json")
    return json.load(open(path)) if os.path.exists(path) else None
def note(stats, prefix):
    return next((x for x in stats["notes"] if x.startswith(prefix)), "")
print("## Binary vs exact shadows\n")
print(f"`bench/linespace_exact.sh`: line space (N={n}, d={d}), {res}, disk light 0.1 of the scene radius, 25 samples per")
print("pixel, error against the Embree reference with the same samples (wrong = |diff| > 0.05). `ls` traces every")
print("covered pixel, `srt` only its PIP pixels (same tracer for those); the BVH rows are frt and srt on `--tracer bvh`.")
print(f"Trace ms: median of {repeat} frames after one warm-up; frame ms: median [min-max]. visits/ray and tests/ray from")
print("the kernels' counters (BVH: nodes and triangles; line space: classified nodes, and in exact mode the leaf")
print("triangles tested). ns/step: trace time per (node visit + triangle test). B/ray: the bytes each ray's steps")
print("fetch, from the counters and the record sizes (BVH: a 64-byte node per visit, a 48-byte triangle per test; line")
print("space: a 32-byte node, a tree entry and a bit word per visit, a list entry and a 48-byte triangle per test).")
print("Memory: the line space's pools (exact: of which the leaf groups, leaf records, lists and triangles) or the BVH.")
first = load("s0_bvh", "frt")
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
print(f"Machine: {first['context']['driver'] if first else '?'} on {os.cpu_count()} cores of a shared {cpu}; times")
print("are indicative (other jobs share the machine).\n")
print("| scene | triangles | tracer | method | rmse | wrong % | trace ms | frame ms | visits/ray | tests/ray | ns/step | B/ray | memory MB |")
print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
rows = []
for i, scene in enumerate(scenes):
    name = os.path.basename(scene).replace(".gltf", "")
    for tag, label in (("bvh", "BVH"), ("binary", "LS binary"), ("exact", "LS exact")):
        for method in (("frt", "srt") if tag == "bvh" else ("ls", "srt")):
            st = load(f"s{i}_{tag}", method)
            if not st:
                err = open(os.path.join(work, f"s{i}_{tag}.err")).read().strip().splitlines()
                print(f"| {name} | ? | {label} | {method} | failed: {err[-1] if err else '?'} |")
                continue
            t, tr, e = st["time_ms"], st["traversal"], st["error"]
            rays = max(st["rays_traced"], 1)
            visits, tests = tr.get("node_visits") or 0, tr.get("triangle_tests") or 0
            if tag == "bvh":
                mem = f"{st['memory_bytes'].get('bvh', 0) / 1e6:.1f}"
            else:
                mem = f"{st['memory_bytes']['linespace'] / 1e6:.1f}"
                extra = note(st, "line space exact shadows")
                if extra:
                    mem += " (" + extra.split(", ")[2].split(" MB")[0] + " exact)"
            step = t["trace"] * 1e6 / max(visits + tests, 1)
            fetched = (64 * visits + 48 * tests) if tag == "bvh" else (40 * visits + 52 * tests)
            rows.append((name, label, method, t["trace"], rays, visits, tests, step, fetched / rays))
            print(f"| {name} | {st['context']['triangles']} | {label} | {method} | {e['rmse']:.4f} | "
                  f"{100 * e['wrong_pixel_fraction']:.2f} | {t['trace']:.1f} | {t['total']:.0f} [{t['total_min']:.0f}-{t['total_max']:.0f}] | "
                  f"{visits / rays:.1f} | {tests / rays:.1f} | {step:.1f} | {fetched / rays:.0f} | {mem} |")
print()
# Per scene, ls exact against frt: ray rate and where the time goes.
for scene in dict.fromkeys(r[0] for r in rows):
    get = lambda label, method: next((r for r in rows if r[0] == scene and r[1] == label and r[2] == method), None)
    frt, lb, le = get("BVH", "frt"), get("LS binary", "ls"), get("LS exact", "ls")
    if not (frt and lb and le):
        continue
    rate = lambda r: r[4] / r[3] / 1e3  # Mrays/s
    print(f"- {scene}: frt {rate(frt):.1f} Mrays/s, ls binary {rate(lb):.1f}, ls exact {rate(le):.1f} "
          f"(exact / frt trace time {le[3] / frt[3]:.2f}x; binary {lb[3] / frt[3]:.2f}x). Per step: frt {frt[7]:.0f} ns, "
          f"binary {lb[7]:.0f} ns, exact {le[7]:.0f} ns; fetched per ray: frt {frt[8]:.0f} B, binary {lb[8]:.0f} B, "
          f"exact {le[8]:.0f} B; triangle tests per ray: frt {frt[6] / frt[4]:.1f}, exact {le[6] / le[4]:.1f}.")
print("""
Why the line space does not beat the BVH here (from the columns above): memory traffic is not it. A binary
line-space ray fetches fewer bytes than a BVH ray on every scene (B/ray), yet each line-space step costs 1.5-3x
a BVH step (ns/step): a visit is a slab test, the entry and exit faces and patches, the shaft index, a bit fetch and a
DDA step with a per-level state stack, where a BVH visit is two slab tests; on llvmpipe every SIMD lane runs
that code and lanes at different levels of the DDA stack diverge. The line space wins only where the BVH needs
many steps per ray (maple's foliage: ~57 BVH steps per ray against ~6 line-space visits), and there binary
mode's error is largest. Exact mode adds triangle tests the BVH does not make: a triangle is listed in every
leaf cell it overlaps and the DDA tests it again in each cell the ray crosses (no mailbox), and the receiver's
own large triangles are listed in the ray's start cells, so it tests many more triangles per ray than the BVH
on scenes of large triangles (courtyard, fence_stage: 15-25x), and 2-3x as many on maple. So exact mode is
the BVH's answer at 1.2-7x the BVH's trace time and about 2-3x binary mode's memory on this machine: it keeps binary
mode's error out of comparisons and is the base for closest-hit rays (lsClosestHit), but binary stays the
default (the method's point is the approximation, and exact answers are faster from the BVH here).""")
PY
cat "$section"
# Replace the section (from its heading to the next "## " heading or the end), keep the rest.
python3 - bench/results/linespace.md "$section" <<'PY'
import sys
path, section = sys.argv[1], open(sys.argv[2]).read()
lines = open(path).read().splitlines(keepends=True)
out, skip = [], False
for line in lines:
    if line.startswith("## "):
        skip = line.strip() == "## Binary vs exact shadows"
    if not skip:
        out.append(line)
text = "".join(out).rstrip("\n") + "\n\n" + section
open(path, "w").write(text)
PY
rm -f "$section"
bench_done
