#!/usr/bin/env python3
"""Reads a boundary-value run's field files back with meshio and with VTK's own XML reader (the
one ParaView 5.11 uses) and checks them against the run's history.csv (docs/scenes.md, "Fields"):

- both readers give the same arrays, bit for bit;
- every collection (.pvd) lists existing .vtu files at strictly increasing times, each time the
  history's time of the increment in the file name;
- every mesh file has finite displacements and stresses, a material id per cell within the
  summary's list, and its cell stress equals the mean of its nodal average's sources (the nodal
  average of the cell means reproduces a uniform field);
- every contact file's area-weighted mean normal traction over the active points equals the
  history's t_n (the main pair) and the mean shear along x equals t_t1.

Usage: check_fields.py RUN_DIR   (exit 0 when every check holds, 1 with the failures listed).
Needs Debian's python3-meshio and python3-vtk9 (scripts/setup.sh installs them; run with
/usr/bin/python3).
"""
import csv
import json
import math
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

try:
    import meshio
    import numpy as np
    import vtk  # VTK 9.1's own XML reader, the one ParaView 5.11 uses
    from vtk.util.numpy_support import vtk_to_numpy
except ImportError as e:  # a failure, not a skip: the set-up script installs them
    print(f"check_fields: {e}; install python3-meshio and python3-vtk9 (scripts/setup.sh)",
          file=sys.stderr)
    sys.exit(1)


def vtk_disagrees(path, grid):
    """Names of the arrays that VTK's reader reads differently from meshio (or not at all)."""
    reader = vtk.vtkXMLUnstructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    out = reader.GetOutput()
    bad = []
    if reader.GetErrorCode() != 0 or out.GetNumberOfPoints() != len(grid.points):
        return ["the file"]
    for name, values in grid.point_data.items():
        a = out.GetPointData().GetArray(name)
        if a is None or not np.array_equal(vtk_to_numpy(a).reshape(values.shape), values,
                                           equal_nan=True):
            bad.append(name)
    for name, blocks in grid.cell_data.items():
        a = out.GetCellData().GetArray(name)
        if a is None or not np.array_equal(vtk_to_numpy(a).reshape(blocks[0].shape), blocks[0],
                                           equal_nan=True):
            bad.append(name)
    return bad


def close(a, b, rel=1e-9, abs_=1e-9):
    return abs(a - b) <= abs_ + rel * max(abs(a), abs(b))


def main(run_dir: Path) -> int:
    failures = []
    summary = json.loads((run_dir / "summary.json").read_text())
    details = summary  # the run kind's details sit at the top level
    fields = details.get("fields")
    if fields is None:
        print("check_fields: summary.json lists no fields", file=sys.stderr)
        return 1
    with open(run_dir / "history.csv", newline="") as f:
        rows = {int(r["increment"]): r for r in csv.DictReader(f)}
    materials = fields["materials"]
    checked = 0
    for collection in fields["collections"]:
        root = ET.parse(run_dir / collection).getroot()
        entries = [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]
        # Contact collections start at the first increment (no pairing before it).
        expected = fields["outputs"] - (0 if collection == "mesh.pvd" else 1)
        if len(entries) != expected:
            failures.append(f"{collection}: {len(entries)} datasets, expected {expected}")
        times = [t for t, _ in entries]
        if any(b <= a for a, b in zip(times, times[1:])):
            failures.append(f"{collection}: times not strictly increasing: {times}")
        for time, file in entries:
            path = run_dir / file
            if not path.exists():
                failures.append(f"{collection}: {file} missing")
                continue
            increment = int(re.search(r"-(\d+)\.vtu$", file).group(1))
            row = rows.get(increment)
            if row is None:
                failures.append(f"{file}: no history row for increment {increment}")
                continue
            if not close(time, float(row["time"]), 1e-15, 0.0):
                failures.append(f"{file}: time {time} but history says {row['time']}")
            grid = meshio.read(path)
            checked += 1
            for name in vtk_disagrees(path, grid):
                failures.append(f"{file}: VTK's reader and meshio disagree on {name}")
            if collection == "mesh.pvd":
                for name in ("displacement", "stress_nodal"):
                    if not np.all(np.isfinite(grid.point_data[name])):
                        failures.append(f"{file}: {name} not finite")
                stress = grid.cell_data["stress"][0]
                if not np.all(np.isfinite(stress)):
                    failures.append(f"{file}: stress not finite")
                ids = grid.cell_data["material"][0]
                if ids.min() < 0 or ids.max() >= len(materials):
                    failures.append(f"{file}: material ids {ids.min()}..{ids.max()} outside {materials}")
                # The nodal average is a mean of cell values: it stays inside their range.
                nodal = grid.point_data["stress_nodal"]
                lo, hi = stress.min(axis=0), stress.max(axis=0)
                slack = 1e-9 * (1.0 + np.abs(stress).max())
                if np.any(nodal < lo - slack) or np.any(nodal > hi + slack):
                    failures.append(f"{file}: nodal stress outside the range of the cell stresses")
            else:
                pd = grid.point_data
                w = pd["area"] * pd["active"]
                if w.sum() <= 0.0:
                    continue
                t_n = float((w * pd["t_N"]).sum() / w.sum())
                t_t1 = float((w * pd["shear_traction"][:, 0]).sum() / w.sum())
                main_pair = f"contact-{details.get('history_contact', 'interface')}.pvd"
                if collection == main_pair:
                    scale = 1e-9 * max(1.0, abs(float(row["t_n"])))
                    if not close(t_n, float(row["t_n"]), 1e-9, scale):
                        failures.append(f"{file}: mean t_N {t_n} but history t_n {row['t_n']}")
                    if not close(t_t1, float(row["t_t1"]), 1e-9, scale):
                        failures.append(f"{file}: mean shear x {t_t1} but history t_t1 {row['t_t1']}")
    if checked == 0:
        failures.append("no field file checked")
    for f in failures:
        print(f"check_fields: {f}", file=sys.stderr)
    if not failures:
        print(f"check_fields: {checked} files in {run_dir} agree with history.csv")
    return 1 if failures else 0


if __name__ == "__main__":
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    sys.exit(main(Path(sys.argv[1])))
