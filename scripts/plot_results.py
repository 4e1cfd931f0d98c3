#!/usr/bin/env python3
"""Plots the results of ifsim runs: one PNG per run directory, or one comparison of runs.

Usage: plot_results.py DIR [DIR ...]
       plot_results.py --compare OUT.png [--height H] DIR1 DIR2 [DIR ...]

Each DIR is a run's output directory (history.csv, summary.json) or a directory whose
subdirectories are run directories (e.g. results/). The figure goes to DIR/overview.png.
Plotters are chosen by the run's kind (summary.json "kind"); add a function to PLOTTERS for
a new kind. Every curve is coloured by stage (viridis, early stages dark; a legend for up to
6 stages, a colour bar for more).
  element-test    stress path, stress-strain, compression, volume change; an undrained run
                  (eps11 + eps22 + eps33 = 0 in every row while the stress changes) shows the
                  excess pore pressure du instead of the last two, over the strain (and over
                  the step for cyclic runs). history.csv holds effective stresses; du assumes
                  a constant total cell pressure (triaxial: du = p'0 + (q - q0)/3 - p') or a
                  constant total vertical stress s11 (simple shear: du = s'v0 - s'v)
  boundary-value  t_t1, t_n, u_n, the mobilised stress ratio t_t1/|t_n| (with contact) and
                  s_p1, s_p2, eps_n, band_thickness, e_interface of a continuum interface
                  over u_t1 (mm); cyclic runs also get cycles.png as interface tests
  interface-test  paper Fig. 6 style: t_t1, s_p1, s_p2, sample_s22, sample_s33, u_n and the
                  interface's eps_n, eps_p1 (eps_p2), e_interface, band_thickness over the
                  plate displacement u_t1 (mm); Coulomb friction (no band): t_t1, t_t1/|t_n|,
                  slip, sample_s22, sample_s33, u_n. For cyclic runs also DIR/cycles.png in
                  the style of Fig. 7: t_t1 and u_n over u_t1 for cycle N = 1 and N = 11 (or
                  the last complete cycle). A cycle starts where u_t1 passes its start value
                  moving in the direction of stage 1; the stages give the directions.
A degraded run (summary.json quality) has "DEGRADED: <warning codes>" in red in its titles;
steps of an interface test that ran on a clamped band (band_collapse = "clamp") are drawn over
a thick grey band in every panel.
--compare overlays t_t1, s_p1 and sample_s22 over u_t1 of several runs in OUT.png (novel vs
Stutz, paper Appendix C Fig. C1). An element-test run among them (the sample sheared alone)
is drawn as the test without interface: u_t1 = 2 eps12 H (H = --height, default 0.02 m),
t_t1 = s12, s_p1 = sample_s22 = s22.
Runs with Debian's /usr/bin/python3 (python3-matplotlib); without matplotlib it says so and
exits 0, the data stay in the CSV files.
"""

import csv
import json
import math
import os
import sys

HISTORY = "history.csv"
SUMMARY = "summary.json"
FIGURE = "overview.png"
DPI = 110
LEGEND_STAGES = 6  # more stages get a colour bar: a legend that long would hide the curves
LINE_STYLES = ("-", "--", ":")  # several quantities in one panel, each still coloured by stage
CLAMPED_STYLE = dict(color="0.55", lw=7, alpha=0.45, solid_capstyle="butt", zorder=1)
BAD_TITLE = "crimson"


def read_history(run_dir):
    """Columns of history.csv as lists of floats, by column name."""
    with open(os.path.join(run_dir, HISTORY), newline="") as f:
        reader = csv.reader(f)
        header = next(reader)
        columns = {name: [] for name in header}
        for row in reader:
            if len(row) != len(header):
                continue  # a truncated last line of an aborted run
            for name, value in zip(header, row):
                # An empty field is a quantity the run does not have (boundary-value runs).
                columns[name].append(float(value) if value != "" else math.nan)
    return columns


def read_summary(run_dir):
    path = os.path.join(run_dir, SUMMARY)
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        return json.load(f)


# ---------------------------------------------------------------------------------------------
# Titles: what ran, and whether the result can be trusted as stated


def warnings_of(summary):
    """summary.json warnings; a summary written before `quality` existed (an older results/)
    still tells of a clamped band by its counter."""
    if "quality" in summary:
        return summary.get("warnings") or []
    clamped = (summary.get("counters") or {}).get("band_clamped_steps", 0)
    return [{"code": "band_clamped", "count": clamped}] if clamped else []


def is_degraded(summary):
    return summary.get("quality") == "degraded" or bool(warnings_of(summary))


def degraded_note(summary):
    """'DEGRADED: code (count), ...' for a degraded run, else ''."""
    if not is_degraded(summary):
        return ""
    codes = []
    for w in warnings_of(summary):
        count = w.get("count")
        codes.append(f"{w.get('code', '?')} ({count:g})" if count is not None
                     else str(w.get("code", "?")))
    return "DEGRADED: " + (", ".join(codes) or "see summary.json")


