"""meshio and h5py read a ckpd run: each body's XDMF series (DIR/fields_<body>.xdmf) through
meshio's TimeSeriesReader, the frames through h5py.

    python3 tests/meshio_reads_run.py CKPD_BINARY

Runs tests/data/block_and_floor/case.yaml (a deformable block and a moving mesh-wall floor, a
frame every 4 of 12 steps) into a temporary folder; checks for each body: the grid is named by the
body, the points and cells of the first frame, each frame's time and every point array (the
current position among them) against the frame files read with h5py. Exit 0 when all hold.
"""
import os
import pathlib
import subprocess
import sys
import tempfile

try:
    import h5py
    import numpy as np
    from meshio.xdmf import TimeSeriesReader
except ImportError as e:  # CI installs them (scripts/setup.sh)
    sys.exit(f"meshio_reads_run: {e}: install python3-meshio and python3-h5py (scripts/setup.sh)")

def check(condition, what):
    if not condition:
        sys.exit(f"meshio_reads_run: {what}")


def main():
    ckpd = sys.argv[1]
    case = pathlib.Path(__file__).resolve().parent / "data" / "block_and_floor" / "case.yaml"
    with tempfile.TemporaryDirectory(prefix="ckpd-meshio-") as tmp:
        tmp = pathlib.Path(tmp)
        out = tmp / "out"
        run = subprocess.run([ckpd, "run", str(case), "--quiet", "--threads", "1",
                              "--out", str(out)], capture_output=True, text=True)
        check(run.returncode == 0, f"ckpd run failed: {run.stdout}{run.stderr}")
        for b, name in enumerate(["block", "floor"]):
            series = out / f"fields_{name}.xdmf"
            check(series.is_file(), f"{series} is missing")
            # meshio resolves the heavy data relative to the XDMF file: read it from elsewhere.
            os.chdir(tmp)
            with TimeSeriesReader(str(series)) as reader:
                check(reader.collection[0].get("Name") == name,
                      f"{series}: grid named {reader.collection[0].get('Name')}, not {name}")
                points, cells = reader.read_points_cells()
                check(reader.num_steps == 4, f"{series}: {reader.num_steps} steps, not 4")
                for k in range(reader.num_steps):
                    t, point_data, _ = reader.read_data(k)
                    frame = out / "fields" / f"frame_{k:06d}.h5"
                    with h5py.File(frame, "r") as f:
                        group = f[f"body_{b}"]
                        stored = group.attrs["name"]
                        stored = stored.decode() if isinstance(stored, bytes) else stored
                        check(stored == name, f"{frame}: body_{b} is named {stored}, not {name}")
                        check(t == f.attrs["time"], f"{series}: time {t} at step {k}")
                        x = group["position"][()]
                        if k == 0:
                            check(np.array_equal(points, x), f"{series}: first points differ")
                            kind = "triangle" if name == "floor" else "vertex"
                            check(cells[0].type == kind, f"{series}: cells {cells[0].type}")
                            count = 2 if name == "floor" else len(x)  # points are cells
                            check(len(cells[0].data) == count, f"{series}: {len(cells[0].data)} cells")
                        check(np.array_equal(point_data["position"], x),
                              f"{series}: position at step {k}")
                        wanted = [a for a in group if a not in ("connectivity", "triangles")]
                        check(sorted(point_data) == sorted(wanted),
                              f"{series}: point data {sorted(point_data)} at step {k}")
                        for array in wanted:
                            check(np.array_equal(point_data[array], group[array][()]),
                                  f"{series}: {array} at step {k}")
                        check(np.all(point_data["body_id"] == b), f"{series}: body_id")
        print("ok: meshio read both bodies' series (4 frames each) and h5py every frame")


if __name__ == "__main__":
    main()
