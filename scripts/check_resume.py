#!/usr/bin/env python3
"""Kill-and-resume check of checkpoints (docs/scenes.md, "Checkpoint and resume"): runs a
scene once uninterrupted, then again with checkpoints, killing it with SIGKILL
at random moments after a checkpoint was written (KILLS times, resuming after each), and
finally lets `ifsim resume` finish it. history.csv of the interrupted run must equal the
uninterrupted one byte for byte.

Works for every scene kind. With --fields both runs write field output and every .pvd
collection and VTU file must be identical too.

Usage: check_resume.py IFSIM SCENE WORKDIR [--every N] [--kills K] [--seed S] [--fields]
                       [--set KEY=VALUE]...
Exit 0 when identical, 1 otherwise.
"""
import argparse
import filecmp
import os
import random
import shutil
import signal
import subprocess
import sys
import time


def wait_for_new_checkpoint(path, after_mtime, proc, timeout=60.0):
    """Waits until the checkpoint file is newer than after_mtime (or the run ended)."""
    t0 = time.time()
    while time.time() - t0 < timeout:
        if proc.poll() is not None:
            return False
        try:
            if os.stat(path).st_mtime_ns > after_mtime:
                return True
        except FileNotFoundError:
            pass
        time.sleep(0.01)
    return False


def field_files(run):
    """The .pvd collections and VTU files of a run, relative to its folder."""
    out = sorted(f for f in os.listdir(run) if f.endswith(".pvd"))
    fields = os.path.join(run, "fields")
    if os.path.isdir(fields):
        out += sorted(os.path.join("fields", f) for f in os.listdir(fields))
    return out


def compare_fields(whole, cut):
    a, b = field_files(whole), field_files(cut)
    if a != b:
        print(f"check_resume: field files differ: {sorted(set(a) ^ set(b))}")
        return False
    differing = [f for f in a if not filecmp.cmp(os.path.join(whole, f), os.path.join(cut, f),
                                                 shallow=False)]
    print(f"check_resume: {len(a)} field file(s); "
          f"{'identical' if not differing else 'DIFFER: ' + ', '.join(differing[:5])}")
    if not a:
        print("check_resume: --fields given but the run wrote no field files")
        return False
    return not differing


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ifsim")
    ap.add_argument("scene")
    ap.add_argument("workdir")
    ap.add_argument("--every", type=int, default=20)
    ap.add_argument("--kills", type=int, default=2)
    ap.add_argument("--seed", type=int, default=None)
    ap.add_argument("--set", action="append", default=[])
    ap.add_argument("--fields", action="store_true")
    a = ap.parse_args()
    rng = random.Random(a.seed)
    sets = [x for s in a.set for x in ("--set", s)] + (["--fields"] if a.fields else [])
    shutil.rmtree(a.workdir, ignore_errors=True)
    whole, cut = os.path.join(a.workdir, "whole"), os.path.join(a.workdir, "interrupted")
    t0 = time.time()
    subprocess.run([a.ifsim, "run", a.scene, "--out", whole, "-q"] + sets, check=True)
    # The kill lands somewhere between checkpoints, within a run as long as the uninterrupted
    # one: a fixed pause would miss a run of a tenth of a second (element tests) on a fast or
    # idle machine. If every kill still missed, the interrupted run starts over with pauses
    # half as long.
    pause = min(0.3, (time.time() - t0) / 4.0)
    ckp = os.path.join(cut, "checkpoint")
    kills = 0
    for _ in range(6):
        shutil.rmtree(cut, ignore_errors=True)
        cmd = [a.ifsim, "run", a.scene, "--out", cut, "-q", "--checkpoint-every",
               str(a.every)] + sets
        for attempt in range(a.kills):
            if os.path.exists(os.path.join(cut, "history.csv")):
                break  # finished before the next kill
            proc = subprocess.Popen(cmd)
            before = os.stat(ckp).st_mtime_ns if os.path.exists(ckp) else -1
            if not wait_for_new_checkpoint(ckp, before, proc):
                proc.wait()
                break
            time.sleep(rng.uniform(0.0, pause))  # somewhere between checkpoints
            if proc.poll() is None:
                proc.send_signal(signal.SIGKILL)
                proc.wait()
                kills += 1
            cmd = [a.ifsim, "resume", cut, "-q"]
        if os.path.exists(ckp):
            subprocess.run([a.ifsim, "resume", cut, "-q"], check=True)
        if kills > 0:
            break
        pause /= 2.0
    same = filecmp.cmp(os.path.join(whole, "history.csv"), os.path.join(cut, "history.csv"),
                       shallow=False)
    print(f"check_resume: {kills} kill(s); history.csv {'identical' if same else 'DIFFERS'}")
    if a.fields:
        same = compare_fields(whole, cut) and same
    if kills == 0:
        print("check_resume: the run ended before any kill; use a longer scene or --every")
        return 1
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
