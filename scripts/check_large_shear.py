#!/usr/bin/env python3
"""Checks a finished run of the large-scale cyclic interface shear test (paper §6).

Usage: check_large_shear.py RUN_DIR

Properties the test demands, independent of the mesh and the interface model:
  - the run finished (summary.json status ok) and every number in history.csv is finite
    (empty cells are allowed: the point recorders have none in row 0);
  - the rough segment stays in contact (closed points in every wall row) under compression
    (t_n < 0);
  - at the end of each wall stage the mean shear traction on the soil points along the wall's
    last motion: positive (t1 = downwards) after a downward stage, negative after an upward one;
  - continuum interfaces: the dense sand's band dilates while the wall goes down the first time
    (eps_n rises over stage 5) and its void ratio stays inside the model's bounds (0.5 .. 1.0).
Exits 1 naming the first property that fails.
"""
import csv
import json
import math
import sys
from pathlib import Path


def fail(msg):
    print(f"check_large_shear: {msg}", file=sys.stderr)
    sys.exit(1)


def main():
    if len(sys.argv) != 2:
        fail("usage: check_large_shear.py RUN_DIR")
    run = Path(sys.argv[1])
    summary = json.loads((run / "summary.json").read_text())
    if summary.get("status") != "ok":
        fail(f"{run}: status {summary.get('status')}: {summary.get('reason')}")
    with open(run / "history.csv", newline="") as f:
        rows = list(csv.DictReader(f))
    for i, r in enumerate(rows):
        for k, v in r.items():
            if v == "":  # a column without a value in this row (point recorders in row 0)
                continue
            if not math.isfinite(float(v)):
                fail(f"row {i}: {k} = {v}")
    wall = [r for r in rows if int(r["stage"]) >= 5]
    if not wall:
        fail("no rows of the wall stages (5 and later)")
    for r in wall:
        if int(float(r["closed_points"])) <= 0 or float(r["t_n"]) >= 0.0:
            fail(f"increment {r['increment']}: the rough segment lost contact "
                 f"(closed_points {r['closed_points']}, t_n {r['t_n']})")
    last = {}
    for r in wall:
        last[int(r["stage"])] = r
    for stage, r in sorted(last.items()):
        down = (stage - 5) % 2 == 0  # 5, 7: down; 6, 8: up
        t = float(r["t_t1"])
        if (t <= 0.0) if down else (t >= 0.0):
            fail(f"end of stage {stage} ({'down' if down else 'up'}): mean shear t_t1 = {t} kPa "
                 "does not follow the wall")
    if "eps_n" in rows[0]:
        s5 = [r for r in rows if int(r["stage"]) == 5]
        if float(s5[-1]["eps_n"]) <= float(s5[0]["eps_n"]):
            fail(f"the band did not dilate in stage 5 (eps_n {s5[0]['eps_n']} -> {s5[-1]['eps_n']})")
        for r in rows:
            e = float(r["e_interface"])
            if not 0.5 < e < 1.0:
                fail(f"increment {r['increment']}: interface void ratio {e} outside 0.5 .. 1.0")
    print(f"check_large_shear: {run}: {len(rows)} rows, every property holds")


if __name__ == "__main__":
    main()