def run_title(run_dir, summary, details=()):
    """Scene, model, details; FAILED and the DEGRADED note last, where they catch the eye."""
    scene = summary.get("scene") or run_dir
    name = os.path.splitext(os.path.basename(os.path.normpath(scene)))[0]
    parts = [name]
    if summary.get("model"):
        parts.append(summary["model"])
    parts += [d for d in details if d]
    if summary.get("status") == "failed":
        parts.append("FAILED")
    note = degraded_note(summary)
    if note:
        parts.append(note)
    return " | ".join(parts)


def set_title(fig, text, summary):
    # Red, so that a degraded or failed run is not taken for a clean one at a glance.
    bad = is_degraded(summary) or summary.get("status") == "failed"
    fig.suptitle(text, color=BAD_TITLE if bad else "black",
                 fontweight="bold" if bad else "normal")


def save(fig, plt, run_dir, name=FIGURE):
    out = os.path.join(run_dir, name)
    fig.savefig(out, dpi=DPI)
    plt.close(fig)
    return out


# ---------------------------------------------------------------------------------------------
# Stage colours, panels and the clamped-band marking shared by all plotters


def stages_of(stage_column):
    return sorted({int(s) for s in stage_column if s > 0})


def stage_colours(plt, stage_column):
    """A distinct colour for every stage, from a sequential colormap so that the order of the
    stages reads off the colour (the default cycle repeats after 10 stages)."""
    stages = stages_of(stage_column)
    cmap = plt.get_cmap("viridis")
    if len(stages) == 1:
        return {stages[0]: cmap(0.3)}
    # Stop short of viridis' pale yellow end, which hardly shows on white.
    return {s: cmap(0.82 * k / (len(stages) - 1)) for k, s in enumerate(stages)}


def by_stage(x, y, stage):
    """Splits a curve at stage changes, so each stage gets its own colour."""
    pieces, start = [], 0
    for i in range(1, len(stage) + 1):
        if i == len(stage) or stage[i] != stage[i - 1]:
            lo = max(start - 1, 0)  # join the pieces at the stage boundary
            if stage[i - 1] > 0:  # step 0 (stage 0) starts the first stage's curve
                pieces.append((int(stage[i - 1]), x[lo:i], y[lo:i]))
            start = i
    return pieces


def panel_grid(plt, n, width=4.5, height=3.4):
    """n panels on a grid of up to 3 columns (2 x 2 for four), readable on a laptop screen;
    constrained layout leaves room for the colour bar and the title."""
    cols = 2 if n == 4 else min(n, 3)
    rows = (n + cols - 1) // cols
    fig, ax = plt.subplots(rows, cols, figsize=(width * cols, height * rows + 0.4),
                           layout="constrained", squeeze=False)
    axes = [a for row in ax for a in row]
    for a in axes[n:]:
        a.set_visible(False)
    return fig, axes[:n]


def panel(title, ylabel, series, x, xlabel, decorate=None):
    """One panel: series is a list of (y, label) drawn over x (label only when several)."""
    return dict(title=title, ylabel=ylabel, series=series, x=x, xlabel=xlabel,
                decorate=decorate)


def style_axes(ax, xlabel, ylabel, title):
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title, fontsize=10)
    ax.ticklabel_format(useOffset=False)
    ax.grid(True, alpha=0.3)


def widen_flat_axis(axis):
    """A quantity held constant (t_n under CNL) shows ±5 % around its value, not its
    round-off noise in 15-digit tick labels."""
    lo, hi = axis.get_ylim()
    mid = 0.5 * (lo + hi)
    if mid != 0.0 and hi - lo < 1e-6 * abs(mid):
        axis.set_ylim(mid - 0.05 * abs(mid), mid + 0.05 * abs(mid))


def draw_panels(axes, panels, stage, colours, clamped=None):
    """Draws every panel, each series coloured by stage, lettered (a), (b), ...; a panel with
    several series tells their line styles apart in its own legend. Returns the line-style
    handles of the first panel, whose legend stage_key redraws."""
    from matplotlib.lines import Line2D
    lw = 0.8 if len(colours) > LEGEND_STAGES else 1.2
    first = []
    for k, (axis, p) in enumerate(zip(axes, panels)):
        for style, (y, _) in zip(LINE_STYLES, p["series"]):
            for s, xs, ys in by_stage(p["x"], y, stage):
                axis.plot(xs, ys, lw=lw, ls=style, color=colours[s])
            if clamped:
                mark_clamped(axis, p["x"], y, clamped)
        style_axes(axis, p["xlabel"], p["ylabel"], f"({chr(ord('a') + k)}) {p['title']}")
        widen_flat_axis(axis)
        if len(p["series"]) > 1:
            handles = [Line2D([], [], color="k", lw=1.2, ls=style, label=label)
                       for style, (_, label) in zip(LINE_STYLES, p["series"])]
            axis.legend(handles=handles, fontsize=8)
            first = handles if k == 0 else first
        if p["decorate"]:
            p["decorate"](axis)
    return first


