#!/usr/bin/env python3
"""Figures of the large-scale cyclic interface shear test (paper §6) from ifsim runs.

Usage: plot_large_shear.py OUT.png RUN_DIR [RUN_DIR ...]

Each RUN_DIR is a run of a scene of scenes/large-shear*.toml (history.csv with the `wall`
recorder and the `p` point recorder). Panels, over the wall's displacement (mm, positive
downwards) from the start of the wall movement:
  (a) mean shear stress of the rough segment on the soil, t_t1 (t1 = down)  -- Fig. 9 top
  (b) mean normal stress of the rough segment, t_n                          -- Fig. 9 bottom
  (c) the interface point of recorder p: sigma_p1 (along t1: vertical) and sigma_p2
      (horizontal, along the wall)                                           -- Fig. 10
One curve per run, labelled by the run directory's name.
"""
import csv
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(run):
    with open(Path(run) / "history.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or "wall" not in rows[0]:
        sys.exit(f"plot_large_shear: {run}: history.csv has no 'wall' recorder column")
    return rows


def num(r, k):
    v = r.get(k, "")
    return float(v) if v not in ("", None) else float("nan")


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    out = sys.argv[1]
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.5))
    colours = plt.rcParams["axes.prop_cycle"].by_key()["color"]
    for k, run in enumerate(sys.argv[2:]):
        rows = read(run)
        # From the last row before the wall moves (end of gravity) on.
        start = max(i for i, r in enumerate(rows) if int(r["stage"]) <= 4)
        rows = rows[start:]
        w = [1e3 * num(r, "wall") for r in rows]
        label = Path(run).name
        c = colours[k % len(colours)]  # one colour per run in every panel
        ax[0].plot(w, [num(r, "t_t1") for r in rows], color=c, label=label)
        ax[1].plot(w, [num(r, "t_n") for r in rows], color=c, label=label)
        ax[2].plot(w, [num(r, "p.s_p1") for r in rows], color=c,
                   label=f"{label}: σ_p1 (vertical)")
        ax[2].plot(w, [num(r, "p.s_p2") for r in rows], "--", color=c,
                   label=f"{label}: σ_p2 (horizontal)")
    titles = ["(a) mean shear stress, rough segment", "(b) mean normal stress, rough segment",
              "(c) interface point in the lower half (Fig. 10)"]
    ylabels = ["t_t1 on the soil [kPa] (t1 = down)", "t_n [kPa]", "stress [kPa]"]
    for a, t, y in zip(ax, titles, ylabels):
        a.set_title(t, fontsize=10)
        a.set_xlabel("wall displacement [mm] (positive downwards)")
        a.set_ylabel(y)
        a.grid(alpha=0.3)
        a.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    print(f"plot_large_shear: {out}")


if __name__ == "__main__":
    main()
