#!/usr/bin/env python3
"""Where a boundary-value run's Newton iterations go: accepted attempts against cut ones.

Usage: newton_attempts.py RUN_DIR [--json] [--check]

Reads RUN_DIR/iterations.csv (written by `ifsim run ... --iteration-log`), RUN_DIR/scene.toml and
RUN_DIR/summary.json. An attempt is one try at an increment: consecutive rows with the same
increment, start, end and cut depth. It was cut when the next attempt retries the same
increment from the same start. A row is a residual check: the first guess (iteration 0), a
restart after a re-gather of the novel interface's in-plane targets or a released sub-increment
partition, or a Newton iteration (all other rows).

Prints, per stage and for the run, the Newton iterations and seconds of accepted and of failed
attempts. A failed attempt is followed by a cut (a smaller step) or is repeated at the same step
(the viscous retry of `slip_viscosity_use = "retry"` after the finest cut). It
ended at the scene's max_gathers (the targets' fixed point still moving), or otherwise
(divergence, cycles, failed points). For the attempts that ended at
max_gathers it gives the targets' contraction per gather, estimated from the restart residuals
of their last four solves. --json prints the same as one JSON object. --check exits 1 unless the
Newton iterations add up to summary.json's newton_iterations and the cut attempts to its cuts
(the property scripts and the tests rely on).
"""
import csv
import json
import statistics
import sys
import tomllib
from pathlib import Path


def fail(msg):
    print(f"newton_attempts: {msg}", file=sys.stderr)
    sys.exit(1)


def read_attempts(path):
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    attempts = []
    for r in rows:
        key = (r["increment"], r["t_begin"], r["t_end"], r["cut_depth"])
        if not attempts or attempts[-1]["key"] != key or r["iteration"] == "0":
            attempts.append({"key": key, "rows": []})
        attempts[-1]["rows"].append(r)
    for i, a in enumerate(attempts):
        nxt = attempts[i + 1]["key"] if i + 1 < len(attempts) else None
        retried = nxt is not None and nxt[0] == a["key"][0] and nxt[1] == a["key"][1]
        # a retry of a smaller step is a cut; one of the same step is the viscous retry after
        # the finest cut, or a first guess rejected for the zero guess
        a["cut"] = retried and nxt[3] != a["key"][3]
        a["repeated"] = retried and not a["cut"]
        a["failed"] = retried
        a["stage"] = int(a["rows"][0]["stage"])
        a["seconds"] = sum(float(r["seconds"]) for r in a["rows"])
        a["gathers"] = int(a["rows"][-1]["gathers"])
        a["iterations"] = 0
        a["restart_residuals"] = []
        prev = None
        for r in a["rows"]:
            if prev is not None:
                if r["gathers"] != prev["gathers"]:
                    a["restart_residuals"].append(float(r["residual"]))
                elif r["partition_solves"] == prev["partition_solves"]:
                    a["iterations"] += 1
            prev = r
    return attempts


def contraction(a):
    """The targets' change per gather over the attempt's last four restarts (None if fewer)."""
    r = a["restart_residuals"]
    if len(r) < 4 or r[-4] <= 0.0:
        return None
    return (r[-1] / r[-4]) ** (1.0 / 3.0)


def summarise(attempts, max_gathers):
    def tally(group):
        return {"attempts": len(group), "newton_iterations": sum(a["iterations"] for a in group),
                "seconds": round(sum(a["seconds"] for a in group), 3)}

    cut = [a for a in attempts if a["cut"]]
    failed = [a for a in attempts if a["failed"]]
    at_limit = [a for a in failed if max_gathers > 0 and a["gathers"] >= max_gathers]
    ratios = [c for c in (contraction(a) for a in at_limit) if c is not None]
    stages = {}
    for s in sorted({a["stage"] for a in attempts}):
        mine = [a for a in attempts if a["stage"] == s]
        stages[str(s)] = {"accepted": tally([a for a in mine if not a["failed"]]),
                          "failed": tally([a for a in mine if a["failed"]])}
    out = {"max_gathers": max_gathers,
           "accepted": tally([a for a in attempts if not a["failed"]]),
           "failed": tally(failed),
           "cut": tally(cut),
           "repeated": tally([a for a in failed if a["repeated"]]),
           "failed_at_max_gathers": tally(at_limit),
           "failed_otherwise": tally([a for a in failed if a not in at_limit]),
           "stages": stages}
    if ratios:
        out["gather_contraction"] = {"median": round(statistics.median(ratios), 3),
                                     "min": round(min(ratios), 3), "max": round(max(ratios), 3)}
    return out


def print_table(s):
    def line(name, t):
        print(f"{name:<28} {t['attempts']:>8} {t['newton_iterations']:>10} {t['seconds']:>10.1f}")

    print(f"{'':<28} {'attempts':>8} {'Newton it.':>10} {'seconds':>10}")
    line("accepted attempts", s["accepted"])
    line("failed attempts", s["failed"])
    line("  then cut", s["cut"])
    line("  then repeated, same step", s["repeated"])
    line(f"  ended at max_gathers ({s['max_gathers']})", s["failed_at_max_gathers"])
    line("  ended otherwise", s["failed_otherwise"])
    for name, st in s["stages"].items():
        line(f"stage {name}, accepted", st["accepted"])
        line(f"stage {name}, failed", st["failed"])
    if "gather_contraction" in s:
        g = s["gather_contraction"]
        print(f"targets' change per gather in the attempts ended at max_gathers: median {g['median']}"
              f" (range {g['min']}-{g['max']})")


def main():
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    flags = {a for a in sys.argv[1:] if a.startswith("--")}
    if len(args) != 1 or flags - {"--json", "--check"}:
        fail("usage: newton_attempts.py RUN_DIR [--json] [--check]")
    run = Path(args[0])
    log = run / "iterations.csv"
    if not log.is_file():
        fail(f"{log}: not found (run the scene with --iteration-log)")
    max_gathers = 10  # the scene contract's default (docs/scenes.md, [solver])
    scene = run / "scene.toml"
    if scene.is_file():
        with open(scene, "rb") as f:
            max_gathers = int(tomllib.load(f).get("solver", {}).get("max_gathers", max_gathers))
    attempts = read_attempts(log)
    if not attempts:
        fail(f"{log}: no rows")
    s = summarise(attempts, max_gathers)
    if "--json" in flags:
        print(json.dumps(s, indent=1))
    else:
        print_table(s)
    if "--check" in flags:
        with open(run / "summary.json") as f:
            counters = json.load(f)["counters"]
        its = s["accepted"]["newton_iterations"] + s["failed"]["newton_iterations"]
        if its != counters["newton_iterations"]:
            fail(f"{its} Newton iterations in {log}, {counters['newton_iterations']} in summary.json")
        if s["cut"]["attempts"] != counters["cuts"]:
            fail(f"{s['cut']['attempts']} cut attempts in {log}, {counters['cuts']} cuts in "
                 "summary.json")


if __name__ == "__main__":
    main()