def stage_key(fig, axes, colours, extra=()):
    """Which colour is which stage: a legend in the first panel for a few stages, a colour
    bar beside the grid for many. `extra` are further handles for that legend (the first
    panel's line styles, the clamped band)."""
    import matplotlib as mpl
    from matplotlib.lines import Line2D
    handles = list(extra)
    stages = list(colours)
    if 1 < len(stages) <= LEGEND_STAGES:
        handles = [Line2D([], [], color=c, lw=1.5, label=f"stage {s}")
                   for s, c in colours.items()] + handles
    elif len(stages) > LEGEND_STAGES:
        bounds = [s - 0.5 for s in stages] + [stages[-1] + 0.5]
        mappable = mpl.cm.ScalarMappable(
            norm=mpl.colors.BoundaryNorm(bounds, len(stages)),
            cmap=mpl.colors.ListedColormap([colours[s] for s in stages]))
        every = (len(stages) + 11) // 12  # at most ~12 tick labels
        fig.colorbar(mappable, ax=axes, ticks=stages[::every], label="stage",
                     shrink=0.9, aspect=40, pad=0.01)
    if handles:
        axes[0].legend(handles=handles, fontsize=8)


def clamp_floor(h, summary):
    """min_band_fraction x d_s0 of a run that may clamp its band (band_collapse = "clamp"),
    else None."""
    clamp = summary.get("band_collapse") == "clamp" or (
        "band_collapse" not in summary and warnings_of(summary))  # an older summary
    if not clamp or "band_thickness" not in h:
        return None
    # 0.05: the engine's default, for summaries that do not say (kernels/interface_settings.hpp)
    return summary.get("min_band_fraction", 0.05) * summary.get("shear_band_thickness", 0.0)


def clamped_steps(h, summary):
    """Per row i: True when step i (row i-1 to row i) ran on a clamped shear band. The engine
    clamps d_s for a step whose starting band_thickness = d_s0 (1 + eps_n) (Eq. 26, the
    column) is at or below min_band_fraction x d_s0; only interface tests with
    band_collapse = "clamp" can do so. None when no step was clamped."""
    floor = clamp_floor(h, summary)
    if floor is None:
        return None
    below = [d <= floor * (1.0 + 1e-9) for d in h["band_thickness"]]
    flags = [False] + below[:-1]
    return flags if any(flags) else None


def clamped_segments(flags):
    """Row ranges [first, last] joined by consecutive clamped steps."""
    segments = []
    for i, clamped in enumerate(flags):
        if not clamped or i == 0:
            continue
        if segments and segments[-1][1] == i - 1:
            segments[-1][1] = i
        else:
            segments.append([i - 1, i])
    return segments


def mark_clamped(axis, x, y, flags):
    # A thick grey band under the curve: exact also where a cyclic run passes the same u_t1
    # on an unclamped band (a background span over u_t1 would cover those too).
    for first, last in clamped_segments(flags):
        axis.plot(x[first:last + 1], y[first:last + 1], **CLAMPED_STYLE)


def clamped_handle():
    from matplotlib.lines import Line2D
    return Line2D([], [], label="clamped band (degraded)", **CLAMPED_STYLE)


def check_clamped_count(run_dir, flags, summary):
    """Says so when the rows marked as clamped do not add up to the run's own count."""
    counted = sum(flags) if flags else 0
    for w in warnings_of(summary):
        if w.get("code") == "band_clamped" and w.get("count") != counted:
            print(f"plot_results: {run_dir}: {counted} steps marked as on a clamped band, "
                  f"summary.json says {w.get('count'):g}", file=sys.stderr)


# ---------------------------------------------------------------------------------------------
# Element tests


def element_quantities(h):
    """Mean effective pressure p', signed deviator q, strains of an element test (compression
    positive), and the deviator q_ax = s'_axial - s'_radial with axis 11 axial."""
    n = len(h["step"])
    p, q, q_ax, eps_v, eps_axial, gamma, tau, s_v = [], [], [], [], [], [], [], []
    for i in range(n):
        s = [h[c][i] for c in ("s11", "s22", "s33", "s12", "s13", "s23")]
        mean = (s[0] + s[1] + s[2]) / 3.0
        dev = [s[0] - mean, s[1] - mean, s[2] - mean]
        j2 = 0.5 * (dev[0] ** 2 + dev[1] ** 2 + dev[2] ** 2) + s[3] ** 2 + s[4] ** 2 + s[5] ** 2
        # Positive in triaxial compression (axial stress 11 the most compressive).
        sign = 1.0 if 0.5 * (s[1] + s[2]) - s[0] >= 0.0 else -1.0
        p.append(-mean)
        q.append(sign * math.sqrt(3.0 * j2))
        q_ax.append(0.5 * (s[1] + s[2]) - s[0])
        eps_v.append(-100.0 * (h["eps11"][i] + h["eps22"][i] + h["eps33"][i]))
        eps_axial.append(-100.0 * h["eps11"][i])
        gamma.append(200.0 * h["eps12"][i])
        tau.append(s[3])
        s_v.append(-s[0])
    return dict(p=p, q=q, q_ax=q_ax, eps_v=eps_v, eps_axial=eps_axial, gamma=gamma, tau=tau,
                s_v=s_v, e=h["e"], stage=h["stage"], step=h["step"])


