#!/usr/bin/env python3
"""A run stopped by a signal ends defined (docs/scenes.md, "Stopping a run"): starts SCENE,
waits until ROWS rows of history are written, sends SIGNAL (default SIGTERM) and checks

- the exit status is 128 + the signal's number;
- summary.json exists, says "failed" with a reason naming the signal and "interrupted";
- history.csv (not .partial) exists and every line has as many fields as the header, with the
  row count summary.json gives;
- with --resume: the stop wrote a checkpoint, `ifsim resume` finishes the run, and its
  history.csv equals an uninterrupted run's byte for byte;
- with --resume-set KEY=VALUE (a setting that must not change the results, e.g.
  solver.check_tangent=true): the resume is given it, its scene.toml notes it, the files named
  by --expect-file appear, and the history is still the uninterrupted run's; a resume with a
  key the state was made with (mesh.file) is refused with exit 2 and leaves DIR as it was;
- with --twice: the signal is sent twice at once (as coreutils' `timeout` does, to the process
  and then its group), and the run still ends as above: one stop.

Usage: check_stop_signal.py IFSIM SCENE WORKDIR [--rows N] [--signal TERM|INT|HUP] [--resume]
                            [--twice]
                            [--set KEY=VALUE]... [--resume-set KEY=VALUE]... [--expect-file F]...
Exit 0 when every check holds, 1 otherwise.
"""
import argparse
import filecmp
import json
import os
import shutil
import signal
import subprocess
import sys
import time


def rows_in(path):
    try:
        with open(path, "rb") as f:
            return f.read().count(b"\n") - 1
    except FileNotFoundError:
        return -1


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ifsim")
    ap.add_argument("scene")
    ap.add_argument("workdir")
    ap.add_argument("--rows", type=int, default=20)
    ap.add_argument("--signal", default="TERM", choices=["TERM", "INT", "HUP"])
    ap.add_argument("--resume", action="store_true")
    # The signal twice at once, as coreutils' `timeout` sends it (process, then process group):
    # one stop, the same defined end.
    ap.add_argument("--twice", action="store_true")
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--resume-set", action="append", default=[])
    ap.add_argument("--expect-file", action="append", default=[])
    a = ap.parse_args()
    sig = getattr(signal, "SIG" + a.signal)
    sets = [x for s in a.set for x in ("--set", s)]
    shutil.rmtree(a.workdir, ignore_errors=True)
    run = os.path.join(a.workdir, "stopped")
    cmd = [a.ifsim, "run", a.scene, "--out", run, "-q"] + sets
    if a.resume:
        cmd += ["--checkpoint-every", "1000000"]  # the only checkpoint is the stop's
    failures = []
    proc = subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True)
    partial = os.path.join(run, "history.csv.partial")
    t0 = time.time()
    while proc.poll() is None and rows_in(partial) < a.rows and time.time() - t0 < 120:
        time.sleep(0.005)
    if proc.poll() is not None:
        print("check_stop_signal: the run ended before the signal; use a longer scene")
        return 1
    proc.send_signal(sig)
    if a.twice:
        proc.send_signal(sig)
    _, err = proc.communicate(timeout=60)
    if proc.returncode != 128 + sig:
        failures.append(f"exit status {proc.returncode}, expected {128 + sig}")
    summary_path = os.path.join(run, "summary.json")
    history = os.path.join(run, "history.csv")
    if not os.path.exists(summary_path):
        failures.append("no summary.json")
        summary = {}
    else:
        with open(summary_path) as f:
            summary = json.load(f)
        if summary.get("status") != "failed":
            failures.append(f"status {summary.get('status')!r}, expected 'failed'")
        name = "SIG" + a.signal
        if f"interrupted by {name}" not in summary.get("reason", ""):
            failures.append(f"reason {summary.get('reason')!r} does not name {name}")
        if summary.get("interrupted") != name:
            failures.append(f"summary 'interrupted' is {summary.get('interrupted')!r}")
    if os.path.exists(partial) or not os.path.exists(history):
        failures.append("history.csv.partial left, or no history.csv")
    else:
        with open(history) as f:
            lines = f.read().split("\n")
        if lines[-1] != "":
            failures.append("history.csv does not end in a newline (half a row)")
        width = lines[0].count(",")
        bad = [i for i, l in enumerate(lines[1:-1], 1) if l.count(",") != width]
        if bad:
            failures.append(f"rows with a wrong number of fields: {bad[:5]}")
        if "rows" in summary and summary["rows"] != len(lines) - 2:
            failures.append(f"summary rows {summary['rows']} but history.csv has {len(lines) - 2}")
    if a.resume and not failures:
        if not os.path.exists(os.path.join(run, "checkpoint")):
            failures.append("the stop wrote no checkpoint")
        else:
            resume_sets = [x for s in a.resume_set for x in ("--set", s)]
            if a.resume_set:
                # A key the checkpoint's state was made with is refused, and DIR stays as it was.
                kept = {f: open(os.path.join(run, f), "rb").read()
                        for f in ("scene.toml", "checkpoint")}
                refused = subprocess.run([a.ifsim, "resume", run, "-q", "--set",
                                          'mesh.file="other.msh"'] + resume_sets,
                                         capture_output=True, text=True)
                if refused.returncode != 2 or "mesh.file" not in refused.stderr:
                    failures.append(f"resume --set mesh.file: exit {refused.returncode}, "
                                    f"expected 2 naming the key ({refused.stderr.strip()!r})")
                failures += [f"{f} changed by the refused resume" for f, b in kept.items()
                             if open(os.path.join(run, f), "rb").read() != b]
            subprocess.run([a.ifsim, "resume", run, "-q"] + resume_sets, check=True)
            if a.resume_set:
                with open(os.path.join(run, "scene.toml")) as f:
                    copy = f.read()
                if "# Resumed after increment" not in copy:
                    failures.append("scene.toml does not note the resume's overrides")
                failures += [f"scene.toml does not list --set {s}" for s in a.resume_set
                             if f"#   --set {s}" not in copy]
            failures += [f"no {f} after the resume" for f in a.expect_file
                         if not os.path.exists(os.path.join(run, f))]
            whole = os.path.join(a.workdir, "whole")
            subprocess.run([a.ifsim, "run", a.scene, "--out", whole, "-q"] + sets, check=True)
            if not filecmp.cmp(os.path.join(whole, "history.csv"), history, shallow=False):
                failures.append("resumed history.csv differs from the uninterrupted run's")
    print(f"check_stop_signal: SIG{a.signal} at >= {a.rows} rows: "
          + ("ok" if not failures else "; ".join(failures)))
    if failures:
        print(err, file=sys.stderr)
    return 0 if not failures else 1


if __name__ == "__main__":
    sys.exit(main())
