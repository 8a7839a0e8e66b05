#!/usr/bin/env python3
"""Timing benchmark with the accuracy next to the time: runs named cases (or a scene at several
mesh sizes) a few times on 1 and 2 ranks and prints medians of wall time, steps, step cuts,
Newton and Krylov iterations, time per stage (assembly from timings.txt; PC setup, LU numeric
factorisations, Krylov solve and submatrix copies -- fieldsplit blocks, the VI reduced system --
from -log_view), DoFs, peak
memory (the largest rank's peak resident set, `max_rss_mib` in timings.txt), and
the case's key observables (peak force, F(35 s), p(X_U) at 5 s; p_center error for Cryer;
stress_zz at 100 s for the relaxation). Unless --no-halved, each case is run once more with halved
steps (dt, dt_max, error_tolerance halved, growth square-rooted) and 10x tighter Newton and Krylov
tolerances, and the relative differences of the observables are printed: the accuracy bought by
the time.

    python3 scripts/bench.py [--case default remodel ...] [--repeat 3] [--ranks 1 2]
    python3 scripts/bench.py --scene cryer --h 12.5 8.33      # a scene at several mesh sizes (default cryer)
    python3 scripts/bench.py --sweep [--repeat 3] [--ranks 2]  # many small cases: one mpirun each or sweeps
    python3 scripts/bench.py --targets [--repeat 3]            # every 3-D plate scene against issue 27's targets
    python3 scripts/bench.py --fit [--repeat 3] [--level coarse]  # a 3-parameter fit of a meridian curve
    python3 scripts/bench.py --tst [--repeat 3]                 # the 1000-s tensiometry hold on 2 ranks
    python3 scripts/bench.py --creep [tools] [--repeat 3] [--write]  # a force-controlled hold against a displacement one

`--creep`: the shipped `creep_plates` (meridian, 30 um in 5 s, then 40 uN held to 65 s) and the
same experiment with the hold displacement-controlled (the plate held at 30 um), alternated
--repeat times on 1 rank in one invocation: the median wall times (mpirun's), their ratio, and
the steps and Newton iterations of each. Target (issue 53): force control costs <= 1.5 x.
`--creep tools`: the same for a [[tools]] sphere (tests/data/hertz_block.toml made permeable,
its top drained): pressed 1 um in 0.25 s, then held to 60 s at the force the ramp reaches or at
1 um. With --write the medians and the ratio replace the case's rows of
scripts/data/creep_bench.csv (docs/performance.md, "Force control").

`--tst`: the shipped `tst_hold` (meridian, 30% held 1000 s, sigma_y = 0, gamma = 5 mN/m) to the
end of its hold on 2 ranks, --repeat times: the median wall time with the steps, and the plate
force at the end of the ramp and of the hold against the converged values (references.csv, case
tst_hold). Target: F(1005 s) within 1% in <= 10 s.

`--targets`: every shipped 3-D plate scene (and `reference` at the parameters matched to FEBio's
Holmes-Mow, mu = 33.33 kPa) run alone to t_end = 60 s on 2 ranks, --repeat times: the median wall
time (mpirun's, start-up included) with the runs, the steps, the peak force and F(35 s) with their
errors against the converged meridian values of scripts/data/references.csv, and whether the case
meets the 3-D targets (peak within 1%, F(35 s) within 0.5%, <= 60 s). About 15 min with --repeat 3.

`--sweep`: sixteen axisymmetric cases (remodel_40 on its meridian to t = 10 s, λp × σy 4 × 4,
about 1-2 s each) through the study runner three ways — one `mpirun -n RANKS` per case (as the
scripts ran before sweeps), one sweep with k = RANKS (one group), one sweep with k = 1 (RANKS
groups) — with the cases per minute of each (medians of --repeat), then the calibration example
(docs/studies.md: λp, σy from the relaxation scene's own curve) one mpirun per run (on RANKS
ranks one at a time, the scripts' default before sweeps; on 1 rank two at a time, `--no-sweep
--ranks 1 --jobs 2`) and one sweep per batch (k = 1): its wall time and fitted values each way.

`--fit`: a three-parameter fit (µ, λp, σy) of one synthetic meridian curve, the coverage study's
case and its first data set (poroplast_tools/synthetic.py; scripts/coverage.py), by
scripts/calibrate.py on 2 ranks from the truth × 1.1, --repeat times into fresh directories:
the median wall time with the runs, the sweeps and the seconds per run (where the time goes),
and the accuracy beside it: each estimate's error against the truth in units of its standard
error, and the model's discretisation error (its true curve against the `fine` level's at the
data times, in units of the noise). Target: 60 s.

Cases: default (the `reference` scene), remodel (remodel_40), fine (reference at h = 10 µm,
h_pole = 4 µm), graded (reference on a surface-graded mesh, h_surf = 5 µm, the stabilisation
faded; 47 613 dofs), full (reference_full), cryer100k (cryer at h = 6.5 µm, 85k dofs), relaxation;
on the meridian: axi (reference_axi, the meridian's default mesh), axi_fine (reference with h = 5, surface and poles at 1 µm, the
finest level of scripts/references.py), axi_remodel (remodel_155), axi_converged (the converged level of the
whole experiment: h = 10, surface and poles at 2 µm, no stabilisation, ⅛ of the steps). For the
reference scenes the accuracy line gives each value's error against the converged values of
scripts/data/references.csv (the `reference` case). Every run is a one-case `poroplast sweep`
into a fresh directory (never skipped: the timings are the point), its observables the sweep's.
The large ones (fine, graded, full, cryer100k) take minutes per run on 2 cores.
"""
import argparse
import csv
import json
import math
import re
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

