#!/usr/bin/env python3
"""Writes the point cloud of LAMMPS's examples/peri/in.peri.pmb target as a ckpd CSV.

LAMMPS: `lattice sc 0.0005`, `region target cylinder y 0 0 0.0050 -0.0050 0.0`, `create_atoms`:
every site i*dx (i integer) with x^2 + z^2 <= R^2 and -5 mm <= y <= 0 (boundaries included),
3487 points. ckpd's lattice sampler puts points at cell centres of the bounding box, which for
this cylinder gives a different point set, so the cloud is given explicitly. Volume dx^3 each
(LAMMPS: `set group all volume 1.25e-10`).

    python3 bench/lammps/make_cylinder_points.py > bench/lammps/cylinder_points.csv
"""
import sys

DX = 0.0005  # m
RADIUS = 0.0050  # m
Y_LO, Y_HI = -0.0050, 0.0  # m

n_r = round(RADIUS / DX)
out = sys.stdout
out.write("# LAMMPS in.peri.pmb target: sc lattice 0.0005 m, cylinder along y, radius 5 mm,\n")
out.write("# -5 mm <= y <= 0; written by bench/lammps/make_cylinder_points.py. Units: m, m^3.\n")
out.write("x,y,z,volume\n")
count = 0
for j in range(round(Y_LO / DX), round(Y_HI / DX) + 1):
    for k in range(-n_r, n_r + 1):
        for i in range(-n_r, n_r + 1):
            if i * i + k * k <= n_r * n_r:  # integer test: no round-off at the rim
                out.write(f"{i * DX!r},{j * DX!r},{k * DX!r},{DX**3!r}\n")
                count += 1
if count != 3487:
    sys.exit(f"expected LAMMPS's 3487 points, made {count}")
