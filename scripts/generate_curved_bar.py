#!/usr/bin/env python3
"""Writes the point cloud of the curved bar (seed 000 section 5, docs/THEORY.md section 8) as CSV.

The bar follows f(x) = cos(pi x / 2) for root points x in [-L/2, L/2], L = 1 m. Root points are
spaced evenly in arc length, about dx apart (the first and last lie on the ends x = -L/2 and
x = L/2). Through each root point, N_n points lie on the normal of the curve, dx apart, centred
on the curve: offsets t = (k + 1/2) dx - W/2, k = 0 .. N_n - 1, so the bar is W = N_n dx wide.
In 3D, N_n such layers are stacked along z at z = (k + 1/2) dx - W/2, i.e. inside [-W/2, W/2].

Normals: seed 000 eq. 5.1 writes the normal line through a root point with slope 1/f'(x_i); the
line perpendicular to the curve has slope -1/f'(x_i), and the pulse directions n_l, n_r of
eqs. 5.4-5.5 (the end tangents) are only perpendicular to the end layers with the latter. We
use the perpendicular normal (docs/THEORY.md: "points along normals").

Volumes come from the local spacing: a point at offset t from the curve, whose curvature is
kappa, has along-curve spacing ds (1 + kappa t) (the normal points away from the centre of
curvature: cos is concave), so its volume is ds (1 + kappa t) dx in 2D (an area) and
ds (1 + kappa t) dx dx in 3D. Every point, the end ones included, stands for a whole cell
centred on it (as a lattice sample does), so the bar reaches half a cell past the end layers.

    scripts/generate_curved_bar.py --dim 2 --points-per-normal 20 --out cases/data/curved_bar_2d.csv
    scripts/generate_curved_bar.py --dim 3 --points-per-normal 5 --out cases/data/curved_bar_3d.csv

It also prints the quantities the case file needs: dx, the end points, the pulse directions
n_l = (sin a, cos a), n_r = (-sin a, cos a) with a = atan(-1 / f'(L/2)), and half-spaces that
select exactly the end layers. Python 3 standard library only.
"""
import argparse
import math
import sys

LENGTH = 1.0  # m: root points x in [-L/2, L/2]
WIDTH = 0.0625  # m: W, the width along each normal


def f(x: float) -> float:
    return math.cos(math.pi * x / 2)


def df(x: float) -> float:
    return -math.pi / 2 * math.sin(math.pi * x / 2)


def d2f(x: float) -> float:
    return -((math.pi / 2) ** 2) * math.cos(math.pi * x / 2)


def arc_length(a: float, b: float, intervals: int = 2000) -> float:
    """Arc length of f from a to b (composite Simpson; the integrand is smooth)."""
    h = (b - a) / intervals
    total = 0.0
    for i in range(intervals + 1):
        w = 1 if i in (0, intervals) else (4 if i % 2 else 2)
        total += w * math.sqrt(1 + df(a + i * h) ** 2)
    return total * h / 3


def x_at_arc_length(s: float, x0: float) -> float:
    """The x whose arc length from x0 is s (bisection: arc length is monotonic in x)."""
    lo, hi = x0, x0 + s  # |dx| <= ds along any curve
    for _ in range(80):
        mid = (lo + hi) / 2
        if arc_length(x0, mid, 200) < s:
            lo = mid
        else:
            hi = mid
    return (lo + hi) / 2


