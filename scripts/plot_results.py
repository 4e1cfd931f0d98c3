#!/usr/bin/env python3
"""Plots the results of ifsim runs: one PNG per run directory.

Usage: plot_results.py DIR [DIR ...]

Each DIR is a run's output directory (history.csv, summary.json) or a directory whose
subdirectories are run directories (e.g. results/). The figure goes to DIR/overview.png.
Plotters are chosen by the run's kind (summary.json "kind"); add a function to PLOTTERS for
a new kind. Runs with Debian's /usr/bin/python3 (python3-matplotlib); without matplotlib it
says so and exits 0, the data stay in the CSV files.
"""

import csv
import json
import math
import os
import sys

HISTORY = "history.csv"
SUMMARY = "summary.json"
FIGURE = "overview.png"


def read_history(run_dir):
    """Columns of history.csv as lists of floats, by column name."""
    with open(os.path.join(run_dir, HISTORY), newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        columns = {name: [] for name in header}
        for row in reader:
            if len(row) != len(header):
                continue  # a truncated last line of an aborted run
            for name, value in zip(header, row):
                columns[name].append(float(value))
    return columns


def read_summary(run_dir):
    path = os.path.join(run_dir, SUMMARY)
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return json.load(f)


def run_title(run_dir, summary):
    scene = summary.get("scene") or run_dir
    name = os.path.splitext(os.path.basename(os.path.normpath(scene)))[0]
    parts = [name]
    if summary.get("model"):
        parts.append(summary["model"])
    if summary.get("status") == "failed":
        parts.append("FAILED")
    return " | ".join(parts)


def element_quantities(h):
    """Mean pressure p, signed deviator q, strains of an element test (compression positive)."""
    n = len(h["step"])
    p, q, eps_v, eps_axial, gamma, tau = [], [], [], [], [], []
    for i in range(n):
        s = [h[c][i] for c in ("s11", "s22", "s33", "s12", "s13", "s23")]
        mean = (s[0] + s[1] + s[2]) / 3.0
        dev = [s[0] - mean, s[1] - mean, s[2] - mean]
        j2 = 0.5 * (dev[0] ** 2 + dev[1] ** 2 + dev[2] ** 2) + s[3] ** 2 + s[4] ** 2 + s[5] ** 2
        # Positive in triaxial compression (axial stress 11 the most compressive).
        sign = 1.0 if 0.5 * (s[1] + s[2]) - s[0] >= 0.0 else -1.0
        p.append(-mean)
        q.append(sign * math.sqrt(3.0 * j2))
        eps_v.append(-100.0 * (h["eps11"][i] + h["eps22"][i] + h["eps33"][i]))
        eps_axial.append(-100.0 * h["eps11"][i])
        gamma.append(200.0 * h["eps12"][i])
        tau.append(s[3])
    return dict(p=p, q=q, eps_v=eps_v, eps_axial=eps_axial, gamma=gamma, tau=tau, e=h["e"], stage=h["stage"])


def by_stage(x, y, stage):
    """Splits a curve at stage changes, so each stage gets its own colour."""
    pieces, start = [], 0
    for i in range(1, len(stage) + 1):
        if i == len(stage) or stage[i] != stage[i - 1]:
            lo = max(start - 1, 0)  # join the pieces at the stage boundary
            if stage[i - 1] > 0:  # step 0 (stage 0) starts the first stage's curve
                pieces.append((int(stage[i - 1]), x[lo:i], y[lo:i]))
            start = i
    return pieces


def plot_element_test(plt, run_dir, h, summary):
    v = element_quantities(h)
    shear = any(abs(g) > 0.0 for g in v["gamma"])
    fig, ax = plt.subplots(2, 2, figsize=(11, 8.5))
    if shear:
        strain, strain_label = v["gamma"], "shear strain $\\gamma_{12} = 2\\varepsilon_{12}$ [%]"
        panels = [
            (ax[0][0], v["p"], v["tau"], "mean pressure $p$ [kPa]",
             "shear stress $\\sigma_{12}$ [kPa]", "stress path"),
            (ax[0][1], strain, v["tau"], strain_label, "shear stress $\\sigma_{12}$ [kPa]",
             "stress-strain"),
        ]
    else:
        strain, strain_label = v["eps_axial"], "axial strain $-\\varepsilon_{11}$ [%]"
        panels = [
            (ax[0][0], v["p"], v["q"], "mean pressure $p$ [kPa]", "deviator stress $q$ [kPa]",
             "stress path"),
            (ax[0][1], strain, v["q"], strain_label, "deviator stress $q$ [kPa]",
             "stress-strain"),
        ]
    panels += [
        (ax[1][0], v["p"], v["e"], "mean pressure $p$ [kPa]", "void ratio $e$", "compression"),
        (ax[1][1], strain, v["eps_v"], strain_label,
         "volumetric strain $-\\varepsilon_v$ [%] (compaction +)", "volume change"),
    ]
    for axis, x, y, xlabel, ylabel, title in panels:
        for stage, xs, ys in by_stage(x, y, v["stage"]):
            axis.plot(xs, ys, lw=1.2, label=f"stage {stage}")
        axis.set_xlabel(xlabel)
        axis.set_ylabel(ylabel)
        axis.set_title(title, fontsize=10)
        axis.ticklabel_format(useOffset=False)
        if "pressure" in xlabel:
            axis.set_xlim(left=0.0)  # the origin shows the slope of the stress ratio
        axis.grid(True, alpha=0.3)
    stages = {int(s) for s in v["stage"] if s > 0}
    if 1 < len(stages) <= 12:
        ax[0][1].legend(fontsize=8)
    fig.suptitle(run_title(run_dir, summary))
    fig.tight_layout()
    out = os.path.join(run_dir, FIGURE)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


PLOTTERS = {"element-test": plot_element_test}


def guess_kind(h):
    return "element-test" if "eps11" in h and "s11" in h else None


def run_dirs(paths):
    """The run directories among the arguments and their immediate subdirectories, and the
    arguments that hold none."""
    found, empty = [], []
    for path in paths:
        if os.path.exists(os.path.join(path, HISTORY)):
            found.append(path)
            continue
        runs = []
        if os.path.isdir(path):
            subs = sorted(os.path.join(path, d) for d in os.listdir(path))
            runs = [d for d in subs if os.path.exists(os.path.join(d, HISTORY))]
        if not runs:
            print(f"plot_results: {path}: no {HISTORY} here or one level below", file=sys.stderr)
            empty.append(path)
        found += runs
    return found, empty


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) >= 2 else 2
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_results: matplotlib is not available for this Python "
              f"({sys.executable}); no plots drawn (try /usr/bin/python3)")
        return 0
    found, empty = run_dirs(argv[1:])
    status = 1 if empty else 0
    for run_dir in found:
        try:
            h = read_history(run_dir)
            summary = read_summary(run_dir)
            kind = summary.get("kind") or guess_kind(h)
            plotter = PLOTTERS.get(kind)
            if plotter is None:
                print(f"plot_results: {run_dir}: no plot for kind {kind!r} yet")
                continue
            if not h.get("step"):
                print(f"plot_results: {run_dir}: {HISTORY} has no rows")
                continue
            print(f"plot_results: {plotter(plt, run_dir, h, summary)}")
        except (OSError, ValueError, KeyError, StopIteration) as err:
            print(f"plot_results: {run_dir}: cannot plot: {err}", file=sys.stderr)
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))