from poroplast_tools import synthetic as syn
from poroplast_tools.measured import write_curve
from poroplast_tools.cases import ROOT, run_cases, scene_values
from poroplast_tools.coverage import normalised_error
from poroplast_tools.history import history, timings
from poroplast_tools.levels import CONVERGED_LEVEL, grid_cases, h_levels, refined_steps
from poroplast_tools.refs import SHIPPED, references

CASES = {   # shipped scene, --set overrides
    "default": ("reference", []),
    "remodel": ("remodel_40", []),
    "fine": ("reference", ["mesh.params.h=10.0", "mesh.params.h_pole=4.0"]),
    "full": ("reference_full", []),
    # The most accurate mesh that runs the whole experiment in minutes (docs/studies.md): graded
    # towards the surface, the stabilisation faded (the constant term costs a mesh level).
    "graded": ("reference", ["mesh.params.h_surf=5.0", "mesh.params.h_pole=5.0", "mesh.params.w_surf=30.0",
                                "fem.stabilisation_fade=0.03"]),
    "cryer100k": ("cryer", ["mesh.params.h=6.5", "mesh.params.h_pole=6.5"]),   # 85 440 dofs
    "relaxation": ("relaxation", []),
    # The meridian (axisymmetric) model: the reference scene's own mesh parameters, and the finest
    # level of the converged references (scripts/references.py: surface and poles at 1 um).
    "axi": ("reference_axi", []),
    "axi_fine": ("reference", ["mesh.geometry=axisymmetric", "mesh.params.h=5", "mesh.params.h_pole=1",
                               "mesh.params.h_surf=1", "mesh.params.w_surf=30"]),
    "axi_remodel": ("remodel_155", ["mesh.geometry=axisymmetric"]),
    # The converged level of the whole experiment (docs/performance.md): h = 10 with surface and
    # poles at 2 um, no stabilisation (it is the largest error on these meshes), 1/8 of the steps.
    "axi_converged": ("reference", CONVERGED_LEVEL + ["time.dt=0.0025", "time.dt_max=0.25", "time.growth=1.0333"]),
}
# The accuracy columns: name -> the sweep's observable (NaN ones are left out).
ACCURACY = {"peak_F_mg": "max:force_total_mg", "F35_mg": "force_total_mg@35", "p5_kPa": "probe_p@5",
            "p_center_err": "maxerr:p_center@1:inf", "stress_zz_100": "stress_zz@100"}
# The converged values of the elastic experiment (the `reference` case of references.csv): each
# reference scene's error against them is printed beside its time.
CONVERGED = {k: ("reference", ACCURACY[k]) for k in ("peak_F_mg", "F35_mg", "p5_kPa")}
# -log_view events: PC setup (AMG hierarchies, factorisations), Krylov solves, submatrix copies
# (the fieldsplit blocks and, with contact, the VI solver's reduced system).
EVENTS = {"pc_setup": "PCSetUp", "ksp_solve": "KSPSolve", "factor": "MatLUFactorNum", "submatrix": "MatCreateSubMat"}


def log_view(path):
    """Max-over-ranks time of the EVENTS in a -log_view file."""
    out = {k: 0.0 for k in EVENTS}
    for line in open(path):
        f = line.split()
        for key, ev in EVENTS.items():
            if f and f[0] == ev and len(f) > 3:
                out[key] += float(f[3])
    return out


