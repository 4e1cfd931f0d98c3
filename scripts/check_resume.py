#!/usr/bin/env python3
"""Kill-and-resume check of checkpoints (docs/scenes.md, "Checkpoint and resume"): runs a
boundary-value scene once uninterrupted, then again with checkpoints, killing it with SIGKILL
at random moments after a checkpoint was written (KILLS times, resuming after each), and
finally lets `ifsim resume` finish it. history.csv of the interrupted run must equal the
uninterrupted one byte for byte.

Usage: check_resume.py IFSIM SCENE WORKDIR [--every N] [--kills K] [--seed S] [--set KEY=VALUE]...
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


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ifsim")
    ap.add_argument("scene")
    ap.add_argument("workdir")
    ap.add_argument("--every", type=int, default=20)
    ap.add_argument("--kills", type=int, default=2)
    ap.add_argument("--seed", type=int, default=None)
    ap.add_argument("--set", action="append", default=[])
    a = ap.parse_args()
    rng = random.Random(a.seed)
    sets = [x for s in a.set for x in ("--set", s)]
    shutil.rmtree(a.workdir, ignore_errors=True)
    whole, cut = os.path.join(a.workdir, "whole"), os.path.join(a.workdir, "interrupted")
    subprocess.run([a.ifsim, "run", a.scene, "--out", whole, "-q"] + sets, check=True)
    ckp = os.path.join(cut, "checkpoint")
    cmd = [a.ifsim, "run", a.scene, "--out", cut, "-q", "--checkpoint-every", str(a.every)] + sets
    kills = 0
    for attempt in range(a.kills):
        if os.path.exists(os.path.join(cut, "history.csv")):
            break  # finished before the next kill
        proc = subprocess.Popen(cmd)
        before = os.stat(ckp).st_mtime_ns if os.path.exists(ckp) else -1
        if not wait_for_new_checkpoint(ckp, before, proc):
            proc.wait()
            break
        time.sleep(rng.uniform(0.0, 0.3))  # somewhere between checkpoints
        if proc.poll() is None:
            proc.send_signal(signal.SIGKILL)
            proc.wait()
            kills += 1
        cmd = [a.ifsim, "resume", cut, "-q"]
    if os.path.exists(ckp):
        subprocess.run([a.ifsim, "resume", cut, "-q"], check=True)
    same = filecmp.cmp(os.path.join(whole, "history.csv"), os.path.join(cut, "history.csv"),
                       shallow=False)
    print(f"check_resume: {kills} kill(s); history.csv {'identical' if same else 'DIFFERS'}")
    if kills == 0:
        print("check_resume: the run ended before any kill; use a longer scene or --every")
        return 1
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
