#!/usr/bin/env bash
# Mutation check: that the tests can fail. Each case plants a one-line bug in a method (a file, the
# exact text it replaces, its replacement), rebuilds the test program that should catch it, runs the
# named tests and expects them to FAIL; the file is restored whatever happens. Prints one line per
# case and exits 1 if a planted bug went unnoticed. Takes ~2 minutes a case on 2 cores (each
# rebuilds its shaders and relinks). Usage: bash tests/mutation_check.sh [CASE_NUMBER...]
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/env.sh

# number # file # text # replacement # test program # gtest filter
cases=(
  "1#shaders/pip_classify.comp#delta > push.deltaThreshold) flags |= PIP_EDGE#delta > push.deltaThreshold) flags |= 0u#pass_tests#Scenes/SelectiveOnScene.*"
  "2#shaders/pip_classify.comp#rules |= blockerWithinReach(p, offsetP#rules |= 0u * blockerWithinReach(p, offsetP#pass_tests#SoftSelective.MatchesFullRayTracingForSmallMediumLargeLights"
  "3#shaders/shared/light.h#return (0.5f * r) * vec2(cos(phi), sin(phi));#return (0.5f * r * abs(r)) * vec2(cos(phi), sin(phi));#raytrace_tests#EmbreeTracer.AreaLightSamplesConvergeToTheExactVisibleFraction"
  "4#shaders/shared/indirect.h#float r = sqrt(u.x);#float r = u.x;#pass_tests#Indirect.BounceOffALitWallIsItsFormFactor"
  "5#shaders/shadow_lookup.comp#lit /= float((2 * k + 1) * (2 * k + 1));#lit /= float((2 * k + 1) * (2 * k + 1) + 1);#render_tests#KnownAnswer.PcfTapsMatchTheSquaresAnalyticShadow"
  "6#shaders/shadow_lookup.comp#* lightSize / zB;#* 0.5 * lightSize / zB;#render_tests#KnownAnswer.SoftBaselinesApproachTheSquaresExactPenumbra"
  "7#shaders/bitmask_resolve.comp#float weight = ((c & 1) != 0 ? f.x : 1.0 - f.x)#float weight = ((c & 1) != 0 ? 1.0 - f.x : f.x)#pass_tests#Bitmask.ReceiverMatchesTheReferenceWithTheSameSamples"
  "8#shaders/triangle_test.glsl#if (!(t >= tMin && t <= tMax)) return -1.0f;#if (!(t >= tMin && t <= 0.5f * tMax)) return -1.0f;#pass_tests#Selective.FullRayTracingIsTheSameOnBvhAndEmbree"
  "9#gpu/timer.cpp#context_.timestampPeriodNs() * 1e-6#context_.timestampPeriodNs() * 1e-3#render_tests#GpuDevice.PerPassTimesAreReported"
  "10#shaders/compact_scatter.comp#point.rayMax = rayMax[p];#point.rayMax = rayMax[p] * 0.5;#pass_tests#Compact/CompactSizes.MatchesCpuReference/91x91"
  "11#shaders/depth_pyramid.comp#return vec4(centre, g, below + kFitSlack);#return vec4(centre, g, kFitSlack);#pass_tests#PenumbraMask.SurfaceFitsBoundEveryTexelOfTheirTiles"
  "12#hybrid/traced_method.cpp#(classify ? c.classifyMs : c.traceAllMs) = timedTrace(r, tracer, classify, shade, stats);#c.classifyMs = timedTrace(r, tracer, true, shade, stats);#pass_tests#SoftSelective.ChoiceFramesAreThePapersOrFullRayTracings"
  "13#shaders/pip_tiles.glsl#farthest = max(farthest, axisDepth(m.clip));#farthest = farthest < -1e38 ? axisDepth(m.clip) : min(farthest, axisDepth(m.clip));#pass_tests#PenumbraMask.TileTestLeavesEveryPixelsMaskAsItWas"
  "14#shaders/pip_tiles.glsl#if (lit && withinReach(cone, 0u, farthest, PYRAMID_SURFACE#if (false && withinReach(cone, 0u, farthest, PYRAMID_SURFACE#pass_tests#PenumbraMask.TileTestLeavesEveryPixelsMaskAsItWas"
  "15#hybrid/cheaper_of.h#last_ = *ms_[1] <= *ms_[0];#last_ = *ms_[1] >= *ms_[0];#pass_tests#PenumbraMask.TileTestAutoTakesTheCheaperAndTimesTheOtherAgain"
  "16#shaders/denoise_spatial.comp#ivec2 lo = max(pix - ivec2(reach), ivec2(0)) / DENOISE_GROUP_SIZE;#ivec2 lo = pix / DENOISE_GROUP_SIZE;#pass_tests#Denoise.SkippingAgreeingPixelsChangesNothing"
  "17#shaders/pip_tiles.glsl#tileDoubt[tile] = tileDoubtLast[tile] | PIP_TILE_TRACED;#tileDoubt[tile] = PIP_TILE_TRACED;#pass_tests#PenumbraMask.TileChoiceTracesWholeTheTilesFoundDoubtful"
  "18#hybrid/frame_classify.cpp#double tileTestMs = 0.0, traceMs = lastTraceHostMs_;#double tileTestMs = 0.0, traceMs = 0.0;#pass_tests#PenumbraMask.TileChoicePricesTheFramesOwnPasses"
)

wanted=("$@")
backup=$(mktemp)
restore=""
trap '[ -n "$restore" ] && cp "$backup" "$restore"; rm -f "$backup"' EXIT
missed=0
for c in "${cases[@]}"; do
  IFS='#' read -r number file text replacement program filter <<<"$c"
  if [ ${#wanted[@]} -gt 0 ] && [[ ! " ${wanted[*]} " =~ " $number " ]]; then continue; fi
  grep -qF "$text" "$file" || { echo "case $number: '$text' is no longer in $file; update the case" >&2; exit 2; }
  cp "$file" "$backup"
  restore=$file
  python3 - "$file" "$text" "$replacement" <<'EOF'
import sys
path, old, new = sys.argv[1:]
s = open(path).read()
open(path, "w").write(s.replace(old, new, 1))
EOF
  cmake --build build -j"$(nproc)" --target "$program" >/dev/null
  if build/bin/"$program" --gtest_brief=1 --gtest_filter="$filter" >/tmp/mutation_$number.log 2>&1; then
    echo "case $number: MISSED  $file: '$text' -> '$replacement' ($program $filter passed)"
    missed=1
  else
    echo "case $number: caught  $file: '$text' -> '$replacement' ($program $filter failed)"
  fi
  cp "$backup" "$file"
  restore=""
done
cmake --build build -j"$(nproc)" >/dev/null  # back to the unmutated build
exit $missed
