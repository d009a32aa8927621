#!/usr/bin/env pvpython
"""Opens a ckpd run's fields.xdmf with each of ParaView's XDMF readers (XDMFReader, Xdmf3ReaderS,
Xdmf3ReaderT) and checks what a user would see: one block per body, every body's points as
cells (Polyvertex) or a wall's triangles, the point arrays named in the XDMF, and the frames'
times; then each body's series (fields_<body>.xdmf) the same way. Optionally renders the damage
of one frame to a PNG.

    pvbatch --force-offscreen-rendering scripts/validate_paraview.py runs/CASE
    xvfb-run -a -s "-screen 0 1600x1000x24 +extension GLX" pvbatch scripts/validate_paraview.py \
        runs/CASE --screenshot docs/img/damage.png --time 9e-5 --array damage

Run with pvpython or pvbatch (Debian: apt-get install paraview python3-paraview; a screenshot
needs an X server: Debian's ParaView renders through GLX, so use xvfb-run, package xvfb). Exit 0 when
every reader passes; otherwise each failure is printed and the exit status is 1. The file is
opened by its absolute path and, from inside the run directory, as ./fields.xdmf (a bare
"fields.xdmf" makes ParaView 5.11's Xdmf3 readers abort; docs/PARAVIEW.md).
"""
import argparse
import glob
import os
import sys
import xml.etree.ElementTree as ET

from paraview import servermanager
from paraview.simple import (ColorBy, GetActiveViewOrCreate, GetAnimationScene, ResetCamera,
                             SaveScreenshot, Show, UpdatePipeline, XDMFReader, Xdmf3ReaderS,
                             Xdmf3ReaderT)

READERS = {"XDMFReader": XDMFReader, "Xdmf3ReaderS": Xdmf3ReaderS, "Xdmf3ReaderT": Xdmf3ReaderT}


def expected(xdmf):
    """Per body name: (points, cells, arrays) of the last frame, and the frame times. The file is
    fields.xdmf (each frame a collection of the bodies' grids) or a body's series
    fields_<body>.xdmf (each frame that body's grid)."""
    root = ET.parse(xdmf).getroot()
    frames = root.find("Domain").find("Grid").findall("Grid")
    times = [float(f.find("Time").get("Value")) for f in frames]
    bodies = {}
    grids = frames[-1].findall("Grid") or [frames[-1]]
    for grid in grids:
        topology = grid.find("Topology")
        points = int(grid.find("Geometry").find("DataItem").get("Dimensions").split()[0])
        bodies[grid.get("Name")] = (points, int(topology.get("NumberOfElements")),
                                    sorted(a.get("Name") for a in grid.findall("Attribute")))
    return bodies, times


def leaves(data, name=""):
    """(name, dataset) of every leaf of a composite dataset: multiblocks (named blocks) hold
    datasets or, with the Xdmf3 readers, multipiece sets of one piece each."""
    if data.IsA("vtkMultiBlockDataSet"):
        out = []
        for k in range(data.GetNumberOfBlocks()):
            block = data.GetBlock(k)
            if block is None:
                continue
            meta = data.GetMetaData(k) if data.HasMetaData(k) else None
            child = meta.Get(data.NAME()) if meta is not None and meta.Has(data.NAME()) else ""
            out += leaves(block, child or name or str(k))
        return out
    if data.IsA("vtkPartitionedDataSet"):  # vtkMultiPieceDataSet
        out = []
        for k in range(data.GetNumberOfPartitions()):
            piece = data.GetPartition(k)
            if piece is not None:
                out += leaves(piece, name)
        return out
    return [(name, data)]


def components(xdmf):
    """Per array name: the number of components the XDMF gives it (1, 3, 6 or 9)."""
    out = {}
    for a in ET.parse(xdmf).getroot().iter("Attribute"):
        dims = a.find("DataItem").get("Dimensions").split()
        out[a.get("Name")] = int(dims[1]) if len(dims) > 1 else 1
    return out


# What a reader may make of an attribute of n components: XDMFReader expands a Tensor6 (xx, xy,
# xz, yy, yz, zz) into the full symmetric 3 x 3 tensor, the Xdmf3 readers keep its 6.
ACCEPTED = {1: (1,), 3: (3,), 6: (6, 9), 9: (9,)}


def check_components(reader_name, leaf, counts, problems):
    """Every array has the components its attribute type allows; an expanded Tensor6 holds the
    same values as its 6 (xy in both off-diagonal places)."""
    data = leaf.GetPointData()
    for name, n in counts.items():
        array = data.GetArray(name)
        if array is None:
            continue
        got = array.GetNumberOfComponents()
        if got not in ACCEPTED.get(n, (n,)):
            problems.append(f"{reader_name}: array {name} has {got} components, expected {n}")
        elif n == 6 and got == 9 and array.GetNumberOfTuples() > 0:
            t = array.GetTuple(0)
            if t[1] != t[3] or t[2] != t[6] or t[5] != t[7]:
                problems.append(f"{reader_name}: array {name} expanded to a tensor that is not "
                                f"symmetric: {t}")


