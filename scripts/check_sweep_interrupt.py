#!/usr/bin/env python3
"""A sweep stopped by SIGTERM part-way and then run again ends with the table of a sweep that
was never stopped: the stopped sweep exits 143 with sweep.csv.partial, sweep.json "interrupted"
and no sweep.csv; the second command redoes only what did not finish.

Usage: check_sweep_interrupt.py IFSIM WORKDIR
Exit 0 when all holds, 1 otherwise.
"""
import csv
import json
import os
import shutil
import signal
import subprocess
import sys
import time

SWEEP = """scene = "{scene}"
[grid]
"initial.void_ratio" = [0.62, 0.66, 0.70, 0.74]
[set]
"stage.1.steps" = 400
"""


def table(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    wall = rows[0].index("wall_s")
    return [r[:wall] + r[wall + 1:] for r in rows]


def main():
    ifsim, work = sys.argv[1:3]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    sweep = os.path.join(work, "sweep.toml")
    with open(sweep, "w") as f:
        f.write(SWEEP.format(scene=os.path.abspath("scenes/element-hypo-triaxial-drained-dense.toml")))
    whole, stopped = os.path.join(work, "whole"), os.path.join(work, "stopped")
    subprocess.run([ifsim, "sweep", sweep, "--out", whole, "-q", "--jobs", "1"], check=True)
    failures = []
    proc = subprocess.Popen([ifsim, "sweep", sweep, "--out", stopped, "--jobs", "1"],
                            stderr=subprocess.PIPE, text=True)
    for line in proc.stderr:  # stop once the first run has ended
        if "[1/4]" in line:
            proc.send_signal(signal.SIGTERM)
            break
    proc.stderr.read()
    code = proc.wait()
    summary = json.load(open(os.path.join(stopped, "sweep.json")))
    if code != 128 + signal.SIGTERM:
        failures.append(f"the stopped sweep exited with {code}, not 143")
    if os.path.exists(os.path.join(stopped, "sweep.csv")):
        failures.append("a stopped sweep left a sweep.csv")
    if not os.path.exists(os.path.join(stopped, "sweep.csv.partial")):
        failures.append("no sweep.csv.partial")
    if summary.get("status") != "interrupted" or summary.get("ok", 0) >= 4:
        failures.append(f"sweep.json: status {summary.get('status')}, ok {summary.get('ok')}")
    done_before = summary.get("ok", 0)
    time.sleep(0.1)
    subprocess.run([ifsim, "sweep", sweep, "--out", stopped, "-q", "--jobs", "1"], check=True)
    summary = json.load(open(os.path.join(stopped, "sweep.json")))
    if summary.get("reused") != done_before or summary.get("ok") != 4:
        failures.append(f"second command: reused {summary.get('reused')} (expected "
                        f"{done_before}), ok {summary.get('ok')}")
    if table(os.path.join(whole, "sweep.csv")) != table(os.path.join(stopped, "sweep.csv")):
        failures.append("the resumed sweep's table differs from the uninterrupted one")
    if os.path.exists(os.path.join(stopped, "sweep.csv.partial")):
        failures.append("sweep.csv.partial left next to the complete table")
    for f in failures:
        print(f"check_sweep_interrupt: FAILED: {f}")
    if not failures:
        print(f"check_sweep_interrupt: stopped after {done_before} of 4 runs; run again, the "
              "table equals the uninterrupted sweep's")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