def is_undrained(h):
    """Constant volume to round-off in every row while the stress changes: the stresses are
    then effective stresses of an undrained test, the pore water carrying the rest."""
    strains = [h[c] for c in ("eps11", "eps22", "eps33", "eps12", "eps13", "eps23")]
    scale = max((abs(v) for col in strains for v in col), default=0.0)
    eps_v = max(abs(a + b + c) for a, b, c in zip(*strains[:3]))
    stresses = [h[c] for c in ("s11", "s22", "s33", "s12", "s13", "s23")]
    s_scale = max(abs(v) for col in stresses for v in col)
    s_change = max(abs(v - col[0]) for col in stresses for v in col)
    return scale > 0.0 and eps_v <= 1e-9 * scale and s_change > 1e-9 * s_scale


def excess_pore_pressure(v, shear):
    """du with the total stress held where the test holds it: simple shear, the total vertical
    stress s11: du = s'v0 - s'v; triaxial, the total cell pressure: du = p'0 + (q - q0)/3 - p'
    (q = s'11 - s'radial; this is the drop of the radial effective stress)."""
    if shear:
        return [v["s_v"][0] - sv for sv in v["s_v"]], v["s_v"][0]
    p0, q0 = v["p"][0], v["q_ax"][0]
    return [p0 + (q - q0) / 3.0 - p for p, q in zip(v["p"], v["q_ax"])], p0


def ratio_axis(reference, label):
    """Decorator: a right-hand axis with du / (initial effective stress)."""
    def decorate(axis):
        if reference > 0.0:
            secondary = axis.secondary_yaxis(
                "right", functions=(lambda d: d / reference, lambda r: r * reference))
            secondary.set_ylabel(label)
    return decorate


def cycle_axis(h, key):
    """Decorator: cycle numbers on a top axis and faint lines where each cycle starts."""
    numbers = cycle_numbers(h, key)
    starts = [0] + [i for i in range(1, len(numbers)) if numbers[i] != numbers[i - 1]]

    def decorate(axis):
        steps = [h["step"][i] for i in starts]
        for s in steps[1:]:
            axis.axvline(s, color="0.6", lw=0.6, ls=":")
        top = axis.secondary_xaxis("top")
        top.set_xticks(steps, labels=[str(numbers[i]) for i in starts])
        top.set_xlabel("cycle N starts", fontsize=8)
        top.tick_params(labelsize=7)
    return decorate


def pressure_from_zero(axis):
    axis.set_xlim(left=0.0)  # the origin shows the slope of the stress ratio


def element_panels(h, v, shear):
    """The four panels of an element test: drained (compression, volume change) or undrained
    (excess pore pressure)."""
    p_label = "mean effective pressure $p'$ [kPa]"
    if shear:
        strain, strain_label = v["gamma"], "shear strain $\\gamma_{12} = 2\\varepsilon_{12}$ [%]"
        stress, stress_label = v["tau"], "shear stress $\\sigma_{12}$ [kPa]"
    else:
        strain, strain_label = v["eps_axial"], "axial strain $-\\varepsilon_{11}$ [%]"
        stress, stress_label = v["q"], "deviator stress $q$ [kPa]"
    panels = [
        panel("stress path", stress_label, [(stress, "")], v["p"], p_label, pressure_from_zero),
        panel("stress-strain", stress_label, [(stress, "")], strain, strain_label),
    ]
    if not is_undrained(h):
        return panels + [
            panel("compression", "void ratio $e$", [(v["e"], "")], v["p"], p_label,
                  pressure_from_zero),
            panel("volume change", "volumetric strain $-\\varepsilon_v$ [%] (compaction +)",
                  [(v["eps_v"], "")], strain, strain_label),
        ]
    du, reference = excess_pore_pressure(v, shear)
    if shear:
        du_label = "$\\Delta u = \\sigma'_{v0} - \\sigma'_v$ [kPa]"
        assumption = "undrained, constant total $\\sigma_{11}$"
        ratio = ratio_axis(reference, "$\\Delta u / \\sigma'_{v0}$")
    else:
        du_label = "$\\Delta u = p'_0 + (q - q_0)/3 - p'$ [kPa]"
        assumption = "undrained, constant total cell pressure"
        ratio = ratio_axis(reference, "$\\Delta u / p'_0$")
    du_strain = panel(f"excess pore pressure ({assumption})", du_label, [(du, "")], strain,
                      strain_label, ratio)
    du_loops = panel("excess pore pressure over the strain", du_label, [(du, "")], strain,
                     strain_label, ratio)
    key = "eps12" if shear else "eps11"
    if is_cyclic(h, key):
        def both(axis):
            ratio(axis)
            cycle_axis(h, key)(axis)
        return panels + [
            panel(f"excess pore pressure ({assumption})", du_label, [(du, "")], v["step"],
                  "step", both),
            du_loops,
        ]
    if shear:
        stress_ratio = [t / s if s > 0.0 else math.nan for t, s in zip(v["tau"], v["s_v"])]
        ratio_label = "stress ratio $\\sigma_{12} / \\sigma'_{11}$"
    else:
        stress_ratio = [q / p if p > 0.0 else math.nan for q, p in zip(v["q"], v["p"])]
        ratio_label = "stress ratio $q / p'$"
    return panels + [du_strain,
                     panel("mobilised stress ratio", ratio_label, [(stress_ratio, "")], strain,
                           strain_label)]


