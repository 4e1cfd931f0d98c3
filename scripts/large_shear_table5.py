#!/usr/bin/env python3
"""The Table 5 analog of the large-scale cyclic interface shear test (paper §6.3).

Runs the four scenes of scenes/large-shear/ (Coulomb, novel hypoplastic, novel Sanisand, Stutz
hypoplastic) one after another and prints, per run: status and quality, increments, global
Newton iterations, total time and the time in the contact routines, the element loop (element
updates and assembly) and the linear solver, next to the paper's Table 5 (4 cores) and the
ratio of core-seconds (paper total x 4 over ours x threads). Writes

  OUT/<run>/             the ordinary outputs of every run
  OUT/table5.csv         one row per run
  OUT/table5.md          the same as a Markdown table

Usage: scripts/large_shear_table5.py [--ifsim build/ifsim] [--out out/table5]
       [--mesh fine|medium|coarse] [--runs coulomb,novel-hypo,novel-sanisand,stutz-hypo]
       [--threads N] [--timeout-minutes M] [--reuse]

--mesh coarse runs the same scenes on scenes/meshes/large-shear-coarse.msh (minutes instead
of hours; not the paper's resolution); --mesh medium on large-shear-medium.msh (the mesh study
of docs/large-scale-test.md). --timeout-minutes stops a run with SIGTERM after M
minutes (ifsim then ends it in a defined state and says where); the table shows it as
"stopped". --reuse takes a finished run's summary.json instead of running it again.
Exits 1 when a run did not end ok.
"""
import argparse
import csv
import json
import os
import signal
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "scenes" / "large-shear"

# Paper Table 5: global iterations, total time [s], contact time [s], 4 cores (i9 9900K).
PAPER = {
    "coulomb": (2600, 5969, 618),
    "novel-hypo": (2950, 8540, 2524),
    "novel-sanisand": (2710, 9343, 3459),
    "stutz-hypo": (2730, 8504, 2463),
}
PAPER_CORES = 4
COLUMNS = ["run", "status", "quality", "increments", "newton_iterations", "total_s",
           "contact_s", "element_s", "solve_s", "threads", "paper_iterations", "paper_total_s",
           "paper_contact_s", "core_seconds_ratio"]


def fail(msg):
    print(f"large_shear_table5: {msg}", file=sys.stderr)
    sys.exit(2)


def run_scene(ifsim, name, out, mesh, threads, timeout_minutes):
    cmd = [str(ifsim), "run", str(SCENES / f"large-shear-{name}.toml"), "--out", str(out),
           "--replace", "--quiet", "--threads", str(threads)]
    if mesh != "fine":
        cmd += ["--set", f"mesh.file=../meshes/large-shear-{mesh}.msh"]
    print(f"large_shear_table5: {' '.join(cmd)}", flush=True)
    proc = subprocess.Popen(cmd)
    try:
        proc.wait(timeout=timeout_minutes * 60.0 if timeout_minutes else None)
    except subprocess.TimeoutExpired:
        proc.send_signal(signal.SIGTERM)  # ifsim ends the run defined and resumable
        proc.wait()
        return "stopped"
    return None


def row_of(name, summary, stopped, threads):
    t = summary.get("timing", {})
    p = t.get("phases", {})
    c = summary.get("counters", {})
    total = t.get("wall_s", float("nan"))
    contact = sum(p.get(k, 0.0) for k in ("contact_search", "contact_gather", "contact_kernels",
                                           "contact_scatter"))
    it, paper_total, paper_contact = PAPER[name]
    used = summary.get("threads", threads)
    ratio = paper_total * PAPER_CORES / (total * used) if total and used else float("nan")
    return {
        "run": name,
        "status": stopped or summary.get("status", "?"),
        "quality": summary.get("quality", ""),
        "increments": c.get("increments", ""),
        "newton_iterations": c.get("newton_iterations", ""),
        "total_s": round(total, 1),
        "contact_s": round(contact, 1),
        "element_s": round(p.get("element", 0.0) + p.get("assembly", 0.0), 1),
        "solve_s": round(p.get("solve", 0.0), 1),
        "threads": used,
        "paper_iterations": it,
        "paper_total_s": paper_total,
        "paper_contact_s": paper_contact,
        "core_seconds_ratio": round(ratio, 1),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--ifsim", default=str(ROOT / "build" / "ifsim"))
    ap.add_argument("--out", default="out/table5")
    ap.add_argument("--mesh", choices=["fine", "medium", "coarse"], default="fine")
    ap.add_argument("--runs", default=",".join(PAPER))
    ap.add_argument("--threads", type=int, default=os.cpu_count() or 1)
    ap.add_argument("--timeout-minutes", type=float, default=0.0)
    ap.add_argument("--reuse", action="store_true")
    a = ap.parse_args()
    names = [n for n in a.runs.split(",") if n]
    for n in names:
        if n not in PAPER:
            fail(f"--runs: unknown run '{n}'; expected some of {', '.join(PAPER)}")
    if a.threads < 1:
        fail(f"--threads: expected >= 1, got {a.threads}")
    if not Path(a.ifsim).is_file():
        fail(f"--ifsim: {a.ifsim} does not exist (build first: README)")
    out = Path(a.out)
    out.mkdir(parents=True, exist_ok=True)
    rows = []
    for n in names:
        d = out / n
        stopped = None
        summary_path = d / "summary.json"
        if not (a.reuse and summary_path.is_file()):
            stopped = run_scene(a.ifsim, n, d, a.mesh, a.threads, a.timeout_minutes)
        if not summary_path.is_file():
            fail(f"{summary_path}: the run wrote no summary")
        rows.append(row_of(n, json.loads(summary_path.read_text()), stopped, a.threads))

    with open(out / "table5.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=COLUMNS)
        w.writeheader()
        w.writerows(rows)
    lines = [f"Mesh: {a.mesh}. Paper: 4 cores (i9 9900K, 3.6 GHz). Ratio: paper core-seconds "
             "over ours.", "",
             "| " + " | ".join(COLUMNS) + " |", "|" + "---|" * len(COLUMNS)]
    lines += ["| " + " | ".join(str(r[k]) for k in COLUMNS) + " |" for r in rows]
    (out / "table5.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    sys.exit(0 if all(r["status"] == "ok" for r in rows) else 1)


if __name__ == "__main__":
    main()
