#!/usr/bin/env python3
"""Reaction-force curve of the 2D mode I case (cases/mode1_2d.yaml): the force the top grip
exerts on the plate against the grip opening, sampled during the run, plotted without ParaView.

The grip's points move at a prescribed velocity (constant, so no acceleration): the force the
grip supplies balances the plate's force on them, R = -sum_i f_i V_i over the grip points
(N per m of thickness in 2D).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/mode1_reaction_force.py --quick
"""
import argparse
import os
import pathlib

import numpy as np

import ckpd

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="dx = 20 mm (50 x 50 points), seconds")
    p.add_argument("--out", default="runs/mode1_reaction_force")
    args = p.parse_args()
    overrides = {}
    if args.quick:  # as cases/sweeps/mode1_horizon_ratio.yaml: three rows per grip at 20 mm
        overrides = {"bodies.plate.spacing": 0.02, "conditions.0.region.min": [0, 0.945],
                     "conditions.1.region.max": [1, 0.055]}
    sim = ckpd.Simulation(ROOT / "cases" / "mode1_2d.yaml", overrides=overrides, out=args.out)
    top = sim.conditions[0]
    plate = sim.bodies["plate"]
    volumes = plate.volumes[top.points]
    opening, force, broken = [], [], []

    def sample(s):
        f = plate.force_density  # a view: no copy per sample
        force.append(-np.sum(f[top.points, 1] * volumes))
        opening.append(2 * np.mean(plate.displacements[top.points, 1]))
        broken.append(s.broken_bonds)

    sim.run(callback=sample, every=max(1, sim.planned_steps // 300))
    peak = int(np.argmax(force))
    print(f"{sim.step_number} steps, {sim.broken_bonds} broken bonds; peak reaction "
          f"{force[peak]:.4g} N/m at opening {opening[peak] * 1e6:.3g} um; results in {args.out}")

    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(6, 4))
    ax.plot(np.array(opening) * 1e6, np.array(force) / 1e3)
    ax.set_xlabel("grip opening (um)")
    ax.set_ylabel("reaction force on the top grip (kN/m)")
    ax.set_title("mode I 2D" + (" (dx = 20 mm)" if args.quick else ""))
    ax2 = ax.twinx()
    ax2.plot(np.array(opening) * 1e6, broken, color="tab:red", lw=0.8)
    ax2.set_ylabel("broken bonds", color="tab:red")
    fig.tight_layout()
    png = os.path.join(args.out, "reaction_force.png")
    fig.savefig(png, dpi=120)
    print(f"plot: {png}")


if __name__ == "__main__":
    main()
