#!/usr/bin/env python3
"""Reproduce the figures of Di Stefano et al. (ZAMP 2022) with remodelling: runs the builtin
scenes remodel_40, remodel_155, remodel_155_c2, elastic_155, remodel_405, reference_405 and four
variants of remodel_405 (lambda_p = 0.1, 0.5 (MPa s)^-1; sigma_y = 1, 4 kPa) on 2 MPI ranks (one
`poroplast sweep` for the cases to run: 3-D ones one at a time on both ranks, meridians two at a
time on one each; --ranks, --ranks-per-case, --no-sweep as in the other study scripts),
then draws the probe curves (Figs 4, 11), the force sweeps (Figs 7-9) and mid-plane sections
(Figs 3, 5-6, 11c) into <out>/figures/, and writes <out>/summary.csv (also printed).
Every case is a case of the store <out>/cases (`poroplast sweep`; the sweep's lines in
<out>/sweep.log); a case that completed with the same settings is not run again, so an
interrupted study resumes.
With --axisymmetric every case runs on its meridian (`--set mesh.geometry=axisymmetric`; the
section figures then show the meridian itself, mirrored), by default into runs/reproduce_axi.

    python3 scripts/reproduce.py [--out runs/reproduce] [--only NAME ...] [--plots-only] [--docs]
                                 [--axisymmetric] [--ranks 2] [--ranks-per-case K] [--no-sweep]
                                 [--converged DIR] [--references CSV]
"""
import argparse
import csv
import math
import shutil
import subprocess
from functools import lru_cache
from pathlib import Path

import h5py
import numpy as np
import matplotlib
matplotlib.use("Agg")
import matplotlib.pyplot as plt
import matplotlib.tri as mtri
from matplotlib.colors import TwoSlopeNorm

from poroplast_tools import fields
from poroplast_tools import cases as store
from poroplast_tools.cases import ROOT, find_case
from poroplast_tools.history import at as value_at, history, timings
from poroplast_tools.refs import references
from poroplast_tools.tables import write_rows

# case -> (builtin scene, `--set` overrides, t_end of the loading in s)
R405 = "material.remodelling"
CASES = {
    "remodel_40": ("remodel_40", [], 40.0),
    "remodel_155": ("remodel_155", [], 155.0),
    "remodel_155_c2": ("remodel_155_c2", [], 155.0),
    "elastic_155": ("elastic_155", [], 155.0),
    "remodel_405": ("remodel_405", [], 405.0),
    "reference_405": ("reference_405", [], 405.0),
    "lambda_0.1": ("remodel_405", [f"{R405}.lambda_p=0.0001"], 405.0),   # 0.1 (MPa s)^-1
    "lambda_0.5": ("remodel_405", [f"{R405}.lambda_p=0.0005"], 405.0),
    "sigma_1": ("remodel_405", [f"{R405}.sigma_y=1.0"], 405.0),          # kPa
    "sigma_4": ("remodel_405", [f"{R405}.sigma_y=4.0"], 405.0),
    # soft solid: no pressure bubble (paper, mu = 3 kPa, nu = 0.2); Forgacs' aggregates (nu = 0.45)
    "mu3_nu0.2": ("remodel_155", ["material.mu=3.0"], 155.0),
    "mu3_nu0.45": ("remodel_155", ["material.mu=3.0", "material.nu=0.45"], 155.0),
    # why the syringe effect comes later than in the paper: the (40a) rate form, a coarser mesh
    "remodel_155_40a": ("remodel_155", [f'{R405}.form="40a"'], 155.0),
    "remodel_155_h25": ("remodel_155", [f"mesh.params.{k}={v}" for k, v in
                                        dict(R=100.0, h=25.0, h_pole=8.0, r_pole=50.0).items()], 155.0),
    # R = 900 µm (the paper: no syringe effect), every length scaled by 9, X_U = (360, 0, 1710) µm
    "remodel_155_R900": ("remodel_155", [f"mesh.params.{k}={v}" for k, v in
                                         dict(R=900.0, h=180.0, h_pole=54.0, r_pole=450.0).items()]
                         + ["plates.radius=900.0", "plates.probe_point=[360.0, 0.0, 1710.0]"], 155.0),
    # Fig 11a: H/W after 60 s of rest, k0 = 2.5779e-3 isotropic against c = 2, before and after 1 min
    **{f"hw_{t}{'_c2' if c2 else ''}": ("remodel_40", [f"plates.t_end={t}.0", f"time.t_end={t + 60}.0",
                                                       "material.k0=2.5779", "output.fields_at=[]",
                                                       *(["material.permeability_c=2.0"] if c2 else [])], t + 60.0)
       for t in (10, 65) for c2 in (False, True)},
}
T_RAMP = 5.0
PROBE = (40.0, 0.0, 190.0)       # X_U, um
EXTRA_SETS = []   # --set overrides of every case (--axisymmetric)
RANKS = [2]       # MPI ranks per case (--ranks)


