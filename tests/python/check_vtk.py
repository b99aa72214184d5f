"""Reads the VTK frames of `dda run --vtk` back with VTK's own XML reader
(the `vtk` package) and checks them against history.csv and contacts.csv:
cell counts and types, each block's centroid from its cell's points, the
velocity array, the contacts' normal forces, and the .pvd times.

    python tests/python/check_vtk.py [path/to/dda]

The dda binary defaults to $DDA_BIN, else target/release/dda under
$CARGO_TARGET_DIR or the repository. Ends with "N passed, N failed" and a
non-zero exit code when a check fails.
"""

import csv
import os
import re
import subprocess
import sys
import tempfile
import xml.etree.ElementTree as ET
from pathlib import Path

import vtk
from vtk.util.numpy_support import vtk_to_numpy

ROOT = Path(__file__).resolve().parents[2]

# (example, shortened duration in s): a 2D arch of 25 voussoirs that starts
# to collapse, and the 3D wedge sliding on two planes.
SCENES = [("arch_heyman_collapse_2d.ron", 0.2), ("wedge_3d.ron", 0.1)]

passed, failed = 0, 0


def check(ok, what):
    global passed, failed
    if ok:
        passed += 1
    else:
        failed += 1
        print(f"FAILED: {what}", file=sys.stderr)


def close(a, b, scale):
    return abs(a - b) <= 1e-9 * max(scale, abs(a), abs(b))


def dda_binary():
    if len(sys.argv) > 1:
        return Path(sys.argv[1])
    if os.environ.get("DDA_BIN"):
        return Path(os.environ["DDA_BIN"])
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return target / "release" / "dda"


def short_scene(example, duration, folder):
    """The example with a shorter duration, writing contacts.csv too."""
    text = (ROOT / "examples" / example).read_text()
    text, n = re.subn(r"duration: [0-9.e+-]+", f"duration: {duration}", text, count=1)
    assert n == 1, f"{example}: no duration to shorten"
    text, n = re.subn(r"output: \(", "output: (contacts: true, ", text, count=1)
    assert n == 1, f"{example}: no output section"
    path = folder / example
    path.write_text(text)
    return path


def rows_by_step(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    steps = {}
    for r in rows:
        steps.setdefault(int(r["step"]), []).append(r)
    return [steps[s] for s in sorted(steps)]


def read_vtu(path):
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def polygon_centroid(points):
    """Area centroid of a polygon (shoelace)."""
    area, cx, cy = 0.0, 0.0, 0.0
    for i in range(len(points)):
        (x0, y0), (x1, y1) = points[i][:2], points[(i + 1) % len(points)][:2]
        c = x0 * y1 - x1 * y0
        area += c
        cx += (x0 + x1) * c
        cy += (y0 + y1) * c
    return cx / (3 * area), cy / (3 * area)


def polyhedron_centroid(grid, cell_id):
    """Volume centroid of a polyhedron cell: tetrahedra from a point inside
    to the fan-triangulated faces as the file gives them."""
    faces = vtk.vtkIdList()
    grid.GetFaceStream(cell_id, faces)
    ids = [faces.GetId(i) for i in range(faces.GetNumberOfIds())]
    pts = vtk_to_numpy(grid.GetPoints().GetData())
    cell = grid.GetCell(cell_id)
    corner = [pts[cell.GetPointId(i)] for i in range(cell.GetNumberOfPoints())]
    o = sum(corner) / len(corner)
    volume, moment = 0.0, 0.0
    k = 1
    for _ in range(ids[0]):
        n = ids[k]
        face = [pts[j] for j in ids[k + 1 : k + 1 + n]]
        k += n + 1
        for i in range(1, n - 1):
            a, b, c = face[0] - o, face[i] - o, face[i + 1] - o
            v = (a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0])
                 + a[2] * (b[0] * c[1] - b[1] * c[0])) / 6.0
            volume += v
            moment = moment + v * (o + face[0] + face[i] + face[i + 1]) / 4.0
    return moment / volume, volume