def plot_element_test(plt, run_dir, h, summary):
    v = element_quantities(h)
    shear = any(abs(g) > 0.0 for g in v["gamma"])
    panels = element_panels(h, v, shear)
    colours = stage_colours(plt, h["stage"])
    fig, axes = panel_grid(plt, len(panels), width=5.2, height=3.9)
    draw_panels(axes, panels, h["stage"], colours)
    stage_key(fig, axes, colours)
    details = ["undrained (stresses effective)"] if is_undrained(h) else []
    set_title(fig, run_title(run_dir, summary, details), summary)
    return save(fig, plt, run_dir)


# ---------------------------------------------------------------------------------------------
# Cycles


def mm(values):
    return [1000.0 * v for v in values]


def percent(values):
    return [100.0 * v for v in values]


def stage_directions(h, key="u_t1"):
    """Sign (+1, -1 or 0) of the change of `key` over each stage, by stage number."""
    u, stage = h[key], h["stage"]
    direction, start = {}, 0
    for i in range(1, len(stage) + 1):
        if i == len(stage) or stage[i] != stage[i - 1]:
            s = int(stage[i - 1])
            if s > 0:
                change = u[i - 1] - u[max(start - 1, 0)]
                direction[s] = (change > 0) - (change < 0)
            start = i
    return direction


def cycle_numbers(h, key="u_t1"):
    """Cycle number of every row: cycle 1 starts at step 0; a new cycle starts where `key`
    (u_t1, or a strain of an element test) passes its start value again moving in the
    direction of the first stage that moves it (an FE run's consolidation stage does not)."""
    u, stage = h[key], h["stage"]
    direction = stage_directions(h, key)
    d0 = next((d for _, d in sorted(direction.items()) if d != 0), 0)
    amplitude = max((abs(x - u[0]) for x in u), default=0.0)
    tol = 1e-9 * amplitude
    numbers, n = [1], 1
    for i in range(1, len(u)):
        if d0 and direction.get(int(stage[i]), 0) == d0:
            before, after = (u[i - 1] - u[0]) * d0, (u[i] - u[0]) * d0
            if before < -tol and after >= -tol:
                n += 1
        numbers.append(n)
    return numbers


def is_cyclic(h, key="u_t1"):
    directions = [d for _, d in sorted(stage_directions(h, key).items()) if d != 0]
    return any(a != b for a, b in zip(directions, directions[1:]))


def cycle_rows(numbers, n):
    """Row indices of cycle n, closed by the first row of the next cycle."""
    rows = [i for i, c in enumerate(numbers) if c == n]
    if rows and rows[-1] + 1 < len(numbers):
        rows.append(rows[-1] + 1)
    return rows


def complete_cycles(numbers):
    """Cycles that came back to the start value: the current (last) cycle number is open, or
    was just opened by the run's last row where it returned to the start."""
    return numbers[-1] - 1 if numbers else 0


U_LABEL = "plate displacement $u_{t1}$ [mm]"


def plot_interface_cycles(plt, run_dir, h, summary, wanted=(1, 11)):
    numbers = cycle_numbers(h)
    done = complete_cycles(numbers)
    if done < 1:
        return None
    flags = clamped_steps(h, summary)
    cycles = sorted({min(n, done) for n in wanted})
    fig, ax = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
    for n in cycles:
        rows = cycle_rows(numbers, n)
        u = [1000.0 * h["u_t1"][i] for i in rows]
        t = [h["t_t1"][i] for i in rows]
        un = [1000.0 * h["u_n"][i] for i in rows]
        ax[0].plot(u, t, lw=1.2, label=f"N = {n}")
        ax[1].plot(u, un, lw=1.2, label=f"N = {n}")
        if flags:
            # A step inside the cycle: its row and the row before it both belong to the cycle.
            sub = [j > 0 and flags[i] for j, i in enumerate(rows)]
            mark_clamped(ax[0], u, t, sub)
            mark_clamped(ax[1], u, un, sub)
    style_axes(ax[0], U_LABEL, "shear stress $t_{t1}$ [kPa]", "shear stress")
    style_axes(ax[1], U_LABEL, "normal displacement $u_n$ [mm] (dilation +)",
                   "normal displacement")
    for a in ax:
        handles, _ = a.get_legend_handles_labels()
        a.legend(handles=handles + ([clamped_handle()] if flags else []), fontsize=8)
    set_title(fig, f"{run_title(run_dir, summary)} | cycles ({done} complete)", summary)
    return save(fig, plt, run_dir, "cycles.png")


