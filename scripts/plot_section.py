#!/usr/bin/env python3
"""Stress fields of a 3D boundary-value run on a plane section, drawn from its VTU files
(docs/scenes.md, "Fields"): the element faces lying in an axis-aligned plane through a layer of
nodes (e.g. the symmetry plane y = 0), coloured by their element's stress, one panel per
component, deformed with scaled displacements. Paper Fig. 13 is
`plot_section.py RUN --normal y --at 0 --components 13 11 33 --material sand --time T`.

Usage: plot_section.py RUN_DIR --out PNG [--normal x|y|z] [--at COORD]
       [--components 13 11 33] [--increment N | --time T] [--scale S] [--material NAME]
       [--change-from-time T0]
(/usr/bin/python3 with Debian's python3-meshio and python3-matplotlib).
"""
import argparse
import json
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import meshio  # noqa: E402
import numpy as np  # noqa: E402
from matplotlib.collections import PolyCollection  # noqa: E402

COMPONENTS = ["11", "22", "33", "12", "23", "13"]  # the files' order (ParaView's tensor order)
AXES = "xyz"
# The six faces of a VTK hexahedron, each as a closed loop of local node numbers.
HEX_FACES = [(0, 1, 2, 3), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)]


def datasets(pvd):
    root = ET.parse(pvd).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def output_number(file):
    m = re.search(r"-(\d+)\.vtu$", file)
    if not m:
        sys.exit(f"plot_section: {file}: not an ifsim field file name (NAME-NNNNNN.vtu)")
    return int(m.group(1))


def pick(entries, increment, time):
    """The output of an increment, the first at or after a time, or the last one."""
    if not entries:
        sys.exit("plot_section: the collection lists no output")
    if increment is not None:
        for t, file in entries:
            if output_number(file) == increment:
                return t, file
        sys.exit(f"plot_section: no output of increment {increment}")
    if time is not None:
        later = [e for e in entries if e[0] >= time - 1e-12]
        if not later:
            sys.exit(f"plot_section: no output at or after time {time:g} "
                     f"(the last is at {entries[-1][0]:g})")
        return min(later)
    return entries[-1]


def hexahedron_cells(mesh):
    """The hexahedra of all cell blocks and, per hexahedron, its index into the joined cell
    data of all blocks (cell data is stored per block)."""
    blocks, index, offset = [], [], 0
    for c in mesh.cells:
        if c.type == "hexahedron":
            blocks.append(c.data)
            index.append(np.arange(offset, offset + len(c.data)))
        offset += len(c.data)
    if not blocks:
        return np.empty((0, 8), dtype=int), np.empty(0, dtype=int)
    return np.concatenate(blocks), np.concatenate(index)


def section_faces(mesh, normal, at, keep):
    """(cell index into the joined cell data, 4 node ids) of every hexahedron face lying in the
    plane; where the plane runs between two elements, the face of the one on its + side."""
    hexes, cells = hexahedron_cells(mesh)
    coord = mesh.points[:, normal]
    tol = 1e-6 * max(np.ptp(mesh.points, axis=0).max(), 1.0)
    on_plane = np.abs(coord - at) <= tol
    faces = {}
    for nodes, cell in zip(hexes, cells):
        if not keep[cell]:
            continue
        for f in HEX_FACES:
            ids = nodes[list(f)]
            if on_plane[ids].all():
                key = frozenset(int(i) for i in ids)
                plus_side = coord[nodes].mean() > at
                if key not in faces or plus_side:
                    faces[key] = (cell, ids)
    return list(faces.values())


def cell_array(mesh, name, file):
    if name not in mesh.cell_data:
        sys.exit(f"plot_section: {file} has no cell array {name!r}")
    return np.concatenate(list(mesh.cell_data[name]))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run_dir", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--normal", default="y", choices=list(AXES), help="axis normal to the plane")
    ap.add_argument("--at", type=float, default=0.0, help="the plane's coordinate (m)")
    ap.add_argument("--components", nargs="+", default=["13", "11", "33"], choices=COMPONENTS)
    group = ap.add_mutually_exclusive_group()
    group.add_argument("--increment", type=int)
    group.add_argument("--time", type=float, help="the first output at or after this time")
    ap.add_argument("--scale", type=float, default=20.0, help="displacement magnification")
    ap.add_argument("--material", help="draw only the elements of this [material] name")
    ap.add_argument("--change-from-time", type=float, metavar="T0",
                    help="draw the change of stress since the first output at or after T0")
    a = ap.parse_args()

    pvd = a.run_dir / "mesh.pvd"
    if not pvd.exists():
        sys.exit(f"plot_section: {pvd} not found (run with --fields or [output] fields)")
    time, file = pick(datasets(pvd), a.increment, a.time)
    mesh = meshio.read(a.run_dir / file)
    increment = output_number(file)
    if not any(c.type == "hexahedron" for c in mesh.cells):
        sys.exit("plot_section: 3D (hexahedron) meshes only; plot_fields.py draws 2D runs")
    stress = cell_array(mesh, "stress", file)
    since = ""
    if a.change_from_time is not None:
        t0, file0 = pick(datasets(pvd), None, a.change_from_time)
        before = meshio.read(a.run_dir / file0)
        stress = stress - cell_array(before, "stress", file0)
        since = f" since time {t0:g}"
    keep = np.ones(len(stress), dtype=bool)
    if a.material:
        names = json.loads((a.run_dir / "summary.json").read_text())["fields"]["materials"]
        if a.material not in names:
            sys.exit(f"plot_section: no material {a.material!r}; the run has {names}")
        keep = cell_array(mesh, "material", file) == names.index(a.material)

    normal = AXES.index(a.normal)
    faces = section_faces(mesh, normal, a.at, keep)
    if not faces:
        sys.exit(f"plot_section: no element face lies in the plane {a.normal} = {a.at:g} "
                 "(the plane must pass through a layer of nodes)")
    inplane = [i for i in range(3) if i != normal]
    if "displacement" not in mesh.point_data:
        sys.exit(f"plot_section: {file} has no point array 'displacement'")
    x = mesh.points + a.scale * mesh.point_data["displacement"]
    polygons = np.array([x[ids][:, inplane] for _, ids in faces])
    elements = np.array([e for e, _ in faces])

    fig, axes = plt.subplots(1, len(a.components), figsize=(3.6 * len(a.components) + 1, 5.5),
                             squeeze=False)
    for ax, comp in zip(axes[0], a.components):
        values = stress[elements, COMPONENTS.index(comp)]
        poly = PolyCollection(polygons, array=values, cmap="viridis", edgecolors="k",
                              linewidths=0.15)
        ax.add_collection(poly)
        ax.autoscale()
        ax.set_aspect("equal")
        fig.colorbar(poly, ax=ax, label=f"{'Δ' if since else ''}σ{comp} (kPa)", shrink=0.8)
        ax.set_xlabel(f"{AXES[inplane[0]]} (m)")
        ax.set_ylabel(f"{AXES[inplane[1]]} (m)")
        ax.set_title(f"{'Δ' if since else ''}σ{comp}{since}")
    fig.suptitle(f"{a.run_dir.name}: increment {increment}, time {time:g}, plane "
                 f"{a.normal} = {a.at:g}; displacements × {a.scale:g}")
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(f"plot_section: {a.out} (increment {increment}, time {time:g}, {len(faces)} faces)")


if __name__ == "__main__":
    main()
