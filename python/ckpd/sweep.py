"""Sweeps from Python: a sweep file (run as `ckpd sweep` does, child processes of the ckpd
program) or a list of cases (dicts or files, run here one after another); the table back."""
from __future__ import annotations

import csv
import os
import re
import time
from typing import Any, Dict, Iterable, List, Mapping, Optional, Sequence, Union

import numpy as np

from . import _ckpd

Cell = Union[str, int, float, bool, None]
"""A table cell: a number (int or float), a bool, a string, or None where the CSV cell is empty."""

# Columns that hold text whatever it looks like (a hash or a description may be all digits).
_TEXT_COLUMNS = frozenset({"description", "hash", "folder", "status", "message"})
_INTEGER = re.compile(r"[+-]?[0-9]+")
_FLOAT = re.compile(r"[+-]?([0-9]+\.?[0-9]*|\.[0-9]+)([eE][+-]?[0-9]+)?|[+-]?(nan|inf|infinity)",
                    re.IGNORECASE)


def _cell(column: str, text: str) -> Cell:
    """A CSV cell as its type: '' -> None, integers -> int, other numbers -> float,
    true/false -> bool, anything else (and every cell of a text column) -> str."""
    if column in _TEXT_COLUMNS:
        return text
    if text == "":
        return None
    if text in ("true", "false"):
        return text == "true"
    if _INTEGER.fullmatch(text):
        return int(text)
    if _FLOAT.fullmatch(text):
        return float(text)
    return text


def _program() -> str:
    program = os.environ.get("CKPD_PROGRAM")
    if program:
        return program
    from ._program import PROGRAM

    return PROGRAM


class SweepTable:
    """A sweep's table, as its CSV file (sweep.csv, cases.csv) holds it.

    rows: one dict per run, column name -> typed cell: int or float for numbers, bool for
        true/false, None for an empty cell, str otherwise (the columns description, hash,
        folder, status and message are always str). Units are those of the case keys and
        summary.json paths the columns name (SI).
    header: the column names, in order.
    path: the CSV file.
    exit_status: the sweep's exit status (0 all runs completed, 4 some failed; 0 for run_cases).
    table["name"] (or column("name")): a column as a numpy array.
    """

    def __init__(self, path: str, header: List[str], rows: List[Dict[str, Cell]],
                 exit_status: int = 0) -> None:
        """A table of `rows` (dicts of typed cells) with columns `header`, as the CSV file
        `path` holds it; SweepTable.read(path) reads one."""
        self.path = path
        self.header = header
        self.rows = rows
        self.exit_status = exit_status

    @classmethod
    def read(cls, path: Union[str, "os.PathLike[str]"], exit_status: int = 0) -> "SweepTable":
        """Reads a sweep table from its CSV file (cells typed as in `rows`)."""
        path = os.fspath(path)
        with open(path, newline="") as f:
            reader = csv.DictReader(f)
            rows: List[Dict[str, Cell]] = [{k: _cell(k, v) for k, v in r.items()} for r in reader]
            header = list(reader.fieldnames or [])
        return cls(path, header, rows, exit_status)

    def column(self, name: str) -> np.ndarray:
        """The column `name` as an array: int64 when every cell is an integer, float64 when
        every cell is a number or empty (empty: nan), bool when every cell is a bool, else an
        object array of the cells. KeyError names the columns there are."""
        if name not in self.header:
            raise KeyError(f"{self.path}: no column {name!r} ({', '.join(self.header)})")
        cells = [r.get(name) for r in self.rows]
        if cells and all(isinstance(c, bool) for c in cells):
            return np.array(cells, dtype=bool)
        numbers = [c for c in cells if c is not None]
        if all(isinstance(c, (int, float)) and not isinstance(c, bool) for c in numbers):
            if len(numbers) == len(cells) and all(isinstance(c, int) for c in numbers):
                return np.array(cells, dtype=np.int64)
            if numbers:
                return np.array([np.nan if c is None else c for c in cells], dtype=float)
        return np.array(cells, dtype=object)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.column(name)

    def __len__(self) -> int:
        return len(self.rows)

    @property
    def completed(self) -> bool:
        """True when every run's status is 'completed'."""
        return all(r.get("status") == "completed" for r in self.rows)

    def __repr__(self) -> str:
        return (f"<ckpd.SweepTable {self.path}: {len(self.rows)} runs, "
                f"columns {', '.join(self.header)}>")