# ---------------------------------------------------------------------------------------------
# Interface tests and FE runs


def all_missing(values):
    return not values or all(math.isnan(v) for v in values)


def has_band(h, summary):
    """A continuum interface (novel, Stutz): Coulomb friction has no band and writes 0 (or
    nothing) in the band columns."""
    if summary.get("formulation") == "coulomb":
        return False
    d = h.get("band_thickness", [])
    return not all_missing(d) and any(x != 0.0 for x in d if not math.isnan(x))


def friction_ratio(h):
    """t_t1 / |t_n|, undefined where the contact carries (almost) no normal stress."""
    scale = max((abs(t) for t in h["t_n"] if not math.isnan(t)), default=0.0)
    return [t / abs(n) if abs(n) > 1e-6 * scale else math.nan
            for t, n in zip(h["t_t1"], h["t_n"])]


def friction_lines(mu, ratio):
    """Decorator: the friction coefficient, the bound of t_t1/|t_n| (-mu only when the run
    shears backwards, not to squash a one-way curve)."""
    def decorate(axis):
        if not mu:
            return
        signs = [1.0] + ([-1.0] if any(r < 0.0 for r in ratio if not math.isnan(r)) else [])
        for sign in signs:
            axis.axhline(sign * mu, color="0.4", lw=0.8, ls="--")
            axis.text(0.99, sign * mu, f"$\\mu$ = {mu:g}" if sign > 0 else "$-\\mu$",
                      transform=axis.get_yaxis_transform(), fontsize=8, color="0.3",
                      ha="right", va="top" if sign > 0 else "bottom")
    return decorate


def same_curve(a, b):
    """Equal to round-off (eps_p1 and eps_p2 of a symmetric test differ in the last bits)."""
    scale = max((abs(x) for x in a + b if not math.isnan(x)), default=0.0)
    return all(abs(x - y) <= 1e-9 * scale for x, y in zip(a, b) if not math.isnan(x - y))


def floor_line(floor):
    """Decorator: the band floor d_s is held at on a clamped band."""
    def decorate(axis):
        if floor:
            axis.axhline(1000.0 * floor, color="0.4", lw=0.8, ls="--")
            axis.text(0.99, 1000.0 * floor, "clamp floor", transform=axis.get_yaxis_transform(),
                      fontsize=8, color="0.3", ha="right", va="bottom")
    return decorate


def band_panels(h, u, floor=None):
    """The interface's own state: strains, band thickness (Eq. 26; with the floor it is held
    at when clamped) and void ratio."""
    strains = [(percent(h["eps_n"]), "$\\varepsilon_N$")]
    if "eps_p1" in h:
        if "eps_p2" in h and not same_curve(h["eps_p1"], h["eps_p2"]):
            strains += [(percent(h["eps_p1"]), "$\\varepsilon_{p1}$"),
                        (percent(h["eps_p2"]), "$\\varepsilon_{p2}$")]
        else:
            strains.append((percent(h["eps_p1"]), "$\\varepsilon_{p1} = \\varepsilon_{p2}$"))
    return [
        panel("interface strains" if len(strains) > 1 else "interface normal strain",
              "strain [%] (extension +)", strains, u, U_LABEL),
        panel("shear band thickness $d_s = d_{s0}(1 + \\varepsilon_N)$", "$d_s$ [mm]",
              [(mm(h["band_thickness"]), "")], u, U_LABEL, floor_line(floor)),
        panel("interface void ratio", "$e$ (interface)", [(h["e_interface"], "")], u, U_LABEL),
    ]


def interface_test_panels(h, summary, floor=None):
    u = mm(h["u_t1"])
    shear = panel("interface shear stress", "shear stress $t_{t1}$ [kPa]", [(h["t_t1"], "")],
                  u, U_LABEL)
    sample = [
        panel("sample normal stress $\\sigma_{22}$", "$\\sigma_{22}$ [kPa]",
              [(h["sample_s22"], "")], u, U_LABEL),
        panel("sample normal stress $\\sigma_{33}$", "$\\sigma_{33}$ [kPa]",
              [(h["sample_s33"], "")], u, U_LABEL),
        panel("normal displacement", "normal displacement $u_n$ [mm] (dilation +)",
              [(mm(h["u_n"]), "")], u, U_LABEL),
    ]
    if not has_band(h, summary):
        # Coulomb: no band, no sigma_p; what the friction law mobilises instead.
        ratio = friction_ratio(h)
        friction = [
            panel("mobilised friction", "$t_{t1} / |t_n|$", [(ratio, "")], u, U_LABEL,
                  friction_lines(summary.get("friction_coefficient"), ratio)),
        ]
        if "slip1" in h:
            friction.append(panel("interface slip", "slip $g_{T1}$ [mm]",
                                  [(mm(h["slip1"]), "")], u, U_LABEL))
        return [shear] + friction + sample
    return ([shear,
             panel("interface normal stress $\\sigma_{p1}$", "$\\sigma_{p1}$ [kPa]",
                   [(h["s_p1"], "")], u, U_LABEL),
             panel("interface normal stress $\\sigma_{p2}$", "$\\sigma_{p2}$ [kPa]",
                   [(h["s_p2"], "")], u, U_LABEL)]
            + sample + band_panels(h, u, floor))