def accuracy(result):
    """The case's accuracy columns, whichever apply (the sweep's observables; NaN ones left out;
    the relaxation's stress only where the scene has no plates)."""
    obs = {k: result.get(spec, math.nan) for k, spec in ACCURACY.items()}
    if not math.isnan(obs["peak_F_mg"]):
        obs["stress_zz_100"] = math.nan
    return {k: v for k, v in obs.items() if not math.isnan(v)}


def halved(scene, overrides):
    """Overrides that halve every step of the case (`levels.refined_steps`)."""
    given = dict(o.split("=", 1) for o in overrides)
    return list(overrides) + [f"{k}={v!r}" for k, v in refined_steps(scene_values(scene)["time"], given, 0.5)]


def run_once(scene, overrides, ranks, work, petsc=()):
    """One run (a one-case sweep into the fresh directory `work`: never skipped, the timings are
    the point) with -log_view."""
    work.mkdir(parents=True, exist_ok=True)
    lv = work / "log_view.txt"
    t0 = time.time()
    [(run, res)] = run_cases(scene, [[tuple(o.split("=", 1)) for o in overrides]], [], work, ranks,
                             ("-log_view", f":{lv}", *petsc), list(ACCURACY.values()), sweep=True,
                             ranks_per_case=ranks)
    if res["status"] != "ok":
        raise SystemExit(f"bench.py: {scene} {' '.join(overrides)} failed: {res['error']} (see {work / 'sweep.log'})")
    wall = time.time() - t0
    tm = timings(run)
    r = dict(tm)
    r.update(log_view(lv))
    r["wall"] = wall
    r["rss_MiB"] = tm.get("max_rss_mib")           # the largest rank's peak resident memory
    r["assembly"] = tm["residual_assembly"] + tm["jacobian_assembly"] + tm.get("history_commit", 0.0)
    r.update(accuracy(res))
    return r


# --sweep: the cases (λp in (kPa s)^-1, σy in kPa) and the calibration example (tests/study.rs).
SWEEP_SCENE = "remodel_40"
SWEEP_SETS = [("mesh.geometry", "axisymmetric"), ("time.t_end", "10"), ("output.fields", "false"),
              ("output.fields_at", "[]")]
SWEEP_GRID = [("material.remodelling.lambda_p", ["0.0005", "0.001", "0.002", "0.004"]),
              ("material.remodelling.sigma_y", ["1.0", "1.5", "2.0", "3.0"])]
CALIBRATION = ["relaxation", "--column", "stress_zz", "--param", "material.remodelling.lambda_p=0.001",
               "--param", "material.remodelling.sigma_y=2.0", "--synthetic", "material.remodelling.lambda_p=0.0005",
               "--synthetic", "material.remodelling.sigma_y=1.5", "--set", "time.t_end=100", "--set", "time.dt_max=1.0"]


def sweep_bench(a, work):
    """Cases per minute of 16 small cases one mpirun each, in a sweep with k = ranks and with
    k = 1; the calibration example's wall time one mpirun per run and one sweep per iteration."""
    cases = grid_cases([([k], [[v] for v in vs]) for k, vs in SWEEP_GRID])
    ways = [("one mpirun per case", False, a.ranks), (f"sweep, k = {a.ranks}", True, a.ranks),
            ("sweep, k = 1", True, 1)]
    print(f"{len(cases)} cases ({SWEEP_SCENE}, " + ", ".join(f"{k}={v}" for k, v in SWEEP_SETS)
          + f"; {' x '.join(k for k, _ in SWEEP_GRID)}) on {a.ranks} rank(s), medians of {a.repeat}; work dir {work}")
    rows = []
    for name, sweep, k in ways:
        walls = []
        for rep in range(a.repeat):
            t0 = time.time()
            done = run_cases(SWEEP_SCENE, cases, SWEEP_SETS, work / f"{name.replace(' ', '_')}-{rep}",
                             a.ranks, observe=["max:force_total_mg"], sweep=sweep, ranks_per_case=k)
            walls.append(time.time() - t0)
            if any(r["status"] != "ok" for _, r in done):
                raise SystemExit(f"bench.py: a case failed ({name})")
            peaks = [r["max:force_total_mg"] for _, r in done]
        rows.append((name, statistics.median(walls), walls, peaks))
    calib = []
    for name, opts in [(f"one mpirun per run, one at a time (--no-sweep --ranks {a.ranks})",
                         ["--no-sweep", "--ranks", str(a.ranks)]),
                       ("one mpirun per run, two at a time (--no-sweep --ranks 1 --jobs 2)",
                        ["--no-sweep", "--ranks", "1", "--jobs", "2"]),
                       (f"one sweep per iteration (--ranks {a.ranks} --ranks-per-case 1)",
                        ["--ranks", str(a.ranks), "--ranks-per-case", "1"])]:
        walls, fit = [], None
        for rep in range(a.repeat):
            d = work / f"calibration-{len(calib)}-{rep}"
            t0 = time.time()
            subprocess.run([sys.executable, str(Path(__file__).parent / "calibrate.py"), *CALIBRATION, *opts,
                            "--dir", str(d)], check=True, stdout=subprocess.DEVNULL)
            walls.append(time.time() - t0)
            res = json.loads((d / "calibration.json").read_text())["result"]
            fit = {k: v["value"] for k, v in res.items() if isinstance(v, dict) and "value" in v} | {"runs": res["runs"]}
        calib.append((name, statistics.median(walls), walls, fit))
    print(f"\n| way ({len(cases)} cases, {a.ranks} ranks) | wall (s), median | cases/min | runs (s) |")
    print("|---|---|---|---|")
    for name, wall, walls, _ in rows:
        print(f"| {name} | {wall:.1f} | {60 * len(cases) / wall:.1f} | {', '.join(f'{w:.1f}' for w in walls)} |")
    for name, _, _, peaks in rows[1:]:
        worst = max(abs(p / q - 1) for p, q in zip(peaks, rows[0][3]))
        print(f"\npeak forces, {name} against {rows[0][0]}: "
              + ("identical" if worst == 0 else f"largest relative difference {worst:.1e}"), end="")
    print()
    print("\n| calibration example | wall (s), median | runs (s) | fitted values, runs |")
    print("|---|---|---|---|")
    for name, wall, walls, fit in calib:
        print(f"| {name} | {wall:.1f} | {', '.join(f'{w:.1f}' for w in walls)} | "
              + ", ".join(f"{k.split('.')[-1]} {v:.9g}" for k, v in fit.items()) + " |")