def run_sweep(file: Union[str, "os.PathLike[str]"], out: Union[str, "os.PathLike[str]", None] = None,
              jobs: int = 0, threads_per_run: int = 0, progress: bool = False) -> SweepTable:
    """Runs a sweep file as `ckpd sweep FILE --out OUT` does and returns its sweep.csv.

    out: the sweep's folder (default runs/<file name>). jobs: runs at a time (0: hardware
    threads / threads per run); threads_per_run: OpenMP threads of each run (0: hardware
    threads / jobs); each 0 to 4096. progress: print what the runner prints (a line per run);
    False: only errors. Bad sweep files raise SweepError (CaseError for the base case); failed
    runs are rows with status 'failed' (and exit_status 4)."""
    file = os.fspath(file)
    if out is None:
        out = os.path.join("runs", os.path.splitext(os.path.basename(file))[0])
    out = os.fspath(out)
    status = _ckpd._run_sweep_file(file, out, _program(), jobs, threads_per_run, not progress)
    return SweepTable.read(os.path.join(out, "sweep.csv"), status)


def run_cases(cases: Iterable[Union[Mapping[str, Any], str, "os.PathLike[str]"]],
              out: Union[str, "os.PathLike[str]"], metrics: Optional[Mapping[str, str]] = None,
              overrides: Union[Mapping[str, Any], Sequence[str], None] = None, threads: int = 0,
              progress: bool = False) -> SweepTable:
    """Runs each case (a dict or a case file) in this process, into OUT/NNNN, and returns the
    table (also written to OUT/cases.csv, after each case).

    Columns: index, folder, status, message, one per metric (name -> path into summary.json,
    as in sweep files) and wall_seconds (s). overrides: applied to every case (as in
    Simulation); threads: OpenMP threads (0: all cores). progress: a line per case and each
    run's progress line. A case that is rejected or goes unstable is a row with status
    failed/unstable; the others go on."""
    out = os.fspath(out)
    os.makedirs(out, exist_ok=True)
    metrics = dict(metrics or {})
    header = ["index", "folder", "status", "message", *metrics, "wall_seconds"]
    rows: List[Dict[str, Cell]] = []
    path = os.path.join(out, "cases.csv")
    for index, case in enumerate(cases):
        folder = os.path.join(out, f"{index:04d}")
        row: Dict[str, Cell] = {"index": index, "folder": folder, "message": ""}
        start = time.perf_counter()
        if progress:
            print(f"case {index}: {folder}", flush=True)
        try:
            sim = _ckpd.Simulation(case, overrides=overrides, out=folder, threads=threads,
                                   progress=progress)
            sim.run()
            row["status"] = sim.status
        except _ckpd.CaseError as e:
            row["status"], row["message"] = "failed", str(e)
        except _ckpd.InstabilityError as e:
            row["status"], row["message"] = "unstable", str(e)
        seconds = time.perf_counter() - start
        row["wall_seconds"] = seconds
        summary = os.path.join(folder, "summary.json")
        text = None
        if os.path.exists(summary):
            with open(summary) as f:
                text = f.read()
        for name, where in metrics.items():
            row[name] = _cell(name, _ckpd._summary_value(text, where) if text else "")
        rows.append(row)
        if progress:
            print(f"case {index}: {row['status']} in {seconds:.3g} s", flush=True)
        _write(SweepTable(path, header, rows))
    return SweepTable(path, header, rows)


def _write(table: SweepTable) -> None:
    temp = table.path + ".tmp"
    with open(temp, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=table.header)
        writer.writeheader()
        writer.writerows({k: _text(v) for k, v in r.items()} for r in table.rows)
    os.replace(temp, table.path)


def _text(cell: Cell) -> str:
    """A cell as the CSV writes it (the sweep runner's spelling: true/false, '' for None)."""
    if cell is None:
        return ""
    if isinstance(cell, bool):
        return "true" if cell else "false"
    if isinstance(cell, float):
        return repr(cell)
    return str(cell)
