#!/usr/bin/python3
"""Renders the damage field of one frame of a ckpd run as a PNG, and measures crack angles.

Reads RUN/fields/frame_NNNNNN.h5 (groups body_<i> with position, optionally displacement and
damage; attributes time and step) and draws the points of one body coloured by damage:
2D bodies as they are; 3D bodies seen along their thinnest axis (the plate normal), either the
layer nearest the mid-plane (--layer mid, default) or every point with the most damaged drawn
on top (--layer all). Points are drawn at their reference positions when the frame has
displacement, else at their current ones.

    scripts/render_damage.py runs/curved_bar_2d --time 5.8e-3 --out docs/img/curved_bar_2d.png

--kalthoff TIP_X,TIP_Y measures the Kalthoff-Winkler crack angles at the notch tips (TIP_X, +TIP_Y)
and (TIP_X, -TIP_Y): the crack is traced in rows of one spacing across the direction away from
the impacted section (|y| growing), from --r-min to --r-max beyond the tip, following in each row
the cluster of damaged points (D > --threshold, all layers) nearest the previous row's; a line
fitted to the trace gives the angle from the notch direction (+x), as in the literature (about
70 deg in the experiment). Prints one JSON line and draws the traces.

Needs h5py, numpy and matplotlib (Debian: python3-h5py, python3-matplotlib).
"""
import argparse
import glob
import json
import math
import os
import sys

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def pick_frame(run, frame, time):
    files = sorted(glob.glob(os.path.join(run, "fields", "frame_*.h5")))
    if not files:
        sys.exit(f"{run}: no frames under fields/ (did the case ask for field output?)")
    if frame is not None:
        if not 0 <= frame < len(files) and not -len(files) <= frame < 0:
            sys.exit(f"{run}: frame {frame} does not exist ({len(files)} frames)")
        return files[frame]
    if time is None:
        return files[-1]
    times = []
    for f in files:
        with h5py.File(f, "r") as h:
            times.append(float(h.attrs["time"]))
    return files[int(np.argmin(np.abs(np.array(times) - time)))]


def read_body(path, body):
    with h5py.File(path, "r") as h:
        groups = sorted(k for k in h.keys() if k.startswith("body_"))
        group = None
        for g in groups:
            name = h[g].attrs.get("name", b"")
            name = name.decode() if isinstance(name, bytes) else str(name)
            if body in (g, name, g[len("body_"):]):
                group = h[g]
        if group is None:
            if body is not None:
                sys.exit(f"{path}: no body '{body}' (groups {groups})")
            group = h[groups[0]]
        if "damage" not in group:
            sys.exit(f"{path}: no damage field; add damage to the case's output fields")
        pos = group["position"][:]
        reference = "displacement" in group
        if reference:
            pos = pos - group["displacement"][:]
        name = group.attrs.get("name", b"")
        return {
            "position": pos,
            "damage": group["damage"][:].reshape(-1),
            "dimension": int(group.attrs.get("dimension", 3)),
            "name": name.decode() if isinstance(name, bytes) else str(name),
            "reference": reference,
            "time": float(h.attrs["time"]),
            "step": int(h.attrs["step"]),
        }


def spacing_estimate(p):
    """Median nearest-neighbour distance of a sample of points, 2 or 3 columns (no SciPy)."""
    n, dim = p.shape
    extent = np.ptp(p, axis=0)
    live = extent > 0
    cell = float(np.prod(extent[live]) / n) ** (1 / max(1, int(live.sum()))) if n > 1 else 1.0
    keys = {}
    for i, k in enumerate(map(tuple, np.floor(p / cell).astype(np.int64))):
        keys.setdefault(k, []).append(i)
    rng = np.random.default_rng(0)
    nearest = []
    offsets = np.array(np.meshgrid(*[(-1, 0, 1)] * dim)).reshape(dim, -1).T
    for i in rng.choice(n, size=min(n, 400), replace=False):
        k = np.floor(p[i] / cell).astype(np.int64)
        best = math.inf
        for o in offsets:
            for j in keys.get(tuple(k + o), []):
                if j != i:
                    best = min(best, float(np.linalg.norm(p[j] - p[i])))
        if best < math.inf:
            nearest.append(best)
    return float(np.median(nearest)) if nearest else cell


