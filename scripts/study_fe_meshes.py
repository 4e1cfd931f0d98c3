#!/usr/bin/env python3
"""Mesh study of the FE shear box (docs/fem.md, "Refined meshes").

Runs the shear box of scenes/fe-simple-shear-cnl-2d.toml and -3d.toml on a sequence of
structured and unstructured (Gmsh) meshes with the novel, Stutz and Coulomb interfaces, under
CNL and CNS, plus the contact-opening scene, and writes

  OUT/runs/<case>/             the ordinary outputs of every run
  OUT/fe-meshes.csv            one row per run: status, time, counters, peak and final shear
                               stress, final normal displacement
  OUT/fe-meshes.md             the same as a Markdown table
  OUT/fe-mesh-convergence.png  shear stress and dilation against plate travel per mesh, with
                               the point-level test (plane strain) for reference

Usage: scripts/study_fe_meshes.py [--ifsim build/ifsim] [--out out/fe-meshes] [--quick]
       [--threads N]. Unstructured meshes are made with gmsh (Debian package gmsh) from the
.geo files in scenes/meshes when gmsh is installed; otherwise those cases are skipped.
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
SCENES = ROOT / "scenes"
ADAPTIVE = 'interface.subincrement="adaptive"'


def structured(dim, elements):
    text = "[" + ",".join(str(n) for n in elements) + "]"
    return ["body.1.elements=" + text]


def coulomb():
    # The Coulomb twin: the model keys of the continuum interface are replaced.
    return "coulomb"


def cases(quick, msh_dir):
    """(name, scene, overrides, group) of every run."""
    two_d = SCENES / "fe-simple-shear-cnl-2d.toml"
    three_d = SCENES / "fe-simple-shear-cnl-3d.toml"
    out = []
    meshes_2d = [(1, 1), (2, 1), (4, 1), (4, 2), (10, 2), (20, 4)] + ([] if quick else [(40, 8)])
    for m in meshes_2d:
        out.append((f"2d-novel-{m[0]}x{m[1]}", two_d, structured(2, m) + [ADAPTIVE], "2d-novel"))
    for m in [(4, 2), (20, 4)] + ([] if quick else [(40, 8)]):
        out.append((f"2d-stutz-{m[0]}x{m[1]}", two_d,
                    structured(2, m) + [ADAPTIVE, 'interface.formulation="stutz"'], "2d-stutz"))
        out.append((f"2d-coulomb-{m[0]}x{m[1]}", two_d, structured(2, m) + ["@coulomb"],
                    "2d-coulomb"))
    cns = SCENES / "fe-simple-shear-cns-2d.toml"
    for m in [(4, 2)] + ([] if quick else [(20, 4)]):
        for f in ["novel", "stutz"]:
            out.append((f"2d-cns-{f}-{m[0]}x{m[1]}", cns,
                        structured(2, m) + [ADAPTIVE, f'interface.formulation="{f}"'], "2d-cns"))
    for h in ([0.005] if quick else [0.005, 0.0025]):
        msh = msh_dir / f"box2d-{h}.msh"
        if msh.exists():
            for f in ["novel", "stutz"]:
                out.append((f"2d-gmsh-{f}-h{h}", SCENES / "fe-simple-shear-cnl-2d-unstructured.toml",
                            [f'mesh.file="{msh}"', f'interface.formulation="{f}"'], "2d-gmsh"))
    meshes_3d = [(1, 1, 1), (2, 2, 1), (4, 4, 2)] + ([] if quick else [(8, 8, 2)])
    for m in meshes_3d:
        out.append((f"3d-novel-{m[0]}x{m[1]}x{m[2]}", three_d, structured(3, m) + [ADAPTIVE],
                    "3d-novel"))
    out.append(("3d-stutz-4x4x2", three_d,
                structured(3, (4, 4, 2)) + [ADAPTIVE, 'interface.formulation="stutz"'], "3d-stutz"))
    msh3 = msh_dir / "box3d.msh"
    if msh3.exists():
        out.append(("3d-gmsh-novel", SCENES / "fe-simple-shear-cnl-3d.toml",
                    ["@gmsh3d:" + str(msh3), ADAPTIVE], "3d-gmsh"))
    out.append(("2d-lift-off-novel", SCENES / "fe-lift-off-2d.toml", [], "opening"))
    out.append(("2d-lift-off-stutz", SCENES / "fe-lift-off-2d.toml",
                ['interface.formulation="stutz"'], "opening"))
    out.append(("2d-lift-off-and-back-novel", SCENES / "fe-lift-off-and-back-2d.toml", [],
                "opening"))
    out.append(("2d-lift-off-and-back-stutz", SCENES / "fe-lift-off-and-back-2d.toml",
                ['interface.formulation="stutz"'], "opening"))
    out.append(("2d-novel-one-increment", two_d,
                ["stage.2.steps=1", ADAPTIVE], "coarse"))
    out.append(("2d-novel-10-increments", two_d,
                ["stage.2.steps=10", ADAPTIVE], "coarse"))
    return out


def scene_text(scene, overrides, work):
    """The scene to run (a rewritten copy for the Coulomb and 3D Gmsh variants)."""
    sets = [o for o in overrides if not o.startswith("@")]
    special = [o for o in overrides if o.startswith("@")]
    if not special:
        return scene, sets
    text = scene.read_text()
    for s in special:
        if s == "@coulomb":
            start = text.index("formulation = ")
            end = text.index("[output]")
            text = text[:start] + ('formulation = "coulomb"\nfriction_coefficient = 0.5\n'
                                   'tangential_stiffness = 1.0e6\n\n') + text[end:]
        elif s.startswith("@gmsh3d:"):
            msh = s.split(":", 1)[1]
            start = text.index("[[body]]")
            end = text.index("[material.sand]")
            text = (text[:start] + '[[region]]\nset = "soil"\nmaterial = "sand"\n\n'
                    '[[region]]\nset = "plate"\nmaterial = "steel"\n\n' + text[end:])
            text = text.replace('integration = "full"', f'integration = "full"\nfile = "{msh}"')
    path = work / (scene.stem + "-variant.toml")
    text = text.replace('"meshes/', f'"{SCENES / "meshes"}/')
    path.write_text(text)
    return path, sets


def make_meshes(msh_dir):
    gmsh = shutil.which("gmsh")
    if not gmsh:
        print("study: gmsh not found (apt-get install gmsh): unstructured meshes skipped")
        return
    msh_dir.mkdir(parents=True, exist_ok=True)
    geo2 = SCENES / "meshes" / "shear-box-2d-unstructured.geo"
    geo3 = SCENES / "meshes" / "shear-box-3d-unstructured.geo"
    for h in [0.005, 0.0025]:
        subprocess.run([gmsh, "-2", "-format", "msh41", "-setnumber", "h", str(h), str(geo2),
                        "-o", str(msh_dir / f"box2d-{h}.msh")], check=True,
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    subprocess.run([gmsh, "-3", "-format", "msh41", "-setnumber", "h", "0.025", str(geo3), "-o",
                    str(msh_dir / "box3d.msh")], check=True, stdout=subprocess.DEVNULL,
                   stderr=subprocess.DEVNULL)


def read_history(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ifsim", default=str(ROOT / "build" / "ifsim"))
    ap.add_argument("--out", default=str(ROOT / "out" / "fe-meshes"))
    ap.add_argument("--quick", action="store_true", help="the smaller meshes only")
    ap.add_argument("--threads", type=int, default=0, help="threads per run (0: all)")
    ap.add_argument("--plot-only", action="store_true",
                    help="redraw the plot from OUT/fe-meshes.csv and the runs (no runs)")
    a = ap.parse_args()
    out = Path(a.out).resolve()  # mesh paths in the scenes are taken relative to the scene
    if a.plot_only:
        with open(out / "fe-meshes.csv") as f:
            plot(out, list(csv.DictReader(f)))
        return 0
    (out / "runs").mkdir(parents=True, exist_ok=True)
    msh_dir = out / "meshes"
    make_meshes(msh_dir)
    rows = []
    todo = cases(a.quick, msh_dir)
    for k, (name, scene, overrides, group) in enumerate(todo, 1):
        run_dir = out / "runs" / name
        path, sets = scene_text(scene, overrides, out)
        cmd = [a.ifsim, "run", str(path), "--out", str(run_dir), "-q"]
        for s in sets:
            cmd += ["--set", s]
        if a.threads > 0:
            cmd += ["--threads", str(a.threads)]
        t0 = time.time()
        proc = subprocess.run(cmd, capture_output=True, text=True)
        wall = time.time() - t0
        if not (run_dir / "history.csv").exists():  # refused before it ran (scene error)
            print(f"[{k}/{len(todo)}] {name}: not run: {proc.stderr.strip()}", flush=True)
            rows.append({"case": name, "group": group, "status": "error",
                         "reason": proc.stderr.strip()[:160]})
            continue
        summary = json.loads((run_dir / "summary.json").read_text())
        hist = read_history(run_dir / "history.csv")
        shear = [r for r in hist if int(r["stage"]) >= 2]
        c = summary.get("counters", {})
        row = {
            "case": name, "group": group, "status": summary.get("status"),
            "reason": (summary.get("reason") or "")[:160], "wall_s": round(wall, 2),
            "elements": summary.get("mesh", {}).get("elements"),
            "contact_points": None,
            "increments": c.get("increments"), "newton_iterations": c.get("newton_iterations"),
            "cuts": c.get("cuts"), "line_search_steps": c.get("line_search_steps"),
            "stagnation_accepts": c.get("stagnation_accepts"), "gathers": c.get("gathers"),
            "relaxed_point_updates": c.get("contact_relaxed_point_updates"),
            "contact_evaluations_per_point_update":
                round(c.get("contact_constitutive_evaluations", 0) /
                      max(1, c.get("contact_point_updates", 1)), 1),
            "peak_t_t1": round(max((float(r["t_t1"]) for r in shear), default=0.0), 3),
            "final_t_t1": round(float(shear[-1]["t_t1"]), 3) if shear else None,
            "final_u_n_mm": round(1e3 * float(shear[-1]["u_n"]), 5) if shear else None,
            "final_t_n": round(float(shear[-1]["t_n"]), 3) if shear else None,
        }
        if c.get("contact_point_updates") and c.get("contact_evaluations"):
            row["contact_points"] = round(c["contact_point_updates"] / c["contact_evaluations"])
        rows.append(row)
        print(f"[{k}/{len(todo)}] {name}: {row['status']} in {wall:.1f} s, peak "
              f"{row['peak_t_t1']} kPa, final {row['final_t_t1']} kPa"
              + ("" if row["status"] == "ok" else f" ({row['reason']})"), flush=True)
    keys = max((list(r.keys()) for r in rows), key=len)
    for r in rows:
        for k2 in keys:
            r.setdefault(k2, None)
    with open(out / "fe-meshes.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=keys)
        w.writeheader()
        w.writerows(rows)
    shown = ["case", "status", "wall_s", "elements", "contact_points", "increments",
             "newton_iterations", "cuts", "stagnation_accepts", "gathers",
             "relaxed_point_updates", "contact_evaluations_per_point_update", "peak_t_t1",
             "final_t_t1", "final_u_n_mm"]
    with open(out / "fe-meshes.md", "w") as f:
        f.write("| " + " | ".join(shown) + " |\n|" + "---|" * len(shown) + "\n")
        for r in rows:
            f.write("| " + " | ".join("" if r[k] is None else str(r[k]) for k in shown) + " |\n")
    plot(out, rows)
    failed = [r for r in rows if r["status"] != "ok"]
    print(f"study: {len(rows) - len(failed)} of {len(rows)} runs completed; table in "
          f"{out / 'fe-meshes.md'}")
    return 1 if failed else 0


def plot(out, rows):
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("study: matplotlib missing, no plot (Debian's python3-matplotlib: run this script "
              "with /usr/bin/python3, or again with --plot-only)")
        return
    fig, ax = plt.subplots(2, 2, figsize=(11, 7.5), sharex=True)
    for col, group in enumerate(["2d-novel", "3d-novel"]):
        for r in rows:
            if r["group"] not in (group, "2d-gmsh" if col == 0 else "3d-gmsh") or r["status"] != "ok":
                continue
            if r["group"] == "2d-gmsh" and "stutz" in r["case"]:
                continue
            hist = read_history(out / "runs" / r["case"] / "history.csv")
            shear = [h for h in hist if int(h["stage"]) >= 2]
            u = [1e3 * float(h["u_t1"]) for h in shear]
            style = "--" if "gmsh" in r["case"] else "-"
            label = r["case"].split("-", 2)[-1] + (f" ({r['elements']} el.)" if r["elements"] else "")
            ax[0][col].plot(u, [float(h["t_t1"]) for h in shear], style, lw=1.2, label=label)
            ax[1][col].plot(u, [1e3 * float(h["u_n"]) for h in shear], style, lw=1.2)
        ax[0][col].set_title(("2D plane strain" if col == 0 else "3D") + ", novel hypoplastic interface, CNL 100 kPa")
        ax[0][col].set_ylabel("mean shear traction t_t1 [kPa]")
        ax[1][col].set_ylabel("normal displacement of the soil top u_n [mm]")
        ax[1][col].set_xlabel("plate travel u_t1 [mm]")
        ax[0][col].legend(fontsize=7)
        ax[0][col].grid(alpha=0.3)
        ax[1][col].grid(alpha=0.3)
    fig.tight_layout()
    fig.savefig(out / "fe-mesh-convergence.png", dpi=110)


if __name__ == "__main__":
    sys.exit(main())
