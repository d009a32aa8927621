#!/usr/bin/python3
"""What returning to linear and a corotated screen would buy the far field (issue 20).

Reads an exact run's frames (fields damage and displacement) of a lattice body.

    scripts/far_field_screens.py RUN M T1,T2,...   (M: the horizon ratio; body_0 of the frames)

Per point and frame: s_vec = max_j |u^j - u^i| / L (the far field's screen), s_len = max_j
| |x^j - x^i| / L - 1 | (the bond stretch, a lower bound of any rotation-free strain), and
whether any family member (or i) has damage (D > 0; a superset of the rule's failed bonds among
the family). Exact-by-screen fractions per frame: sticky (the rule), non-sticky (returns), and
non-sticky with the stretch instead of the vector screen (an upper bound of corotation's gain).
"""
import glob
import math
import sys

import h5py
import numpy as np

run, m = sys.argv[1], float(sys.argv[2])
Ts = [float(t) for t in sys.argv[3].split(',')]
files = sorted(glob.glob(run + '/fields/frame_*.h5'))
with h5py.File(files[0], 'r') as h:
    X = h['body_0']['position'][:] - h['body_0']['displacement'][:]
dx = np.min(np.diff(np.unique(np.round(X[:, 0], 9))))
I = np.round((X - X.min(0)) / dx).astype(int)
shape = I.max(0) + 1
idx = -np.ones(shape, int); idx[I[:, 0], I[:, 1], I[:, 2]] = np.arange(len(X))
r = int(math.floor(m))
offs = [(a, b, c) for a in range(-r, r + 1) for b in range(-r, r + 1) for c in range(-r, r + 1)
        if 0 < a * a + b * b + c * c <= m * m]


def shifted(o):
    # neighbour index of every point at offset o, -1 where outside
    J = I + np.array(o)
    ok = np.all((J >= 0) & (J < shape), axis=1)
    nb = -np.ones(len(X), int); nb[ok] = idx[J[ok, 0], J[ok, 1], J[ok, 2]]
    return nb


nbs = [shifted(o) for o in offs]
Ls = [dx * math.sqrt(a * a + b * b + c * c) for (a, b, c) in offs]
sticky = {T: np.zeros(len(X), bool) for T in Ts}
print('time_us,' + ','.join(f'T{T}_sticky,T{T}_return,T{T}_stretch_return' for T in Ts) + ',damaged_family')
for f in files:
    with h5py.File(f, 'r') as h:
        g = h['body_0']; u = g['displacement'][:]; D = g['damage'][:]; t = h.attrs['time']
    svec = np.zeros(len(X)); slen = np.zeros(len(X)); dam = D > 0
    for nb, L in zip(nbs, Ls):
        ok = nb >= 0; j = nb[ok]
        d = u[j] - u[ok]
        svec[ok] = np.maximum(svec[ok], np.linalg.norm(d, axis=1) / L)
        l = np.linalg.norm(X[j] - X[ok] + d, axis=1)
        slen[ok] = np.maximum(slen[ok], np.abs(l / L - 1))
        dam[ok] |= D[j] > 0
    row = [f'{t * 1e6:.1f}']
    for T in Ts:
        now = dam | (svec >= T)
        sticky[T] |= now
        row += [f'{sticky[T].mean():.3f}', f'{now.mean():.3f}', f'{(dam | (slen >= T)).mean():.3f}']
    row.append(f'{dam.mean():.3f}')
    print(','.join(row), flush=True)
