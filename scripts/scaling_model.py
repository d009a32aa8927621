#!/usr/bin/env python3
"""The on-paper scaling model of docs/SCALING.md (issue 14): time per step and memory per rank of
a lattice box (Kalthoff-Winkler's plate) at many MPI ranks, for ckpd's replicated state and for
the planned halo exchange.

  scaling_model.py decompose --scale S --ranks N       per-rank points, work and halo
  scaling_model.py table [--scales 8 64] [--ranks ...]  the model's tables (markdown)
  scaling_model.py check REFERENCE.txt [--ckpd BIN]     the decomposition against `ckpd check`

The decomposition is src/engine/decomposition.cpp redone on the lattice: recursive coordinate
bisection of the points (cut perpendicular to the longest side of the group's box, where the
work on the two sides is in the ratio of their ranks, floor(N/2) ranks on the low side, ties in
a coordinate broken by point index), each point weighted by its interaction work (23 flops per
bond share, 70 per triangle share, 26 per tetrahedron share: point_work), and a rank's halo is
every point of another rank in the family of one of its points. The lattice is sampled as
src/geometry/lattice.cpp samples a box (cell-centred, x fastest), families are the lattice
offsets within the horizon, and a point's two- and three-neighbour counts are those of the
ckpd census (pairwise-adjacent, non-degenerate sets), computed once per distinct truncation of
the family by the box faces. Three-dimensional bodies only (their sets are bonds and
tetrahedra; triangles, which only 2D bodies have, are counted but not tested). `check` compares all of it with `ckpd check --ranks N` output,
number for number, so a change of either side cannot go unnoticed (ctest runs it).
"""
import argparse
import math
import os
import re
import subprocess
import sys
import tempfile

import numpy as np

# decomposition.cpp: operation counts per bond, triangle and tetrahedron.
BOND_OPS, TRIANGLE_OPS, TETRAHEDRON_OPS = 23.0, 70.0, 26.0
HORIZON_TOLERANCE = 1e-12  # bodies/bond_family.hpp kHorizonTolerance

# Kalthoff-Winkler's plate (cases/kalthoff_winkler.yaml) at 1x: 88 x 177 x 8 points.
KW_LO = (0.0, -0.0995625, -0.0045)
KW_HI = (0.099, 0.0995625, 0.0045)
KW_SPACING = 0.001125
KW_RATIO = 3.015  # horizon_ratio: the horizon is 3.015 spacings at every resolution
# Bytes a ghost costs a step on distributed memory: 6 doubles of state in, 3 of force back
# (src/engine/distribution.hpp halo_bytes_per_step).
HALO_BYTES = 72.0


_CENSUS = {}  # census of one family cut, by (horizon^2, sets counted, canonical cut)


