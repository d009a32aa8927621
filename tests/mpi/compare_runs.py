#!/usr/bin/env python3
"""Compares ckpd runs of one case made at different rank counts (tests/mpi/, issue 14).

  compare_runs.py REFERENCE_DIR OTHER_DIR [OTHER_DIR ...] [--tolerance 1e-12]
                  [--extra-history-step S] [--files [--derived-tolerance 1e-9]]

Each OTHER run must match REFERENCE: the same status, steps and history rows; in every history
row the same broken bonds and each energy column within the tolerance relative to that column's
largest magnitude (a vector's components: relative to its largest component); per body the same
broken bonds and fragments (summary.json); in the last field
frame every point's position within the tolerance relative to the body's largest coordinate. The
displacement and velocity differences (relative to their own largest magnitudes) are printed too.
--extra-history-step S: the OTHER runs' history row of step S is left out when REFERENCE has none
(a run stopped by a signal writes a row at the step it stopped at, kept when it is continued
from its checkpoint).
--files: every frame file and the checkpoint compared dataset by dataset too (compare_files.py;
the fields taken from differences over a family within --derived-tolerance, default 1e-9).
Exit status 1 on any mismatch.
"""
import argparse
import csv
import json
import os
import sys

import h5py
import numpy as np

import compare_files


def history(path):
    with open(os.path.join(path, "history.csv"), newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], np.array([[float(x) for x in r] for r in rows[1:]])


def last_frame(path):
    names = sorted(n for n in os.listdir(os.path.join(path, "fields")) if n.endswith(".h5"))
    return h5py.File(os.path.join(path, "fields", names[-1]), "r")


def relative(a, b, scale=0.0):
    scale = max(np.max(np.abs(a)), scale, 1e-300)
    return float(np.max(np.abs(a - b)) / scale)


def vector_scale(head, rows, name):
    """A vector's component (columns NAME_x, _y, _z) is judged against the vector's largest
    component: a momentum along z leaves x and y at round-off, which no rank count repeats."""
    if name[-2:] not in ("_x", "_y", "_z"):
        return 0.0
    group = [c for c, n in enumerate(head) if n[:-2] == name[:-2] and n[-2:] in ("_x", "_y", "_z")]
    return float(np.max(np.abs(rows[:, group])))


def compare(ref, other, tol, extra_step=None):
    problems = []
    s_ref = json.load(open(os.path.join(ref, "summary.json")))
    s_oth = json.load(open(os.path.join(other, "summary.json")))
    for key in ("status", "steps", "points"):
        if s_ref[key] != s_oth[key]:
            problems.append(f"summary {key}: {s_ref[key]} vs {s_oth[key]}")
    for b_ref, b_oth in zip(s_ref["bodies"], s_oth["bodies"]):
        for key in ("broken_bonds", "fragments", "largest_fragments"):
            if key in b_ref and b_ref[key] != b_oth.get(key):
                problems.append(f"body {b_ref['name']} {key}: {b_ref[key]} vs {b_oth.get(key)}")
    head_ref, h_ref = history(ref)
    head_oth, h_oth = history(other)
    if extra_step is not None and h_oth.size and extra_step not in h_ref[:, 0]:
        h_oth = h_oth[h_oth[:, head_oth.index("step")] != extra_step]
    if head_ref != head_oth or h_ref.shape != h_oth.shape:
        problems.append(f"history: columns or rows differ ({h_ref.shape} vs {h_oth.shape})")
    else:
        worst = 0.0
        for c, name in enumerate(head_ref):
            if name in ("step", "broken_bonds", "inverted"):
                if not np.array_equal(h_ref[:, c], h_oth[:, c]):
                    problems.append(f"history column {name} differs")
                continue
            if name == "external_work" or name == "balance_error":
                continue  # near zero here: round-off of other columns; compared through them
            err = relative(h_ref[:, c], h_oth[:, c], vector_scale(head_ref, h_ref, name))
            worst = max(worst, err)
            if err > tol:
                problems.append(f"history column {name}: relative difference {err:.3g}")
        print(f"  history: {h_ref.shape[0]} rows, largest relative difference {worst:.3g}")
    f_ref, f_oth = last_frame(ref), last_frame(other)
    if f_ref.attrs["step"] != f_oth.attrs["step"]:
        problems.append("last frames are of different steps")
    for body in f_ref:
        errs = {q: relative(f_ref[body][q][...], f_oth[body][q][...])
                for q in ("position", "displacement", "velocity") if q in f_ref[body]}
        print(f"  {body} at step {f_ref.attrs['step']}: " +
              ", ".join(f"{q} {e:.3g}" for q, e in errs.items()))
        if errs["position"] > tol:
            problems.append(f"{body}: positions differ by {errs['position']:.3g} relative")
        # A mesh wall's frame has its surface, without damage.
        if "damage" in f_ref[body] and not np.array_equal(f_ref[body]["damage"][...],
                                                          f_oth[body]["damage"][...]):
            problems.append(f"{body}: damage differs")
    return problems


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("reference")
    p.add_argument("others", nargs="+")
    p.add_argument("--tolerance", type=float, default=1e-12)
    p.add_argument("--extra-history-step", type=int)
    p.add_argument("--files", action="store_true")
    p.add_argument("--derived-tolerance", type=float, default=1e-9)
    a = p.parse_args()
    failed = False
    for other in a.others:
        print(f"{other} against {a.reference}:")
        problems = compare(a.reference, other, a.tolerance, a.extra_history_step)
        if a.files:
            problems += compare_files.compare(a.reference, other, a.tolerance, a.derived_tolerance)
        for problem in problems:
            print("  MISMATCH: " + problem)
            failed = True
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
