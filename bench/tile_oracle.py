"""What per-tile decisions (issue 39, items 1 and 2) could save at most on this device, from its own frames.

For each configuration it renders sm, srt (the paper's path, --srt-choice off) and frt through the Python
module (warm-up 1, median per pass of REPEAT frames) and takes srt's last frame's flags, which do not
change between frames. Over the classification's 16x16 tiles (PIP_GROUP_SIZE) it prices two oracles at
the frame's own mean costs per pixel:

  c_c  srt's classify pass / covered pixels      (what classifying a pixel costs)
  c_l  sm's lookup pass / covered pixels         (what the map's answer alone costs)
  c_p  srt's trace pass / flagged pixels         (a doubtful pixel's rays)
  c_e  (frt's trace - srt's trace) / unflagged   (an undoubtful pixel's rays, were it traced)

  certain: a tile whose covered pixels are all unflagged, were it proven so for free (item 1, a
           conservative tile test), keeps only the map's answer: saves N (c_c - c_l). A provable rule
           certifies a subset of these tiles, so this is the most it can save.
  choice:  every other tile takes the cheaper of classifying (N c_c + P c_p) and tracing outright
           (P c_p + (N - P) c_e), knowing its flagged count P for free (item 2): saves
           max(0, N c_c - (N - P) c_e).

oracle = srt - both savings, beside srt's model bound (the sm frame plus the PIP share of frt's trace)
and min(frt, srt): where the oracle misses a target, no tile test or per-tile choice reaches it here.

Soft rows also render the Embree reference with the same samples and price a third oracle, a mask as
tight as those samples allow (item 3 asks only that it be no wider than today's):
  penumbra: covered pixels whose reference visibility lies strictly between 0 and 1
  excess:   mask pixels the reference has fully lit or fully dark (a tight mask would not trace them),
            also split into the lit and the dark ones
  tight:    the oracle less the excess's share of srt's trace, at the mask's mean cost per pixel
A mask sound for any light sample (today's) must keep some of the excess: pixels of the continuous
penumbra that no sample of this pattern crosses; one sound for the frame's own samples (srt is judged
against the reference with the same samples) need not. tight is the floor of both.
Usage: tile_oracle.py OUT_PREFIX  (writes OUT_PREFIX.md and .csv)
"""
import os
import statistics
import sys

import numpy as np

import penumbra

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "report"))
import table  # noqa: E402

REPEAT = int(os.environ.get("REPEAT", "3"))
TILE = 16
G = "bench/scenes/generated"
BUNNY = dict(light="disk:-2.668,6.326,1.601:0.378,0.236,-0.227", camera="1.201,2.106,1.715:0,0.991,0")
FZK = dict(light="disk:-2.483,5.372,1.490:0.153,0.100,-0.092", camera="1.118,1.444,1.596:0,0.407,0")
SCENES = [("courtyard", "default", "builtin:courtyard", {})]
if os.path.isdir(G):
    SCENES += [
        ("Stanford Bunny", "close", G + "/bunny_stage.gltf", BUNNY),
        ("FZK-Haus", "close", G + "/fzk-haus_stage.gltf", FZK),
        ("Japanese maple", "default", G + "/maple.gltf", {}),
        ("USS Truman", "close", G + "/truman.gltf", dict(camera="0.512,0.678,0.731:0,0.203,0")),
        ("oasago2 (OpenArena)", "default", G + "/oasago2.gltf", {}),
    ]
KINDS = {"hard": {}, "soft": dict(light_size=0.1, spp=16)}


def frames(renderer, method):
    renderer.render(method)  # warm-up
    out = [renderer.render(method) for _ in range(REPEAT)]
    passes = {k: statistics.median(f.stats["time_ms"].get(k, 0.0) for f in out) for k in out[0].stats["time_ms"]}
    return out[-1], passes


