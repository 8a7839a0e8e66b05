#!/usr/bin/env python3
"""Reproduce the figures of Di Stefano et al. (ZAMP 2022) with remodelling: runs the builtin
scenes remodel_40, remodel_155, remodel_155_c2, elastic_155, remodel_405, reference_405 and four
variants of remodel_405 (lambda_p = 0.1, 0.5 (MPa s)^-1; sigma_y = 1, 4 kPa) on 2 MPI ranks (one
`poroplast sweep` for the cases to run: 3-D ones one at a time on both ranks, meridians two at a
time on one each; --ranks, --ranks-per-case, --no-sweep as in the other study scripts),
then draws the paper's figures, one file each (Figs 3-11; Fig 11c, a map, apart), at their
printed width (poroplast_tools/paper_figures.py, maps.py) into <out>/figures/, and writes
<out>/summary.csv (also printed) and
<out>/flow.csv (the outflow through the free boundary by phase, of FLOW_CASES; with --docs on the
meridian: scripts/data/flow_meridian.csv, which the claims table reads).
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
import os
import shutil
import subprocess
from concurrent.futures import ThreadPoolExecutor
from functools import lru_cache
from pathlib import Path

import numpy as np

from poroplast_tools import fields
from poroplast_tools import paper_figures as figs
from poroplast_tools.paper_figures import have
from poroplast_tools import cases as store
from poroplast_tools.cases import ROOT, SceneError, find_case
from poroplast_tools.history import at as value_at, history, relaxation_time, timings
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
TABLE_CASES = list(CASES)   # the table's cases, run in 3-D too; the ones below only on the meridian
# Figs 7-9 c-f: the other sweeps of remodel_405 (figs.SWEEPS), each one parameter of Table 1.
CASES.update({
    "mu_10": ("remodel_405", ["material.mu=10.0"], 405.0), "mu_40": ("remodel_405", ["material.mu=40.0"], 405.0),
    "nu_0.1": ("remodel_405", ["material.nu=0.1"], 405.0), "nu_0.3": ("remodel_405", ["material.nu=0.3"], 405.0),
    "k0_2.58e-3": ("remodel_405", ["material.k0=2.5779"], 405.0),
    "k0_2.58e-4": ("remodel_405", ["material.k0=0.25779"], 405.0),
    "u_0.1": ("remodel_405", ["plates.compression=0.1"], 405.0),
    "u_0.2": ("remodel_405", ["plates.compression=0.2"], 405.0),
    # the scenes are scale-free: the mesh, the plates and X_U follow R
    "R_300": ("remodel_405", ["mesh.params.R=300.0"], 405.0), "R_900": ("remodel_405", ["mesh.params.R=900.0"], 405.0),
})
# Fig 6's caption: the two plates' σ_VM differ because of gravity (its region means without it).
CASES["remodel_40_g0"] = ("remodel_40", ["material.gravity=[0.0, 0.0, 0.0]"], 40.0)
# Figs 10-11a: H/W after 60 s of rest against the compression time t_end (figs.HW_SETS).
_HW_SETS = {"l0.1": ["material.remodelling.lambda_p=0.0001"], "l0.5": ["material.remodelling.lambda_p=0.0005"],
            "l1": [], "l0.5_k2.58e-3": ["material.remodelling.lambda_p=0.0005", "material.k0=2.5779"],
            "l0.5_k2.58e-4": ["material.remodelling.lambda_p=0.0005", "material.k0=0.25779"],
            "l1_k2.58e-3": ["material.k0=2.5779"], "l1_k2.58e-3_c2": ["material.k0=2.5779", "material.permeability_c=2.0"]}
CASES.update({f"hw_{s}_{t}": ("remodel_40", [f"plates.t_end={t}.0", f"time.t_end={t + 60}.0", "output.fields_at=[]",
                                             *sets], t + 60.0)
              for s, sets in _HW_SETS.items() for t in figs.HW_TIMES})
T_RAMP = 5.0
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
    """The run directories of the completed cases in the store, as the binary finds them (a
    missing one: a path that does not exist)."""
    find = lambda c: find_case(out, CASES[c][0], case_overrides(c), extra_sets()) or out / "cases" / f"(no run of {c})"
    try:
        with ThreadPoolExecutor(os.cpu_count()) as pool:    # a call of the binary each: its start-up, mostly
            return dict(zip(CASES, pool.map(find, CASES)))
    except SceneError as e:
        raise SystemExit(f"reproduce.py: finding the cases of {out}: {e}")


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
    s["peak_Fc_mg"], s["t_peak_Fc_s"] = h["force_constitutive_mg"].max(), t[h["force_constitutive_mg"].argmax()]
    s["peak_Fc60_mg"] = h["force_constitutive_mg"][t <= 60.0].max()   # as the converged case: to 60 s
    s["peak_Fp_mg"] = h["force_pressure_mg"].max()
    s["p_share_peak"] = h["force_pressure_mg"][f.argmax()] / f.max()     # the pressure part at the total's peak
    p = h["probe_p"]
    s["p_XU_5"], s["p_XU_30"] = at("probe_p", 5.0), at("probe_p", 30.0)
    s["contact_radius_5"] = at("contact_radius_upper", 5.0)
    # first zero crossing of p(X_U) after the ramp, interpolated between the two rows around it
    neg = np.nonzero((t > T_RAMP) & (p < 0))[0]
    s["t_p_neg_s"] = None
    if len(neg):
        j = neg[0]
        s["t_p_neg_s"] = t[j] if p[j - 1] < 0 else t[j - 1] + (t[j] - t[j - 1]) * p[j - 1] / (p[j - 1] - p[j])
    hold = (t >= T_RAMP) & (t <= th)
    s["p_nonneg_hold"] = bool(np.all(p[hold] >= 0)) if t[-1] >= th else None
    s["p_min_hold"] = p[hold].min() if t[-1] >= th else None        # how negative, if it is
    s["Fp_min_hold_mg"] = h["force_pressure_mg"][hold].min() if t[-1] >= th else None
    s["phi_XU_min"] = h["probe_porosity"][t <= th].min()
    s["phi_XU_hold_end"] = at("probe_porosity", th)
    s["vm_hold_kPa"] = at("max_von_mises", th)
    s["vm_max_kPa"] = h["max_von_mises"].max() if "max_von_mises" in h else None
    s["norm_ep_final"] = h["max_norm_ep"][-1] if "max_norm_ep" in h else None
    s["det_bp_dev_max"] = h["det_bp_max_dev"].max() if "det_bp_max_dev" in h else None
    s["height_um"], s["width_um"], s["t_last_s"] = h["height"][-1], h["width"][-1], t[-1]
    s["hw_final"] = h["height"][-1] / h["width"][-1]
    return s


# The stationary force the λp and k0 variants relax to: Table 1's at 400 s (neither changes it,
# the paper says; its other variants have plateaus of their own).
PLATEAU_CASE = "remodel_405"
PLATEAU_SHARED = ("remodel_405", "lambda_0.1", "lambda_0.5", "k0_2.58e-3", "k0_2.58e-4")


def write_summary(dirs, out):
    rows = {c: summarise(c, d) for c, d in dirs.items() if (d / "history.csv").exists()}
    if not rows:
        return print("no runs to summarise")
    plateau = rows.get(PLATEAU_CASE, {}).get("F_hold_mg")
    for c, s in rows.items():   # 95% of the way from the peak to Table 1's plateau, within the hold
        h, th = history(dirs[c]), CASES.get(c, (None, None, 405.0))[2] - 5.0
        s["t_relax95_s"] = relaxation_time(h["time"], h["force_total_mg"], plateau, th) \
            if plateau is not None and c in PLATEAU_SHARED else None
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


# ---------------------------------------------------------------- the fluid's exchange

# The claims on where the fluid goes (P7, P16, P20, P65) and on the shape after the release (P26),
# read from history.csv: `outflow` (µm³/s, full sphere) is the fluid leaving through the drained
# surface, positive out, negative in; with the default impermeable plates that surface is the
# free boundary. Sums are Σ dt · outflow over the rows in a window, as `outflow_total` sums them.
FLOW_CASES = ("remodel_405", "reference_405", "remodel_155", "elastic_155", "remodel_40")


def flow(case, d):
    """The outflow through the free boundary of one case, by phase, and H/W through the rest."""
    h = history(d)
    t, q, dt, th = h["time"], h["outflow"], h["dt"], CASES[case][2] - 5.0
    hold = (t > T_RAMP) & (t <= th)
    into = np.nonzero((t > 0) & (q < 0))[0]
    s = {"case": case, "t_hold_end_s": th}
    s["t_inflow_s"] = None   # the outflow's first change of sign, interpolated between its rows
    if len(into):
        j = into[0]
        s["t_inflow_s"] = t[j - 1] + (t[j] - t[j - 1]) * q[j - 1] / (q[j - 1] - q[j])
    s["outflow_min_0_40"], s["outflow_40"] = q[(t > 0) & (t < 40.0)].min(), value_at(h, "outflow", 40.0)
    s["outflow_min_hold"], s["outflow_max_hold"] = q[hold].min(), q[hold].max()
    later = hold & (t >= s["t_inflow_s"]) if s["t_inflow_s"] is not None else hold & False
    s["outflow_max_hold_after_inflow"] = q[later].max() if later.any() else None   # < 0: it keeps entering
    s["outflow_hold_end"] = value_at(h, "outflow", th)
    s["out_0_40_um3"] = (dt * q)[(t > 0) & (t <= 40.0)].sum()
    s["out_hold_um3"] = (dt * np.clip(q, 0, None))[hold].sum()
    s["in_hold_um3"] = (dt * np.clip(-q, 0, None))[hold].sum()
    s["volume_0_um3"] = h["fluid_volume"][0]
    for k in ("out_0_40", "out_hold", "in_hold"):   # as shares of the aggregate's volume at t = 0
        s[f"{k}_share"] = s[f"{k}_um3"] / s["volume_0_um3"]
    for x in (40.0, 60.0):
        s[f"hw_{x:g}"] = value_at(h, "height", x) / value_at(h, "width", x)
    s["hw_last"], s["t_last_s"] = h["height"][-1] / h["width"][-1], t[-1]
    return s


def write_flow(dirs, out):
    """<out>/flow.csv: `flow` of each FLOW_CASES case that has a run."""
    rows = [flow(c, dirs[c]) for c in FLOW_CASES if (dirs[c] / "history.csv").exists()]
    if rows:
        cell = lambda v: "" if v is None else v if isinstance(v, str) else f"{v:.6g}"
        write_rows(out / "flow.csv", [{k: cell(v) for k, v in r.items()} for r in rows])
        print(f"wrote {out / 'flow.csv'}")


# ---------------------------------------------------------------- figures' numbers

def detachment(dirs):
    """remodel_40's upper detachment (Figs 5-6 text); the region means and the positive region are
    the figures' data (fig5_6_zones.csv, fig3_*.csv)."""
    if have(dirs, ["remodel_40"], "fields.h5"):
        t, before, after = fields.detachment(dirs["remodel_40"], 35.0)
        print(f"  upper detachment after t = {t:.3f} s: largest σ_VM {before:.2f} kPa before, {after:.2f} kPa after")


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
     lambda d: _diff(d, "lambda_0.1", "remodel_405", "peak_Fc60_mg")),
    ("λp 1 → 0.1: total-force peak change (mg)", "+≈ 2", "λp 1 → 0.1: total-force peak change (mg)",
     lambda d: _diff(d, "lambda_0.1", "remodel_405", "peak_F_mg")),
    # The paper's σ_VM "near the contacts", ≈ 4.0 kPa before the upper detachment and ≈ 3.5 kPa
    # after it, beside the contact-zone means claims P24a and P24b judge them by: at 37 s (the end
    # of the paper's "]35, 37[ s", just before ours detaches) and at 40 s. The largest σ_VM is a
    # point value at the contact edge, ours only.
    ("mean σ_VM in the contact zones at 35 s (kPa)", "", ("remodel_40", "vm_contact@35"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.zone_mean(r, "von_mises", "contact", 35.0))),
    ("mean σ_VM in the contact zones at 37 s, before the upper detachment (kPa)", "≈ 4.0",
     ("remodel_40", "vm_contact@37"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.zone_mean(r, "von_mises", "contact", 37.0))),
    ("mean σ_VM in the contact zones at 40 s (kPa)", "≈ 3.5", ("remodel_40", "vm_contact@40"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.zone_mean(r, "von_mises", "contact", 40.0))),
    ("largest σ_VM, last step in upper contact (kPa)", "", ("remodel_40", "vm_max_before_detach"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.detachment(r, 35.0)[1])),
    ("largest σ_VM, first step after the detachment (kPa)", "", ("remodel_40", "vm_max_after_detach"),
     lambda d: _fields(d, "remodel_40", lambda r: fields.detachment(r, 35.0)[2])),
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
        dirs.update(run_cases(out, a.only or (list(CASES) if a.axisymmetric else TABLE_CASES)))
    dirs.update({k: Path(v) for k, v in (x.split("=", 1) for x in a.dirs)})
    write_summary(dirs, out)
    write_flow(dirs, out)
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
    P, C = figs.fig_pressure, CASES
    steps = [lambda: figs.fig_probe(dirs, out, C, [("remodel_155", "remodelling"), ("elastic_155", "no remodelling")],
                                    "fig4_probe.png", ("remodel_155_R900", "R = 900 µm, remodelling (its X_U)")),
             lambda: figs.fig_forces(dirs, out, C),
             lambda: figs.fig_share(dirs, out, C),
             lambda: figs.fig_hw(dirs, out, C),
             lambda: figs.fig_permeability(dirs, out, C, [("remodel_155_c2", "c = 2, k0 = 2.58e-3"),
                                                          ("remodel_155", "isotropic, k0 = 3.77e-3 (Table 1)"),
                                                          ("k0_2.58e-3", "isotropic, k0 = 2.58e-3")]),
             lambda: figs.fig_midplane(dirs, out, C),
             lambda: P(dirs, out, C, ["remodel_405", "reference_405"], [5, 25, 30, 35, 45], "fig3_pressure.png",
                       ("remodelling", "elastic")),
             lambda: P(dirs, out, C, ["remodel_405", "reference_405"], [60, 100, 200, 400], "fig3_later_pressure.png",
                       ("remodelling", "elastic")),
             lambda: detachment(dirs),
             lambda: figs.fig_soft(dirs, out, C),
             lambda: P(dirs, out, C, ["remodel_155", "mu3_nu0.2"], [30, 45], "fig_soft_pressure.png",
                       ("µ = 20 kPa", "µ = 3 kPa")),
             lambda: P(dirs, out, C, ["remodel_155", "remodel_155_c2"], [30], "fig11c_pressure.png",
                       ("isotropic", "c = 2"))]
    for make in steps:
        make()
    if a.docs:
        publish(out, a.axisymmetric)


def publish(out, meridian):
    """--docs: the meridian's figures and their data into docs/figures (the docs show those);
    each set's summary and table of reported numbers into docs/figures/data."""
    dst = ROOT / "docs" / "figures"
    (dst / "data").mkdir(parents=True, exist_ok=True)
    tag = "meridian" if meridian else "3d"
    for name in ("summary", "reported"):
        if (out / f"{name}.csv").exists():
            shutil.copy(out / f"{name}.csv", dst / "data" / f"{name}_{tag}.csv")
    if meridian and (out / "flow.csv").exists():   # the claims' outflow (claims.SOURCES)
        shutil.copy(out / "flow.csv", ROOT / "scripts" / "data" / "flow_meridian.csv")
    if meridian:   # the figures this version draws (not an older version's left in <out>), and their data
        for f in [out / "figures" / n for n in figs.WIDTHS] + sorted((out / "figures" / "data").glob("*.csv")):
            if f.exists():
                shutil.copy(f, dst / f.relative_to(out / "figures"))
    print(f"copied the {tag} set's results to {dst}")


if __name__ == "__main__":
    main()
