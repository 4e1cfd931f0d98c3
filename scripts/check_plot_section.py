#!/usr/bin/env python3
"""Checks the section logic of plot_section.py on a 3D run with fields whose soil body is a
structured block of NX x NY x NZ hexahedra (a CTest runs it on the 3D shear box):

- the plane y = y_min of the soil holds NX x NZ faces, x = x_min NY x NZ, z = z_min NX x NY,
  each face of a distinct soil element lying on that side of the block; so does the first node
  layer inside, each face drawn once, from the element on the plane's + side;
- a plane between two node layers holds no face;
- the picture of the change of stress since an output is written.

Usage: check_plot_section.py RUN_DIR NX NY NZ   (/usr/bin/python3 with python3-meshio)
"""
import json
import subprocess
import sys
import tempfile
from pathlib import Path

import meshio
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import plot_section  # noqa: E402


def main():
    run, nx, ny, nz = Path(sys.argv[1]), *map(int, sys.argv[2:5])
    failures = []
    _, file = plot_section.pick(plot_section.datasets(run / "mesh.pvd"), None, None)
    mesh = meshio.read(run / file)
    names = json.loads((run / "summary.json").read_text())["fields"]["materials"]
    soil = np.concatenate(list(mesh.cell_data["material"])) == names.index("sand")
    hexes, cells = plot_section.hexahedron_cells(mesh)
    nodes_of = dict(zip(cells, hexes))
    soil_points = np.unique(hexes[soil[cells]])
    lo = mesh.points[soil_points].min(axis=0)
    hi = mesh.points[soil_points].max(axis=0)
    for axis, expected in ((0, ny * nz), (1, nx * nz), (2, nx * ny)):
        layer = (hi[axis] - lo[axis]) / (nx, ny, nz)[axis]
        # the soil's side, and the first node layer inside (two elements share each face)
        for at in (lo[axis], lo[axis] + layer):
            faces = plot_section.section_faces(mesh, axis, at, soil)
            elements = {e for e, _ in faces}
            if len(faces) != expected or len(elements) != expected:
                failures.append(f"plane {'xyz'[axis]} = {at:g}: {len(faces)} faces of "
                                f"{len(elements)} elements, expected {expected}")
            for e, ids in faces:
                if not np.allclose(mesh.points[ids, axis], at):
                    failures.append(f"face of element {e} is not in the plane {'xyz'[axis]}")
                if not mesh.points[nodes_of[e], axis].mean() > at:
                    failures.append(f"face of element {e} drawn from the - side of the plane")
        between = lo[axis] + 0.5 * layer
        if plot_section.section_faces(mesh, axis, between, soil):
            failures.append(f"plane {'xyz'[axis]} = {between:g} between node layers holds faces")
    with tempfile.TemporaryDirectory() as tmp:
        png = Path(tmp) / "section.png"
        last_time = plot_section.datasets(run / "mesh.pvd")[-1][0]
        r = subprocess.run([sys.executable, str(Path(plot_section.__file__)), str(run), "--out",
                            str(png), "--material", "sand", "--change-from-time",
                            str(last_time)], capture_output=True, text=True)
        if r.returncode != 0 or not png.exists():
            failures.append(f"plot_section.py failed: {r.stderr.strip()}")
    for f in failures:
        print(f"check_plot_section: {f}")
    print(f"check_plot_section: {'FAILED' if failures else 'ok'}")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()
