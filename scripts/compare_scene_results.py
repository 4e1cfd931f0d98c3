#!/usr/bin/env python3
"""Runs every example scene and compares its history.csv with a stored set, byte for byte.

A change that must not change any number (a refactoring) is checked like this:

  scripts/compare_scene_results.py --store out/reference      # before the change
  ... change, build ...
  scripts/compare_scene_results.py --against out/reference    # after: exit 1 on a difference

For every scene of scenes/ (or those given with --scenes) it runs `ifsim run SCENE --out
OUT/<scene> -q --threads N` and, with --against, compares OUT/<scene>/history.csv with
REF/<scene>/history.csv: identical, or the first differing row and column with both values and
the largest relative difference over all numeric cells (for a change meant to move numbers
only at the solver's tolerance).
A scene whose run fails is a difference too (its status and reason are printed).
"""
import argparse
import csv
import io
import json
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent


def run_scene(ifsim, scene, out, threads):
    t0 = time.time()
    proc = subprocess.run([ifsim, "run", str(scene), "--out", str(out), "-q", "--threads",
                           str(threads)], capture_output=True, text=True)
    return proc.returncode, time.time() - t0, proc.stderr.strip()


def first_difference(new_path, ref_path):
    """None when the files are identical, else a sentence naming the first difference."""
    new = new_path.read_bytes()
    ref = ref_path.read_bytes()
    if new == ref:
        return None
    new_rows = list(csv.reader(io.StringIO(new.decode())))
    ref_rows = list(csv.reader(io.StringIO(ref.decode())))
    if new_rows[:1] != ref_rows[:1]:
        return f"columns differ: {new_rows[:1]} vs {ref_rows[:1]}"
    header = new_rows[0]
    for k, (a, b) in enumerate(zip(new_rows[1:], ref_rows[1:]), start=1):
        if a != b:
            for c, (x, y) in enumerate(zip(a, b)):
                if x != y:
                    return f"row {k}, column {header[c]}: {x} (now) vs {y} (stored)"
            return f"row {k}: {len(a)} vs {len(b)} values"
    return f"{len(new_rows) - 1} rows now, {len(ref_rows) - 1} stored"


# How the solver got there, not the result: left out of the relative difference.
SOLVER_COLUMNS = {"increment", "stage", "newton_iterations", "cuts", "residual", "iterations",
                  "substeps", "subincrements"}


def largest_relative_difference(new_path, ref_path):
    """The largest |a - b| / max(|a|, |b|, floor) over the numeric cells of two histories with
    the same rows, with its column; floor keeps values near zero from dominating."""
    new_rows = list(csv.reader(io.StringIO(new_path.read_text())))
    ref_rows = list(csv.reader(io.StringIO(ref_path.read_text())))
    if len(new_rows) != len(ref_rows) or new_rows[:1] != ref_rows[:1]:
        return None
    header = new_rows[0]
    worst = (0.0, "")
    for a, b in zip(new_rows[1:], ref_rows[1:]):
        for c, (x, y) in enumerate(zip(a, b)):
            if header[c] in SOLVER_COLUMNS:
                continue
            try:
                fx, fy = float(x), float(y)
            except ValueError:
                continue
            scale = max(abs(fx), abs(fy), 1.0e-3)
            worst = max(worst, (abs(fx - fy) / scale, header[c]))
    return worst


def main():
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ifsim", default=str(ROOT / "build" / "ifsim"))
    mode = ap.add_mutually_exclusive_group(required=True)
    mode.add_argument("--store", metavar="REF", help="run the scenes into REF (the reference)")
    mode.add_argument("--against", metavar="REF", help="run into --out and compare with REF")
    ap.add_argument("--out", default=str(ROOT / "out" / "compare"),
                    help="where the new runs go with --against")
    ap.add_argument("--scenes", nargs="*", help="scene files (default: every scenes/*.toml)")
    ap.add_argument("--threads", type=int, default=2)
    a = ap.parse_args()
    scenes = [Path(s) for s in a.scenes] if a.scenes else sorted((ROOT / "scenes").glob("*.toml"))
    target = Path(a.store or a.out)
    target.mkdir(parents=True, exist_ok=True)
    differences = 0
    for scene in scenes:
        name = scene.stem
        code, wall, err = run_scene(a.ifsim, scene, target / name, a.threads)
        status = "ok" if code == 0 else f"failed (exit {code}: {err[:200]})"
        if a.store:
            print(f"{name}: stored, {status}, {wall:.1f} s", flush=True)
            continue
        ref = Path(a.against) / name / "history.csv"
        new = target / name / "history.csv"
        if code != 0:
            why = status
        elif not ref.exists():
            why = f"no stored history ({ref})"
        else:
            why = first_difference(new, ref)
        if why is None:
            print(f"{name}: identical ({wall:.1f} s)", flush=True)
        else:
            differences += 1
            rel = largest_relative_difference(new, ref) if code == 0 and ref.exists() else None
            size = f"; largest relative difference {rel[0]:.2e} ({rel[1]})" if rel else ""
            print(f"{name}: DIFFERS: {why}{size}", flush=True)
    if a.against:
        print(f"{len(scenes) - differences} of {len(scenes)} scenes identical")
        return 1 if differences else 0
    (target / "stored.json").write_text(json.dumps({"scenes": [s.stem for s in scenes]}))
    return 0


if __name__ == "__main__":
    sys.exit(main())
