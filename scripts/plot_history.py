#!/usr/bin/python3
"""Plot a run's DIR/history.csv into a PNG: energies, the energy balance error, broken bonds and
damage, and the case's chosen history quantities (output.history), one panel each.

    scripts/plot_history.py runs/CASE/history.csv -o runs/CASE/history.png
    scripts/plot_history.py runs/CASE/history.csv --columns contact_force_ball_plate_z -o f.png

Panels: (1) kinetic, strain, contact, dissipated energy, contact damping and friction losses
and external work (each only when the file has the column and it is not zero throughout); (2)
the balance error, absolute and as a percentage of max(|external work|, kinetic + strain); (3)
broken bonds and maximum damage; (4) the far field's fraction of exact points, when the file has
it; then one panel per chosen quantity (its x, y, z columns together). Only columns the file's
header names are drawn, so histories of every ckpd version plot. With --columns only those
columns are drawn after the standard panels. Time in microseconds.
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

# Columns every history has; a file without them is not a ckpd history.
REQUIRED = ["step", "time", "kinetic", "strain", "contact", "external_work", "dissipated",
            "balance_error", "broken_bonds", "max_damage"]
# Standard columns that only some ckpd versions or cases write (drawn in the standard panels
# when present, never as panels of their own).
OPTIONAL = ["contact_damping", "contact_friction", "inverted", "exact_fraction"]
ENERGIES = ["kinetic", "strain", "contact", "dissipated", "contact_damping", "contact_friction",
            "external_work"]


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    if not rows:
        sys.exit(f"{path}: empty")
    header, body = rows[0], [r for r in rows[1:] if len(r) == len(rows[0])]
    return {name: [float(r[k]) for r in body] for k, name in enumerate(header)}, header


def groups(names):
    """Chosen columns grouped by quantity: name_x, name_y, name_z share a panel."""
    out = {}
    for n in names:
        base = n[:-2] if n[-2:] in ("_x", "_y", "_z") else n
        out.setdefault(base, []).append(n)
    return out


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("history", help="DIR/history.csv")
    ap.add_argument("--columns", nargs="+", help="chosen columns to draw (default: all)")
    ap.add_argument("--title", help="figure title (default: the file name)")
    ap.add_argument("-o", "--out", required=True, help="PNG file")
    args = ap.parse_args()
    data, header = read(args.history)
    missing = [c for c in REQUIRED if c not in data]
    if missing:
        sys.exit(f"{args.history}: not a ckpd history (missing {', '.join(missing)})")
    chosen = [c for c in header if c not in REQUIRED and c not in OPTIONAL]
    if args.columns:
        unknown = [c for c in args.columns if c not in data]
        if unknown:
            sys.exit(f"unknown column(s) {', '.join(unknown)}; the file has: {', '.join(header)}")
        chosen = args.columns
    extra = groups(chosen)
    t = [1e6 * x for x in data["time"]]
    far_field = "exact_fraction" in data
    standard = 4 if far_field else 3
    panels = standard + len(extra)
    fig, axes = plt.subplots(panels, 1, figsize=(8, 2.6 * panels), sharex=True, squeeze=False)
    axes = axes[:, 0]
    for name in ENERGIES:
        if name in data and any(v != 0 for v in data[name]):
            axes[0].plot(t, data[name], label=name)
    axes[0].set_ylabel("energy [J]")
    axes[0].legend(fontsize=8)
    scale = [max(abs(w), k + s, 1e-300)
             for w, k, s in zip(data["external_work"], data["kinetic"], data["strain"])]
    percent = [100 * abs(e) / s for e, s in zip(data["balance_error"], scale)]
    axes[1].plot(t, data["balance_error"], color="C3", label="balance error [J]")
    axes[1].set_ylabel("balance error [J]")
    twin = axes[1].twinx()
    twin.plot(t, percent, color="C7", linestyle="--", label="% of energy scale")
    twin.set_ylabel("[%]")
    axes[1].legend(loc="upper left", fontsize=8)
    twin.legend(loc="upper right", fontsize=8)
    axes[2].plot(t, data["broken_bonds"], color="C4", label="broken bonds")
    axes[2].set_ylabel("broken bonds")
    twin = axes[2].twinx()
    twin.plot(t, data["max_damage"], color="C5", linestyle="--", label="max damage")
    twin.set_ylabel("max damage")
    twin.set_ylim(0, 1.05)
    if far_field:
        axes[3].plot(t, data["exact_fraction"], color="C2", label="far field: fraction exact")
        axes[3].set_ylabel("exact fraction")
        axes[3].set_ylim(0, 1.05)
        axes[3].legend(fontsize=8)
    for ax, (base, cols) in zip(axes[standard:], extra.items()):
        for c in cols:
            ax.plot(t, data[c], label=c)
        ax.set_ylabel(base, fontsize=8)
        ax.legend(fontsize=8)
    axes[-1].set_xlabel("time [us]")
    fig.suptitle(args.title or args.history)
    fig.tight_layout()
    fig.savefig(args.out, dpi=110)
    print(f"{args.out}: {panels} panels, {len(t)} rows")


if __name__ == "__main__":
    main()
