#!/usr/bin/env python3
"""A small sweep from Python: the 2D mode I case at three grip speeds, run as a list of case
dicts; the dissipated energy and broken bonds from the returned table, plotted.

    PYTHONPATH=build/python /usr/bin/python3 examples/python/sweep_plot.py --quick

(A sweep file runs the same way: ckpd.run_sweep("cases/sweeps/mode1_horizon_ratio.yaml").)
"""
import argparse
import copy
import os
import pathlib

import yaml

import ckpd

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="dx = 40 mm, 3 ms: seconds in all")
    p.add_argument("--out", default="runs/sweep_mode1_speed")
    args = p.parse_args()
    base = yaml.safe_load((ROOT / "cases" / "mode1_2d.yaml").read_text())
    dx = 0.04 if args.quick else 0.02
    base["bodies"][0]["spacing"] = dx
    base["conditions"][0]["region"]["min"] = [0, 1 - 3 * dx]
    base["conditions"][1]["region"]["max"] = [1, 3 * dx]
    if args.quick:
        base["time"]["end"] = 3e-3
    speeds = [0.005, 0.01, 0.02]  # m/s per grip
    cases = []
    for v in speeds:
        case = copy.deepcopy(base)
        case["conditions"][0]["value"] = [0, v]
        case["conditions"][1]["value"] = [0, -v]
        cases.append(case)
    table = ckpd.run_cases(cases, args.out, metrics={
        "dissipated": "energy.dissipated", "work": "energy.external_work",
        "broken_bonds": "bodies.plate.broken_bonds", "fragments": "bodies.plate.fragments"})
    for v, row in zip(speeds, table.rows):  # cells typed: numbers are numbers
        print(f"v = {v} m/s: {row['status']}, dissipated {row['dissipated']:.4g} J/m, "
              f"{row['broken_bonds']} broken bonds, {row['fragments']} fragments")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(5, 3.5))
    ax.plot(speeds, table["dissipated"], "o-", label="dissipated")
    ax.plot(speeds, table["work"], "s--", label="external work")
    ax.set_xlabel("grip speed (m/s)")
    ax.set_ylabel("energy (J/m)")
    ax.legend()
    fig.tight_layout()
    png = os.path.join(args.out, "sweep.png")
    fig.savefig(png, dpi=120)
    print(f"table: {table.path}; plot: {png}")


if __name__ == "__main__":
    main()
