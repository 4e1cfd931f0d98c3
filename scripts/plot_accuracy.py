#!/usr/bin/env python3
"""Plots the accuracy study of the interface knobs (bench/study_interface_accuracy).

Usage: plot_accuracy.py CSV OUT.png [--table]

CSV is the study's accuracy.csv. One row of panels per test (mono-novel, mono-stutz,
cyclic-novel): error of the shear stress against wall time (left) and against constitutive
evaluations (right), both log-log. Each knob has its own colour and marker; numeric knobs are
joined in the order of their value (through the default), every point is labelled with its
value; the engine defaults are a gold star, the paper's settings (no polishing Newton step) a red
square; failed runs are drawn hollow with an x. The reference run (error 0 by definition) is left
out.

With --table the script also prints, as markdown, one table per test, the error/evaluation
front with the runs that beat the engine default and the paper, and the evaluations saved by
adaptive sub-increments at no worse error than the fixed 5e-6 runs.

Runs with Debian's /usr/bin/python3 (python3-matplotlib).
"""

import csv
import math
import sys

STYLE = {
    "max_subincrement": ("tab:blue", "o"),
    "max_subincrement_tight_step": ("navy", "o"),
    "tolerance": ("tab:orange", "s"),
    "polish_iterations": ("tab:red", "D"),
    "jacobian": ("tab:purple", "^"),
    "theta": ("tab:brown", "v"),
    "step_tolerance": ("tab:gray", "P"),
    "model_tolerance": ("tab:olive", "X"),
    "inner_jacobian": ("tab:pink", "h"),
    "adaptive_tolerance": ("tab:green", "<"),
    "adaptive_tolerance_tight_step": ("tab:cyan", ">"),
    "adaptive_model_tolerance": ("darkgreen", "p"),
    "adaptive_inner_tolerance": ("lime", "d"),
}


# Knobs with a numeric value in a CSV column of the same name (the default has one too).
NUMERIC = ("max_subincrement", "tolerance", "polish_iterations", "theta", "step_tolerance",
           "model_tolerance")


def number(text):
    try:
        v = float(text)
    except (TypeError, ValueError):
        return math.nan
    return v


def load(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"{path}: no rows")
    for r in rows:
        for k in ("err_tau", "err_un", "wall_s", "evaluations"):
            r[k] = number(r.get(k))
        r["ok"] = r.get("ok") == "1"
        r["is_default"] = r.get("is_default") == "1"
        r["is_paper"] = r.get("is_paper") == "1"
    return rows


def usable(r, xkey):
    return (
        r["knob"] != "reference"
        and math.isfinite(r["err_tau"])
        and r["err_tau"] > 0.0
        and math.isfinite(r[xkey])
        and r[xkey] > 0.0
    )


def panel(ax, rows, xkey, xlabel, show_labels):
    default = next((r for r in rows if r["is_default"]), None)
    for knob, (colour, marker) in STYLE.items():
        pts = [r for r in rows if r["knob"] == knob and usable(r, xkey)]
        if not pts:
            continue
        # Numeric knobs: a line through the runs and the default, in the order of the value.
        line = list(pts)
        if knob in NUMERIC and default is not None and usable(default, xkey):
            line.append(default)
            line.sort(key=lambda r: number(r.get(knob)))
        if knob in NUMERIC or knob.startswith("adaptive"):
            ax.plot([r[xkey] for r in line], [r["err_tau"] for r in line], "-", color=colour,
                    alpha=0.35, lw=1)
        for r in pts:
            face = colour if r["ok"] else "none"
            ax.plot(r[xkey], r["err_tau"], marker, color=colour, mfc=face, ms=6, ls="none")
            if not r["ok"]:
                ax.plot(r[xkey], r["err_tau"], "x", color="k", ms=5)
            if show_labels:
                ax.annotate(r["value"], (r[xkey], r["err_tau"]), fontsize=5.5, color=colour,
                            xytext=(3, 2), textcoords="offset points")
        ax.plot([], [], marker, color=colour, ls="-", label=knob)
    if default is not None and usable(default, xkey):
        ax.plot(default[xkey], default["err_tau"], "*", color="k", ms=13, mfc="gold",
                label="engine default", zorder=5)
    for r in rows:
        if r["is_paper"] and usable(r, xkey):
            ax.plot(r[xkey], r["err_tau"], "s", ms=12, mfc="none", mec="red", mew=1.8,
                    label="paper (no polishing)", zorder=5)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(xlabel)
    ax.set_ylabel("max |t_t1 - ref| / max |ref|")
    ax.grid(True, which="both", lw=0.3, alpha=0.5)


# An adaptive run counts as no worse than a fixed one within this factor on both errors.
SLACK = 1.05


def fmt(v, digits=3):
    if isinstance(v, float):
        if not math.isfinite(v):
            return "–"
        return f"{v:.{digits}g}"
    return str(v)


