"""The field frames and checkpoint of ckpd runs of one case made at different rank counts
(tests/mpi/, issue 14), compared: the files the ranks of a distributed run write together must be
those one process writes. Used by compare_runs.py --files.

compare(REFERENCE_DIR, OTHER_DIR, tolerance, derived_tolerance): for every frame file of REFERENCE and its checkpoint.h5 (if it wrote one): OTHER has the same file with the same
datasets of the same shapes and number types; integer datasets (connectivity, point and body ids,
bond flags, triangles) equal; each floating-point dataset within the tolerance relative to its
largest magnitude, with NaN at the same places (the fields taken from differences of positions
over a family, DERIVED, within --derived-tolerance: they amplify the positions' round-off by the
horizon over the displacement); the same attributes (numbers within the tolerance relative to the
largest number attribute of the same object: an energy near zero is round-off of the others; the
content hash is left out, it hashes those round-off bits). fields.xdmf must be the same text. Returns the mismatches found.
"""
import os

import h5py
import numpy as np

DERIVED = ("deformation_gradient", "green_lagrange_strain", "dilatation", "stress")


def datasets(f):
    out = {}
    f.visititems(lambda name, o: out.__setitem__(name, o) if isinstance(o, h5py.Dataset) else None)
    return out


def attributes(f):
    out = {"/": dict(f.attrs)}
    f.visititems(lambda name, o: out.__setitem__(name, dict(o.attrs)))
    return out


def compare_file(ref, other, tol, derived_tol):
    problems, worst = [], {}
    with h5py.File(ref, "r") as a, h5py.File(other, "r") as b:
        da, db = datasets(a), datasets(b)
        if da.keys() != db.keys():
            return [f"datasets differ: {sorted(set(da) ^ set(db))}"], worst
        for name, x in da.items():
            x, y = x[...], db[name][...]
            if x.shape != y.shape or x.dtype != y.dtype:
                problems.append(f"{name}: {x.shape} {x.dtype} vs {y.shape} {y.dtype}")
                continue
            if x.dtype.kind in "iub":
                if not np.array_equal(x, y):
                    problems.append(f"{name}: {int(np.sum(x != y))} values differ")
                continue
            finite = np.isfinite(x)
            if not np.array_equal(finite, np.isfinite(y)):
                problems.append(f"{name}: not finite at other places")
                continue
            if not finite.any():
                continue
            scale = max(float(np.max(np.abs(x[finite]))), 1e-300)
            err = float(np.max(np.abs(x[finite] - y[finite]))) / scale
            field = name.split("/")[-1]
            worst[field] = max(worst.get(field, 0.0), err)
            if err > (derived_tol if field in DERIVED else tol):
                problems.append(f"{name}: relative difference {err:.3g}")
        aa, ab = attributes(a), attributes(b)
        for obj, attrs in aa.items():
            numbers = [abs(u) for u in attrs.values() if isinstance(u, (float, np.floating))]
            scale = max(numbers + [1e-300])
            for key, u in attrs.items():
                if key == "content_hash":
                    continue
                v = ab.get(obj, {}).get(key)
                if isinstance(u, (float, np.floating)):
                    ok = v is not None and abs(u - v) <= tol * scale
                else:
                    ok = str(u) == str(v)
                if not ok:
                    problems.append(f"attribute {obj} {key}: {u} vs {v}")
    return problems, worst


def compare(ref, other, tol, derived_tol):
    problems, worst = [], {}
    frames = sorted(n for n in os.listdir(os.path.join(ref, "fields")) if n.endswith(".h5"))
    others = sorted(n for n in os.listdir(os.path.join(other, "fields")) if n.endswith(".h5"))
    if frames != others:
        problems.append(f"frames: {len(frames)} vs {len(others)}")
    files = [os.path.join("fields", n) for n in frames if n in others]
    if os.path.exists(os.path.join(ref, "checkpoint.h5")):
        files.append("checkpoint.h5")
    for name in files:
        found, w = compare_file(os.path.join(ref, name), os.path.join(other, name), tol,
                                derived_tol)
        problems += [f"{name}: {p}" for p in found]
        for k, v in w.items():
            worst[k] = max(worst.get(k, 0.0), v)
    with open(os.path.join(ref, "fields.xdmf")) as a, open(os.path.join(other, "fields.xdmf")) as b:
        if a.read() != b.read():
            problems.append("fields.xdmf differs")
    print(f"  {len(files)} files; largest relative differences: " +
          ", ".join(f"{k} {v:.2g}" for k, v in sorted(worst.items())))
    return problems
