#!/usr/bin/env python3
"""Plots the results of ifsim runs: one PNG per run directory, or one comparison of runs.

Usage: plot_results.py DIR [DIR ...]
       plot_results.py --compare OUT.png [--height H] DIR1 DIR2 [DIR ...]

Each DIR is a run's output directory (history.csv, summary.json) or a directory whose
subdirectories are run directories (e.g. results/). The figure goes to DIR/overview.png.
Plotters are chosen by the run's kind (summary.json "kind"); add a function to PLOTTERS for
a new kind.
  element-test    stress path, stress-strain, compression, volume change
  boundary-value  t_t1, t_n, u_n (and s_p1, s_p2 of a continuum interface) over u_t1 (mm),
                  one curve per stage; cyclic runs also get cycles.png as interface tests
  interface-test  paper Fig. 6 style: t_t1, s_p1, s_p2, sample_s22, sample_s33 and u_n over
                  the plate displacement u_t1 (mm); for cyclic runs also DIR/cycles.png in the
                  style of Fig. 7: t_t1 and u_n over u_t1 for cycle N = 1 and N = 11 (or the
                  last complete cycle). A cycle starts where u_t1 passes its start value
                  moving in the direction of stage 1; the stages give the directions.
--compare overlays t_t1, s_p1 and sample_s22 over u_t1 of several runs in OUT.png (novel vs
Stutz, paper Appendix C Fig. C1). An element-test run among them (the sample sheared alone)
is drawn as the test without interface: u_t1 = 2 eps12 H (H = --height, default 0.02 m),
t_t1 = s12, s_p1 = sample_s22 = s22.
Runs with Debian's /usr/bin/python3 (python3-matplotlib); without matplotlib it says so and
exits 0, the data stay in the CSV files.
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
                # An empty field is a quantity the run does not have (boundary-value runs).
                columns[name].append(float(value) if value != "" else math.nan)
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


def mm(values):
    return [1000.0 * v for v in values]


def stage_directions(h, key="u_t1"):
    """Sign (+1, -1 or 0) of the change of `key` over each stage, by stage number."""
    u, stage = h[key], h["stage"]
    direction, start = {}, 0
    for i in range(1, len(stage) + 1):
        if i == len(stage) or stage[i] != stage[i - 1]:
            s = int(stage[i - 1])
            if s > 0:
                change = u[i - 1] - u[max(start - 1, 0)]
                direction[s] = (change > 0) - (change < 0)
            start = i
    return direction


def cycle_numbers(h):
    """Cycle number of every row: cycle 1 starts at step 0; a new cycle starts where u_t1
    passes its start value again moving in the direction of the first stage that moves it
    (an FE run's consolidation stage does not)."""
    u, stage = h["u_t1"], h["stage"]
    direction = stage_directions(h)
    d0 = next((d for _, d in sorted(direction.items()) if d != 0), 0)
    amplitude = max((abs(x - u[0]) for x in u), default=0.0)
    tol = 1e-9 * amplitude
    numbers, n = [1], 1
    for i in range(1, len(u)):
        if d0 and direction.get(int(stage[i]), 0) == d0:
            before, after = (u[i - 1] - u[0]) * d0, (u[i] - u[0]) * d0
            if before < -tol and after >= -tol:
                n += 1
        numbers.append(n)
    return numbers


def is_cyclic(h):
    directions = [d for _, d in sorted(stage_directions(h).items()) if d != 0]
    return any(a != b for a, b in zip(directions, directions[1:]))


def cycle_rows(numbers, n):
    """Row indices of cycle n, closed by the first row of the next cycle."""
    rows = [i for i, c in enumerate(numbers) if c == n]
    if rows and rows[-1] + 1 < len(numbers):
        rows.append(rows[-1] + 1)
    return rows


def complete_cycles(numbers):
    """Cycles that came back to the start value: the current (last) cycle number is open, or
    was just opened by the run's last row where it returned to the start."""
    return numbers[-1] - 1 if numbers else 0


def interface_axes(ax, xlabel, ylabel, title):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.ticklabel_format(useOffset=False)
    ax.grid(True, alpha=0.3)


U_LABEL = "plate displacement $u_{t1}$ [mm]"


def plot_interface_cycles(plt, run_dir, h, summary, wanted=(1, 11)):
    numbers = cycle_numbers(h)
    done = complete_cycles(numbers)
    if done < 1:
        return None
    cycles = sorted({min(n, done) for n in wanted})
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5))
    for n in cycles:
        rows = cycle_rows(numbers, n)
        u = [1000.0 * h["u_t1"][i] for i in rows]
        ax[0].plot(u, [h["t_t1"][i] for i in rows], lw=1.2, label=f"N = {n}")
        ax[1].plot(u, [1000.0 * h["u_n"][i] for i in rows], lw=1.2, label=f"N = {n}")
    interface_axes(ax[0], U_LABEL, "shear stress $t_{t1}$ [kPa]", "shear stress")
    interface_axes(ax[1], U_LABEL, "normal displacement $u_n$ [mm] (dilation +)",
                   "normal displacement")
    for a in ax:
        a.legend(fontsize=8)
    fig.suptitle(f"{run_title(run_dir, summary)} | cycles ({done} complete)")
    fig.tight_layout()
    out = os.path.join(run_dir, "cycles.png")
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


