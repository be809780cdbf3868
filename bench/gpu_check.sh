#!/usr/bin/env bash
# The GPU check: on a machine lent for minutes, in one go, what the device is, whether Penumbra's
# answers hold there, and how fast it is in the regime of Lauterbach et al. 2009 (Fig. 8).
#   ./gpu_check.sh OUTDIR          from the bundle (scripts/bundle.sh), on the GPU: at most 8 minutes
#   bench/gpu_check.sh OUTDIR      from a checkout with a build (build/bin)
#   ... --cpu OUTDIR               the same steps on lavapipe at smaller sizes (here: under 10 minutes)
#   ... --programs                 the programs of build/bin it runs (scripts/bundle.sh packs them)
# Steps, each under a time limit cut to what is left, in this order; a failed step does not stop
# the later ones. Writes these 9 files into OUTDIR:
#   system.txt    OS, CPU, memory, nvidia-smi, the Vulkan driver manifests, vulkaninfo --summary
#   device.json   penumbra device --validate: the device picked, driver, Vulkan version, extensions
#                 (ray query, acceleration structures), geometry shaders, subgroups, limits, memory
#                 heaps and what each `auto` setting chose there
#   tests.txt     the test suite's GPU and reference tests (every method against Embree, with the
#                 suite's own bounds, validation layer on: any message fails the test); with --cpu
#                 a quarter of each program's (GoogleTest's shard 0 of 4: CI ran them all before)
#   methods.txt   penumbra compare of every method and tracer against the Embree reference at test
#                 size, with --validate: sm pcf srt frt (each tracer the device offers), pcss msm
#                 bitmask ls, ao and indirect on each tracer, 1-spp srt/frt with the temporal denoiser
#   timing.md     bench tables per scene and resolution: every configuration (median, spread, PIP %,
#                 rays, Mrays/s, memory) and the Fig. 8 shape: sm, srt, frt, srt's model bound
#   timing.csv    the same rows as bench.csv (per-pass GPU times in `passes`)
#   lights.txt    penumbra compare of sm, srt and frt on builtin:street's 64 lamps (16 with --cpu):
#                 one trace for the lamps, a trace dispatch each, and each lamp keeping its own maps
#   summary.md    each step's status and time, and the issue's targets read off timing.md
#   log.txt       every command run, with its output's tail
# Exit 0 when every step passed (on a GPU a step may run out of time: its tables are then missing);
# 1 otherwise.
set -uo pipefail
# The suite's programs that exercise the GPU passes and the reference, run after timer_tests (which
# runs alone); left out are the loader, report (Python, Chromium) and demo (Xvfb) programs, and the
# tests that run other programs a GPU machine does not have (gltfpack, draco_transcoder).
tests=(pass_tests render_tests ray_query_tests linespace_tests candidate_tests stress_scene_tests dynamic_tests
  bandwidth_tests raytrace_tests)
filter='-OptimizedModels*'
if [ "${1:-}" = --programs ]; then  # what scripts/bundle.sh packs for this check
  echo penumbra timer_tests "${tests[@]}"
  exit 0
fi
cpu=0
if [ "${1:-}" = --cpu ]; then cpu=1; shift; fi
if [ $# -ne 1 ]; then
  echo "usage: $0 [--cpu] OUTDIR" >&2
  exit 2
fi
out=$1
mkdir -p "$out"
out=$(cd "$out" && pwd -P)
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd -P)
start=$SECONDS
budget=$((cpu ? 570 : 465))  # seconds, leaving room for the summary within 10 / 8 minutes
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# prog NAME ARGS...: a program of the bundle (through its launcher) or of the checkout's build.
if [ -x "$here/run" ]; then
  prog() { "$here/run" "$@"; }
  bindir=$here/bin
elif [ -x "$here/../build/bin/penumbra" ]; then
  bindir=$(cd "$here/../build/bin" && pwd -P)
  prog() {
    local p=$1
    shift
    if [ -x "$bindir/$p" ]; then "$bindir/$p" "$@"; else "$p" "$@"; fi
  }
  export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp}
else
  echo "gpu_check: neither a bundle (run beside this script) nor a build ($here/../build/bin/penumbra)" >&2
  exit 2
fi

