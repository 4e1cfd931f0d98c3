#!/usr/bin/env python3
"""Checks the output of scripts/large_shear_table5.py.

Usage: check_table5.py OUT_DIR

Every row of OUT/table5.csv must agree with its run's summary.json (status, Newton iterations,
total time), its times must add up (contact, element and solve each at most the total), its
core-seconds ratio must be the paper's total x 4 over the run's total x threads, and
table5.md must list the same runs. Exits 1 naming the first property that fails.
"""
import csv
import json
import math
import sys
from pathlib import Path


def fail(msg):
    print(f"check_table5: {msg}", file=sys.stderr)
    sys.exit(1)


def main():
    if len(sys.argv) != 2:
        fail("usage: check_table5.py OUT_DIR")
    out = Path(sys.argv[1])
    with open(out / "table5.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows:
        fail("table5.csv has no rows")
    md = (out / "table5.md").read_text()
    for r in rows:
        name = r["run"]
        s = json.loads((out / name / "summary.json").read_text())
        if r["status"] != s["status"]:
            fail(f"{name}: status {r['status']} against summary.json's {s['status']}")
        if int(r["newton_iterations"]) != s["counters"]["newton_iterations"]:
            fail(f"{name}: Newton iterations differ from summary.json")
        total = float(r["total_s"])
        if not math.isclose(total, s["timing"]["wall_s"], abs_tol=0.051):
            fail(f"{name}: total {total} against summary.json's {s['timing']['wall_s']}")
        for k in ("contact_s", "element_s", "solve_s"):
            if not 0.0 <= float(r[k]) <= total + 0.1:
                fail(f"{name}: {k} {r[k]} outside [0, total {total}]")
        expected = float(r["paper_total_s"]) * 4 / (s["timing"]["wall_s"] * int(r["threads"]))
        if not math.isclose(float(r["core_seconds_ratio"]), expected, rel_tol=0.01, abs_tol=0.06):
            fail(f"{name}: core-seconds ratio {r['core_seconds_ratio']}, expected {expected:.1f}")
        if f"| {name} |" not in md:
            fail(f"table5.md does not list {name}")
    print(f"check_table5: {out}: {len(rows)} row(s), every property holds")


if __name__ == "__main__":
    main()
