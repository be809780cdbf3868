#!/usr/bin/env bash
# Few-sample soft shadows and the shadow denoiser (issue 23): srt and frt at 1, 4 and 16 light
# samples per pixel, each undenoised and with --denoise temporal (measured at the 8th frame of a
# sequence from a cut), beside pcss and msm, against the converged Embree reference (256 samples),
# on the courtyard and three real models (the Stanford Bunny scan, the FZK-Haus building, a maple
# tree's foliage), light sizes 0.05, 0.1 and 0.2 of the scene radius, 512^2. Temporal stability:
# the mean frame-to-frame visibility change over 8 frames under a light circling 0.25 degrees per
# frame, beside the reference's. Then 1 spp + temporal once more at the 32nd frame (a still view
# keeps converging). Release build, median of REPEAT frames.
# Writes bench/results/denoise.{csv,md,machine.txt}, denoise_frame32.csv and denoise_report/ (report.html).
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
late=$(mktemp -d)
./build/bin/penumbra bench --methods srt,frt --spp 1 --denoise temporal --denoise-frames 32 \
  --scenes "builtin:courtyard,$G/bunny_stage.gltf,$G/fzk-haus_stage.gltf,$G/maple.gltf" --light-sizes 0.05,0.1,0.2 \
  --reference-spp 256 --res "$RES" --warmup 1 --repeat "$REPEAT" --temporal-frames 0 --no-images --no-report --out "$late"
mv "$late/bench.csv" bench/results/denoise_frame32.csv
rm -rf "$late"
echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(uname -m)" |
  tee bench/results/denoise.machine.txt
/usr/bin/python3 - "$RES" <<'PY' > bench/results/denoise.md
import csv, sys, collections
rows = [r for r in csv.DictReader(open("bench/results/denoise.csv")) if r["method"] != "ref"]
for r in csv.DictReader(open("bench/results/denoise_frame32.csv")):
    if r["method"] != "ref":
        r["label"] = f"{r['method']} {r['params_label']} (32nd frame)"
        r["temporal_change"] = ""
        rows.append(r)
first = rows[0]
print("# Few samples and the shadow denoiser\n")
print(f"`bench/denoise.sh`: {sys.argv[1]}, against the Embree reference with 256 light samples per pixel. "
      "`temporal` rows are the 8th frame of a sequence from a cut (each frame new light samples, 1/4/16 per pixel), "
      "or the 32nd where they say so; "
      "the others are single frames. rmse and wrong % (|error| > 0.05) are of the visibility over covered pixels, "
      "FLIP of the shaded image; 'flicker' is the mean frame-to-frame visibility change under a light circling "
      "0.25 degrees per frame divided by the reference's (1.00x = no change beyond the shadows' own); "
      "'x srt16' is the frame time over undenoised 16-spp srt's in the same group.\n")
print(f"Machine: {first['machine']}; device {first['device']}, driver {first['driver']}.\n")
groups = collections.defaultdict(list)
for r in rows: groups[(r["scene"], r["light_size"])].append(r)
for (scene, size), rs in groups.items():
    base = next((float(r["time_ms"]) for r in rs if r["label"] == "srt spp=16 denoise=off"), None)
    print(f"\n## {scene.split('/')[-1]}, light {size}\n")
    print("| configuration | ms (median) | x srt16 | rmse | FLIP | wrong % | flicker |")
    print("|---|---|---|---|---|---|---|")
    for r in rs:
        t = float(r["time_ms"])
        flick = (f"{float(r['temporal_change']) / float(r['ref_temporal_change']):.2f}x"
                 if r["temporal_change"] and r["ref_temporal_change"] and float(r["ref_temporal_change"]) > 0 else "n/a")
        ratio = f"{t / base:.2f}" if base else "n/a"
        print(f"| {r['label']} | {t:.0f} | {ratio} | {float(r['rmse']):.4f} | {float(r['flip_mean']):.4f} | "
              f"{100 * float(r['wrong_pixel_fraction']):.2f} | {flick} |")
PY
echo "wrote bench/results/denoise.md"
