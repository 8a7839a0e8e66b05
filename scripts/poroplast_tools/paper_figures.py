"""The paper's figures redrawn from a set of `reproduce.py` runs, each with the small CSV of
what it plots (`<out>/figures/data/<figure>.csv`), so that the numbers quoted from a figure can be
checked without a rerun.

Every function takes `dirs` ({case: run directory}), the output directory and the case table
`cases` ({case: (scene, overrides, t_end of the loading)}), draws nothing and says so when a
case it needs has not run, and returns the figure's file name (or None)."""
import csv
from pathlib import Path

import h5py
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import matplotlib.tri as mtri
from matplotlib.colors import LogNorm, SymLogNorm

from . import fields
from .history import history

PROBE = (40.0, 0.0, 190.0)       # X_U, um
RELEASE = 5.0                    # s: the plates' return, which ends at t_end


def have(dirs, names, what="history.csv"):
    missing = [n for n in names if n not in dirs or not (Path(dirs[n]) / what).exists()]
    if missing:
        print(f"  skipped: no {what} for {', '.join(missing)}")
    return not missing


def save(fig, out, name):
    if not fig.get_constrained_layout():             # section figures lay out their colour bars
        fig.tight_layout()
    (out / "figures").mkdir(exist_ok=True)
    fig.savefig(out / "figures" / name, dpi=130)
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
    """The hold (light) and the release (darker) of a loading that ends at t_end."""
    ax.axvspan(RELEASE, t_end - RELEASE, color="0.93", zorder=0)
    ax.axvspan(t_end - RELEASE, t_end, color="0.8", zorder=0,
               label=f"release {t_end - RELEASE:g}–{t_end:g} s" if label else None)


def fig_probe(dirs, out, cases, members, name, title, extra=None):
    """p(X_U) and porosity against time (Figs 4, 11b); `members` [(case, label)], `extra` a third
    case, dotted (for Fig 4 R = 900 µm, its own X_U: the probe scales with R)."""
    names = [c for c, _ in members] + ([extra[0]] if extra else [])
    if not have(dirs, names):
        return None
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    t_end = cases[members[0][0]][2]
    for x in ax:
        mark_loading(x, t_end)
    for (case, label), style in zip(members, ("-", "--", "-.")):
        h = history(dirs[case])
        # a run of a longer protocol: its identical part, up to this one's release
        m = h["time"] <= (t_end if cases[case][2] == t_end else t_end - RELEASE)
        ax[0].plot(h["time"][m], h["probe_p"][m], style, label=label)
        ax[1].plot(h["time"][m], h["probe_porosity"][m], style, label=label)
    if extra:
        h = history(dirs[extra[0]])
        ax[0].plot(h["time"], h["probe_p"], ":", color="k", label=extra[1])
        ax[1].plot(h["time"], h["probe_porosity"], ":", color="k", label=extra[1])
    ax[0].axhline(0, color="k", lw=0.7)
    for x, lab in ((ax[0], "pressure p(X_U) [kPa]"), (ax[1], "porosity at X_U [-]")):
        x.set(xlabel="time t [s]", ylabel=lab, xlim=(0, t_end + 10))   # a longer run: to this one's end
        x.legend(fontsize=8)
    fig.suptitle(f"{title}; X_U = {PROBE} µm (0.4 R, 0, 1.9 R)")
    curves(dirs, out, name.removesuffix(".png"), names, ["probe_p", "probe_porosity"])
    return save(fig, out, name)


