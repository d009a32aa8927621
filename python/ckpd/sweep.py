"""Sweeps from Python: a sweep file (run as `ckpd sweep` does, child processes of the ckpd
program) or a list of cases (dicts or files, run here one after another); the table back."""
import csv
import json
import os
import time

import numpy as np

from . import _ckpd


def _program():
    program = os.environ.get("CKPD_PROGRAM")
    if program:
        return program
    from ._program import PROGRAM

    return PROGRAM


class SweepTable:
    """A sweep's table: rows (list of dicts, cells as strings) and columns as arrays (numbers
    where every cell of the column is one, else strings). table["name"] is a column."""

    def __init__(self, path, header, rows, exit_status=0):
        self.path = path
        self.header = header
        self.rows = rows
        self.exit_status = exit_status

    @classmethod
    def read(cls, path, exit_status=0):
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            rows = list(reader)
            header = list(reader.fieldnames or [])
        return cls(path, header, rows, exit_status)

    def column(self, name):
        if name not in self.header:
            raise KeyError(f"{self.path}: no column {name!r} ({', '.join(self.header)})")
        cells = [r[name] for r in self.rows]
        try:
            return np.array([float(c) if c != "" else np.nan for c in cells])
        except ValueError:
            return np.array(cells, dtype=object)

    def __getitem__(self, name):
        return self.column(name)

    def __len__(self):
        return len(self.rows)

    @property
    def completed(self):
        return all(r.get("status") == "completed" for r in self.rows)

    def __repr__(self):
        return f"<ckpd.SweepTable {self.path}: {len(self.rows)} runs, columns {', '.join(self.header)}>"


def run_sweep(file, out=None, jobs=0, threads_per_run=0, quiet=True):
    """Runs a sweep file as `ckpd sweep FILE --out OUT` does and returns its sweep.csv.
    Bad sweep files raise SweepError (or CaseError for the base case); failed runs are rows
    with status `failed` (and exit_status 4)."""
    file = os.fspath(file)
    if out is None:
        out = os.path.join("runs", os.path.splitext(os.path.basename(file))[0])
    out = os.fspath(out)
    status = _ckpd._run_sweep_file(file, out, _program(), jobs, threads_per_run, quiet)
    return SweepTable.read(os.path.join(out, "sweep.csv"), status)


def run_cases(cases, out, metrics=None, overrides=None, threads=0):
    """Runs each case (a dict or a case file) in this process, into OUT/NNNN, and returns the
    table (also written to OUT/cases.csv): index, folder, status, message, one column per
    metric (name -> path into summary.json, as in sweep files) and wall_seconds. A case that
    is rejected or goes unstable is a row with status failed/unstable; the others go on."""
    out = os.fspath(out)
    os.makedirs(out, exist_ok=True)
    metrics = dict(metrics or {})
    header = ["index", "folder", "status", "message", *metrics, "wall_seconds"]
    rows = []
    for index, case in enumerate(cases):
        folder = os.path.join(out, f"{index:04d}")
        row = {"index": str(index), "folder": folder, "message": ""}
        start = time.perf_counter()
        try:
            sim = _ckpd.Simulation(case, overrides=overrides, out=folder, threads=threads)
            sim.run()
            row["status"] = sim.status
        except _ckpd.CaseError as e:
            row["status"], row["message"] = "failed", str(e)
        except _ckpd.InstabilityError as e:
            row["status"], row["message"] = "unstable", str(e)
        row["wall_seconds"] = repr(time.perf_counter() - start)
        summary = os.path.join(folder, "summary.json")
        text = None
        if os.path.exists(summary):
            with open(summary) as f:
                text = f.read()
        for name, path in metrics.items():
            row[name] = _ckpd._summary_value(text, path) if text else ""
        rows.append(row)
        table = SweepTable(os.path.join(out, "cases.csv"), header, rows)
        _write(table)
    return SweepTable(os.path.join(out, "cases.csv"), header, rows)


def _write(table):
    temp = table.path + ".tmp"
    with open(temp, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=table.header)
        writer.writeheader()
        writer.writerows(table.rows)
    os.replace(temp, table.path)
