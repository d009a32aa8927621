#!/usr/bin/python3
"""Plot metrics of a sweep against one of its parameters, from DIR/sweep.csv, into a PNG.

    scripts/plot_sweep.py runs/SWEEP/sweep.csv --x speed --y sphere_vz dissipated -o plot.png

Each metric gets its own panel (shared x axis). Failed or unfinished runs are left out and
counted in the title; with --group PARAM one line per value of another parameter. --logx/--logy
for log axes.
"""
import argparse
import csv
import sys
from collections import defaultdict

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def number(text):
    try:
        return float(text)
    except ValueError:
        return None


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("table", help="sweep.csv")
    ap.add_argument("--x", required=True, help="parameter (column) for the x axis")
    ap.add_argument("--y", required=True, nargs="+", help="metric column(s), one panel each")
    ap.add_argument("--group", help="one line per value of this column")
    ap.add_argument("--labels", nargs="+", help="axis labels for the y columns (with units)")
    ap.add_argument("--xlabel", help="x axis label (default: the column name)")
    ap.add_argument("--title", help="figure title")
    ap.add_argument("--logx", action="store_true")
    ap.add_argument("--logy", action="store_true")
    ap.add_argument("-o", "--out", required=True, help="PNG file")
    args = ap.parse_args()

    with open(args.table, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{args.table}: no runs")
    for col in [args.x] + args.y + ([args.group] if args.group else []):
        if col not in rows[0]:
            sys.exit(f"{args.table}: no column '{col}' (columns: {', '.join(rows[0])})")
    done = [r for r in rows if r["status"] == "completed"]
    skipped = len(rows) - len(done)

    fig, axes = plt.subplots(len(args.y), 1, sharex=True, figsize=(6.4, 2.4 * len(args.y) + 0.8),
                             constrained_layout=True, squeeze=False)
    for k, col in enumerate(args.y):
        ax = axes[k][0]
        groups = defaultdict(list)
        for r in done:
            x, y = number(r[args.x]), number(r[col])
            if x is not None and y is not None:
                groups[r[args.group] if args.group else ""].append((x, y))
        for name, pts in groups.items():
            pts.sort()
            ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-",
                    label=f"{args.group} = {name}" if args.group else None)
        ax.set_ylabel(args.labels[k] if args.labels and k < len(args.labels) else col)
        ax.grid(True, alpha=0.3)
        if args.logx:
            ax.set_xscale("log")
        if args.logy:
            ax.set_yscale("log")
        if args.group:
            ax.legend(fontsize="small")
    axes[-1][0].set_xlabel(args.xlabel or args.x)
    title = args.title or args.table
    if skipped:
        title += f" ({skipped} of {len(rows)} runs failed or unfinished, not shown)"
    fig.suptitle(title, fontsize="medium")
    fig.savefig(args.out, dpi=120)
    print(f"wrote {args.out}: {len(done)} runs, {len(args.y)} panel(s)")


if __name__ == "__main__":
    main()
