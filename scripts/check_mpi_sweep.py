#!/usr/bin/env python3
"""Runs one sweep locally and under `mpirun -np 2` and compares the tables: the same sweep.csv
(rows in the same order, every cell but wall_s equal), runs handed to rank 1 as well as rank 0,
and a second mpirun reusing every finished run.

Usage: check_mpi_sweep.py IFSIM MPIRUN WORKDIR
Exit 0 when all holds, 1 otherwise.
"""
import csv
import json
import os
import shutil
import subprocess
import sys

SWEEP = """scene = "{scene}"
[grid]
"initial.void_ratio" = [0.62, 0.68, 0.74]
"stage.1.steps" = [20, 40]
"""


def table(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    wall = rows[0].index("wall_s")
    return [r[:wall] + r[wall + 1:] for r in rows]


def main():
    ifsim, mpirun, work = sys.argv[1:4]
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    scene = os.path.abspath("scenes/element-hypo-triaxial-drained-dense.toml")
    sweep = os.path.join(work, "sweep.toml")
    with open(sweep, "w") as f:
        f.write(SWEEP.format(scene=scene))
    local, ranks = os.path.join(work, "local"), os.path.join(work, "mpi")
    subprocess.run([ifsim, "sweep", sweep, "--out", local, "-q", "--jobs", "2"], check=True)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    mpi = [mpirun, "-np", "2", ifsim, "sweep", sweep, "--out", ranks]
    first = subprocess.run(mpi, env=env, capture_output=True, text=True)
    print(first.stderr, end="")
    failures = []
    if first.returncode != 0:
        failures.append(f"mpirun sweep exited with {first.returncode}")
    elif table(os.path.join(local, "sweep.csv")) != table(os.path.join(ranks, "sweep.csv")):
        failures.append("sweep.csv differs between the local and the 2-rank sweep")
    summary = json.load(open(os.path.join(ranks, "sweep.json")))
    if summary.get("ranks") != 2 or summary.get("ok") != 6:
        failures.append(f"sweep.json: ranks {summary.get('ranks')}, ok {summary.get('ok')}")
    if " rank 1 " not in first.stderr or " rank 0 " not in first.stderr:
        failures.append("runs were not spread over both ranks")
    again = subprocess.run(mpi + ["-q"], env=env, capture_output=True, text=True)
    summary = json.load(open(os.path.join(ranks, "sweep.json")))
    if again.returncode != 0 or summary.get("reused") != 6:
        failures.append(f"second mpirun: exit {again.returncode}, reused {summary.get('reused')}")
    for f in failures:
        print(f"check_mpi_sweep: FAILED: {f}")
    if not failures:
        print("check_mpi_sweep: the 2-rank sweep gives the local sweep.csv; a second run "
              "reuses every run")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
