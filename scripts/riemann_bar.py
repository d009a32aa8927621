#!/usr/bin/python3
"""The Riemann problem of seed 002 (cases/riemann_bar_2d.yaml): interpenetration counts and pictures.

For every field frame of RUN (fields/frame_NNNNNN.h5; needs the position and reference_position
fields, optionally dilatation), counts the points that crossed x = 0 into the other half (a point
of the left half, X < 0, now at x > 0, or the reverse) and the inverted points (det F <= 0, from
the `dilatation` field det F - 1 <= -1, the correspondence estimate over intact bonds), and draws
the points at their current positions coloured by half, one panel per frame (at most four).

    scripts/riemann_bar.py runs/riemann_sb_m05 --title "state-based, m = 1/2" \
        --out docs/img/riemann_state_based_m05.png

Prints one JSON line per frame. Needs h5py, numpy and matplotlib (Debian: python3-h5py,
python3-matplotlib).
"""
import argparse
import glob
import json
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def frames(run):
    files = sorted(glob.glob(os.path.join(run, "fields", "frame_*.h5")))
    if not files:
        sys.exit(f"{run}: no frames under fields/")
    out = []
    for f in files:
        with h5py.File(f, "r") as h:
            g = h[sorted(k for k in h.keys() if k.startswith("body_"))[0]]
            if "reference_position" not in g:
                sys.exit(f"{f}: needs the reference_position field")
            pos = g["position"][:].reshape(-1, 3)
            ref = g["reference_position"][:].reshape(-1, 3)
            dil = g["dilatation"][:].reshape(-1) if "dilatation" in g else None
            out.append({"time": float(h.attrs["time"]), "position": pos, "reference": ref,
                        "dilatation": dil})
    return out


def counts(f):
    left = f["reference"][:, 0] < 0
    x = f["position"][:, 0]
    crossed = int(np.sum(left & (x > 0)) + np.sum(~left & (x < 0)))
    row = {"time": f["time"], "crossed": crossed, "points": int(len(x))}
    if f["dilatation"] is not None:
        d = f["dilatation"]
        row["inverted"] = int(np.sum(d <= -1))
        row["nonfinite"] = int(np.sum(~np.isfinite(d)))
    return row


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("run")
    p.add_argument("--out", help="PNG to write")
    p.add_argument("--title", default="")
    a = p.parse_args()
    fs = frames(a.run)
    rows = [counts(f) for f in fs]
    for r in rows:
        print(json.dumps(r))
    if a.out:
        shown = fs[:4]
        fig, axes = plt.subplots(2, 2, figsize=(8, 5.2), squeeze=False)
        for ax in axes.flat[len(shown):]:
            ax.axis("off")
        for ax, f, r in zip(axes.flat, shown, rows):
            left = f["reference"][:, 0] < 0
            for mask, colour in ((left, "tab:blue"), (~left, "tab:red")):
                ax.scatter(f["position"][mask, 0], f["position"][mask, 1], s=0.5, c=colour,
                           linewidths=0)
            ax.set_aspect("equal")
            ax.set_xlim(-1.05, 1.05)
            ax.set_ylim(-0.85, 0.85)
            label = f"t = {f['time'] * 1e6:.0f} us, crossed {r['crossed']}"
            if "inverted" in r:
                label += f", det F<=0: {r['inverted']}"
            ax.set_title(label, fontsize=8)
            ax.tick_params(labelsize=6)
        fig.suptitle(a.title, fontsize=9)
        fig.tight_layout()
        fig.savefig(a.out, dpi=150)


if __name__ == "__main__":
    main()
