#!/usr/bin/env python3
"""Time per step and peak memory of a free 3D block (issue 2's benchmark).

Runs `ckpd run bench/block_3d.yaml` for each Poisson's ratio, thread count and block size,
several times, and prints the set-up and the medians as a Markdown table:
points, bonds, N3 (ordered three-neighbour interactions), set-up seconds, seconds per step,
peak RSS. nu = 0.3 has three-neighbour work (C3 > 0); nu = 0.25 has none (C3 = 0).

    python3 bench/block_bench.py [--ckpd build/src/ckpd] [--repeats 3] [--steps 3]
"""
import argparse
import json
import os
import platform
import statistics
import subprocess
import tempfile


def run_once(ckpd, side, nu, threads, steps):
    with tempfile.TemporaryDirectory() as out:
        extent = side * 0.001
        cmd = [ckpd, "run", "bench/block_3d.yaml", "--quiet", "--out", out,
               "--threads", str(threads),
               "--set", f"materials.steel.poisson_ratio={nu}",
               "--set", f"bodies.block.geometry.max=[{extent}, {extent}, {extent}]",
               "--set", f"time.steps={steps}"]
        subprocess.run(cmd, check=True)
        with open(os.path.join(out, "summary.json")) as f:
            return json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ckpd", default="build/src/ckpd")
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--steps", type=int, default=3)
    parser.add_argument("--sides", default="37,40", help="points per side, comma separated")
    args = parser.parse_args()
    cpu = "unknown"
    with open("/proc/cpuinfo") as f:
        for line in f:
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    print(f"machine: {platform.node()}, {os.cpu_count()} cores, {cpu}")
    print(f"block: cubic lattice dx = 1 mm, m = 3.015, E = 210 GPa, {args.steps} steps per run, "
          f"median of {args.repeats} runs")
    print()
    print("| points | nu | threads | bonds | N3 (ordered) | set-up s | s/step | peak RSS MB |")
    print("|---|---|---|---|---|---|---|---|")
    for side in [int(s) for s in args.sides.split(",")]:
        for nu in (0.3, 0.25):
            for threads in (1, 2):
                runs = [run_once(args.ckpd, side, nu, threads, args.steps)
                        for _ in range(args.repeats)]
                med = lambda key: statistics.median(r[key] for r in runs)
                r = runs[0]
                print(f"| {r['points']} | {nu} | {threads} | {r['bonds']} | "
                      f"{r['three_neighbour']} | {med('setup_seconds'):.2f} | "
                      f"{med('seconds_per_step'):.3f} | {med('peak_rss_mb'):.1f} |", flush=True)


if __name__ == "__main__":
    main()