# --targets: (scene, overrides, the references.csv case whose converged values judge it; None:
# no converged force reference exists). Up to 35 s elastic_155 and reference_405 are `reference`,
# remodel_155 and remodel_405 are remodel_40.
TARGETS = [
    ("reference", [], "reference"),
    ("elastic_155", [], "reference"),
    # (their fields_at times beyond 60 s dropped, the earlier ones kept: steps land on them)
    ("reference_405", ["output.fields_at=[5.0, 25.0, 30.0, 35.0, 45.0, 60.0]"], "reference"),
    ("reference_full", [], "reference"),
    ("remodel_40", [], "remodel_40"),
    ("remodel_155", [], "remodel_40"),
    ("remodel_405", ["output.fields_at=[5.0, 25.0, 30.0, 35.0, 45.0, 60.0]"], "remodel_40"),
    ("remodel_155_c2", [], None),
    ("reference", ["material.mu=33.33"], "febio_matched"),
]
# The 3-D targets: relative errors of the peak and F(35 s), wall time (s) to t_end = 60 s.
TARGET = {"peak": 0.01, "F35": 0.005, "wall": 60.0}


def targets_bench(a, work):
    """Every 3-D plate scene to t_end = 60 s on 2 ranks: median wall time, errors, targets met."""
    refs = references()
    print(f"medians of {a.repeat} run(s), 2 ranks, t_end = 60 s; converged values from "
          f"{SHIPPED.name}; "
          f"work dir {work}")
    print("\n| scene | dofs | wall (s), median | runs (s) | steps | peak (mg) | F(35 s) (mg) | targets |")
    print("|---|---|---|---|---|---|---|---|")
    for scene, ov, ref in TARGETS:
        label = scene + "".join(f" {o}" for o in ov if not o.startswith("output."))
        rs = [run_once(scene, ov + ["time.t_end=60"], 2, work / f"{label.replace(' ', '_')}-{k}")
              for k in range(a.repeat)]
        med = lambda key: statistics.median(r[key] for r in rs)
        wall, peak, f35 = med("wall"), med("peak_F_mg"), med("F35_mg")
        if ref:
            e_peak = peak / refs[(ref, "max:force_total_mg")][0] - 1
            e_35 = f35 / refs[(ref, "force_total_mg@35")][0] - 1
            met = abs(e_peak) <= TARGET["peak"] and abs(e_35) <= TARGET["F35"] and wall <= TARGET["wall"]
            cells = f"{peak:.4f} ({100 * e_peak:+.2f}%) | {f35:.4f} ({100 * e_35:+.2f}%) | " \
                    + ("met" if met else "missed")
        else:
            cells = f"{peak:.4f} | {f35:.4f} | no reference" + (" (over 60 s)" if wall > TARGET["wall"] else "")
        runs = ", ".join(f"{r['wall']:.1f}" for r in rs)
        print(f"| {label} | {med('dofs'):.0f} | {wall:.1f} | {runs} | "
              f"{med('steps'):.0f} | {cells} |", flush=True)