def case_overrides(case):
    """The `--set` overrides of one case, as (key, value): a variant of a builtin scene is renamed
    and writes fields rarely (disk) but still at the scene's figure times (fields_at)."""
    base, sets, _ = CASES[case]
    if sets:
        what = ", ".join(sets).replace('"', "'")
        sets = sets + [f'name="{case}"', f'description="{base} with {what} (scripts/reproduce.py)"',
                       "output.fields_every=1000"]
    return [tuple(x.split("=", 1)) for x in sets]


def extra_sets():
    return [tuple(x.split("=", 1)) for x in EXTRA_SETS]


def run_cases(out, names):
    """Runs the cases (one sweep: completed ones skipped); returns {case: run directory}."""
    done = store.run_cases([CASES[c][0] for c in names], [case_overrides(c) for c in names], extra_sets(), out,
                           RANKS[0])
    failed = [f"{c} ({r['error']})" for c, (_, r) in zip(names, done) if r["status"] != "ok"]
    if failed:
        print(f"failed: {', '.join(failed)}; see {out / 'sweep.log'}")
    return {c: d for c, (d, _) in zip(names, done)}


def case_dirs(out):
    """The run directories of the completed cases in the store (a missing one: a path that does
    not exist)."""
    return {c: find_case(out, CASES[c][0], case_overrides(c), extra_sets()) or out / "cases" / f"(no run of {c})"
            for c in CASES}


# ---------------------------------------------------------------- summary

def summarise(case, d):
    h, tim, t_end = history(d), timings(d), CASES.get(case, (None, None, 405.0))[2]
    t, th = h["time"], t_end - 5.0                   # th: end of the hold
    at = lambda col, x: None if math.isnan(v := value_at(h, col, x)) else v
    s = {k: tim.get(v) for k, v in [("wall_s", "total"), ("steps", "steps"), ("newton", "newton_its"),
                                     ("krylov", "ksp_its"), ("step_cuts", "step_cuts")]}
    f = h["force_total_mg"]
    s["peak_F_mg"], s["t_peak_s"] = f.max(), t[f.argmax()]
    s["F_hold_mg"], s["Fc_hold_mg"], s["Fp_hold_mg"] = (at(c, th) for c in
                                                        ("force_total_mg", "force_constitutive_mg", "force_pressure_mg"))
    s["peak_Fc_mg"] = h["force_constitutive_mg"].max()
    p = h["probe_p"]
    s["p_XU_5"], s["p_XU_30"] = at("probe_p", 5.0), at("probe_p", 30.0)
    # first zero crossing of p(X_U) after the ramp, interpolated between the two rows around it
    neg = np.nonzero((t > T_RAMP) & (p < 0))[0]
    s["t_p_neg_s"] = None
    if len(neg):
        j = neg[0]
        s["t_p_neg_s"] = t[j] if p[j - 1] < 0 else t[j - 1] + (t[j] - t[j - 1]) * p[j - 1] / (p[j - 1] - p[j])
    hold = (t >= T_RAMP) & (t <= th)
    s["p_nonneg_hold"] = bool(np.all(p[hold] >= 0)) if t[-1] >= th else None
    s["p_min_hold"] = p[hold].min() if t[-1] >= th else None        # how negative, if it is
    s["vm_hold_kPa"] = at("max_von_mises", th)
    s["vm_max_kPa"] = h["max_von_mises"].max() if "max_von_mises" in h else None
    s["norm_ep_final"] = h["max_norm_ep"][-1] if "max_norm_ep" in h else None
    s["det_bp_dev_max"] = h["det_bp_max_dev"].max() if "det_bp_max_dev" in h else None
    s["height_um"], s["width_um"], s["t_last_s"] = h["height"][-1], h["width"][-1], t[-1]
    return s


