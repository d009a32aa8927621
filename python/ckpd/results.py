"""Reading a run's output folder (history.csv, summary.json, fields/frame_*.h5) into numpy."""
from __future__ import annotations

import csv
import glob
import json
import os
from typing import Any, Dict, List, Optional, Union

import numpy as np


class Run:
    """The results in one output folder of `ckpd run` or of a Simulation with `out=`.

    path: the folder (str).
    history: dict column -> array, one entry per history row: step, time (s), kinetic,
        strain, contact, external_work, dissipated (J; J/m in 2D), balance_error, broken_bonds,
        max_damage, inverted, and the other columns the case's history has.
    summary: the summary.json object (a dict; None while the run has not ended).
    frame_files: the field frames' files, in order.
    times (s), steps: of the field frames, in order (numpy arrays).
    bodies: body names as in the frames (else the summary).
    Fields are in SI units as the frames hold them (docs: the output's field list).
    """

    def __init__(self, path: Union[str, "os.PathLike[str]"]) -> None:
        """Reads the run folder `path` (FileNotFoundError when there is none); open_run(path)
        is the same."""
        self.path: str = os.fspath(path)
        if not os.path.isdir(self.path):
            raise FileNotFoundError(f"{self.path}: no such run folder")
        self.history: Dict[str, np.ndarray] = self._read_history()
        summary = os.path.join(self.path, "summary.json")
        self.summary: Optional[Dict[str, Any]] = None
        if os.path.exists(summary):
            with open(summary) as f:
                self.summary = json.load(f)
        self.frame_files: List[str] = sorted(glob.glob(os.path.join(self.path, "fields", "frame_*.h5")))
        self.times: np.ndarray = np.empty(len(self.frame_files))
        self.steps: np.ndarray = np.empty(len(self.frame_files), dtype=np.int64)
        self._groups: Dict[str, str] = {}  # body name -> group name in the frames
        if self.frame_files:
            import h5py

            for k, name in enumerate(self.frame_files):
                with h5py.File(name, "r") as f:
                    self.times[k] = f.attrs["time"]
                    self.steps[k] = f.attrs["step"]
                    if k == 0:
                        for group in f:
                            body = f[group].attrs["name"]
                            if isinstance(body, bytes):
                                body = body.decode()
                            self._groups[str(body)] = group
        self.bodies: List[str]
        if self._groups:
            self.bodies = list(self._groups)
        elif self.summary:
            self.bodies = [b["name"] for b in self.summary.get("bodies", [])]
        else:
            self.bodies = []

    def _read_history(self) -> Dict[str, np.ndarray]:
        path = os.path.join(self.path, "history.csv")
        if not os.path.exists(path):
            return {}
        with open(path, newline="") as f:
            rows = list(csv.reader(f))
        if not rows:
            return {}
        header, data = rows[0], [r for r in rows[1:] if len(r) == len(rows[0])]
        out = {}
        for c, name in enumerate(header):
            values = [r[c] for r in data]
            integer = name in ("step", "broken_bonds", "inverted")
            out[name] = np.array(values, dtype=np.int64 if integer else float)
        return out

    def fields(self, body: str) -> List[str]:
        """The field names stored for `body` (in the first frame)."""
        import h5py

        with h5py.File(self.frame_files[0], "r") as f:
            return list(f[self._group(body)])

    def _group(self, body: str) -> str:
        if body not in self._groups:
            raise KeyError(f"{self.path}: no body {body!r} in the field frames ({', '.join(self._groups)})")
        return self._groups[body]

    def field(self, body: str, name: str) -> Union[np.ndarray, List[np.ndarray]]:
        """`name` of `body` in every frame, as one array (frames, points[, dim]); a list of
        per-frame arrays when the point count differs between frames."""
        import h5py

        if not self.frame_files:
            raise ValueError(f"{self.path}: the run wrote no field frames")
        group = self._group(body)
        arrays = []
        for file in self.frame_files:
            with h5py.File(file, "r") as f:
                if name not in f[group]:
                    raise KeyError(f"{file}: body {body!r} has no field {name!r} ({', '.join(f[group])})")
                arrays.append(f[group][name][...])
        try:
            return np.stack(arrays)
        except ValueError:  # point counts differ between frames
            return arrays

    def frame(self, k: int) -> Dict[str, Dict[str, np.ndarray]]:
        """Frame k (from 0, in time order): {body: {field: array}}."""
        import h5py

        out = {}
        with h5py.File(self.frame_files[k], "r") as f:
            for body, group in self._groups.items():
                out[body] = {name: f[group][name][...] for name in f[group]}
        return out

    def __repr__(self) -> str:
        status = self.summary["status"] if self.summary else "no summary"
        return f"<ckpd.Run {self.path}: {len(self.history.get('step', []))} history rows, {len(self.frame_files)} frames, {status}>"


def open_run(path: Union[str, "os.PathLike[str]"]) -> Run:
    """Reads the output folder of a run (see Run); FileNotFoundError when there is none."""
    return Run(path)
