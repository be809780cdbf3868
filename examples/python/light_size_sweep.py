#!/usr/bin/python3
"""Speed against accuracy over light sizes: sm, pcss, srt and frt on a scene, each judged against the
Embree reference, plotted as RMSE against frame time (one line per method, one point per light size).

    PYTHONPATH=build/python examples/python/light_size_sweep.py [SCENE] [--res 256] [--out sweep.png]
"""
import argparse

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

import penumbra  # noqa: E402

parser = argparse.ArgumentParser()
parser.add_argument("scene", nargs="?", default="builtin:courtyard")
parser.add_argument("--res", type=int, default=256)
parser.add_argument("--spp", type=int, default=16)
parser.add_argument("--sizes", default="0.02,0.05,0.1,0.2")
parser.add_argument("--out", default="light_size_sweep.png")
args = parser.parse_args()

scene = penumbra.Scene(args.scene)
methods = ["sm", "pcss", "srt", "frt"]
points = {m: [] for m in methods}
for size in [float(s) for s in args.sizes.split(",")]:
    metrics = penumbra.compare(scene, methods, res=(args.res, args.res), light_size=size, spp=args.spp, repeat=3)
    for row in metrics["methods"]:
        points[row["method"]].append((row["time_ms"]["total"], row["error"]["rmse"], size))
        print(f"light {size:<5} {row['method']:<5} {row['time_ms']['total']:8.1f} ms  rmse {row['error']['rmse']:.4f}")

fig, ax = plt.subplots(figsize=(7, 4.5), dpi=100)
for method, pts in points.items():
    ax.plot([p[1] for p in pts], [p[0] for p in pts], "o-", label=method)
    for ms, rmse, size in pts:
        ax.annotate(f"{size:g}", (rmse, ms), fontsize=7, xytext=(3, 3), textcoords="offset points")
ax.set_xlabel("RMSE of the visibility vs the Embree reference")
ax.set_ylabel("frame time (ms)")
ax.set_title(f"{args.scene}, {args.res}x{args.res}, {args.spp} spp: light sizes as labels")
ax.legend()
fig.tight_layout()
fig.savefig(args.out)
print("wrote", args.out)