def write_summary(dirs, out):
    rows = {c: summarise(c, d) for c, d in dirs.items() if (d / "history.csv").exists()}
    if not rows:
        return print("no runs to summarise")
    keys = list(next(iter(rows.values())))
    cell = lambda v: "" if v is None else (str(v) if isinstance(v, bool) else f"{v:.6g}")
    with open(out / "summary.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["case"] + keys)
        for c, s in rows.items():
            w.writerow([c] + [cell(s[k]) for k in keys])
    # transposed so that ten cases fit on a terminal
    print(f"\n{'':>15}" + "".join(f"{c:>15}" for c in rows))
    for k in keys:
        print(f"{k:>15}" + "".join(f"{cell(s[k]):>15}" for s in rows.values()))
    print(f"wrote {out / 'summary.csv'}")


# ---------------------------------------------------------------- figures

def have(dirs, names, what="history.csv"):
    missing = [n for n in names if n not in dirs or not (dirs[n] / what).exists()]
    if missing:
        print(f"  skipped: no {what} for {', '.join(missing)}")
    return not missing


def save(fig, out, name):
    if not fig.get_constrained_layout():             # section figures lay out their colour bars
        fig.tight_layout()
    fig.savefig(out / "figures" / name, dpi=130)
    plt.close(fig)
    print(f"  wrote {out / 'figures' / name}")


def fig_probe(dirs, out, a, b, name, title):
    """p(X_U) and porosity vs time for two cases (Figs 4, 11)."""
    if not have(dirs, [a, b]):
        return
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    for case, style in ((a, "-"), (b, "--")):
        h = history(dirs[case])
        ax[0].plot(h["time"], h["probe_p"], style, label=case)
        ax[1].plot(h["time"], h["probe_porosity"], style, label=case)
    t_end = CASES[a][2]
    ax[0].axhline(0, color="k", lw=0.7)
    for x, lab, unit in ((ax[0], "pressure p(X_U)", " [kPa]"), (ax[1], "porosity at X_U", " [-]")):
        x.axvline(t_end, color="grey", ls=":", label=f"t_end = {t_end:g} s")
        x.set(xlabel="time t [s]", ylabel=lab + unit)
        x.legend()
    fig.suptitle(f"{title}: probe X_U = {PROBE} µm")
    save(fig, out, name)


def fig_forces(dirs, out):
    """Total, constitutive and pressure force for the lambda_p and sigma_y sweeps (Figs 7-9)."""
    sweeps = [("λp sweep (σy = 2 kPa)", [("lambda_0.1", "λp = 0.1 (MPa s)⁻¹"), ("lambda_0.5", "λp = 0.5 (MPa s)⁻¹"),
                                         ("remodel_405", "λp = 1 (MPa s)⁻¹")]),
              ("σy sweep (λp = 1 (MPa s)⁻¹)", [("sigma_1", "σy = 1 kPa"), ("remodel_405", "σy = 2 kPa"),
                                              ("sigma_4", "σy = 4 kPa")])]
    cases = {c for _, s in sweeps for c, _ in s} | {"reference_405"}
    if not have(dirs, sorted(cases)):
        return
    hist = {c: history(dirs[c]) for c in cases}
    cols = [("force_total_mg", "total force"), ("force_constitutive_mg", "constitutive force"),
            ("force_pressure_mg", "pressure force")]
    fig, ax = plt.subplots(2, 3, figsize=(16, 8.5), sharex=True)
    for r, (sweep, members) in enumerate(sweeps):
        for c, (col, lab) in enumerate(cols):
            x = ax[r, c]
            for case, label in members:
                x.plot(hist[case]["time"], hist[case][col], label=label)
            x.plot(hist["reference_405"]["time"], hist["reference_405"][col], "--", color="grey",
                   label="no remodelling")
            x.set(xlim=(0, 420), xlabel="time t [s]", ylabel=f"{lab} [mg]", title=f"{sweep}: {lab}")
            x.legend(fontsize=8)
    fig.suptitle("Figs 7-9: plate forces of remodel_405 variants (t_end = 405 s)")
    save(fig, out, "fig7_9_forces.png")


def fig_soft(dirs, out):
    """A soft solid (µ = 3 kPa): Forgacs' aggregates (ν = 0.45) force, and p(X_U) without a bubble (ν = 0.2)."""
    if not have(dirs, ["mu3_nu0.45", "mu3_nu0.2", "remodel_155"]):
        return
    fig, ax = plt.subplots(1, 2, figsize=(12, 4.5))
    h = history(dirs["mu3_nu0.45"])
    for col, lab in (("force_total_mg", "total"), ("force_constitutive_mg", "constitutive"),
                     ("force_pressure_mg", "pressure")):
        ax[0].plot(h["time"], h[col], label=lab)
    # The same time as summary.csv's t_last_s, which the text quotes: the last converged step.
    status = dirs["mu3_nu0.45"] / "status.txt"
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
    save(fig, out, "fig_soft.png")


def zone_stats(dirs):
    """remodel_40: σ_VM and ‖E_p‖ in the centre vs next to the contact zones (Figs 5-6 text;
    volume means over the regions of scripts/poroplast_tools/fields.py), and remodel_405's positive-pressure
    region (Fig 3)."""
    if have(dirs, ["remodel_40"], "fields.h5"):
        run = dirs["remodel_40"]
        f = fields.fields(run)
        for t in (5, 15, 35, 40, 60):
            vm = f.at("von_mises", t)
            zm = lambda name, zone: fields.zone_mean(run, name, zone, t)
            print(f"  t = {t:3d} s: σ_VM max {vm.max():5.2f} kPa at (r, z) = ({f.r[vm.argmax()]:.0f}, "
                  f"{f.z[vm.argmax()]:.0f}) µm; mean centre {zm('von_mises', 'centre'):5.2f}, contact zones "
                  f"{zm('von_mises', 'contact'):5.2f} kPa; ‖E_p‖ centre {zm('norm_ep', 'centre'):.3f}, "
                  f"contact {zm('norm_ep', 'contact'):.3f}")
        t, before, after = fields.detachment(run, 35.0)
        print(f"  upper detachment after t = {t:.3f} s: largest σ_VM {before:.2f} kPa before, {after:.2f} kPa after")
    if have(dirs, ["remodel_405"], "fields.h5"):
        for t in (35.0, 45.0, 60.0):
            share, where, angle = fields.bubble(dirs["remodel_405"], t)
            print(f"  remodel_405, t = {t:g} s: p > 0 in {100 * share:.1f}% of the volume, p⁺-weighted mean "
                  f"distance from the centre {where:.3f} R at {angle:.0f}° from the axis")


def split_kink(dirs):
    """reference_405: the largest jump of the force's pressure/constitutive split during the hold
    (between two field outputs from 200 s on), and the upper-surface vertex whose pressure fell
    most then, with its gap to the upper plate (Figs 7-9 text)."""
    if not have(dirs, ["reference_405"], "fields.h5"):
        return
    run = dirs["reference_405"]
    h, f = history(run), fields.fields(run)
    T = [t for t in f.times if 200.0 <= t <= 300.0]
    if len(T) < 2:
        return print("  reference_405 has no field outputs between 200 and 300 s (an older scene)")
    fp = lambda t: value_at(h, "force_pressure_mg", t)
    t0, t1 = max(zip(T, T[1:]), key=lambda w: (fp(w[0]) - fp(w[1])) / (w[1] - w[0]))
    X = f.f["/mesh/coordinates"][:]
    r, rho = np.hypot(X[:, 0], X[:, 1]), np.hypot(np.hypot(X[:, 0], X[:, 1]), X[:, 2] - f.radius)
    top = np.nonzero((abs(rho - f.radius) < 1e-3 * f.radius) & (X[:, 2] > f.radius))[0]
    p0, p1 = f.at("p", t0), f.at("p", t1)
    k = top[np.argmin(p1[top] - p0[top])]
    gap = lambda t: 2 * f.radius - X[k, 2] - f.at("u", t)[k, 2]
    print(f"  the pressure part falls fastest between {t0:g} and {t1:g} s ({fp(t0):.3f} -> {fp(t1):.3f} mg); "
          f"the upper-surface vertex at r = {r[k]:.1f} µm (contact radius {value_at(h, 'contact_radius_upper', t0):.1f} µm) "
          f"goes from p = {p0[k]:.2f} to {p1[k]:.2f} kPa, its gap to the plate from {1e3 * gap(t0):.0f} to {1e3 * gap(t1):.0f} nm")


# The numbers the paper reports, each with its converged meridian value (scripts/references.py:
# (case, observable), or a combined value's name) and the 3-D default's (a function of the runs).
@lru_cache(maxsize=None)
def _summarised(case, d):
    """A case's summary, read once for all the table's rows ({} without a run)."""
    return summarise(case, d) if (d / "history.csv").exists() else {}


def _summary(dirs, case, key):
    return _summarised(case, dirs[case]).get(key)


def _diff(dirs, a, b, key):
    x, y = _summary(dirs, a, key), _summary(dirs, b, key)
    return None if x is None or y is None else x - y


def _ratio(dirs, a, b, key):
    x, y = _summary(dirs, a, key), _summary(dirs, b, key)
    return None if not x or not y else x / y


def _hw(dirs, case):
    h = history(dirs[case]) if (dirs[case] / "history.csv").exists() else None
    return None if h is None else h["height"][-1] / h["width"][-1]


def _fields(dirs, case, f):
    return f(dirs[case]) if (dirs[case] / "fields.h5").exists() else None


REPORTED = [
    ("syringe effect: p(X_U) crosses zero (s)", "≈ 40", ("remodel_155", "zero:probe_p"),
     lambda d: _summary(d, "remodel_155", "t_p_neg_s")),
    ("c = 2: p(X_U) crosses zero (s)", "28", ("remodel_155_c2", "zero:probe_p"),
     lambda d: _summary(d, "remodel_155_c2", "t_p_neg_s")),
    ("c = 2 over isotropic: p(X_U, 30 s)", "≈ 0.25", "c = 2 over isotropic, p(X_U, 30 s)",
     lambda d: _ratio(d, "remodel_155_c2", "remodel_155", "p_XU_30")),
    ("λp 1 → 0.1: constitutive-force peak change (mg)", "+≈ 4", "λp 1 → 0.1: constitutive-force peak change (mg)",
     lambda d: _diff(d, "lambda_0.1", "remodel_405", "peak_Fc_mg")),
    ("λp 1 → 0.1: total-force peak change (mg)", "+≈ 2", "λp 1 → 0.1: total-force peak change (mg)",
     lambda d: _diff(d, "lambda_0.1", "remodel_405", "peak_F_mg")),
    ("largest σ_VM, last step in upper contact (kPa)", "≈ 4.0", ("remodel_40", "vm_max_before_detach"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.detachment(r, 35.0)[1])),
    ("largest σ_VM, first step after the detachment (kPa)", "≈ 3.5", ("remodel_40", "vm_max_after_detach"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.detachment(r, 35.0)[2])),
    ("mean σ_VM in the contact zones at 35 s (kPa)", "", ("remodel_40", "vm_contact@35"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.zone_mean(r, "von_mises", "contact", 35.0))),
    ("mean σ_VM in the contact zones at 40 s (kPa)", "", ("remodel_40", "vm_contact@40"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.zone_mean(r, "von_mises", "contact", 40.0))),
    ("σ_VM contact zones over centre at 40 s", "≈ 10", ("remodel_40", "vm_contact/centre@40"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.zone_ratio(r, "von_mises", 40.0))),
    ("σ_VM 10-µm layer under the plates over centre at 40 s", "≈ 10", ("remodel_40", "vm_contact10/centre@40"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.zone_ratio(r, "von_mises", 40.0, 10.0))),
    ("largest σ_VM over the centre's mean at 40 s", "≈ 10", ("remodel_40", "vm_max/centre@40"),
     lambda d: _fields(d, "remodel_40", fields.DERIVED["vm_max/centre@40"])),
    ("‖E_p‖ 10-µm layer over centre (60 s)", "≈ 0", ("remodel_40", "ep_contact10/centre@60"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.zone_ratio(r, "norm_ep", 60.0, 10.0))),
    ("‖E_p‖ contact zones over centre (frozen, 60 s)", "≈ 0 (\"almost none\")", ("remodel_40", "ep_contact/centre@60"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.zone_ratio(r, "norm_ep", 60.0))),
    ("H/W after 60 s rest, c = 2 minus isotropic, 10 s compression", "< 0", "H/W c = 2 minus isotropic, 10 s compression",
     lambda d: None if None in (_hw(d, "hw_10_c2"), _hw(d, "hw_10")) else _hw(d, "hw_10_c2") - _hw(d, "hw_10")),
    ("H/W after 60 s rest, c = 2 minus isotropic, 65 s compression", "> 0", "H/W c = 2 minus isotropic, 65 s compression",
     lambda d: None if None in (_hw(d, "hw_65_c2"), _hw(d, "hw_65")) else _hw(d, "hw_65_c2") - _hw(d, "hw_65")),
    ("no remodelling: 95% of the hold's force relaxation done at (s)", "\"soon after the ramp\"",
     ("reference_405", "settle95:force_total_mg"),
     lambda d: _fields(d, "reference_405", lambda r: fields.settle_time(r, "force_total_mg", 5.0, 400.0, 0.05))),
    *[(f"p > 0 share of the volume at {t} s", "bubble from 35 s", ("remodel_155", f"bubble_share@{t}"),
       (lambda t: lambda d: _fields(d, "remodel_405", lambda r: fields.bubble(r, float(t))[0]))(t)) for t in (35, 45, 60)],
    *[(f"p⁺-weighted distance from the centre at {t} s (R)", "travels outward", ("remodel_155", f"bubble_where@{t}"),
       (lambda t: lambda d: _fields(d, "remodel_405", lambda r: fields.bubble(r, float(t))[1]))(t)) for t in (35, 45, 60)],
    *[(f"p⁺-weighted angle from the axis at {t} s (°)", "", ("remodel_155", f"bubble_angle@{t}"),
       (lambda t: lambda d: _fields(d, "remodel_405", lambda r: fields.bubble(r, float(t))[2]))(t)) for t in (35, 45, 60)],
    ("no remodelling: lowest p(X_U) in the hold (kPa)", "≥ 0", ("reference_405", "min_hold405:probe_p"),
     lambda d: _fields(d, "reference_405", lambda r: fields.hold_min(r, "probe_p", 5.0, 400.0))),
    ("R = 900 µm: p(X_U) crosses zero (s)", "no crossing", ("remodel_155_R900", "zero:probe_p"),
     lambda d: _summary(d, "remodel_155_R900", "t_p_neg_s")),
    ("R = 900 µm: lowest p(X_U) in the hold (kPa)", "≥ 0", ("remodel_155_R900", "min_hold:probe_p"),
     lambda d: _summary(d, "remodel_155_R900", "p_min_hold")),
]


def reported(dirs, out, refs, label):
    """The table of reported numbers: paper, converged ± bar (refs: references.csv), and this set of
    runs' value (`label`: the 3-D default, or the meridian's); printed as markdown and written to
    <out>/reported.csv."""
    conv = {}
    if refs and Path(refs).exists():
        for (case, obs), v in references(refs).items():
            conv[(case, obs)] = v
            if case == "combined":
                conv[obs] = v
    fmt = lambda v: "—" if v is None or v != v else f"{v:.4g}"
    rows = []
    for what, paper, key, three_d in REPORTED:
        v, bar = conv.get(key, (None, None))
        rows.append({"quantity": what, "paper": paper, "converged": v, "error_bar": bar, label: three_d(dirs)})
    write_rows(out / "reported.csv", rows)
    print(f"\n| quantity | paper | converged (meridian) | {label} |\n|---|---|---|---|")
    for r in rows:
        c = "—" if r["converged"] is None else f"{fmt(r['converged'])} ± {r['error_bar']:.2g}"
        print(f"| {r['quantity']} | {r['paper']} | {c} | {fmt(r[label])} |")
    print(f"wrote {out / 'reported.csv'}")


class Section:
    """The mid-plane y = 0 of a run's fields.h5: the faces there of cells with 3 vertices on it
    (every cell of a meridian run), each split in 4 triangles through its mid-edge nodes so that
    deformed boundaries curve."""

    def __init__(self, case, d):
        self.case = case
        self.f = h5py.File(d / "fields.h5", "r")
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

    def draw(self, ax, name, k, **kw):
        """Deformed section, mirrored to x < 0 to show the whole cross-section."""
        u, n = self.field("u", k), len(self.X)
        x, z = self.X[:, 0] + u[:, 0], self.X[:, 2] + u[:, 2]
        tri = mtri.Triangulation(np.r_[x, -x], np.r_[z, z], np.r_[self.tris, self.tris + n])
        v = self.field(name, k)
        if len(v) == n:                              # node field: linear over each sub-triangle
            m = ax.tripcolor(tri, np.r_[v, v], shading="gouraud", **kw)
        else:                                        # cell field: constant per cell
            m = ax.tripcolor(tri, facecolors=np.r_[v[self.owner], v[self.owner]], **kw)
        ax.set(aspect="equal", xlabel="x [µm]", ylabel="z [µm]")
        return m

    def probe(self, k):
        """Deformed position (x, z) of X_U, u interpolated linearly on the reference section."""
        tri = mtri.Triangulation(self.X[:, 0], self.X[:, 2], self.tris)
        u = self.field("u", k)
        ux, uz = (float(mtri.LinearTriInterpolator(tri, u[:, i])(PROBE[0], PROBE[2])) for i in (0, 2))
        return PROBE[0] + ux, PROBE[2] + uz


def fig_midplane(dirs, out):
    """|E_p| and von Mises stress on the mid-plane of remodel_40 (Figs 5-6)."""
    if not have(dirs, ["remodel_40"], "fields.h5"):
        return
    s, ts = Section("remodel_40", dirs["remodel_40"]), [5.0, 15.0, 35.0, 40.0, 60.0]
    ks = [s.index(t) for t in ts]
    print("  remodel_40 times used: " + ", ".join(f"{tt:.4g}" for _, tt in ks))
    fig, ax = plt.subplots(2, 5, figsize=(21, 7.5), sharex=True, sharey=True, layout="constrained")
    for r, (name, lab, cmap) in enumerate([("norm_ep", "‖E_p‖ [-]", "viridis"), ("von_mises", "σ_VM [kPa]", "magma")]):
        for c, (k, tt) in enumerate(ks):
            # A colour scale per time: after the release σ_VM is ten times lower than at the
            # peak, and its inversion (highest next to the former contacts) must stay visible.
            m = s.draw(ax[r, c], name, k, cmap=cmap, vmin=0, vmax=s.field(name, k).max())
            ax[r, c].set_title(f"{lab.split(' ')[0]}, t = {tt:.4g} s")
            fig.colorbar(m, ax=ax[r, c], label=lab, shrink=0.8)
    fig.suptitle("Figs 5-6: remodel_40, mid-plane y = 0 (deformed); each panel has its own colour scale")
    save(fig, out, "fig5_6_midplane.png")


def fig_pressure(dirs, out, cases, ts, name, title):
    """Pressure on the mid-plane, colour map centred on p = 0 (Figs 3, 11c)."""
    if not have(dirs, cases, "fields.h5"):
        return
    secs = {c: Section(c, dirs[c]) for c in cases}
    idx = {c: [secs[c].index(t) for t in ts] for c in cases}
    for c in cases:
        print(f"  {c} times used: " + ", ".join(f"{tt:.4g}" for _, tt in idx[c]))
    ps = [secs[c].field("p", k) for c in cases for k, _ in idx[c]]
    lo, hi = min(p.min() for p in ps), max(p.max() for p in ps)
    norm = TwoSlopeNorm(0.0, min(lo, -1e-3 * abs(hi)), max(hi, 1e-3 * abs(lo)))   # needs lo < 0 < hi
    rows, cols = (len(cases), len(ts)) if len(ts) > 1 else (1, len(cases))   # one time: side by side
    fig, ax = plt.subplots(rows, cols, figsize=(4.2 * cols + 1.5, 3.6 * rows), squeeze=False,
                           sharex=True, sharey=True, layout="constrained")
    panels = [(c, k, tt) for c in cases for k, tt in idx[c]]
    for x, (c, k, tt) in zip(ax.flat, panels):
        m = secs[c].draw(x, "p", k, cmap="RdBu_r", norm=norm)
        x.plot(*secs[c].probe(k), "ko", ms=4, label="X_U (deformed)")
        x.set_title(f"{c}, t = {tt:.4g} s")
    ax.flat[0].legend(loc="lower left", fontsize=8)
    ticks = np.r_[np.linspace(norm.vmin, 0, 3)[:-1], np.linspace(0, norm.vmax, 4)]   # both halves labelled
    fig.colorbar(m, ax=ax.ravel().tolist(), label="pressure p [kPa]", ticks=ticks, format="%.3g")
    fig.suptitle(f"{title}: pressure on the mid-plane y = 0 (deformed)")
    save(fig, out, name)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="runs/reproduce")
    ap.add_argument("--only", nargs="+", choices=list(CASES), metavar="NAME", help="run only these cases: %(choices)s")
    ap.add_argument("--plots-only", action="store_true", help="no runs: figures and summary from existing runs")
    ap.add_argument("--docs", action="store_true", help="also copy the figures to docs/figures/")
    ap.add_argument("--dirs", nargs="+", default=[], metavar="CASE=DIR", help=argparse.SUPPRESS)  # for testing
    ap.add_argument("--axisymmetric", action="store_true", help="every case on its meridian (seconds per case)")
    ap.add_argument("--converged", metavar="DIR", help="also the converged meridian studies (scripts/references.py "
                    "--cases all, scripts/causes.py) into DIR (about 3 h on 2 ranks; completed cases are kept)")
    ap.add_argument("--references", metavar="CSV", help="references.csv for the table of reported numbers "
                    "(default: DIR/references.csv of --converged, else studies/references/references.csv, "
                    "else the shipped scripts/data/references.csv)")
    store.rank_options(ap)
    a = ap.parse_args()
    store.use_rank_options(a)
    RANKS[0] = a.ranks
    if a.axisymmetric:
        EXTRA_SETS.append("mesh.geometry=axisymmetric")
        if a.out == "runs/reproduce":
            a.out = "runs/reproduce_axi"
    out = Path(a.out) if Path(a.out).is_absolute() else ROOT / a.out
    out.mkdir(parents=True, exist_ok=True)
    dirs = case_dirs(out)
    if not a.plots_only:
        dirs.update(run_cases(out, a.only or list(CASES)))
    dirs.update({k: Path(v) for k, v in (x.split("=", 1) for x in a.dirs)})
    write_summary(dirs, out)
    refs = a.references
    if a.converged:
        here = Path(__file__).resolve().parent
        ranks = ["--ranks", str(a.ranks)] + (["--ranks-per-case", str(a.ranks_per_case)] if a.ranks_per_case else []) \
            + (["--no-sweep"] if a.no_sweep else [])      # the studies run as this command says
        subprocess.run(["python3", str(here / "references.py"), "--dir", a.converged, "--cases", "all", *ranks],
                       check=True)
        subprocess.run(["python3", str(here / "causes.py"), "--dir", str(Path(a.converged) / "causes"), *ranks],
                       check=True)
        refs = refs or str(Path(a.converged) / "references.csv")
    # Without --converged: the user's own studies if there are any, else the shipped results
    # (scripts/data/references.csv: `references.py --cases all` on 2026-12-02, this build).
    own = ROOT / "studies" / "references" / "references.csv"
    reported(dirs, out, refs or str(own if own.exists() else ROOT / "scripts" / "data" / "references.csv"),
             "meridian, scene mesh" if a.axisymmetric else "3-D default")
    (out / "figures").mkdir(exist_ok=True)
    print("\nfigures:")
    steps = [("fig4_probe", lambda: fig_probe(dirs, out, "remodel_155", "elastic_155", "fig4_probe.png",
                                              "Fig 4: remodelling vs elastic (t_end = 155 s)")),
             ("fig11_probe", lambda: fig_probe(dirs, out, "remodel_155_c2", "remodel_155", "fig11_probe.png",
                                               "Fig 11: remodelling-dependent permeability (c = 2, k0 = 2.5779e-3) vs isotropic (k0 = 3.7729e-3)")),
             ("fig7_9_forces", lambda: fig_forces(dirs, out)),
             ("fig5_6_midplane", lambda: fig_midplane(dirs, out)),
             ("fig3_pressure", lambda: fig_pressure(dirs, out, ["remodel_405", "reference_405"], [5, 25, 30, 45],
                                                    "fig3_pressure.png", "Fig 3: remodelling vs none")),
             ("fig3_later_pressure", lambda: fig_pressure(dirs, out, ["remodel_405", "reference_405"],
                                                          [60, 100, 200, 400], "fig3_later_pressure.png",
                                                          "Fig 3 continued: later in the hold")),
             ("zone_stats", lambda: zone_stats(dirs)),
             ("split_kink", lambda: split_kink(dirs)),
             ("fig_soft", lambda: fig_soft(dirs, out)),
             ("fig_soft_pressure", lambda: fig_pressure(dirs, out, ["remodel_155", "mu3_nu0.2"], [30, 45],
                                                        "fig_soft_pressure.png", "µ = 20 vs 3 kPa")),
             ("fig11c_pressure", lambda: fig_pressure(dirs, out, ["remodel_155", "remodel_155_c2"], [30],
                                                      "fig11c_pressure.png", "Fig 11c: isotropic vs c = 2, t = 30 s"))]
    for name, make in steps:
        print(f" {name}:")
        make()
    if a.docs:
        dst = ROOT / "docs" / "figures"
        dst.mkdir(parents=True, exist_ok=True)
        suffix = "_axi" if a.axisymmetric else ""   # the meridian's figures beside the 3-D ones
        for png in sorted((out / "figures").glob("*.png")):
            shutil.copy(png, dst / (png.stem + suffix + png.suffix))
        print(f"copied figures to {dst}")


if __name__ == "__main__":
    main()
