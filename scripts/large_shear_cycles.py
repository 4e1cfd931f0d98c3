#!/usr/bin/env python3
"""The rough segment's shear peaks of each wall cycle of §6 runs, split into stress ratio and
normal stress.

Usage: large_shear_cycles.py [--markdown] RUN_DIR [RUN_DIR ...]

Each RUN_DIR holds a history.csv of a scene of scenes/large-shear*.toml (the `wall` recorder
and the rough pair's main columns). For every downward movement of the wall (stages whose
wall displacement grows, after the gravity stages) the row with the largest mean shear t_t1 is
the cycle's peak. Printed per peak: t_t1 (kPa), the wall displacement there (mm), the mean
normal stress t_n, the ratio t_t1 / |t_n|, the interface's in-plane stresses s_p1 (along t1)
and s_p2, its normal strain eps_n and void ratio. t_t1 = ratio x |t_n| tells whether two runs
differ by the band's strength (the ratio) or by the continuum's pressure on the wall (t_n).
"""
import argparse
import csv
import sys
from pathlib import Path

COLUMNS = ("t_t1", "wall", "t_n", "s_p1", "s_p2", "eps_n", "e_interface")


def read_rows(run):
    path = Path(run) / "history.csv"
    try:
        with open(path, newline="") as f:
            rows = list(csv.DictReader(f))
    except OSError as e:
        sys.exit(f"large_shear_cycles: {path}: {e.strerror}")
    if not rows:
        sys.exit(f"large_shear_cycles: {path}: no rows")
    missing = [c for c in ("stage",) + COLUMNS if c not in rows[0]]
    if missing:
        sys.exit(f"large_shear_cycles: {path}: missing column(s) {', '.join(missing)}")
    return rows


def downward_stages(rows):
    """Stages in which the wall moves down (its displacement grows), in order."""
    first = {}
    last = {}
    for r in rows:
        s = int(r["stage"])
        first.setdefault(s, float(r["wall"]))
        last[s] = float(r["wall"])
    return [s for s in sorted(first) if last[s] - first[s] > 1e-6]


def cycle_peaks(rows):
    peaks = []
    for stage in downward_stages(rows):
        in_stage = [r for r in rows if int(r["stage"]) == stage]
        top = max(in_stage, key=lambda r: float(r["t_t1"]))
        v = {c: float(top[c]) for c in COLUMNS}
        v["ratio"] = v["t_t1"] / -v["t_n"] if v["t_n"] < 0.0 else float("nan")
        peaks.append(v)
    return peaks


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("runs", nargs="+", metavar="RUN_DIR")
    ap.add_argument("--markdown", action="store_true", help="print a Markdown table")
    args = ap.parse_args()
    head = ["run", "cycle", "peak t_t1 kPa", "at wall mm", "t_n kPa", "ratio t_t1 / (-t_n)", "s_p1 kPa",
            "s_p2 kPa", "eps_n", "e"]
    lines = []
    for run in args.runs:
        for k, v in enumerate(cycle_peaks(read_rows(run)), start=1):
            lines.append([Path(run).name, str(k), f"{v['t_t1']:.3f}", f"{1e3 * v['wall']:.2f}",
                          f"{v['t_n']:.3f}", f"{v['ratio']:.3f}", f"{v['s_p1']:.2f}",
                          f"{v['s_p2']:.2f}", f"{v['eps_n']:.4f}", f"{v['e_interface']:.4f}"])
    if args.markdown:
        print("| " + " | ".join(head) + " |")
        print("|" + "---|" * len(head))
        for line in lines:
            print("| " + " | ".join(line) + " |")
    else:
        w = csv.writer(sys.stdout, lineterminator="\n")
        w.writerow(head)
        w.writerows(lines)


if __name__ == "__main__":
    main()