def draw_run(plt, run_dir, h, summary, panels, details, flags=None):
    """The grid of panels over u_t1, the stage key, the title; cycles.png for cyclic runs."""
    colours = stage_colours(plt, h["stage"])
    fig, axes = panel_grid(plt, len(panels))
    styles = draw_panels(axes, panels, h["stage"], colours, flags)
    stage_key(fig, axes, colours, styles + ([clamped_handle()] if flags else []))
    set_title(fig, run_title(run_dir, summary, details), summary)
    out = save(fig, plt, run_dir)
    if is_cyclic(h):
        cycles = plot_interface_cycles(plt, run_dir, h, summary)
        if cycles:
            out += f", {cycles}"
    return out


def plot_interface_test(plt, run_dir, h, summary):
    flags = clamped_steps(h, summary)
    check_clamped_count(run_dir, flags, summary)
    details = [summary.get("formulation"), summary.get("normal_control")]
    # The floor only where the band reached it: elsewhere it would squash the d_s curve.
    panels = interface_test_panels(h, summary, clamp_floor(h, summary) if flags else None)
    return draw_run(plt, run_dir, h, summary, panels, details, flags)


def pair_series(h, summary, key):
    """Several contact pairs: each pair's own `key` column (name.key), labelled by its name
    and formulation; one pair: the main column."""
    forms = {c.get("name"): c.get("formulation") for c in summary.get("contacts") or []}
    names = [c[:-len("." + key)] for c in h if c.endswith("." + key)]
    if len(names) < 2:
        return [(h[key], "")]
    return [(h[f"{n}.{key}"], f"{n} ({forms[n]})" if forms.get(n) else n)
            for n in names[:len(LINE_STYLES)]]


def boundary_value_panels(h, summary):
    u = mm(h["u_t1"])
    panels = [
        panel("mean shear traction on the soil", "shear stress $t_{t1}$ [kPa]",
              pair_series(h, summary, "t_t1"), u, U_LABEL),
        panel("mean normal traction", "normal stress $t_n$ [kPa]",
              pair_series(h, summary, "t_n"), u, U_LABEL),
        panel("normal displacement", "normal displacement $u_n$ [mm] (dilation +)",
              [(mm(h["u_n"]), "")], u, U_LABEL),
    ]
    if summary.get("formulation"):  # a contact pair: the stress ratio it mobilises
        mu = (summary.get("interface") or {}).get("friction_coefficient")
        ratio = friction_ratio(h)
        panels.append(panel("mobilised stress ratio", "$t_{t1} / |t_n|$", [(ratio, "")], u,
                            U_LABEL, friction_lines(mu, ratio)))
    # Coulomb friction and runs without interface leave these columns empty.
    for key, symbol in (("s_p1", "\\sigma_{p1}"), ("s_p2", "\\sigma_{p2}")):
        if not all_missing(h.get(key, [])):
            panels.append(panel(f"interface normal stress ${symbol}$", f"${symbol}$ [kPa]",
                                [(h[key], "")], u, U_LABEL))
    if not all_missing(h.get("eps_n", [])) and not all_missing(h.get("band_thickness", [])):
        panels += band_panels(h, u)  # FE: eps_n only, as area-weighted means
    return panels


def plot_boundary_value(plt, run_dir, h, summary):
    """FE runs: t_t1, t_n, u_n (and the interface's state when there) over u_t1, in the
    style of the interface-test plots; cyclic runs also get cycles.png."""
    mesh = summary.get("mesh", {})
    form = summary.get("formulation") or "no interface"
    if len(summary.get("contacts") or []) > 1:  # the main columns are one pair's
        form += f" (columns of pair {summary.get('history_contact')})"
    details = [form, f"{mesh.get('dimension', '?')}D, {mesh.get('elements', '?')} elements"]
    return draw_run(plt, run_dir, h, summary, boundary_value_panels(h, summary), details)


PLOTTERS = {"element-test": plot_element_test, "interface-test": plot_interface_test,
            "boundary-value": plot_boundary_value}


def guess_kind(h):
    if "u_t1" in h and "t_t1" in h:
        return "interface-test"
    return "element-test" if "eps11" in h and "s11" in h else None


