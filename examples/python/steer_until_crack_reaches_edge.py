#!/usr/bin/env python3
"""A steering loop on the 2D mode I case: the grips are pulled slowly; while the crack does not
grow the controller speeds them up (x1.5 per check), once it grows it holds their speed; the run
stops as soon as the crack reaches the plate's right edge (the remaining ligament is broken).

    PYTHONPATH=build/python /usr/bin/python3 examples/python/steer_until_crack_reaches_edge.py --quick
"""
import argparse
import pathlib

import numpy as np

import ckpd

ROOT = pathlib.Path(__file__).resolve().parents[2]


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="dx = 20 mm (50 x 50 points)")
    p.add_argument("--out", default="runs/steer_mode1")
    args = p.parse_args()
    dx = 0.02 if args.quick else 0.005
    overrides = {"bodies.plate.spacing": dx, "conditions.0.region.min": [0, 1 - 3 * dx],
                 "conditions.1.region.max": [1, 3 * dx], "time.end": 0.05}
    sim = ckpd.Simulation(ROOT / "cases" / "mode1_2d.yaml", overrides=overrides, out=args.out)
    top, bottom = sim.conditions
    plate = sim.bodies["plate"]
    x = plate.reference_positions
    band = np.abs(x[:, 1] - 0.5) < 2 * dx  # the points along the crack line
    edge = 1 - dx
    speed = float(top.value[1])
    last_tip = 0.5

    def control(s):
        nonlocal speed, last_tip
        cracked = band & (plate.damage > 0.4)
        tip = x[cracked, 0].max() if cracked.any() else 0.5
        if tip >= edge:
            print(f"t = {s.time * 1e3:.3f} ms: the crack reached the right edge (x = {tip:.3f} m)")
            return False  # stops the run; summary.json says "stopped"
        if tip <= last_tip and speed < 0.2:
            speed *= 1.5
            top.value = [0, speed]
            bottom.value = [0, -speed]
        last_tip = max(last_tip, tip)
        return True

    sim.run(callback=control, every=max(1, int(2e-4 / sim.dt)))
    print(f"status {sim.status} at step {sim.step_number}; grip speed {speed:.4g} m/s; "
          f"{sim.broken_bonds} broken bonds; fragments {plate.fragments()['count']}; "
          f"results in {args.out}")


if __name__ == "__main__":
    main()