def print_tables(rows):
    tests = []
    for r in rows:
        if r["test"] not in tests:
            tests.append(r["test"])
    for test in tests:
        sub = [r for r in rows if r["test"] == test]
        print(f"\n#### {test}\n")
        print("| knob | value | ok | err τ | err u_n | wall (s) | evaluations | outer Newton "
              "| step cuts | note |")
        print("|---|---|---|---|---|---|---|---|---|---|")
        for r in sub:
            note = []
            if r["is_default"]:
                note.append("**engine default**")
            if r["is_paper"]:
                note.append("**paper**")
            if not r["ok"]:
                note.append("failed: " + r.get("reason", ""))
            print(f"| {r['knob']} | {r['value']} | {'yes' if r['ok'] else 'no'} "
                  f"| {fmt(r['err_tau'])} | {fmt(r['err_un'])} | {fmt(r['wall_s'])} "
                  f"| {fmt(r['evaluations'])} | {r.get('outer_newton', '')} "
                  f"| {r.get('step_cuts', '')} | {'; '.join(note)} |")
    print("\n#### Error against evaluations: the front\n")
    print("Runs no other run beats in both err τ and evaluations (max of err τ and err u_n "
          "used as the error), and the runs that beat the engine default and the paper.\n")
    print("| test | on the front (cheapest first) | beat the engine default | beat the paper |")
    print("|---|---|---|---|")
    for test in tests:
        sub = [r for r in rows if r["test"] == test and r["knob"] != "reference" and r["ok"]
               and math.isfinite(r["err_tau"])]
        err = lambda r: max(r["err_tau"], r["err_un"])

        def beats(a, b):
            return (err(a) <= err(b) and a["evaluations"] <= b["evaluations"]
                    and (err(a) < err(b) or a["evaluations"] < b["evaluations"]))

        name = lambda r: f"{r['knob']}={r['value']}"
        front = sorted([r for r in sub if not any(beats(o, r) for o in sub)],
                       key=lambda r: r["evaluations"])
        cols = [", ".join(f"{name(r)} ({fmt(err(r), 2)}, {fmt(r['evaluations'], 2)})"
                          for r in front)]
        for flag in ("is_default", "is_paper"):
            base = next((r for r in sub if r[flag]), None)
            if base is None:
                cols.append("–")
                continue
            better = [name(r) for r in sub if beats(r, base)]
            if not better:
                cols.append("none: on the front")
            elif flag == "is_paper":
                cols.append(f"{len(better)} of {len(sub) - 1} other runs")
            else:
                cols.append(", ".join(better))
        print(f"| {test} | " + " | ".join(cols) + " |")

    print("\n#### Adaptive against fixed 5e-6 sub-increments\n")
    print(f"The cheapest adaptive run (any series) whose err τ and err u_n are both no worse "
          f"than the fixed run's; 'no worse' allows {100 * (SLACK - 1):.0f} % for measurement "
          f"noise.\n")
    print("| test | fixed 5e-6 run | its err τ / err u_n | its evaluations | cheapest adaptive "
          "run no worse | its err τ / err u_n | its evaluations | evaluations saved "
          "| wall time saved |")
    print("|---|---|---|---|---|---|---|---|---|")
    for test in tests:
        sub = [r for r in rows if r["test"] == test]
        bases = []
        for r in sub:
            if r["is_default"]:
                bases.append(("engine default (step tol 1e-4)", r))
            elif r["is_paper"]:
                bases.append(("paper: polish 0 (step tol 1e-4)", r))
            elif r["knob"] == "step_tolerance" and number(r["value"]) < 1e-4:
                bases.append((f"engine default, step tol {r['value']}", r))
        adaptive = [a for a in sub if a["knob"].startswith("adaptive") and a["ok"]]
        for name, base in bases:
            good = [a for a in adaptive
                    if a["err_tau"] <= SLACK * base["err_tau"]
                    and a["err_un"] <= SLACK * base["err_un"]]
            if good:
                best = min(good, key=lambda a: a["evaluations"])
                what = f"{best['knob']} = {best['value']}"
                saved = f"{base['evaluations'] / best['evaluations']:.0f}x"
                tsaved = f"{base['wall_s'] / best['wall_s']:.1f}x"
            elif adaptive:
                best = min(adaptive, key=lambda a: max(a["err_tau"], a["err_un"]))
                what = f"none (most accurate: {best['knob']} = {best['value']})"
                saved = tsaved = "–"
            else:
                best, what, saved, tsaved = None, "none run", "–", "–"
            errs = f"{fmt(best['err_tau'])} / {fmt(best['err_un'])}" if best else "–"
            ev = fmt(best["evaluations"]) if best else "–"
            print(f"| {test} | {name} | {fmt(base['err_tau'])} / {fmt(base['err_un'])} "
                  f"| {fmt(base['evaluations'])} | {what} | {errs} | {ev} | {saved} | {tsaved} |")


def main(argv):
    table = "--table" in argv
    argv = [a for a in argv if a != "--table"]
    if len(argv) != 3:
        sys.exit(__doc__)
    if table:
        print_tables(load(argv[1]))
    try:
        import matplotlib

        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_accuracy.py: matplotlib is not installed (python3-matplotlib); no plot")
        return 0
    rows = load(argv[1])
    tests = []
    for r in rows:
        if r["test"] not in tests:
            tests.append(r["test"])
    fig, axes = plt.subplots(len(tests), 2, figsize=(13, 4.6 * len(tests)), squeeze=False)
    for i, test in enumerate(tests):
        sub = [r for r in rows if r["test"] == test]
        failed = sum(1 for r in sub if not r["ok"])
        panel(axes[i][0], sub, "wall_s", "wall time (s)", True)
        panel(axes[i][1], sub, "evaluations", "constitutive evaluations", True)
        title = test + (f"  ({failed} failed run(s), hollow)" if failed else "")
        axes[i][0].set_title(title + ": error against wall time", fontsize=10)
        axes[i][1].set_title(title + ": error against evaluations", fontsize=10)
    handles, labels = axes[0][1].get_legend_handles_labels()
    seen = {}
    for h, l in zip(handles, labels):
        seen.setdefault(l, h)
    fig.legend(list(seen.values()), list(seen.keys()), loc="upper center", ncol=6, fontsize=8,
               frameon=False)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.7 / (4.6 * len(tests))))
    fig.savefig(argv[2], dpi=130)
    print(f"wrote {argv[2]}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