def plot_interface_test(plt, run_dir, h, summary):
    u = mm(h["u_t1"])
    panels = [
        ("t_t1", "shear stress $t_{t1}$ [kPa]", "(a) interface shear stress"),
        ("s_p1", "$\\sigma_{p1}$ [kPa]", "(b) interface normal stress $\\sigma_{p1}$"),
        ("s_p2", "$\\sigma_{p2}$ [kPa]", "(c) interface normal stress $\\sigma_{p2}$"),
        ("sample_s22", "$\\sigma_{22}$ [kPa]", "(d) sample normal stress $\\sigma_{22}$"),
        ("sample_s33", "$\\sigma_{33}$ [kPa]", "(e) sample normal stress $\\sigma_{33}$"),
        ("u_n", "normal displacement $u_n$ [mm] (dilation +)", "(f) normal displacement"),
    ]
    fig, ax = plt.subplots(2, 3, figsize=(14, 8))
    stages = {int(s) for s in h["stage"] if s > 0}
    for axis, (key, ylabel, title) in zip([a for row in ax for a in row], panels):
        y = mm(h[key]) if key == "u_n" else h[key]
        if len(stages) <= 4:
            for stage, xs, ys in by_stage(u, y, h["stage"]):
                axis.plot(xs, ys, lw=1.2, label=f"stage {stage}")
        else:  # cyclic runs: one curve
            axis.plot(u, y, lw=0.8)
        interface_axes(axis, U_LABEL, ylabel, title)
    if 1 < len(stages) <= 4:
        ax[0][0].legend(fontsize=8)
    details = [summary.get("formulation"), summary.get("normal_control")]
    fig.suptitle(" | ".join([run_title(run_dir, summary)] + [d for d in details if d]))
    fig.tight_layout()
    out = os.path.join(run_dir, FIGURE)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    if is_cyclic(h):
        cycles = plot_interface_cycles(plt, run_dir, h, summary)
        if cycles:
            out += f", {cycles}"
    return out


def plot_boundary_value(plt, run_dir, h, summary):
    """FE runs: t_t1, t_n, u_n (and the interface's s_p1, s_p2 when there) over u_t1, in the
    style of the interface-test plots; cyclic runs also get cycles.png."""
    u = mm(h["u_t1"])
    panels = [
        ("t_t1", "shear stress $t_{t1}$ [kPa]", "(a) mean shear traction on the soil"),
        ("t_n", "normal stress $t_n$ [kPa]", "(b) mean normal traction"),
        ("u_n", "normal displacement $u_n$ [mm] (dilation +)", "(c) normal displacement"),
    ]
    if any(not math.isnan(v) for v in h.get("s_p1", [])):
        panels.append(("s_p1", "$\\sigma_{p1}$ [kPa]", "(d) interface normal stress $\\sigma_{p1}$"))
        panels.append(("s_p2", "$\\sigma_{p2}$ [kPa]", "(e) interface normal stress $\\sigma_{p2}$"))
    fig, ax = plt.subplots(1, len(panels), figsize=(4.6 * len(panels), 4.2))
    stages = {int(s) for s in h["stage"] if s > 0}
    for axis, (key, ylabel, title) in zip(ax, panels):
        y = mm(h[key]) if key == "u_n" else h[key]
        if len(stages) <= 4:
            for stage, xs, ys in by_stage(u, y, h["stage"]):
                axis.plot(xs, ys, lw=1.2, label=f"stage {stage}")
        else:
            axis.plot(u, y, lw=0.8)
        interface_axes(axis, U_LABEL, ylabel, title)
    if 1 < len(stages) <= 4:
        ax[0].legend(fontsize=8)
    mesh = summary.get("mesh", {})
    details = [summary.get("formulation") or "no interface",
               f"{mesh.get('dimension', '?')}D, {mesh.get('elements', '?')} elements"]
    fig.suptitle(" | ".join([run_title(run_dir, summary)] + details))
    fig.tight_layout()
    out = os.path.join(run_dir, FIGURE)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    if is_cyclic(h):
        cycles = plot_interface_cycles(plt, run_dir, h, summary)
        if cycles:
            out += f", {cycles}"
    return out