def oracle(label, view, spec, extra, res, kind):
    options = dict(res=(res, res), tracer="bvh", srt_choice=False, **extra, **KINDS[kind])
    r = penumbra.Renderer(penumbra.Scene(spec), **options)
    _, sm = frames(r, "sm")
    srt_frame, srt = frames(r, "srt")
    _, frt = frames(r, "frt")
    covered = srt_frame.covered.astype(bool)
    flagged = srt_frame.pip.astype(bool) & covered
    n, p = int(covered.sum()), int(flagged.sum())
    c_c = srt["classify"] / n
    c_l = sm["lookup"] / n
    c_p = srt["trace"] / max(p, 1)
    c_e = max(frt["trace"] - srt["trace"], 0.0) / max(n - p, 1)
    h, w = covered.shape
    th, tw = (h + TILE - 1) // TILE, (w + TILE - 1) // TILE

    def per_tile(mask):
        padded = np.zeros((th * TILE, tw * TILE), dtype=np.int64)
        padded[:h, :w] = mask
        return padded.reshape(th, TILE, tw, TILE).sum(axis=(1, 3))

    nt, pt = per_tile(covered), per_tile(flagged)
    certain = (nt > 0) & (pt == 0)
    certain_ms = float((nt[certain] * (c_c - c_l)).sum())
    doubtful = (nt > 0) & (pt > 0)
    gain = np.maximum(0.0, nt * c_c - (nt - pt) * c_e)
    choice_ms = float(gain[doubtful].sum())
    outright = doubtful & (gain > 0)
    bound = sm["total"] + p / n * frt["trace"]
    best = srt["total"] - certain_ms - choice_ms
    f1, f2 = lambda v: "%.1f" % v, lambda v: "%.2f" % v
    tight = dict.fromkeys(["penumbra_pct", "mask_excess_pct", "excess_lit_pct", "excess_dark_pct", "tight_ms", "frt/tight"], "")
    if kind == "soft":
        v = r.render("ref").visibility
        lit, dark = int((flagged & (v == 1.0)).sum()), int((flagged & (v == 0.0)).sum())
        excess = lit + dark
        tight_ms = best - srt["trace"] * excess / max(p, 1)
        tight = {"penumbra_pct": f1(100.0 * (covered & (v > 0.0) & (v < 1.0)).sum() / n),
                 "mask_excess_pct": f1(100.0 * excess / n), "excess_lit_pct": f1(100.0 * lit / n),
                 "excess_dark_pct": f1(100.0 * dark / n), "tight_ms": f1(tight_ms),
                 "frt/tight": f2(frt["total"] / tight_ms)}
    return {
        "scene": label, "view": view, "res": "%dx%d" % (res, res), "shadows": kind,
        "sm_ms": f1(sm["total"]), "srt_ms": f1(srt["total"]), "frt_ms": f1(frt["total"]), "bound_ms": f1(bound),
        "classify_ms": f1(srt["classify"]), "pip_pct": f1(100.0 * p / n),
        "certain_tiles_pct_covered": f1(100.0 * nt[certain].sum() / n), "certain_saves_ms": f1(certain_ms),
        "outright_tiles_pct_covered": f1(100.0 * nt[outright].sum() / n), "choice_saves_ms": f1(choice_ms),
        "oracle_ms": f1(best), "oracle/bound": f2(best / bound), "srt/bound": f2(srt["total"] / bound),
        "frt/oracle": f2(frt["total"] / best), "oracle/min(frt,srt)": f2(best / min(frt["total"], srt["total"])),
        **tight,
    }


def main():
    rows = []
    for label, view, spec, extra in SCENES:
        for res in (512, 1024):
            for kind in KINDS:
                print("==", label, view, res, kind, flush=True)
                rows.append(oracle(label, view, spec, extra, res, kind))
    text = (__doc__.split("Usage:")[0].strip()).replace("\n  ", "\n    ")
    text += ("\n\nFrame totals and passes in ms, warm-up 1, median of %d frames, `--tracer bvh`; certain/outright "
             "tiles as a share of the covered pixels." % REPEAT)
    table.write(sys.argv[1], "What per-tile decisions could save here at most (bench/tile_oracle.sh)", text, rows)


if __name__ == "__main__":
    main()
