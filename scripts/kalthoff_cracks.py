#!/usr/bin/env python3
"""The Kalthoff-Winkler crack census of docs/VALIDATION.md, one JSON line per run.

    scripts/kalthoff_cracks.py RUN [RUN ...] [--time T] [--body plate] [--threshold 0.35]

Reads the frame nearest T (default: the last) and projects the plate's damage onto its mid-plane
(a lattice column is damaged when any of its points has D > threshold). The damaged columns,
joined across the eight neighbours of the lattice, make the cracks; components of fewer than
--min-points columns are left out (isolated broken bonds). For each crack: its size, extent,
whether it reaches a notch tip (within 3 spacings of (0.05, +-0.025) m), the impacted section
(x < 10 mm, |y| < 25 mm) or the far edge (x > 90 mm), and its closest approach to a tip. A
crack that reaches no tip "starts away from the tips". The far-edge damage is the number of
columns with x > 80 mm over the threshold and the largest D there. Crossings count the cracks
that cut a probe line: along the lines y = +-40, +-60 and +-80 mm (cracks running across the
plate's height: a clean picture has one per line, the crack from that side's tip) and along
x = 85 mm (cracks running in from the far edge), each a run of damaged columns, runs more than
1.5 spacings apart counted apart. With the run's summary.json:
the work put in (external work), the energy balance error, broken bonds, wall time and peak RSS.
Needs h5py and numpy.
"""
import argparse
import json
import os
import sys
from collections import deque

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from render_damage import pick_frame, read_body  # noqa: E402

TIPS = ((0.05, 0.025), (0.05, -0.025))


def columns(b, threshold):
    """Lattice columns (i, j) in the x-y plane: the largest damage over the layers of each."""
    xy = b["position"][:, :2]
    dx = float(np.median(np.diff(np.unique(np.round(xy[:, 0], 7)))))
    ij = np.round((xy - xy.min(axis=0)) / dx).astype(int)
    shape = ij.max(axis=0) + 1
    damage = np.zeros(shape)
    np.maximum.at(damage, (ij[:, 0], ij[:, 1]), b["damage"])
    origin = xy.min(axis=0)
    return damage, origin, dx


def components(hit):
    """Eight-connected components of a boolean grid: a list of arrays of (i, j)."""
    seen = np.zeros_like(hit, dtype=bool)
    out = []
    for start in zip(*np.nonzero(hit)):
        if seen[start]:
            continue
        seen[start] = True
        queue, cells = deque([start]), []
        while queue:
            i, j = queue.popleft()
            cells.append((i, j))
            for di in (-1, 0, 1):
                for dj in (-1, 0, 1):
                    a, c = i + di, j + dj
                    if 0 <= a < hit.shape[0] and 0 <= c < hit.shape[1] and hit[a, c] \
                            and not seen[a, c]:
                        seen[a, c] = True
                        queue.append((a, c))
        out.append(np.array(cells))
    return out


def runs_along(line, start, dx):
    """Positions (mm) of the centres of the runs of True in a boolean row of columns."""
    idx = np.nonzero(line)[0]
    if idx.size == 0:
        return []
    cuts = np.where(np.diff(idx) > 1)[0] + 1
    return [round(float(start + np.mean(run) * dx) * 1e3, 1) for run in np.split(idx, cuts)]


def crossings(damage, origin, dx, threshold):
    hit = damage > threshold
    out = {}
    for y in (0.08, 0.06, 0.04, -0.04, -0.06, -0.08):
        j = int(round((y - origin[1]) / dx))
        if 0 <= j < hit.shape[1]:
            out[f"y={y * 1e3:+.0f}mm"] = runs_along(hit[:, j], origin[0], dx)
    i = int(round((0.085 - origin[0]) / dx))
    if 0 <= i < hit.shape[0]:
        out["x=85mm"] = runs_along(hit[i, :], origin[1], dx)
    return out


def census(run, time, body, threshold, min_points):
    b = read_body(pick_frame(run, None, time), body)
    if not b["reference"]:
        sys.exit(f"{run}: frames have no displacement; reference positions are needed")
    damage, origin, dx = columns(b, threshold)
    cracks = []
    for cells in components(damage > threshold):
        if len(cells) < min_points:
            continue
        xy = origin + cells * dx
        tip_distance = min(float(np.min(np.hypot(xy[:, 0] - tx, xy[:, 1] - ty)))
                           for tx, ty in TIPS)
        cracks.append({
            "columns": int(len(cells)),
            "x_mm": [round(float(xy[:, 0].min()) * 1e3, 1), round(float(xy[:, 0].max()) * 1e3, 1)],
            "y_mm": [round(float(xy[:, 1].min()) * 1e3, 1), round(float(xy[:, 1].max()) * 1e3, 1)],
            "reaches_tip": tip_distance <= 3 * dx,
            "tip_distance_mm": round(tip_distance * 1e3, 1),
            "impact_zone": bool(np.any((xy[:, 0] < 0.010) & (np.abs(xy[:, 1]) < 0.025))),
            "far_edge": bool(np.any(xy[:, 0] > 0.090)),
        })
    cracks.sort(key=lambda c: -c["columns"])
    x = origin[0] + np.arange(damage.shape[0]) * dx
    far = damage[x > 0.080, :]
    report = {"run": os.path.basename(os.path.normpath(run)), "time": b["time"],
              "threshold": threshold, "cracks": len(cracks),
              "away_from_tips": sum(1 for c in cracks if not c["reaches_tip"]),
              "far_edge_columns": int((far > threshold).sum()),
              "far_edge_max_damage": round(float(far.max()), 3) if far.size else 0.0,
              "crossings": crossings(damage, origin, dx, threshold),
              "crack_list": cracks}
    summary = os.path.join(run, "summary.json")
    if os.path.exists(summary):
        with open(summary) as f:
            s = json.load(f)
        e = s.get("energy", {})
        report.update({"external_work_J": e.get("external_work"),
                       "balance_error_J": e.get("balance_error"),
                       "broken_bonds": s.get("broken_bonds"), "wall_s": s.get("wall_seconds"),
                       "peak_rss_mb": s.get("peak_rss_mb"), "status": s.get("status")})
    return report


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    ap.add_argument("runs", nargs="+")
    ap.add_argument("--time", type=float, help="the frame nearest this time (default: the last)")
    ap.add_argument("--body", default="plate")
    ap.add_argument("--threshold", type=float, default=0.35)
    ap.add_argument("--min-points", type=int, default=5)
    a = ap.parse_args()
    for run in a.runs:
        print(json.dumps(census(run, a.time, a.body, a.threshold, a.min_points)))


if __name__ == "__main__":
    main()