# --tst: the tensiometry hold's observables (end of the ramp, end of the 1000-s hold) and its
# target: the force at the end of the hold within 1% of the converged value in <= 10 s on 2 ranks.
# Two meshes: the shipped one (the surface graded to 0.025 R, for the Laplace reading's contact
# radius) and the force's (0.02 R at the poles only).
TST_OBSERVE = ["force_total_mg@5", "force_total_mg@1005", "sigma_app@1005"]
TST_TARGET = {"F": 0.01, "wall": 10.0}
TST_MESHES = {"shipped (graded surface)": [],
              "force mesh (poles only)": [("mesh.relative_sizes", "{ h = 0.15, h_pole = 0.02, r_pole = 0.5 }")]}


def tst_bench(a, work):
    """The `tst_hold` scene to the end of its hold (1005 s) on --ranks ranks, --repeat times, on
    each of TST_MESHES: the median wall time (mpirun's, start-up included), the steps, and its
    forces against the converged values of references.csv (case tst_hold); sigma_app beside."""
    refs = references()
    n = a.ranks[0] if isinstance(a.ranks, list) else a.ranks
    print(f"tst_hold to 1005 s, medians of {a.repeat} run(s) on {n} rank(s); converged values from "
          f"{SHIPPED.name}; work dir {work}; gamma = 5 mN/m")
    for m, (label, sets) in enumerate(TST_MESHES.items()):
        rs = []
        for k in range(a.repeat):
            d = work / f"tst-{m}-{k}"
            d.mkdir(parents=True)
            t0 = time.time()
            [(run, res)] = run_cases("tst_hold", [[("time.t_end", "1005"), *sets]], [], d, n, (), TST_OBSERVE,
                                     sweep=True, ranks_per_case=n)
            if res["status"] != "ok":
                raise SystemExit(f"bench.py: tst_hold failed: {res['error']} (see {d / 'sweep.log'})")
            rs.append(dict(wall=time.time() - t0, steps=timings(run)["steps"], dofs=timings(run)["dofs"],
                           **{o: res[o] for o in TST_OBSERVE}))
        med = lambda key: statistics.median(r[key] for r in rs)
        wall = med("wall")
        print(f"\n{label}: {med('dofs'):.0f} dofs\n\n| observable | value (median) | converged | error |")
        print("|---|---|---|---|")
        errs = {}
        for o in TST_OBSERVE:
            if ("tst_hold", o) in refs:
                ref, bar = refs[("tst_hold", o)]
                errs[o] = med(o) / ref - 1
                print(f"| {o} | {med(o):.6g} | {ref:.6g} ± {bar:.2g} | {100 * errs[o]:+.2f}% |")
            else:
                print(f"| {o} | {med(o):.6g} | (gamma = 5) | {100 * (med(o) / 5 - 1):+.2f}% |")
        met = abs(errs["force_total_mg@1005"]) <= TST_TARGET["F"] and wall <= TST_TARGET["wall"]
        runs = ", ".join(f"{r['wall']:.1f}" for r in rs)
        print(f"\nwall {wall:.1f} s (runs {runs}), "
              f"{med('steps'):.0f} steps: target (F(1005 s) within 1%, <= 10 s) " + ("met" if met else "missed"))


# --creep: the displacement-controlled twin of creep_plates' force hold, and the target ratio.
CREEP_DISPLACEMENT = "[{ t = 0.0, displacement = 0.0 }, { t = 5.0, displacement = 30.0 }]"
CREEP_TARGET = 1.5
# --creep tools: a sphere (tests/data/hertz_block.toml, permeable, its top drained) pressed 1 um in
# 0.25 s, then held to 60 s at the force the ramp reaches (0.0499 uN at h_c = 2 um) or at 1 um.
TOOL_RAMP = "{ t = 0.0, displacement = 0.0 }, { t = 0.25, displacement = 1.0 }"
TOOL_SETS = [("material.permeability", "1.0"), ("mesh.params.h_c", "2.0"), ("mesh.params.d_c", "80.0"),
             ("bc", '[{ group = "bottom", displacement = { z = 0.0 } }, { group = "top", pressure = 0.0 }]'),
             ("time.t_end", "60.0"), ("time.dt", "0.25"), ("time.growth", "1.3"), ("time.dt_max", "5.0")]
