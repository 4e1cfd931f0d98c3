#!/usr/bin/env python3
"""Plots a calibration (`ifsim calibrate ... --out DIR`) into DIR/fit.png: the measured shear
stress and normal displacement against the fitted run's over the tangential displacement, and
the cost of every evaluated point (failed runs marked) in the order they ran.

Usage: plot_calibration.py DIR
Runs with Debian's /usr/bin/python3 (python3-matplotlib); without matplotlib it says so and
exits 0.
"""

import csv
import json
import math
import os
import sys


def column(rows, name):
    return [float(r[name]) if r[name] not in ("", "nan") else math.nan for r in rows]


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) == 2 else 2
    out = argv[1]
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_calibration: matplotlib is not available for this Python "
              f"({sys.executable}); no plot drawn (try /usr/bin/python3)")
        return 0
    try:
        summary = json.load(open(os.path.join(out, "calibration.json")))
        fit = list(csv.DictReader(open(os.path.join(out, "fit.csv"))))
        evals = list(csv.DictReader(open(os.path.join(out, "evaluations.csv"))))
    except (OSError, ValueError) as err:
        print(f"plot_calibration: {out}: cannot plot: {err}", file=sys.stderr)
        return 1
    u = [1000.0 * x for x in column(fit, "u_t")]
    fig, axes = plt.subplots(1, 3, figsize=(15, 4.4))
    axes[0].plot(u, column(fit, "t_t_data"), "o", ms=3, color="0.4", label="data")
    axes[0].plot(u, column(fit, "t_t_fit"), "-", color="C0", label="fit")
    axes[0].set_ylabel("shear stress t_t (kPa)")
    has_un = any(r["u_n_data"] for r in fit)
    if has_un:
        axes[1].plot(u, [1000.0 * x for x in column(fit, "u_n_data")], "o", ms=3, color="0.4",
                     label="data")
    axes[1].plot(u, [1000.0 * x for x in column(fit, "u_n_fit")], "-", color="C1", label="fit")
    axes[1].set_ylabel("normal displacement u_n (mm)")
    for ax in axes[:2]:
        ax.set_xlabel("tangential displacement u_t (mm)")
        ax.legend(fontsize=8)
        ax.grid(True, lw=0.3, alpha=0.6)
    ok = [(i + 1, float(e["cost"])) for i, e in enumerate(evals) if e["status"] == "ok"]
    bad = [i + 1 for i, e in enumerate(evals) if e["status"] != "ok"]
    axes[2].semilogy([i for i, _ in ok], [c for _, c in ok], ".", color="C2", label="run")
    if bad:
        low = min((c for _, c in ok), default=1.0)
        axes[2].semilogy(bad, [low] * len(bad), "x", color="crimson", label="failed run")
    axes[2].set_xlabel("evaluation (run) number")
    axes[2].set_ylabel("cost 1/2 sum r^2")
    axes[2].legend(fontsize=8)
    axes[2].grid(True, lw=0.3, alpha=0.6)
    values = ", ".join(f"{p['key'].split('.')[-1]} = {p['fitted']:.4g}"
                       for p in summary["parameters"])
    state = "converged" if summary.get("converged") else "NOT converged"
    fig.suptitle(f"{values} ({state}, {summary.get('iterations')} iterations, "
                 f"rms t_t {summary.get('rms_t_t', math.nan):.3g} kPa)", fontsize=10)
    fig.tight_layout()
    path = os.path.join(out, "fit.png")
    fig.savefig(path, dpi=110)
    print(f"plot_calibration: {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
