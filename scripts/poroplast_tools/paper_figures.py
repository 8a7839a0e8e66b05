"""The paper's figures redrawn from a set of `reproduce.py` runs, one file per figure of the paper
(Fig 11c, a map, apart from Fig 11a-b), each with the small CSV of what it plots
(`<out>/figures/data/<figure>.csv`), so that the numbers quoted from a figure can be checked
without a rerun.

Each figure is drawn at the width it would be printed at (WIDTHS: 17 cm, a page, or 8.5 cm, a
column) at DPI, with no text under MIN_PT points: at 100% on a screen it reads as on paper.

Every function takes `dirs` ({case: run directory}), the output directory and the case table
`cases` ({case: (scene, overrides, t_end of the loading)}), draws nothing and says so when a
case it needs has not run, and returns the figure's file name (or None)."""
import csv
import functools
from pathlib import Path

import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
from matplotlib.colors import LogNorm, Normalize, SymLogNorm
from matplotlib.lines import Line2D

from . import fields, maps
from .history import history

PROBE = maps.PROBE               # X_U, µm
RELEASE = 5.0                    # s: the plates' return, which ends at t_end

PAGE, COLUMN = 17.0, 8.5         # cm: a journal's printed widths
DPI = 200
MIN_PT = 8.0
WIDTHS = {"fig3_pressure.png": PAGE, "fig3_later_pressure.png": PAGE, "fig4_probe.png": PAGE,
          "fig5_plastic_strain.png": PAGE, "fig6_von_mises.png": PAGE, "fig7_total_force.png": PAGE,
          "fig8_constitutive_force.png": PAGE, "fig9_pressure_force.png": PAGE, "fig9_share.png": PAGE,
          "fig10_hw.png": PAGE, "fig11_permeability.png": PAGE, "fig11c_pressure.png": COLUMN,
          "fig_soft.png": PAGE, "fig_soft_pressure.png": PAGE}
STYLE = {"font.size": MIN_PT, "axes.titlesize": MIN_PT, "axes.labelsize": MIN_PT, "xtick.labelsize": MIN_PT,
         "ytick.labelsize": MIN_PT, "legend.fontsize": MIN_PT, "legend.title_fontsize": MIN_PT,
         "figure.titlesize": 9.0, "lines.linewidth": 1.1, "axes.linewidth": 0.6, "xtick.major.width": 0.6,
         "ytick.major.width": 0.6, "legend.handlelength": 1.8, "legend.borderaxespad": 0.3,
         "legend.framealpha": 0.85, "figure.constrained_layout.use": True}


def styled(draw):
    """A figure function drawn with STYLE (the rc settings hold while its text is made)."""
    @functools.wraps(draw)
    def wrapper(*a, **kw):
        with plt.rc_context(STYLE):
            return draw(*a, **kw)
    return wrapper


def figure(name, height_cm, rows=1, cols=1, **kw):
    """A figure of `name`'s printed width and `height_cm`, with its axes."""
    return plt.subplots(rows, cols, figsize=(WIDTHS[name] / 2.54, height_cm / 2.54), squeeze=False, **kw)


def small_text(fig):
    """The visible texts of a figure set under MIN_PT points."""
    return [t.get_text() for t in fig.findobj(matplotlib.text.Text)
            if t.get_visible() and t.get_text().strip() and t.get_fontsize() < MIN_PT - 1e-9]


def have(dirs, names, what="history.csv"):
    missing = [n for n in names if n not in dirs or not (Path(dirs[n]) / what).exists()]
    if missing:
        print(f"  skipped: no {what} for {', '.join(missing)}")
    return not missing


def save(fig, out, name):
    """<out>/figures/<name> at its printed width and DPI (the figure's size is kept: no tight
    bounding box); text under MIN_PT points is an error of the drawing code."""
    small = small_text(fig)
    if small:
        raise ValueError(f"{name}: text under {MIN_PT:g} pt: {small[:5]}")
    (out / "figures").mkdir(exist_ok=True)
    fig.savefig(out / "figures" / name, dpi=DPI)
    plt.close(fig)
    print(f"  wrote {out / 'figures' / name}")
    return name


