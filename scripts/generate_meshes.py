#!/usr/bin/env python3
"""Triangle meshes for the mesh cases and the mesh-sampling benchmark.

  generate_meshes.py cases            writes cases/meshes/notched_plate.stl (binary STL, mm)
                                      and cases/meshes/impactor.obj (sphere, mm)
  generate_meshes.py torus OUT N M    a torus (R = 40 mm, r = 15 mm, in m) with N x M x 2
                                      triangles, as binary STL (the benchmark's mesh)

Surfaces are closed and wound counter-clockwise seen from outside (outward normals).
"""
import math
import os
import struct
import sys


def write_binary_stl(path, vertices, triangles):
    with open(path, "wb") as f:
        f.write(b"ckpd generated mesh".ljust(80, b" "))
        f.write(struct.pack("<I", len(triangles)))
        for a, b, c in triangles:
            pa, pb, pc = vertices[a], vertices[b], vertices[c]
            u = [pb[k] - pa[k] for k in range(3)]
            v = [pc[k] - pa[k] for k in range(3)]
            n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
            length = math.sqrt(sum(x * x for x in n)) or 1.0
            f.write(struct.pack("<12fH", *(x / length for x in n), *pa, *pb, *pc, 0))


def write_obj(path, vertices, triangles):
    with open(path, "w") as f:
        f.write("# ckpd generated mesh\n")
        for p in vertices:
            f.write("v %.9g %.9g %.9g\n" % p)
        for t in triangles:
            f.write("f %d %d %d\n" % tuple(i + 1 for i in t))


def extrude(polygon, caps, thickness):
    n = len(polygon)
    vertices = [(x, y, z) for z in (0.0, thickness) for (x, y) in polygon]
    triangles = []
    for a, b, c in caps:
        triangles.append((a, c, b))
        triangles.append((a + n, b + n, c + n))
    for i in range(n):
        j = (i + 1) % n
        triangles.append((i, j, j + n))
        triangles.append((i, j + n, i + n))
    return vertices, triangles


def notched_plate(W, H, a, b, d, thickness):
    """W x H plate with a (b - a) wide, d deep notch in its top edge (mm)."""
    polygon = [(0, 0), (a, 0), (b, 0), (W, 0), (W, H), (b, H), (b, H - d), (a, H - d), (a, H), (0, H)]
    caps = [(0, 1, 7), (0, 7, 8), (0, 8, 9), (1, 2, 6), (1, 6, 7), (3, 4, 5), (3, 5, 6), (3, 6, 2)]
    return extrude(polygon, caps, thickness)


def sphere(radius, rings, segments):
    vertices = [(0.0, 0.0, -radius)]
    for r in range(1, rings):
        th = math.pi * r / rings - math.pi / 2
        for s in range(segments):
            ph = 2 * math.pi * s / segments
            vertices.append((radius * math.cos(th) * math.cos(ph), radius * math.cos(th) * math.sin(ph),
                             radius * math.sin(th)))
    vertices.append((0.0, 0.0, radius))
    at = lambda r, s: 1 + (r - 1) * segments + s % segments
    top = len(vertices) - 1
    triangles = []
    for s in range(segments):
        triangles.append((0, at(1, s + 1), at(1, s)))
        triangles.append((top, at(rings - 1, s), at(rings - 1, s + 1)))
    for r in range(1, rings - 1):
        for s in range(segments):
            triangles.append((at(r, s), at(r, s + 1), at(r + 1, s + 1)))
            triangles.append((at(r, s), at(r + 1, s + 1), at(r + 1, s)))
    return vertices, triangles


def torus(R, r, around, tube):
    vertices = []
    for i in range(around):
        for j in range(tube):
            u, v = 2 * math.pi * i / around, 2 * math.pi * j / tube
            vertices.append(((R + r * math.cos(v)) * math.cos(u), (R + r * math.cos(v)) * math.sin(u),
                             r * math.sin(v)))
    at = lambda i, j: (i % around) * tube + j % tube
    triangles = []
    for i in range(around):
        for j in range(tube):
            triangles.append((at(i, j), at(i + 1, j), at(i + 1, j + 1)))
            triangles.append((at(i, j), at(i + 1, j + 1), at(i, j + 1)))
    return vertices, triangles


def main():
    if len(sys.argv) >= 2 and sys.argv[1] == "cases":
        root = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "cases", "meshes")
        os.makedirs(root, exist_ok=True)
        # 60 x 30 x 6 mm plate, 6 mm wide, 12 mm deep notch in the middle of its top edge.
        write_binary_stl(os.path.join(root, "notched_plate.stl"), *notched_plate(60, 30, 27, 33, 12, 6))
        write_obj(os.path.join(root, "impactor.obj"), *sphere(5.0, 16, 32))
    elif len(sys.argv) == 5 and sys.argv[1] == "torus":
        write_binary_stl(sys.argv[2], *torus(0.04, 0.015, int(sys.argv[3]), int(sys.argv[4])))
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
