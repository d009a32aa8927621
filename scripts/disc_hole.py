#!/usr/bin/env python3
"""The sphere-through-disc measures of docs/VALIDATION.md and docs/ACCURACY.md, one row per run.

    scripts/disc_hole.py RUN [RUN ...] [--times 2.6e-4,8.6e-4] [--body disc] [--sphere sphere]

Per run: the disc points with damage D > 0.35 at each time (the frame nearest it) and the
largest reference radius among them (the hole), the largest radius with D > 0.1 at the last
time (damage beyond the hole), the sphere's speed at the end (summary.json,
contact.body_motion), broken bonds, the energy balance error, wall time, seconds per step and,
for a far-field run, the history's exact fraction (mean over the rows and last). Radii are
measured from the disc's axis (x = y = 0) in the reference configuration. Needs h5py and numpy.
"""
import argparse
import csv
import json
import math
import os
import sys

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from render_damage import pick_frame, read_body  # noqa: E402


def hole(run, time, body):
    b = read_body(pick_frame(run, None, time), body)
    if not b["reference"]:
        sys.exit(f"{run}: frames have no displacement; reference positions are needed")
    r = np.hypot(b["position"][:, 0], b["position"][:, 1])
    d = b["damage"]
    holed = d > 0.35
    return {
        "time": b["time"],
        "count": int(holed.sum()),
        "radius": float(r[holed].max()) if holed.any() else 0.0,
        "damaged_radius": float(r[d > 0.1].max()) if (d > 0.1).any() else 0.0,
    }


def exact_fraction(run):
    path = os.path.join(run, "history.csv")
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows or "exact_fraction" not in rows[0]:
        return None
    f = [float(r["exact_fraction"]) for r in rows]
    return sum(f) / len(f), f[-1]


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--times", default="2.6e-4,8.6e-4")
    ap.add_argument("--body", default="disc")
    ap.add_argument("--sphere", default="sphere")
    a = ap.parse_args()
    times = [float(t) for t in a.times.split(",")]
    print("| run | D > 0.35 at " + " / ".join(f"{t * 1e3:g}" for t in times) + " ms | largest r (mm) "
          "| largest r with D > 0.1 (mm) | sphere speed (m/s) | broken bonds | balance error (J) "
          "| exact fraction (mean, last) | set-up s | s/step | wall s |")
    print("|---" * 11 + "|")
    for run in a.runs:
        with open(os.path.join(run, "summary.json")) as f:
            s = json.load(f)
        motion = {m["name"]: m for m in s["contact"]["body_motion"]}
        if a.sphere not in motion:
            sys.exit(f"{run}: no body '{a.sphere}' in contact.body_motion")
        speed = math.sqrt(sum(v * v for v in motion[a.sphere]["velocity"]))
        holes = [hole(run, t, a.body) for t in times]
        ef = exact_fraction(run)
        radii = " / ".join(f"{h['radius'] * 1e3:.1f}" for h in holes)
        print(f"| {os.path.basename(os.path.normpath(run))} "
              f"| {' / '.join(str(h['count']) for h in holes)} "
              f"| {radii} "
              f"| {holes[-1]['damaged_radius'] * 1e3:.1f} | {speed:.4f} | {s['broken_bonds']} "
              f"| {s['energy']['balance_error']:.6g} "
              f"| {'-' if ef is None else f'{ef[0]:.3f}, {ef[1]:.3f}'} "
              f"| {s['setup_seconds']:.1f} | {s['seconds_per_step']:.3f} | {s['wall_seconds']:.0f} |")


if __name__ == "__main__":
    main()