PLOTTERS = {"element-test": plot_element_test, "interface-test": plot_interface_test,
            "boundary-value": plot_boundary_value}


def guess_kind(h):
    if "u_t1" in h and "t_t1" in h:
        return "interface-test"
    return "element-test" if "eps11" in h and "s11" in h else None


def comparison_curves(run_dir, height):
    """u_t1 (mm), t_t1, s_p1, sample_s22 and a label of one run for --compare."""
    h = read_history(run_dir)
    summary = read_summary(run_dir)
    kind = summary.get("kind") or guess_kind(h)
    label = run_title(run_dir, summary)
    if kind == "interface-test":
        form = summary.get("formulation", "")
        if form == "stutz" and summary.get("stutz_initial_stress"):
            form += f" ({summary['stutz_initial_stress']})"
        label = f"{label} [{form}]" if form else label
        return label, mm(h["u_t1"]), h["t_t1"], h["s_p1"], h["sample_s22"]
    if kind == "element-test":
        u = [2.0 * e * height * 1000.0 for e in h["eps12"]]
        return f"{label} [no interface]", u, h["s12"], h["s22"], h["s22"]
    raise ValueError(f"kind {kind!r} cannot be compared")


def compare(plt, out, dirs, height):
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.8))
    for run_dir in dirs:
        label, u, tau, sp1, s22 = comparison_curves(run_dir, height)
        ax[0].plot(u, tau, lw=1.2, label=label)
        ax[1].plot(u, sp1, lw=1.2, label=label)
        ax[2].plot(u, s22, lw=1.2, label=label)
    interface_axes(ax[0], U_LABEL, "shear stress $t_{t1}$ [kPa]", "(a) interface shear stress")
    interface_axes(ax[1], U_LABEL, "$\\sigma_{p1}$ [kPa]", "(b) interface normal stress $\\sigma_{p1}$")
    interface_axes(ax[2], U_LABEL, "$\\sigma_{22}$ [kPa]", "(c) sample normal stress $\\sigma_{22}$")
    ax[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return out


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


def compare_main(plt, args):
    """--compare OUT.png [--height H] DIR1 DIR2 ..."""
    height = 0.02
    if "--height" in args:
        i = args.index("--height")
        try:
            height = float(args[i + 1])
        except (IndexError, ValueError):
            print("plot_results: --height expects a sample height in m", file=sys.stderr)
            return 2
        args = args[:i] + args[i + 2:]
    if len(args) < 2 or not args[0].endswith(".png"):
        print("plot_results: usage: --compare OUT.png [--height H] DIR1 DIR2 ...",
              file=sys.stderr)
        return 2
    out, dirs = args[0], args[1:]
    missing = [d for d in dirs if not os.path.exists(os.path.join(d, HISTORY))]
    if missing:
        print(f"plot_results: no {HISTORY} in {', '.join(missing)}", file=sys.stderr)
        return 1
    try:
        print(f"plot_results: {compare(plt, out, dirs, height)}")
    except (OSError, ValueError, KeyError, StopIteration) as err:
        print(f"plot_results: cannot compare: {err}", file=sys.stderr)
        return 1
    return 0


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
    if argv[1] == "--compare":
        return compare_main(plt, argv[2:])
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
            if not (h.get("step") or h.get("increment")):
                print(f"plot_results: {run_dir}: {HISTORY} has no rows")
                continue
            print(f"plot_results: {plotter(plt, run_dir, h, summary)}")
        except (OSError, ValueError, KeyError, StopIteration) as err:
            print(f"plot_results: {run_dir}: cannot plot: {err}", file=sys.stderr)
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))
