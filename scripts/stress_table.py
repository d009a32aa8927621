#!/usr/bin/python3
"""Runs the stiff and extreme cases of cases/stress/ and writes the table of docs/STABILITY.md.

Every run uses the automatic time step (dt: auto, 0.8 x the stable-step estimate). Per run the
table gives: whether it completed at that step, the worst energy balance error, what the guard
reported (status and message), the most inverted tetrahedra/triangles seen and the wall time.

The energy balance error of a history row is kinetic + strain + contact + dissipated - external
work - (kinetic + strain + contact at t = 0) (README, history.csv). The table divides its largest
magnitude over the rows by the energy put in: the initial kinetic + strain + contact energy plus
the largest |external work| over the rows (the quantity the instability guard compares with).

A history with a non-finite number is reported as such (and makes this script exit 1): no NaN
may pass for a result.

    scripts/stress_table.py [--build build] [--only NAME ...] [--threads 1] [--no-write]

Runs go to runs/stress/NAME/. Each case runs with `nice -n 10`; the wall times in the table are
whatever the machine gave, so state its load next to them.
"""
import argparse
import csv
import json
import math
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DOC = os.path.join(ROOT, "docs", "STABILITY.md")
BEGIN, END = "<!-- stress-table:begin -->", "<!-- stress-table:end -->"


def impact(speed):
    return ["conditions.0.value=[0,0,%g]" % -speed, "time.end=%g" % (0.003 / speed)]


ALL_EDGES = ["bodies.sphere.damage_rule=all_edges", "bodies.plate.damage_rule=all_edges"]

# (name, case file, --set overrides, what the row stresses)
RUNS = [
    ("contact_1e3GPa", "contact_stiffness.yaml", ["contact.stiffness=1e12"],
     "contact stiffness 1e3 GPa, two spheres at 2 x 10 m/s"),
    ("contact_1e4GPa", "contact_stiffness.yaml", ["contact.stiffness=1e13"],
     "contact stiffness 1e4 GPa"),
    ("contact_1e5GPa", "contact_stiffness.yaml", ["contact.stiffness=1e14"],
     "contact stiffness 1e5 GPa"),
    ("impact_10", "impact_speed.yaml", impact(10), "sphere into brittle plate, 10 m/s"),
    ("impact_100", "impact_speed.yaml", impact(100), "sphere into brittle plate, 100 m/s"),
    ("impact_500", "impact_speed.yaml", impact(500), "sphere into brittle plate, 500 m/s"),
    ("impact_2000", "impact_speed.yaml", impact(2000), "sphere into brittle plate, 2000 m/s"),
    ("nu_0.05", "poisson.yaml", ["materials.block.poisson_ratio=0.05"],
     "3D nu = 0.05 (C3 < 0), block onto rigid wall at 20 m/s"),
    ("nu_0.49", "poisson.yaml", ["materials.block.poisson_ratio=0.49"],
     "3D nu = 0.49 (large C3), block onto rigid wall at 20 m/s"),
    ("2d_nu_0.2", "plane_2d.yaml", [], "2D plane stress nu = 0.2 (C2 < 0), disc onto wall at 50 m/s"),
    ("compress_50", "compression.yaml", [],
     "polymer block crushed to 50 % between rigid plates at 20 m/s, no remedy"),
    ("compress_50_penalty1", "compression.yaml", ["bodies.block.inversion_penalty=1"],
     "50 % compression, inversion_penalty 1"),
    ("compress_50_penalty16", "compression.yaml", ["bodies.block.inversion_penalty=16"],
     "50 % compression, inversion_penalty 16"),
    ("compress_50_fast", "compression.yaml",
     ["bodies.press.rigid.velocity=[0,0,-200]", "time.end=1.5e-5"],
     "50 % compression at 200 m/s (a quarter of the wave speed), no remedy"),
    ("compress_50_fast_penalty1", "compression.yaml",
     ["bodies.press.rigid.velocity=[0,0,-200]", "time.end=1.5e-5",
      "bodies.block.inversion_penalty=1"], "50 % compression at 200 m/s, inversion_penalty 1"),
    ("spin", "spin.yaml", [], "free sphere spinning at 25,000 rad/s (rim 100 m/s), one turn"),
    ("thin_1_layer", "thin_plate.yaml", [], "one-layer plate, rigid sphere pushed through at 20 m/s"),
    ("thin_2_layers", "thin_plate.yaml", ["bodies.plate.geometry.min=[-0.012,-0.012,-0.001]"],
     "two-layer plate, same load"),
    ("mismatch", "mismatch.yaml", [],
     "fine steel sphere (dx 0.5 mm) into coarse polymer (dx 2 mm, E 70 x lower) at 50 m/s"),
    # The fracture rows again with the conservative damage rule (README, `damage_rule`) on
    # every body that breaks (the sphere breaks too).
    ("impact_100_all_edges", "impact_speed.yaml", impact(100) + ALL_EDGES,
     "impact_100 with damage_rule all_edges"),
    ("impact_500_all_edges", "impact_speed.yaml", impact(500) + ALL_EDGES,
     "impact_500 with damage_rule all_edges"),
    ("impact_2000_all_edges", "impact_speed.yaml", impact(2000) + ALL_EDGES,
     "impact_2000 with damage_rule all_edges"),
    ("thin_2_layers_all_edges", "thin_plate.yaml",
     ["bodies.plate.geometry.min=[-0.012,-0.012,-0.001]", "bodies.plate.damage_rule=all_edges"],
     "thin_2_layers with damage_rule all_edges"),
]


