#!/usr/bin/env bash
# Dynamic scenes (issue 8): one loop of builtin:courtyard-moving (the drone flies and spins for
# 8 s = 240 scripted frames at 1/30 s) through penumbra-demo under Xvfb, the light circling 1 degree
# per frame: frame time, BVH refit time, SAH growth and rebuilds of the moving meshes' BVH, and the
# frame-to-frame visibility change against the reference's (--temporal-reference). srt on the GPU
# BVH and on the two-level line space, frt and sm at the default level; srt again at level 32
# (431K static triangles) to show that the refit cost follows the moving triangles, not the scene.
# Writes bench/results/dynamic.md, dynamic_<config>.csv and dynamic.machine.txt.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
source scripts/env.sh
[ -x build/bin/penumbra-demo ] || bash scripts/build.sh
RES=${RES:-256x256}
FRAMES=${FRAMES:-240}
run() {  # name scene method [options...]
  local name=$1 scene=$2 method=$3
  shift 3
  echo "== $name"
  xvfb-run -a -s "-screen 0 1024x768x24" ./build/bin/penumbra-demo --scene "$scene" --method "$method" --res "$RES" \
    --frames "$FRAMES" --light-path circle --hide-ui --stats-csv "bench/results/dynamic_$name.csv" "$@" | tail -n 1
}
run srt_bvh builtin:courtyard-moving srt --tracer bvh --temporal-reference
run srt_ls builtin:courtyard-moving srt --tracer ls --temporal-reference
run frt_bvh builtin:courtyard-moving frt --tracer bvh --temporal-reference
run sm builtin:courtyard-moving sm --temporal-reference
run srt_bvh_level32 builtin:courtyard-moving:32 srt --tracer bvh
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(uname -m)" |
  tee bench/results/dynamic.machine.txt
/usr/bin/python3 - "$RES" "$FRAMES" <<'PY' > bench/results/dynamic.md
import csv, statistics, sys
res, frames = sys.argv[1], sys.argv[2]
print("# Dynamic scene: one loop of builtin:courtyard-moving\n")
print(f"`bench/dynamic.sh`: penumbra-demo under Xvfb, {res}, {frames} scripted frames (1/30 s each: the drone's 8 s "
      "loop), light circling 1 degree per frame. Times are wall-clock ms per frame on this machine's lavapipe (median, "
      "min-max); refit is the CPU refit (or rebuild) of the moving meshes' BVH and its write into the GPU buffers (sm builds no BVH); SAH growth is the refit "
      "tree's SAH over its SAH when last built (each relative to its root box), rebuilt above 1.5; temporal change is the "
      "mean |visibility change| between frames, the reference's in brackets.\n")
print("| run | frame ms | refit ms (median / max) | SAH growth (min-max) | rebuilds | temporal change (ref) | PIP % (median) |")
print("|---|---|---|---|---|---|---|")
for name in ["srt_bvh", "srt_ls", "frt_bvh", "sm", "srt_bvh_level32"]:
    rows = list(csv.DictReader(open(f"bench/results/dynamic_{name}.csv")))
    f = lambda k: [float(r[k]) for r in rows if r[k]]  # noqa: E731
    ms, refit, growth, temporal, ref, pip = f("total_ms"), f("refit_ms"), f("sah_growth"), f("temporal_change"), \
        f("ref_temporal_change"), f("pip_fraction")
    rebuilt = sum(int(r["rebuilt"] or 0) for r in rows)
    rt = f"{statistics.mean(temporal):.5f}" + (f" ({statistics.mean(ref):.5f})" if ref else "")
    print(f"| {name} | {statistics.median(ms):.0f} ({min(ms):.0f}-{max(ms):.0f}) | "
          + (f"{statistics.median(refit):.3f} / {max(refit):.3f}" if refit else "-") + " | "
          + (f"{min(growth):.2f}-{max(growth):.2f}" if growth else "-") + f" | {rebuilt} | {rt} | "
          + (f"{100 * statistics.median(pip):.1f}" if pip else "-") + " |")
print(f"\n{open('bench/results/dynamic.machine.txt').read().strip()}; Vulkan on lavapipe (llvmpipe), no GPU.")
PY
cat bench/results/dynamic.md
