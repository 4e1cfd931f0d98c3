#!/usr/bin/env python3
"""Overlay plot of an ifsim sweep: every run's curves in one figure, DIR/sweep.png.

Usage: plot_sweep.py DIR [--out FILE.png]

DIR is the output folder of `ifsim sweep` (sweep.csv, runs/<id>/). One colour per run (viridis
in sweep order), labelled by its swept values; a failed run is drawn dashed up to where it
stopped and marked "failed" in the legend. The panels follow the runs' kind:
  interface-test, boundary-value  t_t1, u_n, t_n and t_t1/|t_n| over u_t1 (mm)
  element-test                    q over the axial strain, q over p', void ratio over p',
                                  volumetric strain over the axial strain (compression +)
Runs of several kinds in one sweep: the panels of the first run's kind, the others skipped
with a note. Runs with Debian's /usr/bin/python3 (python3-matplotlib); without matplotlib it
says so and exits 0.
"""

import csv
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from plot_results import element_quantities, read_history, read_summary  # noqa: E402

LEGEND_RUNS = 16  # more runs get a colour bar over the run number instead of a legend
DPI = 110


def read_table(sweep_dir):
    path = os.path.join(sweep_dir, "sweep.csv")
    if not os.path.exists(path):
        path += ".partial"
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    return rows


def swept_keys(rows):
    if not rows:
        return []
    fixed = ("run", "id", "scene", "status", "reason", "wall_s")
    keys = []
    for name in rows[0].keys():
        if name == "status":
            break
        if name not in fixed:
            keys.append(name)
    return keys


def label_of(row, keys, many_scenes):
    parts = [f"{k.split('.')[-1]}={row[k]}" for k in keys]
    if many_scenes:
        parts.insert(0, os.path.basename(row["scene"]))
    text = ", ".join(parts) or f"run {row['run']}"
    return text if row["status"] == "ok" else text + " (failed)"


def interface_panels(h):
    u = [1000.0 * x for x in h["u_t1"]]
    ratio = [t / abs(n) if n else math.nan for t, n in zip(h["t_t1"], h["t_n"])]
    return u, [("shear stress t_t1 (kPa)", h["t_t1"]), ("normal displacement u_n (m)", h["u_n"]),
               ("normal stress t_n (kPa)", h["t_n"]), ("stress ratio t_t1/|t_n|", ratio)], \
        "tangential displacement u_t1 (mm)"


def element_panels(h):
    v = element_quantities(h)
    return None, [(("axial strain (%)", v["eps_axial"]), ("q (kPa)", v["q"])),
                  (("p' (kPa)", v["p"]), ("q (kPa)", v["q"])),
                  (("p' (kPa)", v["p"]), ("void ratio e", v["e"])),
                  (("axial strain (%)", v["eps_axial"]), ("volumetric strain (%)", v["eps_v"]))], \
        None


def curves_of(h, kind):
    """Four (x, xlabel, y, ylabel) curves of one run."""
    if kind in ("interface-test", "boundary-value"):
        x, panels, xlabel = interface_panels(h)
        return [(x, xlabel, y, ylabel) for ylabel, y in panels]
    if kind == "element-test":
        _, panels, _ = element_panels(h)
        return [(px[1], px[0], py[1], py[0]) for px, py in panels]
    raise ValueError(f"no sweep overlay for kind {kind!r}")


def plot(plt, sweep_dir, out):
    rows = read_table(sweep_dir)
    keys = swept_keys(rows)
    many_scenes = len({r["scene"] for r in rows}) > 1
    runs = [r for r in rows if r["status"] in ("ok", "failed")]
    if not runs:
        raise ValueError(f"{sweep_dir}: no run has finished yet")
    fig, axes = plt.subplots(2, 2, figsize=(11, 8))
    axes = axes.ravel()
    cmap = plt.get_cmap("viridis")
    kind0 = None
    skipped = 0
    for i, row in enumerate(runs):
        run_dir = os.path.join(sweep_dir, "runs", row["id"])
        try:
            h = read_history(run_dir)
        except OSError:
            skipped += 1
            continue
        kind = read_summary(run_dir).get("kind")
        kind0 = kind0 or kind
        if kind != kind0:
            skipped += 1
            continue
        colour = cmap(i / max(1, len(runs) - 1))
        style = "-" if row["status"] == "ok" else "--"
        for ax, (x, xlabel, y, ylabel) in zip(axes, curves_of(h, kind)):
            ax.plot(x, y, style, color=colour, lw=1.2, label=label_of(row, keys, many_scenes))
            ax.set_xlabel(xlabel)
            ax.set_ylabel(ylabel)
    for ax in axes:
        ax.grid(True, lw=0.3, alpha=0.6)
    if len(runs) <= LEGEND_RUNS:
        axes[0].legend(fontsize=7, loc="best")
    else:
        sm = plt.cm.ScalarMappable(cmap=cmap, norm=plt.Normalize(1, len(runs)))
        fig.colorbar(sm, ax=axes.tolist(), label="run (sweep.csv row)")
    title = f"{os.path.basename(os.path.normpath(sweep_dir))}: {len(runs)} runs"
    if keys:
        title += " over " + ", ".join(keys)
    if skipped:
        title += f" ({skipped} of another kind or without history, not drawn)"
    fig.suptitle(title, fontsize=10)
    if len(runs) <= LEGEND_RUNS:
        fig.tight_layout()
    fig.savefig(out, dpi=DPI)
    plt.close(fig)
    return out


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) >= 2 else 2
    sweep_dir = argv[1]
    out = os.path.join(sweep_dir, "sweep.png")
    if len(argv) == 4 and argv[2] == "--out":
        out = argv[3]
    elif len(argv) != 2:
        print("plot_sweep: usage: plot_sweep.py DIR [--out FILE.png]", file=sys.stderr)
        return 2
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_sweep: matplotlib is not available for this Python "
              f"({sys.executable}); no plot drawn (try /usr/bin/python3)")
        return 0
    try:
        print(f"plot_sweep: {plot(plt, sweep_dir, out)}")
    except (OSError, ValueError, KeyError) as err:
        print(f"plot_sweep: {sweep_dir}: cannot plot: {err}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
