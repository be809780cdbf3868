#!/usr/bin/python3
"""A light circling the scene: renders srt and the reference per frame into NumPy stacks, then the
temporal metrics: how much each frame's shadows change from the last (flicker), against the
reference's own change, and each frame's error.

    PYTHONPATH=build/python examples/python/moving_light.py [SCENE] [--frames 24] [--res 128]
"""
import argparse
import math

import numpy as np

import penumbra

parser = argparse.ArgumentParser()
parser.add_argument("scene", nargs="?", default="builtin:courtyard")
parser.add_argument("--frames", type=int, default=24)
parser.add_argument("--res", type=int, default=128)
parser.add_argument("--step", type=float, default=2.0, help="degrees the light moves per frame")
args = parser.parse_args()

renderer = penumbra.Renderer(args.scene, res=(args.res, args.res), srt_choice="off")
srt, ref = [], []
for i in range(args.frames):
    a = math.radians(30.0 + args.step * i)
    renderer.light = f"dir:{math.cos(a):.6f},-1,{math.sin(a):.6f}"
    frame = renderer.render("srt")
    srt.append(frame.visibility)
    ref.append(renderer.render("ref").visibility)
    covered = frame.covered
srt, ref = np.stack(srt), np.stack(ref)
mask = covered.astype(bool)
change = np.abs(np.diff(srt, axis=0))[:, mask].mean(axis=1)
ref_change = np.abs(np.diff(ref, axis=0))[:, mask].mean(axis=1)
rmse = np.sqrt(((srt - ref)[:, mask] ** 2).mean(axis=1))
print(f"{args.frames} frames of {args.scene} at {args.res}^2, light moving {args.step} deg per frame")
print(f"mean change per frame: srt {change.mean():.5f}, reference {ref_change.mean():.5f} "
      f"(ratio {change.mean() / max(ref_change.mean(), 1e-12):.3f})")
print(f"rmse against the reference: mean {rmse.mean():.5f}, max {rmse.max():.5f}")
