#!/usr/bin/env bash
# Few-sample soft shadows and the shadow denoiser (issue 23): srt and frt at 1, 4 and 16 light
# samples per pixel, each undenoised and with --denoise temporal (measured at the 8th frame of a
# sequence from a cut), beside pcss and msm, against the converged Embree reference (256 samples),
# on the courtyard and three real models (the Stanford Bunny scan, the FZK-Haus building, a maple
# tree's foliage), light sizes 0.05, 0.1 and 0.2 of the scene radius, 512^2. Under a light circling
# 0.25 degrees per frame (8 frames): the mean frame-to-frame visibility change beside the
# reference's (flicker) and the mean rmse of the moving frames against the reference's same frames.
# Then 1 spp + temporal once more at the 16th and the 32nd frame (a still view keeps converging).
# Release build, median of REPEAT frames.
# Writes bench/results/denoise.{csv,md,machine.txt}, denoise_frame{16,32}.csv and denoise_report/ (report.html).
RES=${RES:-512x512}
source "$(dirname "$0")/lib.sh" denoise  # Release build, Vulkan environment, REPEAT
G=bench/scenes/generated
[ -f "$G/bunny_stage.gltf" ] || { echo "denoise: run bench/fetch_scenes.sh first" >&2; exit 1; }
out=bench/results/denoise_report
rm -rf "$out"
./build/bin/penumbra bench --methods srt,frt,pcss,msm --spp 1,4,16 --denoise off,temporal \
  --scenes "builtin:courtyard,$G/bunny_stage.gltf,$G/fzk-haus_stage.gltf,$G/maple.gltf" --light-sizes 0.05,0.1,0.2 \
  --reference-spp 256 --res "$RES" --warmup 1 --repeat "$REPEAT" --temporal-frames 8 --no-images --out "$out"
mv "$out/bench.csv" bench/results/denoise.csv
for frame in 16 32; do
  late=$(mktemp -d)
  ./build/bin/penumbra bench --methods srt,frt --spp 1 --denoise temporal --denoise-frames "$frame" \
    --scenes "builtin:courtyard,$G/bunny_stage.gltf,$G/fzk-haus_stage.gltf,$G/maple.gltf" --light-sizes 0.05,0.1,0.2 \
    --reference-spp 256 --res "$RES" --warmup 1 --repeat "$REPEAT" --temporal-frames 0 --no-images --no-report --out "$late"
  mv "$late/bench.csv" "bench/results/denoise_frame$frame.csv"
  rm -rf "$late"
done
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(uname -m)" |
  tee bench/results/denoise.machine.txt
/usr/bin/python3 - "$RES" <<'PY' > bench/results/denoise.md
import csv, sys, collections
rows = [r for r in csv.DictReader(open("bench/results/denoise.csv")) if r["method"] != "ref"]
for frame in (16, 32):
    for r in csv.DictReader(open(f"bench/results/denoise_frame{frame}.csv")):
        if r["method"] != "ref":
            r["label"] = f"{r['method']} {r['params_label']} ({frame}th frame)".replace("32th", "32nd")
            r["temporal_change"] = r["moving_rmse"] = ""
            rows.append(r)
first = rows[0]
print("# Few samples and the shadow denoiser\n")
print(f"`bench/denoise.sh`: {sys.argv[1]}, against the Embree reference with 256 light samples per pixel. "
      "`temporal` rows are the 8th frame of a sequence from a cut (each frame new light samples, 1/4/16 per pixel), "
      "or the 16th or 32nd where they say so; "
      "the others are single frames. rmse and wrong % (|error| > 0.05) are of the visibility over covered pixels, "
      "FLIP of the shaded image. Then the light circles 0.25 degrees per frame for 8 frames: 'flicker' is the mean "
      "frame-to-frame visibility change divided by the reference's (1.00x = no change beyond the shadows' own), "
      "'rmse moving' the mean rmse of the frames after the light began to move against the reference's same frames "
      "(a history that lags behind the shadows shows here). "
      "'x srt16' is the frame time over undenoised 16-spp srt's in the same group; every frame renders all its "
      "passes (`--reuse-light-passes off`).\n")
print(f"Machine: {first['machine']}; device {first['device']}, driver {first['driver']}.\n")
groups = collections.defaultdict(list)
for r in rows: groups[(r["scene"], r["light_size"])].append(r)

def f(r, key): return float(r[key])
summary = []
for (scene, size), rs in groups.items():
    by = {r["label"]: r for r in rs}
    base = by.get("srt spp=16 denoise=off")
    name = scene.split('/')[-1].replace(".gltf", "")
    if not base: continue
    def beats(label):
        r = by.get(label)
        return r and f(r, "rmse") <= f(base, "rmse") and f(r, "flip_mean") <= f(base, "flip_mean")
    one = by["srt spp=1 denoise=temporal"]; frt1 = by["frt spp=1 denoise=temporal"]
    flick = lambda r: f(r, "temporal_change") / f(r, "ref_temporal_change")
    summary.append((name, size, beats("srt spp=1 denoise=temporal"), beats("srt spp=1 denoise=temporal (16th frame)"),
                    beats("srt spp=1 denoise=temporal (32nd frame)"), flick(one), flick(base),
                    f(one, "moving_rmse"), f(base, "moving_rmse"), f(one, "time_ms") / f(base, "time_ms"),
                    f(frt1, "time_ms") / f(base, "time_ms")))
print("## Summary: srt 1 spp + temporal against undenoised srt 16 spp\n")
print("| scene | light | rmse and FLIP no worse: 8th / 16th / 32nd frame | flicker 1 spp / 16 spp | rmse moving 1 spp / 16 spp | frame x srt16: srt / frt 1 spp temporal |")
print("|---|---|---|---|---|---|")
yes = lambda b: "yes" if b else "no"
for s in summary:
    print(f"| {s[0]} | {s[1]} | {yes(s[2])} / {yes(s[3])} / {yes(s[4])} | {s[5]:.2f}x / {s[6]:.2f}x | "
          f"{s[7]:.4f} / {s[8]:.4f} | {s[9]:.2f} / {s[10]:.2f} |")
for (scene, size), rs in groups.items():
    base = next((float(r["time_ms"]) for r in rs if r["label"] == "srt spp=16 denoise=off"), None)
    print(f"\n## {scene.split('/')[-1]}, light {size}\n")
    print("| configuration | ms (median) | x srt16 | rmse | FLIP | wrong % | flicker | rmse moving |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rs:
        t = float(r["time_ms"])
        flick = (f"{float(r['temporal_change']) / float(r['ref_temporal_change']):.2f}x"
                 if r["temporal_change"] and r["ref_temporal_change"] and float(r["ref_temporal_change"]) > 0 else "n/a")
        moving = f"{float(r['moving_rmse']):.4f}" if r.get("moving_rmse") else "n/a"
        ratio = f"{t / base:.2f}" if base else "n/a"
        print(f"| {r['label']} | {t:.0f} | {ratio} | {float(r['rmse']):.4f} | {float(r['flip_mean']):.4f} | "
              f"{100 * float(r['wrong_pixel_fraction']):.2f} | {flick} | {moving} |")
PY
echo "wrote bench/results/denoise.md"