: >"$out/log.txt"
log() { echo "$*" | tee -a "$out/log.txt"; }
status=()  # "step|result|seconds" per step, for summary.md
failed=0
remaining() { echo $((budget - (SECONDS - start))); }
# step NAME CAP_SECONDS COMMAND...: runs COMMAND (a shell function or program) with stdout and stderr
# into $tmp/NAME.out, killed after min(CAP, time left); records ok / FAILED / TIMEOUT / skipped.
step() {
  local name=$1 cap=$2 left rc t0
  shift 2
  left=$(remaining)
  [ "$cap" -gt "$left" ] && cap=$left
  if [ "$cap" -lt 5 ]; then
    status+=("$name|skipped: out of time|0")
    log "== $name: skipped, out of time"
    [ $cpu = 1 ] && failed=1  # here the whole check must fit
    return 0
  fi
  log "== $name (limit ${cap}s)"
  t0=$SECONDS
  # COMMAND in a process group of its own (job control on for that one job), so that the watchdog
  # stops it with everything it started.
  set -m
  "$@" >"$tmp/$name.out" 2>&1 &
  local pid=$!
  (sleep "$cap" && touch "$tmp/$name.timeout" && kill -TERM -- -"$pid" && sleep 10 && kill -KILL -- -"$pid") >/dev/null 2>&1 &
  local watchdog=$!
  set +m
  wait "$pid"
  rc=$?
  kill -- -"$watchdog" 2>/dev/null
  [ -e "$tmp/$name.timeout" ] && rc=124
  tail -n 40 "$tmp/$name.out" >>"$out/log.txt"
  local result=ok
  if [ $rc -eq 124 ]; then result=TIMEOUT; elif [ $rc -ne 0 ]; then result="FAILED (exit $rc)"; fi
  [ $rc -ne 0 ] && { [ $rc -ne 124 ] || [ $cpu = 1 ]; } && failed=1  # on a GPU, running out of time is no failure
  status+=("$name|$result|$((SECONDS - t0))")
  log "== $name: $result in $((SECONDS - t0))s"
  return $rc
}

# --- 1. the machine and its Vulkan drivers ---------------------------------------------------
icd_dirs=(/etc/vulkan/icd.d /usr/share/vulkan/icd.d /usr/local/share/vulkan/icd.d)
# NVIDIA's driver with no usable manifest: some containers mount the libraries only, and the
# manifest's libGLX_nvidia.so.0 creates no instance on a machine without an X server (the loader
# says "Could not get 'vkCreateInstance' via 'vk_icdGetInstanceProcAddr'"). Then point the loader
# at libEGL_nvidia.so.0 (the same driver, headless), else libGLX_nvidia.so.0, whichever works.
nvidia_lib() {  # nvidia_lib NAME: the path of NAME from ldconfig or the usual folders
  local f path
  path=$( (ldconfig -p 2>/dev/null | sed -n "s/.*$1.*=> //p" | head -n1) || true)
  for f in /usr/lib/x86_64-linux-gnu/$1 /usr/lib64/$1; do [ -z "$path" ] && [ -e "$f" ] && path=$f; done
  echo "$path"
}
if [ $cpu = 0 ] && ! prog penumbra device >"$tmp/probe.txt" 2>&1; then
  for lib in libEGL_nvidia.so.0 libGLX_nvidia.so.0; do
    path=$(nvidia_lib "$lib")
    [ -n "$path" ] || continue
    printf '{"file_format_version": "1.0.0", "ICD": {"library_path": "%s", "api_version": "1.3.0"}}\n' "$path" \
      >"$tmp/nvidia_icd.json"
    if VK_DRIVER_FILES=$tmp/nvidia_icd.json prog penumbra device >/dev/null 2>&1; then
      export VK_DRIVER_FILES=$tmp/nvidia_icd.json
      log "the machine's Vulkan drivers create no device ($(tail -n1 "$tmp/probe.txt")); using $path"
      break
    fi
  done
