#!/usr/bin/env python3
"""Runs shortened seed cases with two ckpd binaries and compares their summary.json energies.

A refactoring that must not change the physics gives the same energies (kinetic, strain,
contact, external work, dissipated, balance error), broken bonds, steps and dt to a relative
tolerance (default 1e-12). Usage:

  scripts/compare_summaries.py --base /path/to/old/ckpd --new build/src/ckpd --out /tmp/cmp
  scripts/compare_summaries.py --base A --new B --out DIR --case cases/x.yaml time.end=1e-5
  scripts/compare_summaries.py --base A --new B --out DIR --base-rev ee5181a  # converted cases

Runs are on one thread (results are deterministic per build and thread count). Exit status 1
when any figure differs by more than the tolerance.
"""
import argparse
import json
import os
import re
import subprocess
import sys

# (case, overrides): each shortened to a few tens of steps so that one run takes well under a
# minute on a loaded 2-core machine.
DEFAULT_CASES = [
    ("cases/rigid_indenter.yaml", ["time.end=1e-5"]),
    ("cases/mode1_2d.yaml", ["time.end=2.5e-5"]),
    ("cases/mesh_plate_impact.yaml", ["time.end=5e-6"]),
    ("cases/curved_bar_2d.yaml", ["time.end=2e-5"]),
    ("bench/lammps/pmb_cylinder.yaml", ["time.steps=300"]),
    ("cases/stress/spin.yaml", ["time.end=4e-6"]),
    ("cases/stress/poisson.yaml", ["time.end=4e-6"]),
]
ENERGY_KEYS = ["kinetic", "strain", "contact", "external_work", "dissipated", "balance_error"]


def run(binary, case, overrides, out):
    cmd = [binary, "run", case, "--threads", "1", "--quiet", "--out", out]
    for o in overrides:
        cmd += ["--set", o]
    subprocess.run(cmd, check=True)
    with open(os.path.join(out, "summary.json")) as f:
        return json.load(f)


def case_at_revision(rev, case, out):
    """The case file as it was at `rev`, written under `out`, its `file:` paths made absolute."""
    text = subprocess.run(["git", "show", f"{rev}:{os.path.relpath(case)}"], check=True,
                          capture_output=True, text=True).stdout
    folder = os.path.dirname(os.path.abspath(case))
    text = re.sub(r"(\bfile:\s*)([^\s,}]+)",
                  lambda m: m.group(1) + (m.group(2) if os.path.isabs(m.group(2))
                                          else os.path.join(folder, m.group(2))), text)
    os.makedirs(out, exist_ok=True)
    path = os.path.join(out, os.path.basename(case) + f".{rev}.yaml")
    with open(path, "w") as f:
        f.write(text)
    return path


def figures(summary):
    fig = {"energy." + k: summary["energy"][k] for k in ENERGY_KEYS}
    fig["broken_bonds"] = summary["broken_bonds"]
    fig["steps"] = summary["steps"]
    fig["dt"] = summary["dt"]
    return fig


def relative(a, b):
    scale = max(abs(a), abs(b))
    return 0.0 if scale == 0 else abs(a - b) / scale


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawTextHelpFormatter)
    p.add_argument("--base", required=True, help="the ckpd binary before the change")
    p.add_argument("--new", required=True, help="the ckpd binary after the change")
    p.add_argument("--out", required=True, help="directory for the runs")
    p.add_argument("--tolerance", type=float, default=1e-12)
    p.add_argument("--case", nargs="+", action="append", metavar=("CASE", "OVERRIDE"),
                   help="a case and its overrides (repeatable); default: the seed cases")
    p.add_argument("--new-case", action="append", default=[], metavar="OLD=NEW",
                   help="run NEW with the new binary where the base runs OLD (a converted case)")
    p.add_argument("--base-rev", default=None,
                   help="give the base binary each case file as it was at this git revision "
                        "(for case files converted since; relative `file:` paths are kept "
                        "pointing at the case's folder)")
    args = p.parse_args()
    cases = [(c[0], c[1:]) for c in args.case] if args.case else DEFAULT_CASES
    renamed = dict(x.split("=", 1) for x in args.new_case)
    worst_all = 0.0
    print("| case | figure | base | new | relative difference |")
    print("|---|---|---|---|---|")
    for case, overrides in cases:
        name = os.path.splitext(os.path.basename(case))[0]
        base_case = case
        if args.base_rev:
            base_case = case_at_revision(args.base_rev, case, args.out)
        base = figures(run(args.base, base_case, overrides,
                           os.path.join(args.out, name + ".base")))
        new = figures(run(args.new, renamed.get(case, case), overrides,
                          os.path.join(args.out, name + ".new")))
        for key in base:
            d = relative(base[key], new[key])
            worst_all = max(worst_all, d)
            print(f"| {name} | {key} | {base[key]:.17g} | {new[key]:.17g} | {d:.2e} |")
        sys.stdout.flush()
    print(f"\nworst relative difference: {worst_all:.2e} (tolerance {args.tolerance:.0e})")
    return 0 if worst_all <= args.tolerance else 1


if __name__ == "__main__":
    sys.exit(main())
