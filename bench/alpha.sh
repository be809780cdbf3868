#!/usr/bin/env bash
# Alpha-tested cut-outs (issue 41) on real content (bench/fetch_scenes.sh): Sweet Home 3D's bush
# (leaf cards) and football goal (a net), default and close views, hard and soft (disk light, 16
# samples): sm, srt (the paper's path) and frt against the alpha-aware Embree reference; then the
# cost of alpha testing: frt on each exact tracer (bvh, rq where the device has ray queries, Embree)
# on the goal with its net cut out and with the same net opaque (its map_d dropped); and the time
# to load a textured model's images.
# Writes bench/results/alpha.csv (REPEAT frames, median), alpha_load.csv and alpha.machine.txt.
source "$(dirname "${BASH_SOURCE[0]}")/lib.sh" alpha
S=bench/scenes
[ -f "$S/bush/bush_stage.obj" ] && [ -f "$S/goal/goal_stage.obj" ] || { echo "alpha: run bench/fetch_scenes.sh first" >&2; exit 1; }
soft=(--light-size 0.05 --spp 16)
bush=(--scene "$S/bush/bush_stage.obj" --methods sm,srt,frt --tracer bvh --srt-choice off --no-report)
close_bush=(--camera 130,110,130:30,20,-10:45)
for res in 512x512 1024x1024; do
  RES=$res bench_compare "bush default $res hard" "${bush[@]}"
  RES=$res bench_compare "bush close $res hard" "${bush[@]}" "${close_bush[@]}"
done
for res in 512x512 1024x1024; do
  RES=$res bench_compare "bush default $res soft" "${bush[@]}" "${soft[@]}"
  RES=$res bench_compare "bush close $res soft" "${bush[@]}" "${close_bush[@]}" "${soft[@]}"
done

# The goal with an opaque net: the same OBJ beside a material library without map_d.
opaque=$S/goal/opaque
mkdir -p "$opaque"
sed '/map_d/d' "$S/goal/big-football-goal.mtl" >"$opaque/big-football-goal.mtl"
cp "$S/goal/stage.mtl" "$S/goal/goal_stage.obj" "$opaque/"
goal=(--light disk:-200,900,700:0,-200,-85 --camera 250,60,450:0,-150,-120 --methods frt --no-report)
tracers="bvh embree"
./build/bin/penumbra device 2>/dev/null | grep -q "\"VK_KHR_ray_query\": true" && tracers="bvh rq embree"
for tracer in $tracers; do
  for kind in hard soft; do
    extra=()
    [ "$kind" = soft ] && extra=("${soft[@]}")
    for net in cutout opaque; do
      scene=$S/goal/goal_stage.obj
      [ "$net" = opaque ] && scene=$opaque/goal_stage.obj
      RES=512x512 bench_compare "goal close $kind $tracer $net" --scene "$scene" "${goal[@]}" --tracer "$tracer" "${extra[@]}"
    done
  done
done
# Loading a textured model: the Truman (FlightGear) with its PNG textures beside it, and the same
# glb alone (its images missing: colour lost, with warnings); load_ms of `render` (reading, decoding
# and cleaning), REPEAT runs each, into alpha_load.csv.
bare=$S/truman/bare
mkdir -p "$bare"
cp "$S/truman/truman.glb" "$bare/"
load_csv=bench/results/alpha_load.csv
echo "scene,images,run,load_ms,images_mb" >"$load_csv"
for images in beside missing; do
  scene=$S/truman/truman.glb
  [ "$images" = missing ] && scene=$bare/truman.glb
  for run in $(seq "$REPEAT"); do
    out=$(mktemp -d)
    ./build/bin/penumbra render --scene "$scene" --method sm --res 256x256 --out "$out" >/dev/null
    mb=$( (du -cm "$(dirname "$scene")"/*.png 2>/dev/null || true) | tail -1 | cut -f1)
    /usr/bin/python3 -c "import json,sys; print('truman,$images,$run,%.1f,${mb:-0}' % json.load(open(sys.argv[1]))['context']['load_ms'])" \
      "$out/sm.stats.json" >>"$load_csv"
    rm -rf "$out"
  done
done
cat "$load_csv"

bench_done