fi
system_info() {
  echo "date: $(date -u +%Y-%m-%dT%H:%M:%SZ)"
  echo "mode: $([ $cpu = 1 ] && echo "--cpu (lavapipe)" || echo GPU), programs: $bindir"
  [ -f "$here/MANIFEST.txt" ] && head -n 2 "$here/MANIFEST.txt"
  uname -a
  grep -E '^(PRETTY_NAME|VERSION_ID)=' /etc/os-release 2>/dev/null
  echo "cpu: $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2- | sed 's/^ //'), $(nproc) threads"
  echo "memory: $(awk '/MemTotal/ {printf "%.1f GiB", $2 / 1048576}' /proc/meminfo)"
  echo "glibc: $(getconf GNU_LIBC_VERSION 2>/dev/null)"
  echo
  if command -v nvidia-smi >/dev/null; then
    nvidia-smi --query-gpu=name,driver_version,memory.total,clocks.max.sm,compute_cap --format=csv 2>&1
    nvidia-smi 2>&1 | head -n 20
  else
    echo "nvidia-smi: not found"
  fi
  echo
  for d in "${icd_dirs[@]}"; do
    [ -d "$d" ] && for f in "$d"/*.json; do [ -f "$f" ] && echo "$f: $(tr -d '\n' <"$f" | tr -s ' ')"; done
  done
  [ -n "${VK_DRIVER_FILES:-}" ] && echo "VK_DRIVER_FILES=$VK_DRIVER_FILES: $(cat "$VK_DRIVER_FILES")"
  (ldconfig -p 2>/dev/null | grep -E 'libGLX_nvidia|libnvidia-glcore|libEGL_nvidia|libcuda\.so' | head -n 8) || true
  echo
  prog vulkaninfo --summary 2>&1 | head -n 60
  return 0
}
step system 20 system_info
cp "$tmp/system.out" "$out/system.txt"

# --- 2. the device Penumbra picks --------------------------------------------------------------
step device 30 prog penumbra device --validate --out "$out/device.json"
[ -s "$out/device.json" ] || cp "$tmp/device.out" "$out/device.json"
ray_query=0
grep -q '"ray_query": true' "$out/device.json" && ray_query=1
gpu_type=$(sed -n 's/^    "type": "\([A-Za-z]*\)",$/\1/p' "$out/device.json")  # the picked device's (4 spaces in)
if [ $cpu = 0 ] && [ "$gpu_type" = Cpu ]; then
  log "gpu_check: Penumbra picked a CPU device; the GPU's Vulkan driver was not found (see system.txt)"
  failed=1
fi

# --- 3. correctness: the suite's own tests ---------------------------------------------------
run_tests() {
  local t jobs=$((cpu ? 2 : 4)) rc=0
  test_program() {  # test_program NAME: its output and exit code into $tmp
    if [ $cpu = 1 ]; then
      GTEST_TOTAL_SHARDS=4 GTEST_SHARD_INDEX=0 prog "$1" --gtest_brief=1 --gtest_filter="$filter" >"$tmp/$1.txt" 2>&1
    else
      prog "$1" --gtest_brief=1 --gtest_filter="$filter" >"$tmp/$1.txt" 2>&1
    fi
    echo $? >"$tmp/$1.rc"
  }
  test_program timer_tests  # alone: it times deliberately slow passes
  for t in "${tests[@]}"; do
    test_program "$t" &
    while [ "$(jobs -rp | wc -l)" -ge "$jobs" ]; do wait -n; done
  done
  wait
  : >"$tmp/tests.summary"
  for t in timer_tests "${tests[@]}"; do
    echo "# $t (exit $(cat "$tmp/$t.rc" 2>/dev/null || echo '?'))"
    cat "$tmp/$t.txt"
    [ "$(cat "$tmp/$t.rc" 2>/dev/null)" = 0 ] || rc=1
    echo "| $t | $(cat "$tmp/$t.rc" 2>/dev/null || echo killed) | $(grep -hE '^\[  (PASSED|FAILED|SKIPPED) +\] [0-9]+ tests?' "$tmp/$t.txt" |
      sed -E 's/^\[ +([A-Z]+) +\] ([0-9]+) tests?.*/\2 \1/' | tr '\n' ' ')|" >>"$tmp/tests.summary"
  done
  return $rc
}
step tests $((cpu ? 300 : 150)) run_tests
cp "$tmp/tests.out" "$out/tests.txt"

# --- 4. every method and tracer against the reference at test size --------------------------
tracers=(bvh ls embree)
[ $ray_query = 1 ] && tracers=(bvh rq ls embree)
ao_tracers=bvh,ntree,bvh-ls,ntree-ls
[ $ray_query = 1 ] && ao_tracers=bvh,rq,ntree,bvh-ls,ntree-ls
compare_runs() {
  local rc=0 n=0 t
  compare() {
    n=$((n + 1))
    echo "### penumbra compare $*"
    prog penumbra compare --validate --no-report --out "$tmp/compare$n" "$@" || { echo "FAILED: exit $?"; rc=1; }
    echo
  }
  for t in "${tracers[@]}"; do
    compare --scene builtin:courtyard --res 256x256 --methods sm,pcf,srt,frt --tracer "$t"
    compare --scene builtin:courtyard --res 256x256 --methods srt,frt --light-size 0.1 --spp 16 --tracer "$t"
  done
  compare --scene builtin:wires --res 256x256 --methods sm,srt,frt
  compare --scene builtin:room --res 256x256 --methods sm,srt,frt
  compare --scene builtin:courtyard --res 256x256 --methods pcss,msm,bitmask,ls --light-size 0.1 --spp 16
  compare --scene builtin:courtyard --res 256x256 --methods srt,frt --light-size 0.1 --spp 1 --denoise temporal
  compare --scene builtin:courtyard-moving --res 256x256 --methods srt,frt --time 1.5
  compare --scene builtin:courtyard --res 128x128 --methods ao,indirect --tracer "$ao_tracers"
  return $rc
}
step methods $((cpu ? 150 : 90)) compare_runs
cp "$tmp/methods.out" "$out/methods.txt"