def read_history(path):
    rows, nonfinite = [], []
    with open(path) as f:
        for row in csv.DictReader(f):
            values = {}
            for key, text in row.items():
                try:
                    v = float(text)
                except (TypeError, ValueError):
                    nonfinite.append((row.get("step"), key, text))
                    continue
                if not math.isfinite(v):
                    nonfinite.append((row.get("step"), key, text))
                values[key] = v
            rows.append(values)
    return rows, nonfinite


def energy_error(rows):
    """Largest |balance error| over the rows, relative to the energy put in."""
    if not rows:
        return None
    first = rows[0]
    initial = first["kinetic"] + first["strain"] + first["contact"]
    work = max(abs(r["external_work"]) for r in rows)
    supplied = abs(initial) + work
    worst = max(abs(r["balance_error"]) for r in rows)
    return worst / supplied if supplied > 0 else float("inf")


def energy_created(rows):
    """Largest gain of kinetic + strain + contact over the initial energy plus the work done,
    relative to the energy put in: positive means the run made energy, whatever the
    dissipation bookkeeping says (with fracture the balance error also holds any error in the
    energy booked as dissipated)."""
    if not rows:
        return None
    first = rows[0]
    initial = first["kinetic"] + first["strain"] + first["contact"]
    supplied = abs(initial) + max(abs(r["external_work"]) for r in rows)
    gain = max(r["kinetic"] + r["strain"] + r["contact"] - r["external_work"] - initial
               for r in rows)
    return gain / supplied if supplied > 0 else float("inf")


def final_error(rows):
    """|balance error| of the last row, relative to the energy put in."""
    if not rows:
        return None
    first = rows[0]
    initial = first["kinetic"] + first["strain"] + first["contact"]
    supplied = abs(initial) + max(abs(r["external_work"]) for r in rows)
    return abs(rows[-1]["balance_error"]) / supplied if supplied > 0 else float("inf")


def run_one(binary, name, case, sets, threads, timeout, reuse=None):
    out = os.path.join(ROOT, "runs", "stress", name)
    os.makedirs(out, exist_ok=True)
    cmd = ["nice", "-n", "10", binary, "run", os.path.join(ROOT, "cases", "stress", case),
           "--out", out, "--quiet", "--threads", str(threads)]
    for s in sets:
        cmd += ["--set", s]
    start = time.monotonic()
    if reuse is not None:  # read the outputs of an earlier run of this script
        code, stderr, wall = reuse["exit"], reuse["stderr"], reuse["wall_s"]
    else:
        try:
            p = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
            code, stderr = p.returncode, p.stderr
        except subprocess.TimeoutExpired:
            code, stderr = None, "timed out after %d s" % timeout
        wall = time.monotonic() - start
    result = {"name": name, "case": "cases/stress/" + case, "set": sets, "exit": code,
              "wall_s": wall, "stderr": stderr.strip()}
    summary_path = os.path.join(out, "summary.json")
    if os.path.exists(summary_path) and code is not None:
        with open(summary_path) as f:
            s = json.load(f)
        result.update(status=s["status"], message=s.get("message", ""), steps=s["steps"],
                      dt=s["dt"], dt_estimate=s["dt_estimate"], points=s["points"],
                      inversion=s.get("inversion", {}), broken_bonds=s.get("broken_bonds", 0))
    else:
        result.update(status="no summary" if code is not None else "timed out",
                      message=stderr.strip()[-300:])
    history_path = os.path.join(out, "history.csv")
    if os.path.exists(history_path):
        rows, nonfinite = read_history(history_path)
        result["nonfinite"] = nonfinite[:5]
        finite_rows = [r for r in rows if all(math.isfinite(v) for v in r.values())]
        result["energy_error"] = energy_error(finite_rows)
        result["energy_created"] = energy_created(finite_rows)
        result["final_error"] = final_error(finite_rows)
        if rows and rows[-1].get("kinetic", 0) > 0:
            last = rows[-1]
            result["strain_over_kinetic"] = max(r["strain"] / r["kinetic"] for r in rows[1:]
                                                if r["kinetic"] > 0) if len(rows) > 1 else 0
            result["final_kinetic"] = last["kinetic"]
    return result