# ---------------------------------------------------------------------------------------------
# --compare


def comparison_curves(run_dir, height):
    """u_t1 (mm), t_t1, s_p1, sample_s22 and a label of one run for --compare."""
    h = read_history(run_dir)
    summary = read_summary(run_dir)
    kind = summary.get("kind") or guess_kind(h)
    label = run_title(run_dir, summary)
    if kind == "interface-test":
        form = summary.get("formulation", "")
        if form == "stutz" and summary.get("stutz_initial_stress"):
            form += f" ({summary['stutz_initial_stress']})"
        label = f"{label} [{form}]" if form else label
        return label, mm(h["u_t1"]), h["t_t1"], h["s_p1"], h["sample_s22"]
    if kind == "element-test":
        u = [2.0 * e * height * 1000.0 for e in h["eps12"]]
        return f"{label} [no interface]", u, h["s12"], h["s22"], h["s22"]
    raise ValueError(f"kind {kind!r} cannot be compared")


def compare(plt, out, dirs, height):
    fig, ax = plt.subplots(1, 3, figsize=(15, 4.8))
    for run_dir in dirs:
        label, u, tau, sp1, s22 = comparison_curves(run_dir, height)
        ax[0].plot(u, tau, lw=1.2, label=label)
        ax[1].plot(u, sp1, lw=1.2, label=label)
        ax[2].plot(u, s22, lw=1.2, label=label)
    style_axes(ax[0], U_LABEL, "shear stress $t_{t1}$ [kPa]", "(a) interface shear stress")
    style_axes(ax[1], U_LABEL, "$\\sigma_{p1}$ [kPa]", "(b) interface normal stress $\\sigma_{p1}$")
    style_axes(ax[2], U_LABEL, "$\\sigma_{22}$ [kPa]", "(c) sample normal stress $\\sigma_{22}$")
    ax[0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(out, dpi=DPI)
    plt.close(fig)
    return out


# ---------------------------------------------------------------------------------------------
# Command line


def run_dirs(paths):
    """The run directories among the arguments and their immediate subdirectories, and the
    arguments that hold none."""
    found, empty = [], []
    for path in paths:
        if os.path.exists(os.path.join(path, HISTORY)):
            found.append(path)
            continue
        runs = []
        if os.path.isdir(path):
            subs = sorted(os.path.join(path, d) for d in os.listdir(path))
            runs = [d for d in subs if os.path.exists(os.path.join(d, HISTORY))]
        if not runs:
            print(f"plot_results: {path}: no {HISTORY} here or one level below", file=sys.stderr)
            empty.append(path)
        found += runs
    return found, empty


def compare_main(plt, args):
    """--compare OUT.png [--height H] DIR1 DIR2 ..."""
    height = 0.02
    if "--height" in args:
        i = args.index("--height")
        try:
            height = float(args[i + 1])
        except (IndexError, ValueError):
            print("plot_results: --height expects a sample height in m", file=sys.stderr)
            return 2
        args = args[:i] + args[i + 2:]
    if len(args) < 2 or not args[0].endswith(".png"):
        print("plot_results: usage: --compare OUT.png [--height H] DIR1 DIR2 ...",
              file=sys.stderr)
        return 2
    out, dirs = args[0], args[1:]
    missing = [d for d in dirs if not os.path.exists(os.path.join(d, HISTORY))]
    if missing:
        print(f"plot_results: no {HISTORY} in {', '.join(missing)}", file=sys.stderr)
        return 1
    try:
        print(f"plot_results: {compare(plt, out, dirs, height)}")
    except (OSError, ValueError, KeyError, StopIteration) as err:
        print(f"plot_results: cannot compare: {err}", file=sys.stderr)
        return 1
    return 0


def main(argv):
    if len(argv) < 2 or argv[1] in ("-h", "--help"):
        print(__doc__.strip())
        return 0 if len(argv) >= 2 else 2
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("plot_results: matplotlib is not available for this Python "
              f"({sys.executable}); no plots drawn (try /usr/bin/python3)")
        return 0
    if argv[1] == "--compare":
        return compare_main(plt, argv[2:])
    found, empty = run_dirs(argv[1:])
    status = 1 if empty else 0
    for run_dir in found:
        try:
            h = read_history(run_dir)
            summary = read_summary(run_dir)
            kind = summary.get("kind") or guess_kind(h)
            plotter = PLOTTERS.get(kind)
            if plotter is None:
                print(f"plot_results: {run_dir}: no plot for kind {kind!r} yet")
                continue
            if not (h.get("step") or h.get("increment")):
                print(f"plot_results: {run_dir}: {HISTORY} has no rows")
                continue
            print(f"plot_results: {plotter(plt, run_dir, h, summary)}")
        except (OSError, ValueError, KeyError, StopIteration) as err:
            print(f"plot_results: {run_dir}: cannot plot: {err}", file=sys.stderr)
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))