def crack_angles(xy, damage, tip, threshold, r_min, r_max, dx):
    """Kalthoff-Winkler crack angle at each notch tip, in degrees from +x (see the docstring).

    The crack is traced row by row away from the impacted section: rows dx apart, from r_min to
    r_max beyond the tip; in each row the damaged points (D > threshold, all layers) are split
    into clusters at gaps over 1.5 dx, and the cluster nearest the previous row's crack position
    (within 4 dx) continues the trace at its damage-weighted centre. A line x = a + b y fitted to
    the trace gives the angle atan2(1, b) from the notch direction.
    """
    result = {}
    for side, sign in (("upper", 1.0), ("lower", -1.0)):
        q = np.column_stack([xy[:, 0] - tip[0], sign * (xy[:, 1] - sign * tip[1])])
        hit = damage > threshold
        trace, previous, gaps = [], 0.0, 0
        rows = np.arange(r_min, r_max + 0.5 * dx, dx)
        for row in rows:
            sel = hit & (np.abs(q[:, 1] - row) <= 0.5 * dx) & (q[:, 0] > -2 * dx)
            if not sel.any():
                gaps += 1
                if gaps > 2 and trace:
                    break
                continue
            xs, ws = q[sel, 0], damage[sel]
            order = np.argsort(xs)
            xs, ws = xs[order], ws[order]
            cuts = np.where(np.diff(xs) > 1.5 * dx)[0] + 1
            best = None
            for cx, cw in zip(np.split(xs, cuts), np.split(ws, cuts)):
                centre = float(np.average(cx, weights=cw))
                if abs(centre - previous) <= 4 * dx and (
                        best is None or abs(centre - previous) < abs(best - previous)):
                    best = centre
            if best is None:
                if trace:
                    break
                continue
            gaps = 0
            trace.append((best, float(row)))
            previous = best
        entry = {"tip": [tip[0], sign * tip[1]], "rows": len(trace)}
        if len(trace) >= 3:
            t = np.array(trace)
            slope, intercept = np.polyfit(t[:, 1], t[:, 0], 1)
            entry["angle_deg"] = round(math.degrees(math.atan2(1.0, slope)), 2)
            entry["from_to_m"] = [round(float(t[0, 1]), 4), round(float(t[-1, 1]), 4)]
            entry["trace"] = [[round(tip[0] + x, 5), round(sign * (tip[1] + y), 5)] for x, y in trace]
        else:
            entry["angle_deg"] = None
        result[side] = entry
    return result


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("run", help="run folder (holds fields/frame_*.h5)")
    which = parser.add_mutually_exclusive_group()
    which.add_argument("--frame", type=int, help="frame index (negative: from the end)")
    which.add_argument("--time", type=float, help="the frame nearest this time (s)")
    parser.add_argument("--body", help="body name or index (default: the first)")
    parser.add_argument("--out", help="PNG to write (default: RUN/damage_<step>.png)")
    parser.add_argument("--layer", choices=("mid", "all"), default="mid",
                        help="3D: the layer nearest the mid-plane, or all points")
    parser.add_argument("--title", help="plot title (default: body, time)")
    parser.add_argument("--width", type=float, default=8.0, help="figure width, inches")
    parser.add_argument("--dpi", type=int, default=110)
    parser.add_argument("--kalthoff", help="TIP_X,TIP_Y: measure crack angles at (x, +-y)")
    parser.add_argument("--threshold", type=float, default=0.35, help="damaged: D above this")
    parser.add_argument("--r-min", type=float, default=0.005,
                        help="m: first row of the crack trace beyond the tip")
    parser.add_argument("--r-max", type=float, default=0.03,
                        help="m: last row of the crack trace beyond the tip")
    parser.add_argument("--scan", action="store_true",
                        help="print, per frame, the time, max damage and where the damaged "
                             "points are (onset of cracking); draws nothing")
    parser.add_argument("--around", help="X,Y,R: --scan counts only points within R (m) of (X, Y) "
                                         "(in the view plane) whose damage grew since frame 0")
    args = parser.parse_args()

    if args.scan:
        first = None
        for f in sorted(glob.glob(os.path.join(args.run, "fields", "frame_*.h5"))):
            b = read_body(f, args.body)
            if first is None:
                first = b["damage"].copy()  # pre-cracks damage points from the start
            hit = b["damage"] > 0
            if args.around:
                cx, cy, radius = (float(v) for v in args.around.split(","))
                near = np.hypot(b["position"][:, 0] - cx, b["position"][:, 1] - cy) <= radius
                hit = near & (b["damage"] > first + 1e-12)
            row = {"time": b["time"], "step": b["step"], "max_damage": float(b["damage"].max()),
                   "damaged_points": int(hit.sum()),
                   "over_threshold": int((b["damage"] > args.threshold).sum())}
            if hit.any():
                p = b["position"][hit]
                row["damaged_box"] = [np.round(p.min(axis=0), 4).tolist(),
                                      np.round(p.max(axis=0), 4).tolist()]
                k = int(np.argmax(b["damage"]))
                row["max_at"] = np.round(b["position"][k], 4).tolist()
            print(json.dumps(row))
        return

    path = pick_frame(args.run, args.frame, args.time)
    b = read_body(path, args.body)
    p, dmg = b["position"], b["damage"]
    view = "xy"
    if b["dimension"] == 3:
        # Look along the thinnest extent; keep the mid layer or draw all, most damaged on top.
        axis = int(np.argmin(np.ptp(p, axis=0)))
        keep = [a for a in range(3) if a != axis]
        view = "xyz"[keep[0]] + "xyz"[keep[1]]
        if args.layer == "mid":
            # Layers: coordinates along the axis within a quarter spacing of each other.
            z = p[:, axis]
            quarter = 0.25 * spacing_estimate(p)
            levels = [float(v) for v in np.sort(z)]
            centres = [levels[0]]
            for v in levels[1:]:
                if v - centres[-1] > quarter:
                    centres.append(v)
            centres = np.array(centres)
            # Only full layers: a few loose fragments drifting between layers are not one.
            counts = np.array([(np.abs(z - c) <= quarter).sum() for c in centres])
            centres = centres[counts >= 0.5 * counts.max()]
            mid = centres[np.argmin(np.abs(centres - 0.5 * (z.min() + z.max())))]
            sel = np.abs(z - mid) <= quarter
        else:
            sel = np.ones(len(p), dtype=bool)
        all_xy, all_dmg = p[:, keep], dmg
        xy, d = p[sel][:, keep], dmg[sel]
    else:
        all_xy, all_dmg = p[:, :2], dmg
        xy, d = p[:, :2], dmg
    order = np.argsort(d, kind="stable")  # damaged points drawn last
    xy, d = xy[order], d[order]

    extent = np.ptp(xy, axis=0)
    dx = spacing_estimate(p[:, :b["dimension"]])  # before projection: layers overlap
    aspect = extent[1] / extent[0] if extent[0] > 0 else 1.0
    # The axes take about 0.75 of the width (the colour bar the rest); room for the labels.
    height = max(2.5, min(0.75 * args.width * aspect + 1.0, 12.0))
    fig, ax = plt.subplots(figsize=(args.width, height), dpi=args.dpi, layout="constrained")
    # Marker area from the point spacing in display units, so the points tile the body.
    axes_width_pt = 0.75 * args.width * 72
    if 0.75 * args.width * aspect + 1.0 > 12.0:  # height-limited: the axes are narrower
        axes_width_pt = (12.0 - 1.0) / aspect * 72
    size = (axes_width_pt * dx / max(extent[0], 1e-30)) ** 2 * 1.6
    sc = ax.scatter(xy[:, 0], xy[:, 1], c=d, s=size, cmap="inferno_r", vmin=0, vmax=1,
                    marker="s", linewidths=0, rasterized=True)
    ax.set_aspect("equal")
    ax.set_xlabel(f"{view[0]} (m)")
    ax.set_ylabel(f"{view[1]} (m)")
    layer = "" if b["dimension"] == 2 else (" mid layer" if args.layer == "mid" else " all layers")
    ax.set_title(args.title or f"{b['name']}: damage at t = {b['time'] * 1e3:.3f} ms "
                 f"(step {b['step']}){layer}", fontsize=10, wrap=True)
    fig.colorbar(sc, ax=ax, label="damage D", shrink=min(0.8, 3.0 / height + 0.3))
    pad = 2 * dx
    ax.set_xlim(all_xy[:, 0].min() - pad, all_xy[:, 0].max() + pad)
    ax.set_ylim(all_xy[:, 1].min() - pad, all_xy[:, 1].max() + pad)

    report = {"frame": os.path.basename(path), "time": b["time"], "step": b["step"],
              "points": int(len(p)), "max_damage": float(dmg.max()),
              "points_over_threshold": int((dmg > args.threshold).sum())}
    if args.kalthoff:
        tip = [float(v) for v in args.kalthoff.split(",")]
        angles = crack_angles(all_xy, all_dmg, tip, args.threshold, args.r_min, args.r_max, dx)
        report["crack_angles"] = angles
        for side in ("upper", "lower"):
            a = angles[side]
            if a["angle_deg"] is None:
                continue
            t = np.array(a["trace"])
            ax.plot(t[:, 0], t[:, 1], "o", color="tab:cyan", ms=2.5)
            ax.plot([a["tip"][0], t[-1, 0]], [a["tip"][1], t[-1, 1]], color="tab:cyan", lw=1)
            ax.annotate(f"{a['angle_deg']:.1f}°", (t[-1, 0], t[-1, 1]), color="tab:blue",
                        fontsize=10, xytext=(4, 0), textcoords="offset points")
    out = args.out or os.path.join(args.run, f"damage_{b['step']:06d}.png")
    fig.savefig(out)
    report["png"] = out
    report["png_kb"] = round(os.path.getsize(out) / 1024, 1)
    print(json.dumps(report))


if __name__ == "__main__":
    main()