def check_run(example, duration, dda, folder):
    scene = short_scene(example, duration, folder)
    out = folder / (scene.stem + "_out")
    done = subprocess.run([str(dda), "run", str(scene), "--out", str(out), "--vtk"],
                          capture_output=True, text=True)
    if done.returncode != 0:
        sys.exit(f"dda run {scene} failed:\n{done.stderr}")
    three = example.endswith("_3d.ron")
    history = rows_by_step(out / "history.csv")
    with open(out / "contacts.csv", newline="") as f:
        contacts = {}
        for r in csv.DictReader(f):
            contacts.setdefault(int(r["step"]), []).append(r)

    for what in ["blocks", "contacts"]:
        sets = ET.parse(out / f"{what}.pvd").getroot().find("Collection").findall("DataSet")
        check(len(sets) == len(history), f"{example}: {what}.pvd has {len(sets)} frames, history {len(history)} times")
        for s, rows in zip(sets, history):
            check(close(float(s.get("timestep")), float(rows[0]["time"]), 1.0),
                  f"{example}: {what}.pvd time {s.get('timestep')} against {rows[0]['time']}")

    sets = ET.parse(out / "blocks.pvd").getroot().find("Collection").findall("DataSet")
    contact_sets = ET.parse(out / "contacts.pvd").getroot().find("Collection").findall("DataSet")
    for frame, (s, cs, rows) in enumerate(zip(sets, contact_sets, history)):
        grid = read_vtu(out / s.get("file"))
        where = f"{example} frame {frame}"
        check(grid.GetNumberOfCells() == len(rows), f"{where}: {grid.GetNumberOfCells()} cells for {len(rows)} blocks")
        types = {grid.GetCellType(i) for i in range(grid.GetNumberOfCells())}
        check(types == {vtk.VTK_POLYHEDRON if three else vtk.VTK_POLYGON}, f"{where}: cell types {types}")
        pts = vtk_to_numpy(grid.GetPoints().GetData())
        if not three:
            check(abs(pts[:, 2]).max() == 0.0, f"{where}: 2D points off z = 0")
        size = float(abs(pts).max())
        velocity = vtk_to_numpy(grid.GetCellData().GetArray("velocity"))
        block = vtk_to_numpy(grid.GetCellData().GetArray("block"))
        for i, r in enumerate(rows):
            check(int(block[i]) == int(r["block"]), f"{where}: block id {block[i]}")
            cell = grid.GetCell(i)
            if three:
                c, volume = polyhedron_centroid(grid, i)
                check(volume > 0, f"{where}: block {i} has volume {volume} (faces inward?)")
                xyz = [float(r["x"]), float(r["y"]), float(r["z"])]
                check(all(close(c[k], xyz[k], size) for k in range(3)),
                      f"{where}: block {i} centroid {c} against history {xyz}")
                v = [float(r["vx"]), float(r["vy"]), float(r["vz"])]
            else:
                corners = [pts[cell.GetPointId(k)] for k in range(cell.GetNumberOfPoints())]
                c = polygon_centroid(corners)
                xy = [float(r["x"]), float(r["y"])]
                check(all(close(c[k], xy[k], size) for k in range(2)),
                      f"{where}: block {i} centroid {c} against history {xy}")
                v = [float(r["vx"]), float(r["vy"]), 0.0]
            check(all(velocity[i][k] == v[k] for k in range(3)),
                  f"{where}: block {i} velocity {velocity[i]} against history {v}")

        points = read_vtu(out / cs.get("file"))
        step = int(rows[0]["step"])
        expected = contacts.get(step, [])
        check(points.GetNumberOfPoints() == len(expected),
              f"{where}: {points.GetNumberOfPoints()} contact points for {len(expected)} contacts")
        if expected:
            fn = vtk_to_numpy(points.GetPointData().GetArray("normal_force"))
            check(all(fn[k] == float(r["fn"]) for k, r in enumerate(expected)),
                  f"{where}: contact normal forces differ from contacts.csv")
    print(f"{example}: {len(history)} frames checked")


def main():
    dda = dda_binary()
    if not dda.exists():
        sys.exit(f"{dda} not found: build it with `cargo build --release` or give its path")
    print(f"VTK {vtk.vtkVersion.GetVTKVersion()}")
    with tempfile.TemporaryDirectory() as folder:
        for example, duration in SCENES:
            check_run(example, duration, dda, Path(folder))
    print(f"{passed} passed, {failed} failed")
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