CREEP_CASES = {
    "plates": ("creep_plates", "creep_plates to 65 s", [],
               {"force": [], "displacement": [("plates.upper", CREEP_DISPLACEMENT)]}),
    "tools": (ROOT / "tests" / "data" / "hertz_block.toml", "a sphere on a block (hertz_block) to 60 s", TOOL_SETS,
              {"force": [("tools.0.protocol", f"[{TOOL_RAMP}, {{ t = 0.25, force = 0.0499 }}]")],
               "displacement": [("tools.0.protocol", f"[{TOOL_RAMP}]")]}),
}


def creep_bench(a, work):
    """A force-controlled hold and the same experiment with a displacement hold (`--creep
    plates`: creep_plates; `--creep tools`: a sphere, a [[tools]] entry), alternated --repeat
    times on 1 rank: median wall times, their ratio, steps and Newton iterations."""
    scene, title, common, cases = CREEP_CASES[a.creep]
    rs = {k: [] for k in cases}
    for k in range(a.repeat):
        for label, sets in cases.items():
            d = work / f"creep-{label}-{k}"
            d.mkdir(parents=True)
            t0 = time.time()
            [(run, res)] = run_cases(scene, [[("output.fields", "false"), *common, *sets]], [], d, 1, (), [],
                                     sweep=True, ranks_per_case=1)
            if res["status"] != "ok":
                raise SystemExit(f"bench.py: {title} ({label}) failed: {res['error']} (see {d / 'sweep.log'})")
            tm = timings(run)
            rs[label].append(dict(wall=time.time() - t0, steps=tm["steps"], newton=tm["newton_its"]))
    med = {label: {key: statistics.median(r[key] for r in runs) for key in runs[0]} for label, runs in rs.items()}
    print(f"{title} on 1 rank, medians of {a.repeat} run(s) alternated in one invocation; work dir {work}")
    print("\n| hold | wall (s) | steps | Newton iterations |\n|---|---|---|---|")
    for label, m in med.items():
        print(f"| {label} | {m['wall']:.2f} | {m['steps']:.0f} | {m['newton']:.0f} |")
    ratio = med["force"]["wall"] / med["displacement"]["wall"]
    print(f"\nforce / displacement wall time: {ratio:.2f} (target <= {CREEP_TARGET}: "
          + ("met" if ratio <= CREEP_TARGET else "missed") + ")")
    if a.write:
        write_creep(a.creep, med, ratio, a.repeat)


CREEP_CSV = ROOT / "scripts" / "data" / "creep_bench.csv"