# --- 5. timing: Fig. 8's table -------------------------------------------------------------------
trace_list=bvh
[ $ray_query = 1 ] && trace_list=bvh,rq
if [ $cpu = 1 ]; then
  sizes=(256x256 512x512) scenes=(builtin:courtyard builtin:courtyard:16) warmup=1 repeat=3
else
  sizes=(1920x1080 3840x2160) scenes=(builtin:courtyard builtin:courtyard:64 builtin:courtyard:250) warmup=2 repeat=5
fi
: >"$out/timing.md"
: >"$out/timing.csv"
n=0
bench() {  # bench LABEL OPTIONS...: one sweep, its tables and rows appended to timing.md / .csv
  local label=$1 dir
  shift
  n=$((n + 1))
  dir=$tmp/bench$n
  prog penumbra bench --warmup "$warmup" --repeat "$repeat" --temporal-frames 0 --no-images --no-report \
    --tracer "$trace_list" --out "$dir" "$@" || return $?
  { echo "# $label"; echo; echo "\`penumbra bench $*\`"; echo; sed '1,2d' "$dir/tables.md"; echo; } >>"$out/timing.md"
  if [ -s "$out/timing.csv" ]; then tail -n +2 "$dir/bench.csv" >>"$out/timing.csv"; else cat "$dir/bench.csv" >>"$out/timing.csv"; fi
}
# In the order of what matters most, should time run out: Fig. 8 at the first size on each scene, the
# largest first (the issue's targets are on it), the other baselines, then the second size.
hard_soft=(--methods "sm,srt,frt" --light-sizes "0,0.1" --spp 16)
step "bench-${sizes[0]}-${scenes[0]}" 90 bench "${scenes[0]}, ${sizes[0]}: sm, srt, frt, pcss; hard and 16 spp" \
  --scenes "${scenes[0]}" --res "${sizes[0]}" --methods sm,srt,frt,pcss --light-sizes 0,0.1 --spp 16