def write_data(out, name, header, rows):
    """<out>/figures/data/<name>.csv: the numbers a figure plots, 6 significant digits."""
    d = out / "figures" / "data"
    d.mkdir(parents=True, exist_ok=True)
    cell = lambda v: f"{v:.6g}" if isinstance(v, (float, np.floating)) else str(v)
    with open(d / f"{name}.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(header)
        w.writerows([[cell(v) for v in r] for r in rows])


def curves(dirs, out, name, cases, cols):
    """The history columns `cols` of `cases`, one row per (case, output time), as figure data."""
    rows = []
    for c in cases:
        h = history(dirs[c])
        rows += [[c] + [h[k][i] for k in ["time", *cols]] for i in range(len(h["time"]))]
    write_data(out, name, ["case", "time", *cols], rows)


def mark_loading(ax, t_end, label=True):
    """The release of a loading that ends at t_end, shaded (the ramp is the first 5 s, the hold
    all between)."""
    ax.axvspan(t_end - RELEASE, t_end, color="0.8", zorder=0, lw=0,
               label=f"release {t_end - RELEASE:g}–{t_end:g} s" if label else None)


def letter(i):
    return f"({'abcdefghij'[i]})"


@styled
def fig_probe(dirs, out, cases, members, name, extra=None):
    """Fig 4: p(X_U) and porosity against time; `members` [(case, label)], `extra` a third case,
    dotted (R = 900 µm, its own X_U: the probe scales with R)."""
    names = [c for c, _ in members] + ([extra[0]] if extra else [])
    if not have(dirs, names):
        return None
    fig, ax = figure(name, 6.5, 1, 2)
    ax = ax[0]
    t_end = cases[members[0][0]][2]
    for x in ax:
        mark_loading(x, t_end)
    for (case, label), style in zip(members, ("-", "--", "-.")):
        h = history(dirs[case])
        ax[0].plot(h["time"], h["probe_p"], style, label=label)
        ax[1].plot(h["time"], h["probe_porosity"], style, label=label)
    if extra:
        h = history(dirs[extra[0]])
        ax[0].plot(h["time"], h["probe_p"], ":", color="k", label=extra[1])
        ax[1].plot(h["time"], h["probe_porosity"], ":", color="k", label=extra[1])
    ax[0].axhline(0, color="k", lw=0.6)
    for i, (x, lab, what) in enumerate(((ax[0], "pressure p(X_U) [kPa]", "pressure"),
                                        (ax[1], "porosity at X_U [–]", "porosity"))):
        x.set(xlabel="time t [s]", ylabel=lab, xlim=(0, t_end + 10))
        x.set_title(f"{letter(i)} {what} at X_U", loc="left")
    ax[0].legend(loc="best")
    curves(dirs, out, name.removesuffix(".png"), names, ["probe_p", "probe_porosity"])
    return save(fig, out, name)


# Figs 7-9: one panel per swept parameter (a-f as in the paper), the shipped remodel_405 in each.
SWEEPS = [("σy", [("sigma_1", "1 kPa"), ("remodel_405", "2 kPa"), ("sigma_4", "4 kPa")]),
          ("λp", [("lambda_0.1", "0.1 (MPa s)⁻¹"), ("lambda_0.5", "0.5"), ("remodel_405", "1")]),
          ("µ [kPa], ν", [("mu_10", "µ = 10"), ("remodel_405", "µ = 20, ν = 0.2"), ("mu_40", "µ = 40"),
                          ("nu_0.1", "ν = 0.1"), ("nu_0.3", "ν = 0.3")]),
          ("k0 [mm⁴/(N s)]", [("remodel_405", "3.77e-3"), ("k0_2.58e-3", "2.58e-3"), ("k0_2.58e-4", "2.58e-4")]),
          ("ũ_max", [("u_0.1", "0.1"), ("u_0.2", "0.2"), ("remodel_405", "0.3")]),
          ("R", [("remodel_405", "100 µm"), ("R_300", "300 µm"), ("R_900", "900 µm")])]
# (figure, history column, what it is): the paper's Figs 7, 8 and 9
FORCES = [("fig7_total_force.png", "force_total_mg", "total force"),
          ("fig8_constitutive_force.png", "force_constitutive_mg", "constitutive force"),
          ("fig9_pressure_force.png", "force_pressure_mg", "pressure force")]


def fig_forces(dirs, out, cases):
    """Figs 7, 8 and 9: total, constitutive and pressure force on the upper plate of each sweep to
    405 s, one figure each with a panel per parameter (a-f); the R panel divided by (R / 100 µm)²,
    so that its curves share an axis (the force grows about as R²). Their data: one CSV."""
    names = sorted({c for _, m in SWEEPS for c, _ in m})
    if not have(dirs, names):
        return None
    hist = {c: history(dirs[c]) for c in names}
    made = [_forces(hist, out, name, col, what) for name, col, what in FORCES]
    curves(dirs, out, "fig7_9_forces", names, [c for _, c, _ in FORCES])
    return made


@styled
def _forces(hist, out, name, col, what):
    fig, ax = figure(name, 11.0, 2, 3, sharex=True)
    for i, (x, (param, members)) in enumerate(zip(ax.flat, SWEEPS)):
        mark_loading(x, 405.0, label=i == 0)
        for case, label in members:
            scale = (float(label.split()[0]) / 100.0) ** 2 if param == "R" else 1.0
            x.plot(hist[case]["time"], hist[case][col] / scale, label=label)
        x.axhline(0, color="k", lw=0.5)
        x.set_xlim(0, 420)
        x.set_title(f"{letter(i)} {param}", loc="left")
        x.legend(loc="best", ncol=1 if len(members) < 5 else 2, columnspacing=0.8)
        if i >= 3:
            x.set_xlabel("time t [s]")
        if i % 3 == 0:
            x.set_ylabel(f"{what} [mg]")
    ax[1, 2].set_ylabel(f"{what} / (R/100 µm)² [mg]")
    return save(fig, out, name)


@styled
def fig_share(dirs, out, cases):
    """The pressure part's share of the total force against time for the ũ and R sweeps
    (Figs 9e-f against 7e-f): a share, so that the sizes compare across R."""
    groups = [SWEEPS[4], SWEEPS[5]]
    names = sorted({c for _, m in groups for c, _ in m})
    if not have(dirs, names):
        return None
    fig, ax = figure("fig9_share.png", 6.5, 1, 2, sharey=True)
    ax = ax[0]
    rows, seen = [], set()
    for i, (x, (what, members)) in enumerate(zip(ax, groups)):
        for case, label in members:
            h = history(dirs[case])
            ok = (h["force_total_mg"] > 1e-3 * h["force_total_mg"].max()) & (h["time"] <= 400.0)   # the hold
            share = np.where(ok, h["force_pressure_mg"] / np.where(ok, h["force_total_mg"], 1.0), np.nan)
            x.plot(h["time"], share, label=f"{what} = {label}")
            k = int(np.argmax(h["force_total_mg"]))
            if case not in seen:
                rows.append([case, h["time"][k], share[k], float(np.nanmax(share[h["time"] <= 400.0]))])
                seen.add(case)
        x.axhline(0.5, color="k", lw=0.6, ls=":")
        x.set(xscale="log", xlim=(0.1, 400), ylim=(-0.3, 1.05), xlabel="time t [s]")
        x.set_title(f"{letter(i)} {what}", loc="left")
        x.legend(loc="lower left")
    ax[0].set_ylabel("pressure part / total force [–]")
    write_data(out, "fig9_share", ["case", "t_peak_s", "share_at_peak", "largest_share_in_hold"], rows)
    return save(fig, out, "fig9_share.png")


# Figs 10-11a: H/W after 60 s of rest against the compression time (hw_<set>_<t_end>).
HW_TIMES = (10, 40, 65, 155, 305, 605)
HW_SETS = {  # set -> (label, the panel it belongs to: Fig 10a, 10b, 11a)
    "l0.1": ("λp = 0.1 (MPa s)⁻¹", "10a"), "l0.5": ("λp = 0.5", "10a"), "l1": ("λp = 1", "10a"),
    "l0.5_k2.58e-3": ("k0 = 2.58e-3", "10b"), "l0.5_k2.58e-4": ("k0 = 2.58e-4", "10b"),
    "l1_k2.58e-3": ("isotropic (42)", "11a"), "l1_k2.58e-3_c2": ("c = 2 (45)", "11a"),
}


def hw_points(dirs, s):
    """(t_end, H/W at the end of the rest) of one set's completed runs."""
    pts = []
    for t in HW_TIMES:
        d = dirs.get(f"hw_{s}_{t}")
        if d is not None and (Path(d) / "history.csv").exists():
            h = history(d)
            pts.append((t, h["height"][-1] / h["width"][-1]))
    return pts


def hw_panel(ax, dirs, panel):
    """The H/W curves of one panel (10a, 10b, 11a) against the compression time."""
    for s, (label, p) in HW_SETS.items():
        if p == panel and (pts := hw_points(dirs, s)):
            ax.plot(*zip(*pts), "o-", ms=3.5, label=label)
    ax.axvline(300, color="k", lw=0.5, ls=":", label="5 min")
    ax.set(xscale="log", xlabel="compression time t_end [s]")
    ax.set_xticks(HW_TIMES, [f"{t:g}" for t in HW_TIMES])
    ax.minorticks_off()


@styled
def fig_hw(dirs, out, cases):
    """Fig 10: shape recovery, H/W after the rest against the compression time (a: λp; b: k0 at
    λp = 0.5, Table 1's k0 = 3.77e-3 drawn too). Its data holds Fig 11a's sets too."""
    if not any(hw_points(dirs, s) for s in HW_SETS):
        print("  skipped: no hw_* runs")
        return None
    fig, ax = figure("fig10_hw.png", 6.5, 1, 2, sharey=True)
    ax = ax[0]
    hw_panel(ax[0], dirs, "10a")
    hw_panel(ax[1], dirs, "10b")
    if pts := hw_points(dirs, "l0.5"):
        ax[1].plot(*zip(*pts), "s--", ms=3.5, color="grey", label="k0 = 3.77e-3 (Table 1)")
    for i, (x, t) in enumerate(zip(ax, ("λp", "k0 [mm⁴/(N s)] at λp = 0.5 (MPa s)⁻¹"))):
        x.set_title(f"{letter(i)} {t}", loc="left")
        x.legend(loc="lower left", ncol=2, columnspacing=0.8)
    lo, hi = ax[0].get_ylim()
    ax[0].set_ylim(lo - 0.25 * (hi - lo), hi)         # room for the legends under the curves
    ax[0].set_ylabel("H/W after 60 s of rest [–]")
    write_data(out, "fig10_hw", ["set", "t_end_s", "height_over_width"],
               [[s, t, v] for s in HW_SETS for t, v in hw_points(dirs, s)])
    return save(fig, out, "fig10_hw.png")


@styled
def fig_permeability(dirs, out, cases, members):
    """Fig 11a-b: the remodelling-dependent permeability (c = 2) against the isotropic one: H/W
    after the rest (a; its data in fig10_hw.csv) and p(X_U) (b; `members` [(case, label)], each to
    its release)."""
    if not have(dirs, [c for c, _ in members]):
        return None
    name = "fig11_permeability.png"
    fig, ax = figure(name, 6.5, 1, 2)
    ax = ax[0]
    hw_panel(ax[0], dirs, "11a")
    ax[0].set_ylabel("H/W after 60 s of rest [–]")
    ax[0].set_title("(a) shape recovery, k0 = 2.58e-3 mm⁴/(N s)", loc="left")
    ax[0].legend(loc="best")
    t_end = cases[members[0][0]][2]
    mark_loading(ax[1], t_end)
    for (case, label), style in zip(members, ("-", "--", "-.")):
        h = history(dirs[case])
        m = h["time"] <= (t_end if cases[case][2] == t_end else t_end - RELEASE)   # a longer run: its hold
        ax[1].plot(h["time"][m], h["probe_p"][m], style, label=label)
    ax[1].axhline(0, color="k", lw=0.6)
    ax[1].set(xlabel="time t [s]", ylabel="pressure p(X_U) [kPa]", xlim=(0, t_end + 10))
    ax[1].set_title("(b) pressure at X_U", loc="left")
    ax[1].legend(loc="best")
    curves(dirs, out, "fig11_probe", [c for c, _ in members], ["probe_p", "probe_porosity"])
    return save(fig, out, name)


@styled
def fig_soft(dirs, out, cases):
    """A soft solid (µ = 3 kPa): Forgacs' aggregates (ν = 0.45), and p(X_U) without a bubble (ν = 0.2)."""
    if not have(dirs, ["mu3_nu0.45", "mu3_nu0.2", "remodel_155"]):
        return None
    fig, ax = figure("fig_soft.png", 6.5, 1, 2)
    ax = ax[0]
    h = history(dirs["mu3_nu0.45"])
    for col, lab in (("force_total_mg", "total"), ("force_constitutive_mg", "constitutive"),
                     ("force_pressure_mg", "pressure")):
        ax[0].plot(h["time"], h[col], label=lab)
    status = Path(dirs["mu3_nu0.45"]) / "status.txt"
    failed = status.exists() and status.read_text().startswith("failed")
    ax[0].set(xlim=(0, 160), xlabel="time t [s]", ylabel="force on the upper plate [mg]")
    ax[0].set_title("(a) µ = 3 kPa, ν = 0.45" + (f": failed after {h['time'][-1]:.3g} s" if failed else ""),
                    loc="left")
    for case, style, lab in (("remodel_155", "-", "µ = 20 kPa"), ("mu3_nu0.2", "--", "µ = 3 kPa")):
        hh = history(dirs[case])
        ax[1].plot(hh["time"], hh["probe_p"], style, label=lab)
    ax[1].axhline(0, color="k", lw=0.6)
    ax[1].set(xlabel="time t [s]", ylabel="pressure p(X_U) [kPa]")
    ax[1].set_title("(b) ν = 0.2", loc="left")
    for x in ax:
        x.legend(loc="best")
    curves(dirs, out, "fig_soft", ["mu3_nu0.45", "mu3_nu0.2"], ["force_total_mg", "probe_p"])
    return save(fig, out, "fig_soft.png")


# ---------------------------------------------------------------- maps (maps.py)

def map_grid(name, n, height_cm):
    """Axes for n map panels, three to a row, and one more cell for the key (legend and colour
    bar); a single panel on a column's width gets its key below it."""
    if n == 1:
        fig, ax = figure(name, height_cm, 2, 1, height_ratios=[4, 1.9])
        return fig, [ax[0, 0]], ax[1, 0]
    rows = (n + 1 + 2) // 3
    fig, ax = figure(name, height_cm, rows, 3)      # one scale by map_axes' limits: every panel its ticks
    flat = list(ax.flat)
    for x in flat[n + 1:]:
        x.set_visible(False)
    return fig, flat[:n], flat[n]


def key(fig, panels, cax, mappable, label, extra=(), ticks=None):
    """The colour bar and a legend of the lines drawn on the maps: the bar at the right of the
    panels and the legend in the key cell, or, under a single map (a column's width), both in
    the key cell."""
    cax.set_axis_off()
    single = len(panels) == 1
    if single:
        cb = fig.colorbar(mappable, cax=cax.inset_axes([0.08, 0.84, 0.84, 0.1]), orientation="horizontal",
                          ticks=ticks)
    else:
        cb = fig.colorbar(mappable, ax=[*panels, cax], ticks=ticks, shrink=0.85, aspect=30)
    if ticks is not None:
        cb.set_ticklabels([f"{t:g}".replace("-", "−") for t in ticks])
    cb.set_label(label)
    handles = [Line2D([], [], color="k", lw=0.9, ls=(0, (3, 1.5)), path_effects=maps.HALO,
                      label="regions of the table"),
               Line2D([], [], ls="", marker="o", ms=4, mfc="k", mec="w", label="X_U"),
               *extra]
    cax.legend(handles=handles, loc="lower center" if single else "center", frameon=False, borderaxespad=0.0,
               ncol=2 if single else 1)


def map_axes(ax, panels, halves):
    """Equal aspect, the union of the panels' extents (one scale), the axes labelled and the
    halves named."""
    pts = np.concatenate([p.refined.cur for p in panels])
    xm, (z0, z1) = np.abs(pts[:, 0]).max(), (pts[:, 1].min(), pts[:, 1].max())
    pad = 0.04 * (z1 - z0)
    for i, x in enumerate(ax):
        x.set_xlabel("x [µm]")
        if i % 3 == 0:
            x.set_ylabel("z [µm]")
        x.set_aspect("equal")
        x.set_xlim(-xm - pad, xm + pad)
        x.set_ylim(z0 - pad, z1 + 0.16 * (z1 - z0))     # room above for the halves' names
        if halves:
            for side, text in zip((-1, 1), halves):
                x.text(0.5 + side * 0.48, 0.98, text, transform=x.transAxes, va="top",
                       ha="left" if side < 0 else "right")


def write_panels(out, name, panels):
    """The maps' own data (<name>_nodes.csv, <name>_cells.csv): each panel's section nodes
    (reference (x, z), u, the node fields) and 6-node triangles with the cell fields, enough to
    redraw the refined map."""
    nodes, cells = [], []
    for p in panels:
        nn, cn = sorted(p.node), sorted(p.cell)
        nodes += [[p.case, p.t, i, *p.X[i], *p.u[i], *(p.node[k][i] for k in nn)] for i in range(len(p.X))]
        cells += [[p.case, p.t, j, *p.tri6[j], *(p.cell[k][j] for k in cn)] for j in range(len(p.tri6))]
    write_data(out, f"{name}_nodes", ["case", "t_s", "node", "x_ref_um", "z_ref_um", "ux_um", "uz_um", *nn], nodes)
    write_data(out, f"{name}_cells", ["case", "t_s", "cell", *(f"n{k}" for k in range(6)), *cn], cells)


ISOBARS = sorted(s * x for x in (0.03, 0.1, 0.3, 1.0, 3.0, 10.0) for s in (-1, 1))


@styled
def fig_pressure(dirs, out, cases, pair, ts, name, halves):
    """Pressure on the mid-plane y = 0 (Figs 3, 11c): each panel one time, the run pair[0] on the
    left (mirrored), pair[1] on the right, on one symmetric scale, linear within ±0.1 kPa and
    logarithmic beyond (a bubble of 1 kPa shows next to the ramp's 15 kPa), with labelled isobars
    (ISOBARS; p = 0 bold), the table's regions and X_U. Data: per panel the extremes, the
    positive region and X_U's position (<name>.csv), and the fields (write_panels)."""
    if not have(dirs, pair, "fields.h5"):
        return None
    secs = {c: maps.Section(c, dirs[c]) for c in pair}
    panels = [[secs[c].panel(secs[c].index(t)[0], ["p"]) for c in pair] for t in ts]
    top = max(np.abs(p.node["p"]).max() for pp in panels for p in pp)
    norm = SymLogNorm(linthresh=0.1, vmin=-top, vmax=top, base=10)
    fig, ax, cax = map_grid(name, len(ts), 8.8 if len(ts) > 2 else 5.6 if len(ts) > 1 else 9.0)
    data = []
    for i, (x, pp) in enumerate(zip(ax, panels)):
        for side, p in zip((-1, 1), pp):
            m = maps.draw(x, p, "p", side, cmap="RdBu_r", norm=norm, rasterized=True)
            drawn = maps.isobars(x, p, side, ISOBARS)
            maps.outline(x, p, side)
            share, where, angle = fields.bubble(dirs[p.case], p.t)
            v = p.node["p"]
            data.append([p.case, p.t, v.min(), v.max(), share, where, angle, *maps.probe(p),
                         " ".join(f"{z:g}" for z in drawn)])
        x.axvline(0, color="0.3", lw=0.5)
        x.set_title(f"{letter(i)} t = {pp[0].t:.4g} s" if len(ts) > 1 else f"t = {pp[0].t:.4g} s", loc="left")
    map_axes(ax, [p for pp in panels for p in pp], halves)
    ticks = [t for t in (-10, -1, -0.1, 0, 0.1, 1, 10) if -top <= t <= top]
    key(fig, ax, cax, m, "pressure p [kPa] (linear within ±0.1)", ticks=ticks,
        extra=[Line2D([], [], color="k", lw=0.5, label="isobar [kPa]"),
               Line2D([], [], color="k", lw=1.3, label="p = 0")])
    data.sort(key=lambda row: pair.index(row[0]))      # by run, then time (a stable sort)
    write_data(out, name.removesuffix(".png"), ["case", "t_s", "p_min_kPa", "p_max_kPa", "positive_share",
                                               "positive_centre_R", "positive_angle_deg", "x_U_um", "z_U_um",
                                               "isobars_kPa"], data)
    write_panels(out, name.removesuffix(".png"), [p for pp in panels for p in pp])
    return save(fig, out, name)


MIDPLANE_TIMES = [5.0, 15.0, 35.0, 40.0, 60.0]
# (figure, field, colour-bar label, colour map, log scale?): the paper's Figs 5 and 6
MIDPLANE = [("fig5_plastic_strain.png", "norm_ep", "‖E_p‖ [–]", "viridis", False),
            ("fig6_von_mises.png", "von_mises", "σ_VM [kPa] (logarithmic)", "magma", True)]


def fig_midplane(dirs, out, cases):
    """Figs 5 and 6: ‖E_p‖ and σ_VM on the mid-plane of remodel_40, each cell's value as stored,
    one colour scale per figure across the times (σ_VM logarithmic: it falls tenfold at the
    release), with the table's regions; and the region means (fig5_6_zones.csv)."""
    if not have(dirs, ["remodel_40"], "fields.h5"):
        return None
    s = maps.Section("remodel_40", dirs["remodel_40"])
    panels = [s.panel(s.index(t)[0], ["norm_ep", "von_mises"]) for t in MIDPLANE_TIMES]
    made = [_midplane(out, panels, *m) for m in MIDPLANE]
    write_panels(out, "fig5_6_midplane", panels)
    rows = []
    # the region means, and without gravity (the paper: gravity makes the two plates differ)
    for case in [c for c in ("remodel_40", "remodel_40_g0") if c in dirs and (Path(dirs[c]) / "fields.h5").exists()]:
        f = fields.fields(dirs[case])
        for t in MIDPLANE_TIMES:
            v = f.at("von_mises", t)
            zm = lambda name, zone: fields.zone_mean(dirs[case], name, zone, t)
            rows.append([f"{case}@{t:g}", v.max(), f.r[v.argmax()], f.z[v.argmax()],
                         *(zm("von_mises", z) for z in ("centre", "contact", "contact_upper", "contact_lower")),
                         zm("norm_ep", "centre"), zm("norm_ep", "contact"),
                         zm("porosity", "centre"), zm("porosity", "contact")])
    write_data(out, "fig5_6_zones", ["row", "vm_max_kPa", "vm_max_r_ref_um", "vm_max_z_ref_um", "vm_centre_kPa",
                                     "vm_contact_kPa", "vm_contact_upper_kPa", "vm_contact_lower_kPa", "ep_centre",
                                     "ep_contact", "porosity_centre", "porosity_contact"], rows)
    return made


@styled
def _midplane(out, panels, name, field, label, cmap, log):
    values = [p.cell[field] for p in panels]
    ticks = None
    if log:
        lo, hi = max(min(v[v > 0].min() for v in values), 1e-2), max(v.max() for v in values)
        norm = LogNorm(lo, hi)
        ticks = [t for t in (0.1, 0.2, 0.5, 1, 2, 5, 10, 20, 50) if lo <= t <= hi]
    else:
        norm = Normalize(0.0, max(v.max() for v in values))
    fig, ax, cax = map_grid(name, len(panels), 10.0)
    for i, (x, p) in enumerate(zip(ax, panels)):
        for side in (-1, 1):
            m = maps.draw(x, p, field, side, cmap=cmap, norm=norm, rasterized=True)
            maps.outline(x, p, side)
        x.set_title(f"{letter(i)} t = {p.t:.4g} s" + (" (released)" if p.t > 40.0 - RELEASE + 1e-9 else ""),
                    loc="left")
    map_axes(ax, panels, None)
    key(fig, ax, cax, m, label, ticks=ticks)
    return save(fig, out, name)