def write_creep(case, med, ratio, repeat):
    """Replaces `case`'s rows of scripts/data/creep_bench.csv (docs/performance.md binds them):
    per hold its median wall time, steps and Newton iterations, and the ratio on both rows."""
    rows = [r for r in (csv.DictReader(open(CREEP_CSV)) if CREEP_CSV.exists() else []) if r["case"] != case]
    for hold, m in med.items():
        rows.append(dict(case=case, hold=hold, wall_s=f"{m['wall']:.2f}", steps=f"{m['steps']:.0f}",
                         newton_its=f"{m['newton']:.0f}", ratio=f"{ratio:.3f}", runs=repeat,
                         date=time.strftime("%Y-%m-%d", time.gmtime())))
    with open(CREEP_CSV, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    print(f"wrote {CREEP_CSV.relative_to(ROOT)}")


# --fit: the fit's target wall time (s); the noise and data set of the fitted curve.
FIT_TARGET, FIT_NOISE, FIT_SEED = 60.0, 0.02, 41


def critical_path(log):
    """The seconds a calibration's sweeps spent running cases, from its sweep.log: per sweep, its
    busiest group's runs one after another; the wall time beyond it is start-ups and Python."""
    total = 0.0
    for sweep in log.split("\n$ mpirun")[1:]:
        groups = {}
        for seconds, group in re.findall(r" ok in ([0-9.]+) s \[group (\d+)\]", sweep):
            groups[group] = groups.get(group, 0.0) + float(seconds)
        total += max(groups.values(), default=0.0)
    return total


def fit_bench(a, work):
    """A 3-parameter fit of one synthetic meridian curve on 2 ranks, --repeat times: medians of
    wall time, runs, sweeps and seconds per run; the errors in units of sigma; the model's
    discretisation error against the fine level."""
    keys, truth = syn.FITS[3]
    levels = [a.level, "fine"]
    out = run_cases(syn.SCENE, [syn.truth_case(truth) + syn.LEVELS[lv] for lv in levels], syn.CASE, work / "truth",
                    2, ranks_per_case=1)
    if any(r["status"] != "ok" for _, r in out):
        raise SystemExit(f"bench.py: a truth run failed (see {work / 'truth' / 'sweep.log'})")
    (h, hf) = [history(d) for d, _ in out]
    times = syn.data_times(h["time"], h[syn.COLUMN])
    curve = np.interp(times, h["time"], h[syn.COLUMN])
    disc = (curve - np.interp(times, hf["time"], hf[syn.COLUMN])) / (FIT_NOISE * np.abs(curve))
    data = work / "data.csv"
    write_curve(data, times, syn.noisy(curve, FIT_NOISE, FIT_SEED, 0), comment="bench.py --fit")
    print(f"3-parameter fit ({', '.join(k.split('.')[-1] for k in keys)}) of {len(times)} points, "
          f"{100 * FIT_NOISE:g}% noise, level {a.level}, 2 ranks; medians of {a.repeat}; work dir {work}", flush=True)
    rows = []
    for rep in range(a.repeat):
        d = work / f"fit-{rep}"
        t0 = time.time()
        subprocess.run([sys.executable, str(Path(__file__).parent / "calibrate.py"),
                        *syn.calibrate_args(3, a.level, 1.1), "--data", str(data), "--noise", "relative",
                        "--ranks", "2", "--dir", str(d)], check=True, stdout=subprocess.DEVNULL)
        wall = time.time() - t0
        res = json.loads((d / "calibration.json").read_text())["result"]
        log = (d / "runs" / "sweep.log").read_text()
        run_s = [float(x) for x in re.findall(r" ok in ([0-9.]+) s", log)]
        rows.append({"wall": wall, "runs": res["runs"], "sweeps": log.count("\n$ mpirun"),
                     "run_s": statistics.median(run_s), "run_total": sum(run_s), "path": critical_path(log),
                     **{k: normalised_error(res[k]["value"], res[k]["sigma"], truth[k]) for k in keys},
                     **{f"{k}/sigma": res[k]["sigma"] / res[k]["value"] for k in keys}})
        print(f"  run {rep + 1}: {wall:.1f} s, {res['runs']} runs", flush=True)
    med = lambda key: statistics.median(r[key] for r in rows)
    walls = ", ".join(f"{r['wall']:.1f}" for r in rows)
    print(f"\n| wall (s), median | runs (s) | runs | sweeps | s per run (median) | runs' seconds (sum) | "
          f"runs' critical path (s) | "
          f"errors / sigma ({', '.join(k.split('.')[-1] for k in keys)}) | sigma / value | "
          f"discretisation error / noise (rms, largest) | target {FIT_TARGET:g} s |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    print(f"| {med('wall'):.1f} | {walls} | "
          f"{med('runs'):.0f} | {med('sweeps'):.0f} | {med('run_s'):.2f} | {med('run_total'):.1f} | "
          f"{med('path'):.1f} | "
          + ", ".join(f"{med(k):+.2f}" for k in keys) + " | "
          + ", ".join(f"{100 * med(k + '/sigma'):.2g}%" for k in keys) + " | "
          f"{math.sqrt(float(np.mean(disc ** 2))):.2f}, {float(np.max(np.abs(disc))):.2f} (t = "
          f"{times[int(np.argmax(np.abs(disc)))]:g} s) | {'met' if med('wall') <= FIT_TARGET else 'missed'} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--case", nargs="+", choices=list(CASES), default=None)
    ap.add_argument("--scene", default=None, help="instead of --case: a scene at the mesh sizes of --h")
    ap.add_argument("--h", type=float, nargs="*", default=[],
                    help="mesh sizes: mesh.params.h, the scene's other sizes (h_pole, ...) scaled with it")
    ap.add_argument("--t-end", type=float, default=None, help="shorten a --scene run")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--ranks", type=int, nargs="+", default=None, help="rank counts (default 1 2; --sweep: 2)")
    ap.add_argument("--sweep", action="store_true",
                    help="16 small axisymmetric cases one mpirun each and as sweeps (k = ranks, k = 1): cases "
                         "per minute; the calibration example one mpirun per run and one sweep per iteration")
    ap.add_argument("--targets", action="store_true",
                    help="every 3-D plate scene to t_end = 60 s on 2 ranks against the 3-D targets (issue 27)")
    ap.add_argument("--no-halved", action="store_true",
                    help="skip the accuracy check (one run with halved steps and tolerances, 10x tighter Newton)")
    ap.add_argument("--fit", action="store_true",
                    help="a 3-parameter fit of one synthetic meridian curve on 2 ranks (the 60 s target)")
    ap.add_argument("--level", choices=list(syn.LEVELS), default="coarse", help="--fit: the model's mesh and steps")
    ap.add_argument("--tst", action="store_true",
                    help="the tensiometry hold (tst_hold, 1000 s) on 2 ranks against its 1% / 10 s target")
    ap.add_argument("--creep", nargs="?", const="plates", choices=list(CREEP_CASES),
                    help="a force-controlled hold against the displacement-controlled one (<= 1.5x): "
                         "creep_plates (plates, the default) or a sphere of [[tools]] (tools)")
    ap.add_argument("--write", action="store_true",
                    help="--creep: write the medians and the ratio to scripts/data/creep_bench.csv")
    a = ap.parse_args()
    if a.creep:
        return creep_bench(a, Path(tempfile.mkdtemp(prefix="poroplast-bench-creep-")))
    if a.tst:
        a.ranks = (a.ranks or [2])[0]
        return tst_bench(a, Path(tempfile.mkdtemp(prefix="poroplast-bench-tst-")))
    if a.fit:
        return fit_bench(a, Path(tempfile.mkdtemp(prefix="poroplast-bench-fit-")))
    if a.targets:
        return targets_bench(a, Path(tempfile.mkdtemp(prefix="poroplast-bench-targets-")))
    if a.sweep:
        a.ranks = (a.ranks or [2])[0]
        return sweep_bench(a, Path(tempfile.mkdtemp(prefix="poroplast-bench-sweep-")))
    a.ranks = a.ranks or [1, 2]
    if a.h and not a.scene:
        a.scene = "cryer"          # the older form `bench.py --h 12.5 8.33`

    runs = []   # (label, scene, overrides)
    if a.scene:
        # A mesh sweep (levels.h_levels: the scene's other sizes scaled with h), or the scene as it is.
        levels = h_levels(a.scene, a.h) if a.h else [[]]
        for h, mesh in zip(a.h or [None], levels):
            ov = [f"{k}={v}" for k, v in mesh] + ([f"time.t_end={a.t_end!r}"] if a.t_end else [])
            runs.append((f"{a.scene}" + (f" h={h:g}" if h else ""), a.scene, ov))
    else:
        for c in a.case or ["default", "remodel"]:
            name, ov = CASES[c]
            runs.append((c, name, ov))

    cols = ["dofs", "steps", "step_cuts", "error_rejections", "newton_its", "newton/step", "ksp/newton", "wall",
            "assembly", "pc_setup", "factor", "ksp_solve", "submatrix", "output", "rss_MiB"]
    work = Path(tempfile.mkdtemp(prefix="poroplast-bench-"))
    refs = references()
    converged = {k: refs[c][0] for k, c in CONVERGED.items()}
    print(f"medians of {a.repeat} run(s); times in s (-log_view: max over ranks); work dir {work}")
    for label, scene, ov in runs:
        base = None
        for n in a.ranks:
            rs = [run_once(scene, ov, n, work / f"{label.replace(' ', '_')}-np{n}-{k}") for k in range(a.repeat)]
            med = lambda key: statistics.median(r[key] for r in rs if r.get(key) is not None) \
                if any(r.get(key) is not None for r in rs) else None
            row = {k: med(k) for k in cols if "/" not in k}
            row["ksp/newton"] = med("ksp_its") / max(med("newton_its"), 1)
            row["newton/step"] = med("newton_its") / max(med("steps"), 1)
            base = base or row["wall"]
            obs = {k: med(k) for k in rs[0] if k in ("peak_F_mg", "F35_mg", "p5_kPa", "p_center_err", "stress_zz_100")}
            print(f"{label:>14} np={n}: " + "  ".join(
                f"{k} {row[k]:.4g}" for k in cols if row.get(k) is not None) + f"  speed-up {base / row['wall']:.2f}")
            if obs:
                err = lambda k, v: f" ({100 * (v / converged[k] - 1):+.2f}%)" if scene.startswith("reference") \
                    and k in converged else ""
                print(f"{'':>14}       accuracy: " + "  ".join(f"{k} {v:.6g}{err(k, v)}" for k, v in obs.items()
                                                             if v is not None), flush=True)
        if not a.no_halved and obs:
            # Accuracy not traded away silently: the same case with halved steps and tolerances.
            h = run_once(scene, halved(scene, ov), max(a.ranks), work / f"{label.replace(' ', '_')}-halved",
                         petsc=("-snes_rtol", "1e-9", "-ksp_rtol", "1e-9"))
            diffs = "  ".join(f"{k} {h[k]:.6g} ({100 * (obs[k] - h[k]) / h[k]:+.3f}%)" for k in obs
                              if obs[k] is not None and h.get(k) not in (None, 0))
            print(f"{'':>14}       halved steps/tolerances ({h['steps']:.0f} steps, {h['wall']:.1f} s): {diffs}",
                  flush=True)


if __name__ == "__main__":
    main()