# Figs 7-9: one column per swept parameter, the shipped remodel_405 in each.
SWEEPS = [("σy", [("sigma_1", "1 kPa"), ("remodel_405", "2 kPa"), ("sigma_4", "4 kPa")]),
          ("λp", [("lambda_0.1", "0.1 (MPa s)⁻¹"), ("lambda_0.5", "0.5"), ("remodel_405", "1")]),
          ("µ, ν", [("mu_10", "µ = 10 kPa"), ("remodel_405", "µ = 20, ν = 0.2"), ("mu_40", "µ = 40 kPa"),
                    ("nu_0.1", "ν = 0.1"), ("nu_0.3", "ν = 0.3")]),
          ("k0 (mm⁴/(N s))", [("remodel_405", "3.77e-3"), ("k0_2.58e-3", "2.58e-3"), ("k0_2.58e-4", "2.58e-4")]),
          ("ũ_max", [("u_0.1", "0.1"), ("u_0.2", "0.2"), ("remodel_405", "0.3")]),
          ("R", [("remodel_405", "100 µm"), ("R_300", "300 µm"), ("R_900", "900 µm")])]
FORCES = [("force_total_mg", "total force"), ("force_constitutive_mg", "constitutive force"),
          ("force_pressure_mg", "pressure force")]


def fig_forces(dirs, out, cases):
    """Total, constitutive and pressure force of each sweep to 405 s (Figs 7-9 a-f); the R
    column divided by (R / 100 µm)², so that its curves share an axis (the force grows about as
    R²; faster where the larger aggregate drains more slowly)."""
    names = sorted({c for _, m in SWEEPS for c, _ in m})
    if not have(dirs, names):
        return None
    hist = {c: history(dirs[c]) for c in names}
    fig, ax = plt.subplots(3, len(SWEEPS), figsize=(4.2 * len(SWEEPS), 10), sharex=True)
    for c, (what, members) in enumerate(SWEEPS):
        for r, (col, lab) in enumerate(FORCES):
            x = ax[r, c]
            mark_loading(x, 405.0, label=r == 0 and c == 0)
            for case, label in members:
                scale = (float(label.split()[0]) / 100.0) ** 2 if what == "R" else 1.0
                x.plot(hist[case]["time"], hist[case][col] / scale, label=label)
            x.axhline(0, color="k", lw=0.5)
            x.set(xlim=(0, 420), title=f"{lab}: {what}" + (" (force / (R/100 µm)²)" if what == "R" else ""),
                  xlabel="time t [s]" if r == 2 else None)
            if c == 0:
                x.set_ylabel(f"{lab} [mg]")
            x.legend(fontsize=7)
    fig.suptitle("Figs 7-9: plate forces with remodelling (t_end = 405 s, the release shaded); "
                 "each column varies one parameter of Table 1")
    curves(dirs, out, "fig7_9_forces", names, [c for c, _ in FORCES])
    return save(fig, out, "fig7_9_forces.png")


def fig_share(dirs, out, cases):
    """The pressure part's share of the total force against time for the ũ and R sweeps
    (Figs 9e-f against 7e-f): a share, so that the sizes compare across R."""
    groups = [SWEEPS[4], SWEEPS[5]]
    names = sorted({c for _, m in groups for c, _ in m})
    if not have(dirs, names):
        return None
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5), sharey=True)
    rows, seen = [], set()
    for x, (what, members) in zip(ax, groups):
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
        x.set(xscale="log", xlim=(0.1, 400), ylim=(-0.3, 1.05), xlabel="time t [s]", title=f"pressure share: {what}")
        x.legend(fontsize=8)
    ax[0].set_ylabel("pressure part / total force [-]")
    fig.suptitle("Pressure share of the plate force until the release (above 0.5 the pressure carries more than the solid)")
    write_data(out, "fig9_share", ["case", "t_peak_s", "share_at_peak", "largest_share_in_hold"], rows)
    return save(fig, out, "fig9_share.png")