def frame(x: float):
    """Unit tangent (towards +x), unit normal (away from the centre of curvature), curvature."""
    slope = df(x)
    norm = math.sqrt(1 + slope * slope)
    tangent = (1 / norm, slope / norm)
    normal = (-slope / norm, 1 / norm)
    kappa = -d2f(x) / norm**3  # > 0: the curve bends away from the normal
    return tangent, normal, kappa


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--dim", type=int, choices=(2, 3), required=True)
    parser.add_argument("--points-per-normal", type=int, required=True, help="N_n (dx = W / N_n)")
    parser.add_argument("--out", required=True, help="CSV file to write")
    args = parser.parse_args()

    n_n = args.points_per_normal
    if n_n < 1:
        parser.error("--points-per-normal must be at least 1")
    dx = WIDTH / n_n
    total = arc_length(-LENGTH / 2, LENGTH / 2)
    n_root = round(total / dx) + 1
    ds = total / (n_root - 1)
    # Root points evenly spaced in arc length; x from the arc length of the right half (symmetric).
    roots = []
    for i in range(n_root):
        s = i * ds - total / 2
        x = math.copysign(x_at_arc_length(abs(s), 0.0), s) if s else 0.0
        roots.append(x)
    roots[0], roots[-1] = -LENGTH / 2, LENGTH / 2

    offsets = [(k + 0.5) * dx - WIDTH / 2 for k in range(n_n)]
    layers = offsets if args.dim == 3 else [0.0]
    rows = []
    min_factor, max_factor = math.inf, 0.0
    for x in roots:
        tangent, normal, kappa = frame(x)
        for t in offsets:
            factor = 1 + kappa * t
            if factor <= 0:
                print(f"offset {t} m exceeds the radius of curvature at x = {x}", file=sys.stderr)
                return 1
            min_factor, max_factor = min(min_factor, factor), max(max_factor, factor)
            px, py = x + t * normal[0], f(x) + t * normal[1]
            area = ds * factor * dx
            for z in layers:
                rows.append((px, py, z, area * dx if args.dim == 3 else area))

    with open(args.out, "w") as out:
        out.write(f"# curved bar, {args.dim}D, N_n = {n_n}, dx = {dx} m, {len(rows)} points; "
                  f"SI units (m, m^{args.dim})\n")
        out.write(f"# made by: scripts/generate_curved_bar.py --dim {args.dim} "
                  f"--points-per-normal {n_n} --out {args.out}\n")
        out.write("x,y,z,volume\n" if args.dim == 3 else "x,y,volume\n")
        for px, py, z, v in rows:
            if args.dim == 3:
                out.write(f"{px!r},{py!r},{z!r},{v!r}\n")
            else:
                out.write(f"{px!r},{py!r},{v!r}\n")

    alpha = math.atan(-1 / df(LENGTH / 2))
    n_l = (math.sin(alpha), math.cos(alpha))
    n_r = (-math.sin(alpha), math.cos(alpha))
    left, right = (-LENGTH / 2, f(-LENGTH / 2)), (LENGTH / 2, f(LENGTH / 2))
    # Half-spaces bounded half a root spacing inside each end: they hold the end layer only (the
    # next layer is at least ds (1 - kappa W/2) > ds/2 away along the end tangent).
    cut_l = (left[0] + ds / 2 * n_l[0], left[1] + ds / 2 * n_l[1])
    cut_r = (right[0] + ds / 2 * n_r[0], right[1] + ds / 2 * n_r[1])
    print(f"wrote {args.out}: {len(rows)} points ({n_root} root points x {n_n} per normal"
          f"{' x ' + str(n_n) + ' layers' if args.dim == 3 else ''})")
    print(f"dx = {dx} m, arc length {total:.6f} m, root spacing ds = {ds:.6g} m, "
          f"local spacing factor 1 + kappa t in [{min_factor:.4f}, {max_factor:.4f}]")
    print(f"alpha = {math.degrees(alpha):.4f} deg, n_l = ({n_l[0]:.9f}, {n_l[1]:.9f}), "
          f"n_r = ({n_r[0]:.9f}, {n_r[1]:.9f})")
    print(f"left end layer:  half_space point ({cut_l[0]:.9f}, {cut_l[1]:.9f}) normal "
          f"({-n_l[0]:.9f}, {-n_l[1]:.9f})")
    print(f"right end layer: half_space point ({cut_r[0]:.9f}, {cut_r[1]:.9f}) normal "
          f"({-n_r[0]:.9f}, {-n_r[1]:.9f})")
    return 0


if __name__ == "__main__":
    sys.exit(main())
