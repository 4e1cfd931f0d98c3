#!/usr/bin/env python3
"""Runs a scene with --threads 1 and --threads 2 and compares history.csv byte for byte
(results must not depend on the number of threads).

Usage: check_thread_count.py IFSIM SCENE WORKDIR [--set KEY=VALUE]...
Exit 0 when identical, 1 otherwise.
"""
import argparse
import filecmp
import os
import subprocess
import sys


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("ifsim")
    ap.add_argument("scene")
    ap.add_argument("workdir")
    ap.add_argument("--set", action="append", default=[])
    a = ap.parse_args()
    sets = [x for s in a.set for x in ("--set", s)]
    out = {}
    for threads in (1, 2):
        out[threads] = os.path.join(a.workdir, f"threads-{threads}")
        subprocess.run([a.ifsim, "run", a.scene, "--out", out[threads], "-q", "--replace",
                        "--threads", str(threads)] + sets, check=True)
    same = filecmp.cmp(os.path.join(out[1], "history.csv"), os.path.join(out[2], "history.csv"),
                       shallow=False)
    print(f"check_thread_count: history.csv {'identical' if same else 'DIFFERS'} "
          "with 1 and 2 threads")
    return 0 if same else 1


if __name__ == "__main__":
    sys.exit(main())