# Fig 10-11a: H/W after 60 s of rest against the compression time (hw_<set>_<t_end>).
HW_TIMES = (10, 40, 65, 155, 305, 605)
HW_SETS = {  # set -> (label, the panel it belongs to)
    "l0.1": ("λp = 0.1 (MPa s)⁻¹", "a"), "l0.5": ("λp = 0.5", "a"), "l1": ("λp = 1", "a"),
    "l0.5_k2.58e-3": ("λp = 0.5, k0 = 2.58e-3", "b"), "l0.5_k2.58e-4": ("λp = 0.5, k0 = 2.58e-4", "b"),
    "l1_k2.58e-3": ("isotropic (42), k0 = 2.58e-3", "c"), "l1_k2.58e-3_c2": ("c = 2 (45), k0 = 2.58e-3", "c"),
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


def fig_hw(dirs, out, cases):
    """Shape recovery: H/W after the rest against the compression time (Fig 10a: λp; 10b: k0 at
    λp = 0.5, Table 1's k0 = 3.77e-3 drawn too; 11a: c = 2 against isotropic)."""
    if not any(hw_points(dirs, s) for s in HW_SETS):
        print("  skipped: no hw_* runs")
        return None
    fig, ax = plt.subplots(1, 3, figsize=(16, 4.5), sharey=True)
    panels = {"a": ax[0], "b": ax[1], "c": ax[2]}
    rows = []
    for s, (label, p) in HW_SETS.items():
        pts = hw_points(dirs, s)
        rows += [[s, t, v] for t, v in pts]
        if pts:
            panels[p].plot(*zip(*pts), "o-", label=label)
    if pts := hw_points(dirs, "l0.5"):
        ax[1].plot(*zip(*pts), "s--", color="grey", label="λp = 0.5, k0 = 3.77e-3 (Table 1)")
    for x, t in zip(ax, ("Fig 10a: λp", "Fig 10b: k0 at λp = 0.5", "Fig 11a: permeability (λp = 1)")):
        x.axvline(300, color="k", lw=0.5, ls=":")
        x.set(xscale="log", xlabel="compression time t_end [s]", title=t)
        x.legend(fontsize=8)
    ax[0].set_ylabel("H/W after 60 s of rest [-]")
    fig.suptitle("Shape recovery against the compression time (the dotted line: 5 min)")
    write_data(out, "fig10_hw", ["set", "t_end_s", "height_over_width"], rows)
    return save(fig, out, "fig10_hw.png")


def fig_soft(dirs, out, cases):
    """A soft solid (µ = 3 kPa): Forgacs' aggregates (ν = 0.45), and p(X_U) without a bubble (ν = 0.2)."""
    if not have(dirs, ["mu3_nu0.45", "mu3_nu0.2", "remodel_155"]):
        return None
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    h = history(dirs["mu3_nu0.45"])
    for col, lab in (("force_total_mg", "total"), ("force_constitutive_mg", "constitutive"),
                     ("force_pressure_mg", "pressure")):
        ax[0].plot(h["time"], h[col], label=lab)
    status = Path(dirs["mu3_nu0.45"]) / "status.txt"
    failed = f"\nrun failed: last converged step at t = {h['time'][-1]:.2f} s" \
        if status.exists() and status.read_text().startswith("failed") else ""
    ax[0].set(xlim=(0, 160), xlabel="time t [s]", ylabel="force on the upper plate [mg]",
              title="µ = 3 kPa, ν = 0.45, λp = 1 (MPa s)⁻¹ (Forgacs)" + failed)
    for case, style, lab in (("remodel_155", "-", "µ = 20 kPa"), ("mu3_nu0.2", "--", "µ = 3 kPa")):
        hh = history(dirs[case])
        ax[1].plot(hh["time"], hh["probe_p"], style, label=f"{lab} ({case})")
    ax[1].axhline(0, color="k", lw=0.7)
    ax[1].set(xlabel="time t [s]", ylabel="pressure p(X_U) [kPa]", title="µ = 20 vs 3 kPa (ν = 0.2)")
    for x in ax:
        x.legend()
    fig.suptitle("Soft aggregates (t_end = 155 s)")
    curves(dirs, out, "fig_soft", ["mu3_nu0.45", "mu3_nu0.2"], ["force_total_mg", "probe_p"])
    return save(fig, out, "fig_soft.png")


class Section:
    """The mid-plane y = 0 of a run's fields.h5: the faces there of cells with 3 vertices on it
    (every cell of a meridian run), each split in 4 triangles through its mid-edge nodes so that
    deformed boundaries curve."""

    def __init__(self, case, d):
        self.case = case
        self.f = h5py.File(Path(d) / "fields.h5", "r")
        self.X = self.f["/mesh/coordinates"][:]
        top = self.f["/mesh/topology"][:]
        self.times = self.f["/time"][:]
        meridian = top.shape[1] == 6
        nv, edges = (3, fields.TRI6_EDGES) if meridian else (4, fields.TET10_EDGES)
        on = np.abs(self.X[top[:, :nv], 1]) < 1e-9
        tris, owner = [], []
        for c in np.nonzero(on.sum(1) == 3)[0]:
            a, b, e = np.nonzero(on[c])[0]
            mid = {frozenset(pair): top[c, nv + k] for k, pair in enumerate(edges)}
            ab, be, ea = mid[frozenset((a, b))], mid[frozenset((b, e))], mid[frozenset((e, a))]
            A, B, E = top[c, [a, b, e]]
            tris += [(A, ab, ea), (ab, B, be), (ea, be, E), (ab, be, ea)]
            owner += [c] * 4
        self.tris, self.owner = np.array(tris), np.array(owner)

    def index(self, t):
        k = int(np.argmin(np.abs(self.times - t)))
        if abs(self.times[k] - t) > 0.05:            # e.g. a run older than its scene's fields_at
            print(f"  warning: {self.case} has no output at t = {t:g} s; nearest is {self.times[k]:.4g} s")
        return k, self.times[k]

    def field(self, name, k):
        return self.f[f"/fields/{name}/{k:06d}"][:]

    def triangulation(self, k):
        """The deformed section mirrored to x < 0 (the whole cross-section), and the vertex count."""
        u, n = self.field("u", k), len(self.X)
        x, z = self.X[:, 0] + u[:, 0], self.X[:, 2] + u[:, 2]
        return mtri.Triangulation(np.r_[x, -x], np.r_[z, z], np.r_[self.tris, self.tris + n]), n

    def draw(self, ax, name, k, **kw):
        tri, n = self.triangulation(k)
        v = self.field(name, k)
        if len(v) == n:                              # node field: linear over each sub-triangle
            m = ax.tripcolor(tri, np.r_[v, v], shading="gouraud", **kw)
        else:                                        # cell field: constant per cell
            m = ax.tripcolor(tri, facecolors=np.r_[v[self.owner], v[self.owner]], **kw)
        ax.set(aspect="equal", xlabel="x [µm]", ylabel="z [µm]")
        return m

    def isolines(self, ax, name, k, levels):
        """Contours of a node field (isobars): p = 0 bold where p changes sign by more than
        0.01 kPa (the drained surface's p ≈ 0 is not an isobar)."""
        tri, _ = self.triangulation(k)
        v = self.field(name, k)
        inside = [x for x in levels if v.min() < x < v.max() and x != 0]
        if inside:
            ax.tricontour(tri, np.r_[v, v], levels=inside, colors="k", linewidths=0.4)
        if v.min() < -0.01 < 0.01 < v.max():       # not the drained surface's round-off
            ax.tricontour(tri, np.r_[v, v], levels=[0.0], colors="k", linewidths=1.4)

    def probe(self, k):
        """Deformed position (x, z) of X_U, u interpolated linearly on the reference section."""
        tri = mtri.Triangulation(self.X[:, 0], self.X[:, 2], self.tris)
        u = self.field("u", k)
        ux, uz = (float(mtri.LinearTriInterpolator(tri, u[:, i])(PROBE[0], PROBE[2])) for i in (0, 2))
        return PROBE[0] + ux, PROBE[2] + uz


MIDPLANE_TIMES = [5.0, 15.0, 35.0, 40.0, 60.0]


def fig_midplane(dirs, out, cases):
    """‖E_p‖ and σ_VM on the mid-plane of remodel_40 (Figs 5-6), one colour scale per quantity
    across the times (σ_VM logarithmic: it falls tenfold at the release), with the region means."""
    if not have(dirs, ["remodel_40"], "fields.h5"):
        return None
    run = dirs["remodel_40"]
    s = Section("remodel_40", run)
    ks = [s.index(t) for t in MIDPLANE_TIMES]
    fig, ax = plt.subplots(2, len(ks), figsize=(4.2 * len(ks), 7.5), sharex=True, sharey=True, layout="constrained")
    ep_max = max(s.field("norm_ep", k).max() for k, _ in ks)
    vm = [s.field("von_mises", k) for k, _ in ks]
    vm_lo, vm_hi = max(min(v[v > 0].min() for v in vm), 1e-2), max(v.max() for v in vm)
    norms = [("norm_ep", "‖E_p‖ [-]", "viridis", dict(vmin=0, vmax=ep_max)),
             ("von_mises", "σ_VM [kPa]", "magma", dict(norm=LogNorm(vm_lo, vm_hi)))]
    for r, (name, lab, cmap, kw) in enumerate(norms):
        for c, (k, tt) in enumerate(ks):
            m = s.draw(ax[r, c], name, k, cmap=cmap, **kw)
            ax[r, c].set_title(f"{lab.split(' ')[0]}, t = {tt:.4g} s")
        fig.colorbar(m, ax=ax[r, :].tolist(), label=lab, shrink=0.9)
    fig.suptitle("Figs 5-6: remodel_40, mid-plane y = 0 (deformed); one colour scale per row")
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
    return save(fig, out, "fig5_6_midplane.png")


ISOBARS = sorted(s * x for x in (0.03, 0.1, 0.3, 1.0, 3.0, 10.0) for s in (-1, 1))


def fig_pressure(dirs, out, cases, members, ts, name, title):
    """Pressure on the mid-plane with isobars (±0.03, 0.1, 0.3, 1, 3, 10 kPa; p = 0 bold), on one
    symmetric scale, linear within ±0.1 kPa and logarithmic beyond, so that a bubble of 1 kPa
    shows next to the ramp's 15 kPa (Figs 3, 11c); and its positive region as figure data."""
    if not have(dirs, members, "fields.h5"):
        return None
    secs = {c: Section(c, dirs[c]) for c in members}
    idx = {c: [secs[c].index(t) for t in ts] for c in members}
    top = max(np.abs(secs[c].field("p", k)).max() for c in members for k, _ in idx[c])
    norm = SymLogNorm(linthresh=0.1, vmin=-top, vmax=top, base=10)
    rows, cols = (len(members), len(ts)) if len(ts) > 1 else (1, len(members))   # one time: side by side
    fig, ax = plt.subplots(rows, cols, figsize=(4.2 * cols + 1.5, 3.6 * rows), squeeze=False,
                           sharex=True, sharey=True, layout="constrained")
    data = []
    for x, (c, k, tt) in zip(ax.flat, [(c, k, tt) for c in members for k, tt in idx[c]]):
        m = secs[c].draw(x, "p", k, cmap="RdBu_r", norm=norm)
        secs[c].isolines(x, "p", k, ISOBARS)
        x.plot(*secs[c].probe(k), "ko", ms=4, label="X_U (deformed)")
        x.set_title(f"{c}, t = {tt:.4g} s")
        p = secs[c].field("p", k)
        share, where, angle = fields.bubble(dirs[c], float(tt))
        data.append([c, tt, p.min(), p.max(), share, where, angle])
    ax.flat[0].legend(loc="lower left", fontsize=8)
    fig.colorbar(m, ax=ax.ravel().tolist(), label="pressure p [kPa] (linear within ±0.1)")
    fig.suptitle(f"{title}: pressure on the mid-plane y = 0 (deformed); isobars, p = 0 bold")
    write_data(out, name.removesuffix(".png"), ["case", "t_s", "p_min_kPa", "p_max_kPa", "positive_share",
                                               "positive_centre_R", "positive_angle_deg"], data)
    return save(fig, out, name)