class Lattice:
    """A cell-centred box lattice with cubic families of `ratio` spacings (one body)."""

    def __init__(self, lo, hi, spacing, ratio, triangles=False, tetrahedra=True):
        lo, hi = np.asarray(lo, float), np.asarray(hi, float)
        self.n = tuple(max(1, int(round((hi[d] - lo[d]) / spacing))) for d in range(3))
        centre = (lo + hi) / 2
        # One coordinate per index along each axis, as lattice.cpp computes it.
        self.axis = [centre[d] + (np.arange(self.n[d], dtype=float) - (self.n[d] - 1) / 2) * spacing
                     for d in range(3)]
        self.points = self.n[0] * self.n[1] * self.n[2]
        limit2 = (ratio * (1 + HORIZON_TOLERANCE)) ** 2
        reach = int(math.ceil(ratio))
        r = range(-reach, reach + 1)
        self.offsets = np.array([(x, y, z) for z in r for y in r for x in r
                                 if 0 < x * x + y * y + z * z <= limit2], dtype=np.int64)
        self.reach = reach
        self.limit2 = limit2
        self.triangles, self.tetrahedra = triangles, tetrahedra

    def index(self):
        """(i, j, k) of every point in ckpd's order (x fastest, then y, then z)."""
        k, j, i = np.meshgrid(*(np.arange(m) for m in self.n[::-1]), indexing="ij")
        return i.ravel(), j.ravel(), k.ravel()

    def census(self, family):
        """Family size and ordered non-degenerate pair and triple counts of one family."""
        f = family
        d = f[:, None, :] - f[None, :, :]
        adjacent = (d * d).sum(-1) <= self.limit2
        upper = np.triu(np.ones((len(f), len(f)), bool), 1)
        pair = adjacent & upper
        cross = np.cross(f[:, None, :], f[None, :, :])
        n2 = 2 * int((pair & (np.abs(cross).sum(-1) > 0)).sum()) if self.triangles else 0
        n3 = 0
        if self.tetrahedra:
            det = np.einsum("abk,ck->abc", cross, f)
            triple = pair[:, :, None] & pair[None, :, :] & pair[:, None, :]
            n3 = 6 * int((triple & (det != 0)).sum())
        return len(f), n2, n3

    def work(self):
        """point_work of every point, and the totals of bonds, N2 and N3 (ordered)."""
        idx = self.index()
        # A family is the full stencil cut by the box: per axis, how far it may reach down and up.
        keys = np.stack([np.minimum(idx[d], self.reach) for d in range(3)] +
                        [np.minimum(self.n[d] - 1 - idx[d], self.reach) for d in range(3)], axis=1)
        classes, inverse = np.unique(keys, axis=0, return_inverse=True)
        w = np.empty(len(classes))
        counts = np.empty((len(classes), 3), dtype=np.int64)
        for c, key in enumerate(classes):
            # The stencil and the counts are unchanged by reflecting or permuting the axes: one
            # census per canonical cut (20 of them for a large box, not 343).
            canonical = tuple(sorted(tuple(sorted((int(key[d]), int(key[3 + d]))))
                                     for d in range(3)))
            memo = (self.limit2, self.triangles, self.tetrahedra, canonical)
            if memo not in _CENSUS:
                lo = np.array([a for a, _ in canonical])
                hi = np.array([b for _, b in canonical])
                o = self.offsets
                _CENSUS[memo] = self.census(o[np.all((o >= -lo) & (o <= hi), axis=1)])
            n1, n2, n3 = _CENSUS[memo]
            counts[c] = (n1, n2, n3)
            # point_work, operation for operation.
            w[c] = BOND_OPS * (n1 / 2) + TRIANGLE_OPS * (n2 / 2.0 / 3.0) + \
                TETRAHEDRON_OPS * (n3 / 6.0 / 4.0)
        inverse = inverse.ravel()
        totals = counts[inverse].sum(axis=0)
        return w[inverse], {"bonds": int(totals[0]) // 2, "n2": int(totals[1]), "n3": int(totals[2])}


def rcb(coords, work, ranks):
    """decomposition.cpp's bisect: owner rank of every point. coords: (P, 3) floats."""
    owner = np.empty(len(work), dtype=np.int32)
    stack = [(np.arange(len(work)), 0, ranks)]
    while stack:
        items, first, count = stack.pop()
        if count == 1:
            owner[items] = first
            continue
        x = coords[items]
        axis = int(np.argmax(x.max(axis=0) - x.min(axis=0)))  # the first longest, as Eigen's
        items = items[np.lexsort((items, x[:, axis]))]
        w = work[items]
        prefix = np.cumsum(w)  # sequential, as the C++ loop adds
        left = count // 2
        target = prefix[-1] * left / count
        min_cut, max_cut = left, len(items) - (count - left)
        # Cuts min_cut .. max_cut; the first of the nearest (the C++ keeps a strictly better one).
        miss = np.abs(prefix[min_cut - 1:max_cut] - target)
        cut = min_cut + int(np.argmin(miss))
        stack.append((items[cut:], first + left, count - left))
        stack.append((items[:cut], first, left))
    return owner


def halo(lattice, owner, ranks, ranks_per_node=None, chunk=200_000):
    """Per rank: halo points, the halo points owned off its node, and its neighbour ranks."""
    nx, ny, nz = lattice.n
    h = lattice.reach
    grid = np.full((nz + 2 * h, ny + 2 * h, nx + 2 * h), -1, dtype=np.int32)
    grid[h:h + nz, h:h + ny, h:h + nx] = owner.reshape(nz, ny, nx)
    flat = grid.ravel()
    strides = np.array([1, nx + 2 * h, (nx + 2 * h) * (ny + 2 * h)], dtype=np.int64)
    shift = lattice.offsets @ strides
    i, j, k = lattice.index()
    base = (i + h) + (j + h) * strides[1] + (k + h) * strides[2]
    ghosts = np.zeros(ranks, dtype=np.int64)
    off_node = np.zeros(ranks, dtype=np.int64)
    neighbours = np.zeros(ranks, dtype=np.int64)
    pairs = set() if ranks <= 4096 else None
    for s in range(0, len(base), chunk):
        b = base[s:s + chunk]
        mine = flat[b]
        # The ranks holding point j's family members: each, other than j's owner, has j as a ghost
        # (families are symmetric: j in i's family iff i in j's).
        around = np.sort(flat[b[:, None] + shift[None, :]], axis=1)
        first = np.ones_like(around, dtype=bool)
        first[:, 1:] = around[:, 1:] != around[:, :-1]
        hit = first & (around >= 0) & (around != mine[:, None])
        r = around[hit]
        ghosts += np.bincount(r, minlength=ranks)
        if ranks_per_node:
            o = np.broadcast_to(mine[:, None], around.shape)[hit]
            off_node += np.bincount(r[(o // ranks_per_node) != (r // ranks_per_node)],
                                    minlength=ranks)
        if pairs is not None:
            o = np.broadcast_to(mine[:, None], around.shape)[hit]
            pairs.update(np.unique(r.astype(np.int64) * ranks + o).tolist())
    if pairs is not None:
        for p in pairs:
            neighbours[p // ranks] += 1
    return ghosts, off_node, neighbours


def kw_lattice(scale):
    """Kalthoff-Winkler's plate at `scale` times the paper's point count (1, 8, 64: the spacing
    halved per factor 8; the horizon stays 3.015 spacings)."""
    factor = round(scale ** (1 / 3))
    if factor ** 3 != scale:
        raise ValueError(f"scale {scale} is not a cube")
    return Lattice(KW_LO, KW_HI, KW_SPACING / factor, KW_RATIO)


class Decomposed:
    def __init__(self, lattice, ranks, ranks_per_node=None, work=None):
        self.lattice = lattice
        self.ranks = ranks
        if work is None:
            work, self.totals = lattice.work()
        self.point_work = work
        i, j, k = lattice.index()
        coords = np.stack([lattice.axis[0][i], lattice.axis[1][j], lattice.axis[2][k]], axis=1)
        self.owner = rcb(coords, work, ranks)
        self.points = np.bincount(self.owner, minlength=ranks)
        self.work = np.bincount(self.owner, weights=work, minlength=ranks)
        self.ghosts, self.off_node, self.neighbours = halo(lattice, self.owner, ranks,
                                                           ranks_per_node)

    def imbalance(self):
        return float(self.work.max() * self.ranks / self.work.sum())


# ---- `ckpd check --ranks N` output -------------------------------------------------------------

RANK_LINE = re.compile(r"^\s*rank (\d+): (\d+) points, ([\d.]+) % of the work, (\d+) halo points")
HEAD_LINE = re.compile(r"^decomposition over (\d+) ranks .*: imbalance ([\d.e+-]+) .*, (\d+) halo")
BODY_LINE = re.compile(r"(\d+) points, (\d+) bonds, N2 (\d+), N3 (\d+)")


def parse_check(text):
    """{ranks: {"points": [...], "work_percent": [...], "ghosts": [...]}} and the body totals."""
    out, current, body = {}, None, None
    for line in text.splitlines():
        m = BODY_LINE.search(line)
        if m and body is None:
            body = {"points": int(m[1]), "bonds": int(m[2]), "n2": int(m[3]), "n3": int(m[4])}
        m = HEAD_LINE.match(line)
        if m:
            current = {"points": [], "work_percent": [], "ghosts": [], "imbalance": float(m[2])}
            out[int(m[1])] = current
            continue
        m = RANK_LINE.match(line)
        if m and current is not None:
            current["points"].append(int(m[2]))
            current["work_percent"].append(float(m[3]))
            current["ghosts"].append(int(m[4]))
    return out, body


def compare(lattice, recorded, body, label):
    """Problems found comparing the model's decomposition with ckpd's numbers."""
    problems = []
    work, totals = lattice.work()
    if body is not None:
        for key in ("points", "bonds", "n2", "n3"):
            mine = lattice.points if key == "points" else totals[key]
            if mine != body[key]:
                problems.append(f"{label}: {key} {mine}, ckpd {body[key]}")
    for ranks, rec in sorted(recorded.items()):
        d = Decomposed(lattice, ranks, work=work)
        percent = [float(f"{100 * w / d.work.sum():.1f}") for w in d.work]
        same = (d.points.tolist() == rec["points"] and d.ghosts.tolist() == rec["ghosts"]
                and percent == rec["work_percent"])
        print(f"  {label}, {ranks} ranks: halo {int(d.ghosts.sum())} (ckpd "
              f"{sum(rec['ghosts'])}), imbalance {d.imbalance():.6g} (ckpd {rec['imbalance']:.6g})"
              f": {'same' if same else 'DIFFERENT'} per-rank points, work and halo")
        if not same:
            problems.append(f"{label}, {ranks} ranks: per-rank figures differ")
    return problems


SMALL_CASE = """materials:
  steel: {{density: 7850, youngs_modulus: 200e9, poisson_ratio: {nu}}}
bodies:
  - {{name: block, material: steel, spacing: 0.001, horizon_ratio: {ratio},
     geometry: {{type: box, min: [0, 0, 0], max: [{x}, {y}, {z}]}}}}
time: {{steps: 1}}
"""


def live_check(ckpd, problems):
    """Small blocks through the ckpd binary itself: a change to decomposition.cpp (or the
    census) that the recorded Kalthoff-Winkler numbers would not see yet shows here."""
    cases = [  # (points per axis, horizon ratio, Poisson ratio, rank counts)
        ((23, 14, 9), 3.015, 0.3, (2, 5, 7, 12)),   # tetrahedra, no triangles (as KW)
        ((17, 17, 6), 2.015, 0.25, (3, 4, 9)),      # bonds only; a tie in the longest side
        ((9, 30, 12), 2.515, 0.2, (6, 10)),         # c3 < 0; the cuts across y, then z
    ]
    with tempfile.TemporaryDirectory() as tmp:
        for n, ratio, nu, rank_counts in cases:
            path = os.path.join(tmp, "block.yaml")
            with open(path, "w") as f:
                f.write(SMALL_CASE.format(nu=nu, ratio=ratio, x=n[0] * 1e-3, y=n[1] * 1e-3,
                                          z=n[2] * 1e-3))
            recorded, body = {}, None
            for ranks in rank_counts:
                run = subprocess.run([ckpd, "check", path, "--steps", "0", "--ranks", str(ranks),
                                      "--threads", "1"], capture_output=True, text=True)
                if run.returncode != 0:
                    problems.append(f"ckpd check failed: {run.stderr.strip()}")
                    return
                got, body = parse_check(run.stdout)
                recorded.update(got)
            lattice = Lattice((0, 0, 0), (n[0] * 1e-3, n[1] * 1e-3, n[2] * 1e-3), 1e-3, ratio,
                              triangles=body["n2"] > 0, tetrahedra=body["n3"] > 0)
            problems += compare(lattice, recorded, body, f"block {n[0]}x{n[1]}x{n[2]} m={ratio}")


# ---- The time and memory model -----------------------------------------------------------------

class Machine:
    """The figures the model assumes or takes from measurements (docs/SCALING.md discusses each)."""
    # Assumed cluster: nodes of 2 x 32 cores, one single-threaded rank per core.
    ranks_per_node = 64
    node_memory_gb = 256.0
    link_gb_s = 25.0              # InfiniBand HDR 200 Gb/s per node, each direction
    latency_s = 2e-6              # per message between nodes (MPI over HDR: 1-2 us)
    core_copy_gb_s = 3.0          # memory bandwidth one core gets with all 64 busy (~200 GB/s/node)
    # Measured on this machine (docs/PERFORMANCE.md "MPI", quiet, Release, CKPD_ARCH=native):
    # Kalthoff-Winkler 1x, 1 rank x 1 thread, lattice-stencil kernel.
    kw_seconds_per_step = 6.76
    kw_seconds_per_step_2_ranks = 3.31  # 2 ranks x 1 thread, the same runs: the model's check
    # The part of that step every rank repeats today (bond failure over all bonds, integration):
    # 1.2 % of the profile's samples in fail_overstretched_bonds, the rest under 0.3 %
    # (perf record on `ckpd check ... --steps 2 --threads 1`, docs/SCALING.md).
    replicated_fraction = 0.015
    # Peak RSS of one process per point: 1x 133 MB / 124,608, 8x 963 MB / 996,864 (ckpd check).
    bytes_per_point = 966.0
    rank_overhead_mb = 12.0       # MPI library per rank (151 MB at 2 ranks: 133 + 12 + buffers)


def calibration(machine):
    """Seconds per unit of point_work and seconds of replicated work per point, from 1x."""
    lattice = kw_lattice(1)
    work, _ = lattice.work()
    total = machine.kw_seconds_per_step
    per_work = (1 - machine.replicated_fraction) * total / float(work.sum())
    redundant = machine.replicated_fraction * total / lattice.points
    return per_work, redundant


def replicated_time(machine, points, work_max, ranks, per_work, redundant):
    """Today's scheme: (compute, repeated work, messages and the rank-order sum) in seconds."""
    m = machine
    buffer = 24.0 * points  # a rank's partial force buffer (32 bytes a point at energy steps)
    copy = m.core_copy_gb_s * 1e9
    # Ring allgather: N - 1 steps, each rank receives and copies (N - 1) buffers (the node's one
    # link in the ring carries as much, at 25 GB/s it is not the bound); then the sum reads N.
    messages = (ranks - 1) * m.latency_s + (ranks - 1) * buffer / min(copy, m.link_gb_s * 1e9)
    messages += ranks * buffer / copy if ranks > 1 else 0.0
    return work_max * per_work, redundant * points, messages if ranks > 1 else 0.0


def replicated_memory_gb(machine, points, ranks):
    """Whole scene per rank, plus the gather buffer of N partial buffers (32 bytes a point)."""
    m = machine
    gathered = 32.0 * points * ranks if ranks > 1 else 0.0
    return (m.bytes_per_point * points + gathered) / 1e9 + m.rank_overhead_mb / 1e3


def model(d, machine, per_work, redundant):
    """Time per step and memory per rank of one decomposition, for both schemes."""
    m = machine
    n, p = d.ranks, d.lattice.points
    ppn = min(m.ranks_per_node, n)
    nodes = math.ceil(n / ppn)
    copy = m.core_copy_gb_s * 1e9
    collectives = 2 * math.ceil(math.log2(n)) * m.latency_s  # stop flag, guards: two allreduces
    work_max = float(d.work.max())
    compute, repeated, messages = replicated_time(m, p, work_max, n, per_work, redundant)
    replicated = compute + repeated + messages + collectives
    # Halo exchange as src/engine/distribution.cpp sends it: the ghosts' displacements and
    # velocities in and the forces on them back (48 + 24 bytes a ghost: HALO_BYTES), two messages
    # per neighbour rank, packed and unpacked at the core's copy speed; the node's off-node halo
    # through its link. Bond failure and integration over owned + halo points.
    held = d.points + d.ghosts
    node_off = HALO_BYTES * np.bincount(np.arange(n) // ppn, weights=d.off_node).max()
    exchange = (2 * int(d.neighbours.max()) * m.latency_s
                + 2 * HALO_BYTES * float(d.ghosts.max()) / copy
                + (node_off / (m.link_gb_s * 1e9) if nodes > 1 else 0.0))
    halo_time = compute + redundant * float(held.max()) + exchange + collectives
    return {
        "nodes": nodes, "compute": compute, "replicated": replicated,
        "replicated_parts": (repeated, messages),
        "replicated_mem_gb": replicated_memory_gb(m, p, n),
        "halo": halo_time, "halo_exchange": exchange,
        "halo_mem_mb": (m.bytes_per_point * float(held.max())) / 1e6 + m.rank_overhead_mb,
        "halo_ratio": float((d.ghosts / d.points).max()),
        "neighbours_max": int(d.neighbours.max()), "imbalance": d.imbalance(),
    }


def crossover(machine, points, total_work, per_work, redundant):
    """Replicated state, perfectly balanced: the rank count of the shortest step, and the last
    rank count at >= 50 % parallel efficiency."""
    serial = sum(replicated_time(machine, points, total_work, 1, per_work, redundant))
    best, best_n, half = float("inf"), 1, 1
    for n in range(1, 4097):
        t = sum(replicated_time(machine, points, total_work / n, n, per_work, redundant))
        if t < best:
            best, best_n = t, n
        if serial / (n * t) >= 0.5:
            half = n
    return best_n, best, half


def model_check(machine):
    """The time model against the measurements it rests on: 1 rank gives the calibration step,
    2 ranks (one node) must come within 10 % of the measured 2-rank step."""
    per_work, redundant = calibration(machine)
    lattice = kw_lattice(1)
    work, _ = lattice.work()
    one = sum(replicated_time(machine, lattice.points, float(work.sum()), 1, per_work, redundant))
    two = model(Decomposed(lattice, 2, machine.ranks_per_node, work=work), machine, per_work,
                redundant)["replicated"]
    print(f"  model, Kalthoff-Winkler 1x: 1 rank {one:.3f} s (measured "
          f"{machine.kw_seconds_per_step}), 2 ranks {two:.3f} s (measured "
          f"{machine.kw_seconds_per_step_2_ranks})")
    problems = []
    if abs(one / machine.kw_seconds_per_step - 1) > 1e-9:
        problems.append(f"model: 1 rank gives {one} s, not the calibration's step")
    if abs(two / machine.kw_seconds_per_step_2_ranks - 1) > 0.10:
        problems.append(f"model: 2 ranks give {two:.3f} s, over 10 % from the measured step")
    return problems


def table(scales, rank_counts, machine):
    per_work, redundant = calibration(machine)

    def fits(gb_per_rank, ranks):
        node = gb_per_rank * min(ranks, machine.ranks_per_node)
        return "" if node <= machine.node_memory_gb else f" (node {node:,.0f} GB: does not fit)"

    print(f"calibration: {per_work * 1e9:.4f} ns per unit of point_work, "
          f"{redundant * 1e6:.3f} us of repeated work per point per step")
    for scale in scales:
        lattice = kw_lattice(scale)
        work, totals = lattice.work()
        total = float(work.sum())
        serial = total * per_work + redundant * lattice.points
        best_n, best_t, half = crossover(machine, lattice.points, total, per_work, redundant)
        print(f"\nKalthoff-Winkler {scale}x: {lattice.n[0]} x {lattice.n[1]} x {lattice.n[2]} = "
              f"{lattice.points:,} points, {totals['bonds']:,} bonds, N3 {totals['n3']:,}; "
              f"1 rank: {serial:.1f} s per step, {machine.bytes_per_point * lattice.points / 1e9:.2f}"
              f" GB. Replicated state: shortest step {best_t:.3f} s at {best_n} ranks, "
              f">= 50 % efficiency up to {half} ranks.\n")
        print("| ranks | nodes | points per rank | work imbalance | largest halo / owned | "
              "neighbour ranks (most) | compute s | replicated: s per step (repeated work, "
              "messages + sum) | speed-up | memory per rank, replicated | halo exchange: s per "
              "step (exchange ms) | speed-up | memory per rank, halo |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        for n in rank_counts:
            d = Decomposed(lattice, n, machine.ranks_per_node, work=work)
            r = model(d, machine, per_work, redundant)
            rep, msg = r["replicated_parts"]
            print(f"| {n} | {r['nodes']} | {lattice.points / n:,.0f} | {r['imbalance']:.4f} | "
                  f"{100 * r['halo_ratio']:.0f} % | {r['neighbours_max']} | {r['compute']:.3f} | "
                  f"{r['replicated']:.3f} ({rep:.3f}, {msg:.3f}) | "
                  f"{serial / r['replicated']:.0f} | {r['replicated_mem_gb']:.1f} GB"
                  f"{fits(r['replicated_mem_gb'], n)} | "
                  f"{r['halo']:.3f} ({r['halo_exchange'] * 1e3:.2f}) | {serial / r['halo']:.0f} | "
                  f"{r['halo_mem_mb']:.0f} MB |")
            sys.stdout.flush()


def main():
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    sub = p.add_subparsers(dest="command", required=True)
    d = sub.add_parser("decompose")
    d.add_argument("--scale", type=int, default=1)
    d.add_argument("--ranks", type=int, required=True)
    t = sub.add_parser("table")
    t.add_argument("--scales", type=int, nargs="+", default=[8, 64])
    t.add_argument("--ranks", type=int, nargs="+", default=[16, 32, 64, 128, 256, 512, 1024])
    c = sub.add_parser("check")
    c.add_argument("reference", nargs="+", help="saved `ckpd check --ranks N` outputs of "
                   "Kalthoff-Winkler; a file name's 'Nx' (N a cube) gives the scale (default 1x)")
    c.add_argument("--ckpd", help="also check small blocks through this ckpd binary")
    a = p.parse_args()
    if a.command == "decompose":
        dec = Decomposed(kw_lattice(a.scale), a.ranks, Machine.ranks_per_node)
        print(f"{a.ranks} ranks: imbalance {dec.imbalance():.6g}, {int(dec.ghosts.sum())} halo points")
        for r in range(a.ranks):
            print(f"  rank {r}: {dec.points[r]} points, {dec.ghosts[r]} halo points "
                  f"({dec.off_node[r]} off its node), {dec.neighbours[r]} neighbour ranks")
        return 0
    if a.command == "table":
        table(a.scales, a.ranks, Machine())
        return 0
    problems = []
    by_scale = {}
    for path in a.reference:
        m = re.search(r"(\d+)x", os.path.basename(path))
        scale = int(m[1]) if m else 1
        with open(path) as f:
            recorded, body = parse_check(f.read())
        if not recorded:
            problems.append(f"{path}: no decomposition found")
        entry = by_scale.setdefault(scale, [{}, body])
        entry[0].update(recorded)
        entry[1] = entry[1] or body
    for scale, (recorded, body) in sorted(by_scale.items()):
        problems += compare(kw_lattice(scale), recorded, body, f"Kalthoff-Winkler {scale}x")
    if a.ckpd:
        live_check(a.ckpd, problems)
    problems += model_check(Machine())
    for problem in problems:
        print("MISMATCH: " + problem)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
