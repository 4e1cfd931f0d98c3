#!/usr/bin/env python3
"""A picture of a boundary-value run's fields, made from its VTU files (docs/scenes.md,
"Fields"): the mesh coloured by one stress component of the elements (deformed, displacements
scaled) and, below, each contact pair's normal and shear traction and interface void ratio
along the slave surface.

Usage: plot_fields.py RUN_DIR --out PNG [--increment N] [--component 12] [--scale 20]
       [--material NAME]
(the last written output when --increment is not given; /usr/bin/python3 with Debian's
python3-meshio and python3-matplotlib).
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


def datasets(pvd):
    root = ET.parse(pvd).getroot()
    return [(float(d.get("timestep")), d.get("file")) for d in root.iter("DataSet")]


def pick(entries, increment):
    if increment is None:
        return entries[-1]
    for time, file in entries:
        if int(re.search(r"-(\d+)\.vtu$", file).group(1)) == increment:
            return time, file
    sys.exit(f"plot_fields: no output of increment {increment}")


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("run_dir", type=Path)
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--increment", type=int)
    ap.add_argument("--component", default="12", choices=COMPONENTS)
    ap.add_argument("--scale", type=float, default=20.0, help="displacement magnification")
    ap.add_argument("--material", help="draw only the elements of this [material] name")
    a = ap.parse_args()
    time, file = pick(datasets(a.run_dir / "mesh.pvd"), a.increment)
    mesh = meshio.read(a.run_dir / file)
    increment = int(re.search(r"-(\d+)\.vtu$", file).group(1))
    pairs = sorted(a.run_dir.glob("contact-*.pvd"))
    fig, axes = plt.subplots(1 + len(pairs), 1, figsize=(8, 3.2 + 2.6 * len(pairs)),
                             gridspec_kw={"height_ratios": [1.4] + [1] * len(pairs)})
    axes = np.atleast_1d(axes)
    x = mesh.points[:, :2] + a.scale * mesh.point_data["displacement"][:, :2]
    cells = np.concatenate([c.data for c in mesh.cells if c.type == "quad"])
    if mesh.points[:, 2].ptp() > 0:
        sys.exit("plot_fields: 2D runs only (open 3D runs in ParaView: mesh.pvd)")
    values = mesh.cell_data["stress"][0][:, COMPONENTS.index(a.component)]
    if a.material:
        names = json.loads((a.run_dir / "summary.json").read_text())["fields"]["materials"]
        if a.material not in names:
            sys.exit(f"plot_fields: no material {a.material!r}; the run has {names}")
        keep = mesh.cell_data["material"][0] == names.index(a.material)
        cells, values = cells[keep], values[keep]
    poly = PolyCollection(x[cells], array=values, cmap="viridis", edgecolors="k",
                          linewidths=0.3)
    ax = axes[0]
    ax.add_collection(poly)
    ax.autoscale()
    ax.set_aspect("equal")
    fig.colorbar(poly, ax=ax, label=f"σ{a.component} (kPa)")
    ax.set_title(f"{a.run_dir.name}: increment {increment}, time {time:g}; "
                 f"displacements × {a.scale:g}")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    for ax, pvd in zip(axes[1:], pairs):
        entries = [e for e in datasets(pvd) if e[1].endswith(f"-{increment:06d}.vtu")]
        if not entries:
            continue
        c = meshio.read(a.run_dir / entries[0][1])
        order = np.argsort(c.points[:, 0])
        xs = c.points[order, 0]
        ax.plot(xs, c.point_data["t_N"][order], "o-", label="t_N")
        ax.plot(xs, c.point_data["shear_traction"][order, 0], "s-", label="shear, x")
        ax.set_ylabel("kPa")
        ax.set_xlabel("x of the contact point (m)")
        if "void_ratio" in c.point_data:
            ax2 = ax.twinx()
            ax2.plot(xs, c.point_data["void_ratio"][order], "^:", color="C2",
                     label="interface void ratio")
            ax2.set_ylabel("e", color="C2")
        ax.set_title(pvd.stem)
        ax.legend(loc="upper left", fontsize=8)
    fig.tight_layout()
    fig.savefig(a.out, dpi=120)
    print(f"plot_fields: {a.out}")


if __name__ == "__main__":
    main()
