#!/usr/bin/python3
"""Prints, per frame of a ckpd run, the largest bond stretch and where it is, against s_c.

How close an uncracked body came to cracking: bonds are rebuilt from the first frame's positions
(the reference configuration: frame 0 is written at t = 0) with the body's horizon; the stretch is
s = |x_j - x_i| / |X_j - X_i| - 1 (docs/THEORY.md section 4). With --seed-measure it also prints
|(x_j - x_i) - (X_j - X_i)| / |X_j - X_i| (seed 000 eq. 3.2, which docs/THEORY.md rejects because it
counts rotation as stretch), to tell whether that measure would have cracked the body.

    scripts/max_stretch.py runs/curved_bar_2d --horizon 0.00942 --critical 2.6412e-5

Needs h5py and numpy (Debian: python3-h5py).
"""
import argparse
import glob
import os

import h5py
import numpy as np


def bonds(x, horizon):
    """Pairs i < j with |X_j - X_i| <= horizon (grid hash of cell size horizon)."""
    keys = np.floor(x / horizon).astype(np.int64)
    grid = {}
    for i, k in enumerate(map(tuple, keys)):
        grid.setdefault(k, []).append(i)
    offsets = np.array(np.meshgrid((-1, 0, 1), (-1, 0, 1), (-1, 0, 1))).reshape(3, -1).T
    first, second = [], []
    limit = horizon * (1 + 1e-12)
    for k, members in grid.items():
        cand = [j for o in offsets for j in grid.get(tuple(np.array(k) + o), [])]
        cand = np.array(cand)
        for i in members:
            c = cand[cand > i]
            if len(c) == 0:
                continue
            d = np.linalg.norm(x[c] - x[i], axis=1)
            near = c[d <= limit]
            first.extend([i] * len(near))
            second.extend(near.tolist())
    return np.array(first), np.array(second)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run")
    parser.add_argument("--horizon", type=float, required=True, help="m")
    parser.add_argument("--critical", type=float, required=True, help="critical stretch s_c")
    parser.add_argument("--body", default="body_0", help="HDF5 group (default body_0)")
    parser.add_argument("--every", type=int, default=1, help="use every n-th frame")
    parser.add_argument("--seed-measure", action="store_true")
    args = parser.parse_args()

    files = sorted(glob.glob(os.path.join(args.run, "fields", "frame_*.h5")))
    with h5py.File(files[0], "r") as f:
        ref = f[args.body]["position"][:]
    i, j = bonds(ref, args.horizon)
    length = np.linalg.norm(ref[j] - ref[i], axis=1)
    print(f"{len(i)} bonds, s_c = {args.critical:.4g}")
    peak = (0.0, 0.0)
    for path in files[:: args.every]:
        with h5py.File(path, "r") as f:
            x = f[args.body]["position"][:]
            t = float(f.attrs["time"])
        s = np.linalg.norm(x[j] - x[i], axis=1) / length - 1
        k = int(np.argmax(s))
        mid = 0.5 * (ref[i[k]] + ref[j[k]])
        line = (f"t = {t * 1e3:8.4f} ms  max stretch {s[k]:.3e} = {s[k] / args.critical:.3f} s_c"
                f" at ({mid[0]:.4f}, {mid[1]:.4f}, {mid[2]:.4f})")
        if s[k] > peak[0]:
            peak = (s[k], t)
        if args.seed_measure:
            r = np.linalg.norm((x[j] - x[i]) - (ref[j] - ref[i]), axis=1) / length
            line += f"; seed measure {r.max() / args.critical:.3f} s_c"
        print(line)
    print(f"largest: {peak[0]:.3e} = {peak[0] / args.critical:.3f} s_c at t = {peak[1] * 1e3:.4f} ms")


if __name__ == "__main__":
    main()
