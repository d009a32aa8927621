"""Reading a run's output folder (history.csv, summary.json, fields/frame_*.h5) into numpy."""
import csv
import glob
import json
import os

import numpy as np


class Run:
    """The results in one output folder of `ckpd run` or of a Simulation with `out=`.

    history: dict column -> array (step, time, kinetic, strain, contact, external_work,
        dissipated, balance_error, broken_bonds, max_damage, inverted)
    summary: the summary.json object (None while the run has not ended)
    times, steps: of the field frames, in order
    bodies: body names as in the frames (else the summary)
    field(body, name): that field in every frame, stacked: (frames, points[, dim])
    frame(k): {body: {field: array}} of frame k
    """

    def __init__(self, path):
        self.path = os.fspath(path)
        if not os.path.isdir(self.path):
            raise FileNotFoundError(f"{self.path}: no such run folder")
        self.history = self._read_history()
        summary = os.path.join(self.path, "summary.json")
        self.summary = None
        if os.path.exists(summary):
            with open(summary) as f:
                self.summary = json.load(f)
        self.frame_files = sorted(glob.glob(os.path.join(self.path, "fields", "frame_*.h5")))
        self.times = np.empty(len(self.frame_files))
        self.steps = np.empty(len(self.frame_files), dtype=np.int64)
        self._groups = {}  # body name -> group name in the frames
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
        if self._groups:
            self.bodies = list(self._groups)
        elif self.summary:
            self.bodies = [b["name"] for b in self.summary.get("bodies", [])]
        else:
            self.bodies = []

    def _read_history(self):
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

    def fields(self, body):
        """The field names stored for `body` (in the first frame)."""
        import h5py

        with h5py.File(self.frame_files[0], "r") as f:
            return list(f[self._group(body)])

    def _group(self, body):
        if body not in self._groups:
            raise KeyError(f"{self.path}: no body {body!r} in the field frames ({', '.join(self._groups)})")
        return self._groups[body]

    def field(self, body, name):
        """`name` of `body` in every frame, as one array (frames, points[, dim])."""
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

    def frame(self, k):
        """Frame k: {body: {field: array}}."""
        import h5py

        out = {}
        with h5py.File(self.frame_files[k], "r") as f:
            for body, group in self._groups.items():
                out[body] = {name: f[group][name][...] for name in f[group]}
        return out

    def __repr__(self):
        status = self.summary["status"] if self.summary else "no summary"
        return f"<ckpd.Run {self.path}: {len(self.history.get('step', []))} history rows, {len(self.frame_files)} frames, {status}>"


def open_run(path):
    """Reads the output folder of a run (see Run)."""
    return Run(path)