for ((i = ${#scenes[@]} - 1; i > 0; i--)); do
  scene=${scenes[i]}
  step "bench-${sizes[0]}-$scene" 120 bench "$scene, ${sizes[0]}: hard and 16 spp" --scenes "$scene" --res "${sizes[0]}" "${hard_soft[@]}"
done
# srt's own path, classification and all: where tracing everything is cheaper, srt's auto choice
# (above) shows only frt's time.
step "bench-${sizes[0]}-paper-path" 60 bench "${scenes[1]}, ${sizes[0]}: srt's paper path (--srt-choice off)" \
  --scenes "${scenes[1]}" --res "${sizes[0]}" "${hard_soft[@]}" --srt-choice off
step "bench-${sizes[0]}-bitmask" 60 bench "${scenes[0]}, ${sizes[0]}: bitmask, 16 spp" \
  --scenes "${scenes[0]}" --res "${sizes[0]}" --methods bitmask --light-sizes 0.1 --spp 16
step "bench-${sizes[0]}-temporal" 60 bench "${scenes[0]}, ${sizes[0]}: 1 spp with the temporal denoiser (against 256 spp)" \
  --scenes "${scenes[0]}" --res "${sizes[0]}" --methods srt,frt --light-sizes 0.1 --spp 1 --denoise temporal --reference-spp 256
# --- 6. many lights: the street's lamps, one trace for them or a dispatch each, and kept maps ------
lights_runs() {
  local lamps=64 opts t
  [ $cpu = 1 ] && lamps=16
  for t in ${trace_list//,/ }; do
    for opts in "--lights-trace one" "--lights-trace each" "--reuse-light-passes on"; do
      echo "### penumbra compare --scene builtin:street:$lamps --res ${sizes[0]} --tracer $t $opts"
      # shellcheck disable=SC2086 # opts: an option and its value
      prog penumbra compare --scene "builtin:street:$lamps" --res "${sizes[0]}" --methods sm,srt,frt --tracer "$t" \
        --warmup "$warmup" --repeat "$repeat" --no-report --out "$tmp/lights-$t-${opts// /}" $opts || return $?
      echo
    done
  done
}
step lights $((cpu ? 120 : 90)) lights_runs
cp "$tmp/lights.out" "$out/lights.txt"
for scene in "${scenes[@]}"; do
  step "bench-${sizes[1]}-$scene" 120 bench "$scene, ${sizes[1]}: hard and 16 spp" --scenes "$scene" --res "${sizes[1]}" "${hard_soft[@]}"
done

# --- summary -------------------------------------------------------------------------------------
# fig8 SCENE RES LIGHT SPP TRACER: "sm srt frt" ms of that Fig. 8 row of timing.md (empty if absent).
fig8() {
  awk -F'|' -v s="$1" -v r="$2" -v l="$3" -v p="$4" -v t="$5" '/^# / { fig8 = 0 } /^## Lauterbach/ { fig8 = 1 } fig8 && NF == 16 {
      for (i = 2; i < NF; i++) gsub(/^ +| +$/, "", $i)
      if ($2 == s && $3 == r && $4 == l && $5 == p && $6 == t && $7 == "off") { print $8, $9, $10; exit }
    }' "$out/timing.md"
}
target() {  # target WHAT VALUE GOAL: a table row
  local verdict=-
  [ -n "$2" ] && verdict=$(awk -v v="$2" -v g="$3" 'BEGIN { print (v >= g) ? "met" : "missed" }')
  echo "| $1 | ${2:--} | $3 | $verdict |"
}
fps() { [ -n "$1" ] && awk -v ms="$1" 'BEGIN { if (ms > 0) printf "%.1f", 1000 / ms }'; }
{
  echo "# GPU check$([ $cpu = 1 ] && echo " (--cpu: lavapipe, small sizes)")"
  echo
  head -n 8 "$out/system.txt" | sed 's/^/    /'
  echo
  echo "Device: $(sed -n 's/^    "name": "\(.*\)",$/\1/p' "$out/device.json" | tail -n1); driver: $(sed -n 's/^    "driver": "\(.*\)",$/\1/p' "$out/device.json")"
  echo
  echo "| step | result | seconds |"
  echo "|---|---|---|"
  for s in "${status[@]}"; do echo "| ${s//|/ | } |"; done
  echo
  echo "Tests (the suite's own bounds, validation on):"
  echo
  echo "| program | exit | tests |"
  echo "|---|---|---|"
  cat "$tmp/tests.summary" 2>/dev/null
  echo
  big=${scenes[-1]} res=${sizes[0]}
  best=$(sed -n 's/^ *"tracer": "\([a-z]*\)"$/\1/p' "$out/device.json")  # what --tracer auto picked
  [ -n "$best" ] || best=bvh
  read -r _ hard_srt _ <<<"$(fig8 "$big" "$res" 0 1 "$best")"
  read -r _ soft_srt soft_frt <<<"$(fig8 "$big" "$res" 0.1 16 "$best")"
  echo "Targets (issue 38), $big at $res, tracer $best (auto's choice):"
  echo
  echo "| target | measured | goal | |"
  echo "|---|---|---|---|"
  target "srt hard, fps" "$(fps "$hard_srt")" 60
  target "srt 16-spp soft, fps" "$(fps "$soft_srt")" 20
  target "frt/srt, 16-spp soft" "$([ -n "$soft_srt" ] && [ -n "$soft_frt" ] && awk -v a="$soft_frt" -v b="$soft_srt" 'BEGIN { printf "%.2f", a / b }')" 3
  if [ $ray_query = 1 ]; then
    for light in "0 1" "0.1 16"; do
      read -r _ _ rq_frt <<<"$(fig8 "$big" "$res" $light rq)"
      read -r _ _ bvh_frt <<<"$(fig8 "$big" "$res" $light bvh)"
      target "rq's speed-up over bvh (frt), light ${light% *}" "$([ -n "$rq_frt" ] && [ -n "$bvh_frt" ] && awk -v a="$bvh_frt" -v b="$rq_frt" 'BEGIN { printf "%.2f", a / b }')" 1
    done
  else
    echo "| ray queries | not offered by this device | | |"
  fi
  echo
  echo "Finished in $((SECONDS - start)) s; $([ $failed = 0 ] && echo "every step passed" || echo "FAILURES: see log.txt")."
} >"$out/summary.md"
cat "$out/summary.md"
exit $failed