def check(reader_name, path, bodies, times, problems):
    reader = READERS[reader_name](**{"FileNames" if reader_name == "XDMFReader" else "FileName": [path]})
    reader.UpdatePipelineInformation()
    got_times = list(reader.TimestepValues) if reader.TimestepValues else []
    if len(got_times) != len(times) or any(
            abs(a - b) > 1e-12 * max(1.0, abs(b)) for a, b in zip(got_times, times)):
        problems.append(f"{reader_name}: times {got_times[:3]}... (expected {len(times)}: "
                        f"{times[:3]}...)")
    UpdatePipeline(time=times[-1], proxy=reader)
    data = servermanager.Fetch(reader)
    # Xdmf3ReaderS delivers the bodies as unnamed pieces: compare what they hold, not names.
    found = []
    counts = components(os.path.abspath(path))
    for name, leaf in leaves(data):
        check_components(reader_name, leaf, counts, problems)
        arrays = sorted(leaf.GetPointData().GetArrayName(k)
                        for k in range(leaf.GetPointData().GetNumberOfArrays()))
        found.append((leaf.GetNumberOfPoints(), leaf.GetNumberOfCells(), arrays, name))
    want = sorted((p, c, a) for p, c, a in bodies.values())
    got = sorted((p, c, a) for p, c, a, _ in found)
    if len(got) != len(want):
        problems.append(f"{reader_name}: {len(got)} blocks, expected {len(want)} "
                        f"({', '.join(sorted(bodies))})")
    for w, g in zip(want, got):
        if g[0] != w[0] or g[1] != w[1]:
            problems.append(f"{reader_name}: a block has {g[0]} points and {g[1]} cells, "
                            f"expected {w[0]} and {w[1]}")
        missing = [a for a in w[2] if a not in g[2]]
        if missing:
            problems.append(f"{reader_name}: a block of {g[0]} points lacks arrays {missing}")
    print(f"{reader_name} ({path}): {len(got_times)} times, blocks " +
          ", ".join(f"'{n}': {p} points / {c} cells / {len(a)} arrays" for p, c, a, n in found))
    return reader


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("run", help="a ckpd output directory (holding fields.xdmf)")
    ap.add_argument("--screenshot", help="PNG of --array at --time (Xdmf3ReaderS)")
    ap.add_argument("--time", type=float, help="time of the screenshot (default: the last)")
    ap.add_argument("--array", default="damage", help="point array to colour by")
    args = ap.parse_args()
    xdmf = os.path.abspath(os.path.join(args.run, "fields.xdmf"))
    if not os.path.isfile(xdmf):
        sys.exit(f"{xdmf}: not found (did the run write fields?)")
    bodies, times = expected(xdmf)
    problems = []
    for name in READERS:
        check(name, xdmf, bodies, times, problems)
    # A path relative to the working directory, from inside the run directory. (Not the bare
    # name "fields.xdmf": ParaView 5.11's Xdmf3 readers then look for the frames under
    # "fields.xdmffields/" and abort the whole process; docs/PARAVIEW.md.)
    here = os.getcwd()
    os.chdir(os.path.dirname(xdmf))
    try:
        for name in READERS:
            check(name, "./fields.xdmf", bodies, times, problems)
    finally:
        os.chdir(here)
    # Each body's series, by its absolute path.
    for series in sorted(glob.glob(os.path.join(os.path.dirname(xdmf), "fields_*.xdmf"))):
        body, body_times = expected(series)
        for name in READERS:
            check(name, series, body, body_times, problems)
    if args.screenshot:
        reader = Xdmf3ReaderS(FileName=[xdmf])
        t = args.time if args.time is not None else times[-1]
        GetAnimationScene().AnimationTime = t
        view = GetActiveViewOrCreate("RenderView")
        view.ViewSize = [1400, 900]
        view.ViewTime = t
        display = Show(reader, view)
        display.SetRepresentationType("Points")
        display.PointSize = 7
        ColorBy(display, ("POINTS", args.array))
        display.RescaleTransferFunctionToDataRange(True, False)
        display.SetScalarBarVisibility(view, True)
        view.CameraPosition = [0, 0, 1]
        view.CameraFocalPoint = [0, 0, 0]
        view.CameraViewUp = [0, 1, 0]
        view.CameraParallelProjection = 1  # seen along z, undistorted
        ResetCamera(view)
        os.makedirs(os.path.dirname(os.path.abspath(args.screenshot)), exist_ok=True)
        SaveScreenshot(args.screenshot, view, ImageResolution=[1400, 900])
        print(f"{args.screenshot}: {args.array} at t = {t} s")
    for p in problems:
        print("FAIL:", p)
    print("ok" if not problems else f"{len(problems)} problem(s)")
    return 1 if problems else 0


if __name__ == "__main__":
    status = main()
    sys.stdout.flush()
    # Skip ParaView's teardown: under Xvfb it can end in a GLX error after the work is done.
    os._exit(status)