def cell(text):
    return str(text).replace("|", "\\|").replace("\n", " ")


def table(results, descriptions):
    lines = ["| run | stresses | points | steps | dt (s) | completed at dt auto? | worst energy error "
             "| final energy error | energy created | guard status and message | inverted (max; first seen) "
             "| broken bonds; max strain/kinetic | wall (s) |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        inv = r.get("inversion") or {}
        first = inv.get("first")
        inverted = "%d; step %d, t = %.3g s, body %s" % (inv.get("max", 0), first["step"],
                                                          first["time"], first["body"]) \
            if first else "%s" % inv.get("max", "-")
        err = r.get("energy_error")
        err_text = "%.2g" % err if err is not None else "-"
        if r.get("nonfinite"):
            err_text += " (NON-FINITE history values: %s)" % r["nonfinite"][:2]
        ok = "yes" if r["status"] == "completed" else "no"
        message = r.get("message") or ""
        if len(message) > 260:
            message = message[:257] + "..."
        guard = r["status"] + (": " + message if message else "")
        created = r.get("energy_created")
        extra = "%s; %.2g" % (r.get("broken_bonds", "-"), r.get("strain_over_kinetic", 0))
        final = r.get("final_error")
        lines.append("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %.0f |" % (
            r["name"], cell(descriptions[r["name"]] + (" (`--set " + " --set ".join(r["set"]) + "`)"
                                                        if r["set"] else "")),
            r.get("points", "-"), r.get("steps", "-"),
            "%.3g" % r["dt"] if "dt" in r else "-", ok, err_text,
            "%.2g" % final if final is not None else "-",
            "%.2g" % created if created is not None else "-", cell(guard), cell(inverted), extra,
            r["wall_s"]))
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default="build", help="build folder holding src/ckpd")
    ap.add_argument("--only", nargs="*", help="run only these rows (names)")
    ap.add_argument("--threads", type=int, default=1)
    ap.add_argument("--timeout", type=int, default=900, help="seconds per run")
    ap.add_argument("--no-write", action="store_true", help="print the table, leave the doc")
    ap.add_argument("--reuse", action="store_true",
                    help="run nothing: rebuild the table from runs/stress/ and results.json")
    args = ap.parse_args()
    binary = os.path.join(ROOT, args.build, "src", "ckpd")
    if not os.path.exists(binary):
        sys.exit(binary + ": not found (build first, or pass --build)")
    descriptions = {name: what for name, _, _, what in RUNS}
    results_path = os.path.join(ROOT, "runs", "stress", "results.json")
    previous = {}
    if os.path.exists(results_path):
        with open(results_path) as f:
            previous = {r["name"]: r for r in json.load(f)}
    for name, case, sets, _ in RUNS:
        if args.only and name not in args.only:
            continue
        if args.reuse and name not in previous:
            continue
        r = run_one(binary, name, case, sets, args.threads, args.timeout,
                    previous[name] if args.reuse else None)
        previous[name] = r
        print("%-20s %-10s err %-8s inverted %-6s %6.1f s  %s" % (
            name, r["status"], "%.2g" % r["energy_error"] if r.get("energy_error") is not None
            else "-", (r.get("inversion") or {}).get("max", "-"), r["wall_s"],
            (r.get("message") or "")[:100]), flush=True)
    os.makedirs(os.path.dirname(results_path), exist_ok=True)
    with open(results_path, "w") as f:
        json.dump(list(previous.values()), f, indent=1)
    ordered = [previous[name] for name, _, _, _ in RUNS if name in previous]
    text = table(ordered, descriptions)
    if args.no_write:
        print(text)
    else:
        with open(DOC) as f:
            doc = f.read()
        if BEGIN not in doc or END not in doc:
            sys.exit(DOC + ": markers " + BEGIN + " / " + END + " not found")
        head, rest = doc.split(BEGIN, 1)
        _, tail = rest.split(END, 1)
        with open(DOC, "w") as f:
            f.write(head + BEGIN + "\n" + text + "\n" + END + tail)
        print("wrote the table into " + DOC)
    bad = [r["name"] for r in ordered if r.get("nonfinite") and r["status"] == "completed"]
    if bad:
        print("NON-FINITE values in a completed run's history: " + ", ".join(bad))
        sys.exit(1)


if __name__ == "__main__":
    main()
