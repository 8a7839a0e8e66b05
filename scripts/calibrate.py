"""Calibration: fit scene parameters to measured curves by least squares over batch runs.

One curve (a scene, --data or --synthetic, --column) or several experiments at once
(--experiments FILE.toml: each its data, scene, overrides, column, noise model and time range;
the format in poroplast_tools/experiments.py and docs/reference-fit.md). The parameters (--param
KEY=START) are shared by every experiment, or one experiment's own (KEY@NAME=START), and fitted
in log space (they are positive and of different scales).

The fit (poroplast_tools/fit.py) is Levenberg–Marquardt on the residuals r_i = w_i (model(t_i) −
data(t_i)) of every experiment stacked, the model's history column interpolated at the data's
times. The Jacobian is by forward differences (relative step 1e-3), whose runs take the point's
own time steps, each experiment its own run's (`time.steps`: a step cut in one run and not in
the other would make the difference jump). A trial step whose run fails counts as a worse fit.
The weights w_i come from each experiment's noise model (--noise: absolute, relative: sigma_i a
fraction of the model's value m_i, data: each point's sigma from the file, relative+floor:
sigma_i = sqrt((rho m_i)^2 + floor^2), the floor given by --noise-floor;
poroplast_tools/fitstats.py): the sigma (or rho) of each experiment is estimated from its own
residuals with its share of the degrees of freedom, n_e − p n_e / n, so that the stacked
weighted residuals have unit variance; where that changes the weights other than by a common
factor (the model moved, several experiments, a floor) the fit goes on with the new ones until
they settle (iteratively re-weighted: weights by the model, not the data, leave the estimates
unbiased). The standard errors are the square roots of the diagonal of (JᵀJ)⁻¹ with J the
weighted Jacobian at the optimum (its own finite-difference runs if the last step moved it);
the Wald intervals value·exp(±z·sigma/value) with z Student's t of n − p degrees of freedom when
a sigma was estimated, the normal z when every sigma is given (--noise data), for 68.27% and
95%. --profile adds profile-likelihood intervals (poroplast_tools/profile.py): each parameter on a
grid about the optimum (--profile-grid, in standard errors; default 1,2,3,4.5,6), the others
re-optimised there by the fit's own LM (at most --profile-max-it steps, converged when the
Gauss–Newton step predicts a cost decrease below 0.02), walking outward from the optimum: each
point starts from the better of the previous point's optimum extrapolated along the path and
that optimum unchanged. All points still walking move in step: each inner iteration's
finite-difference runs of all of them (each replaying its own point's steps) are one sweep, their
trial steps one more. A side stops once the cost has risen by the 95% threshold; each end is
where the rise reaches z² (the same z), interpolated linearly in √rise between grid points. An
end is printed "open (beyond the grid)" where the grid never reaches the threshold and "unknown"
where the point that reaches it did not converge or a run failed (null in the JSON, the reason in
profileNN_open); one parameter has nothing to re-optimise: its grid is one sweep. A parameter
whose estimate correlates above 0.99 with another's is flagged: its Wald interval takes their
ridge as straight and is not to be trusted; the profile's is (an open end: the data do not bound
it), unless its crossing point did not converge (then neither is). A profile point below the
optimum's cost (the fit stopped early on a flat ridge) is warned of; the rises are then taken
from it.

Before the first step the start point's sensitivities are printed, near-collinear parameter
pairs warned of (with the cause and remedy where known: the surface tension and the yield stress
at one compression), and a parameter that moves no data point refused (poroplast_tools/identify.py).
A start of 0 is refused with what 0 means (surface.tension, sigma_y: their term off); a key the
scene accepts only within a range (surface.tension: 0.01-1000 mN/m) must start within it, a trial
point outside it is not run (a failed step: the damping grows), and an estimate within a factor 2
of the lower end is warned of (`at_bound` in the JSON: the data push it towards 0).
Every run is a case of the case store STUDY/runs/cases/ (`poroplast sweep`: a completed one is
not run again, so an interrupted calibration continues): each iteration's finite-difference
neighbours of all experiments are one batch, one `mpirun -n RANKS poroplast sweep` (--ranks 2,
--ranks-per-case K: 1 on a meridian, RANKS for 3-D), and each trial step one more (a neighbour
that moves another experiment's own parameter takes this experiment's curve from the point's
run: nothing to run); `--no-sweep`
runs one mpirun per run, `--jobs N` points at once. The fit stops when an iteration lowers the
sum of squares by less than `--ftol` (default 0.1%), when its step is below 1e-5 (log space),
or after `--max-it` iterations.

    python3 scripts/calibrate.py remodel_40 --data measured.csv --column force_total_mg \\
        --param material.remodelling.lambda_p=0.001 --param material.remodelling.sigma_y=2.0 \\
        --dir studies/calib [--set KEY=VALUE ...] [--t-min 0 --t-max 40] [--max-it 15] [--profile]
    python3 scripts/calibrate.py --experiments aggregates.toml \\
        --param material.remodelling.lambda_p=0.001 --param material.mu@r150=2.5 --dir studies/calib2

`--data`: a table of a time and the value as a lab writes it, the formats of
poroplast_tools/measured.py (docs/reference-data-files.md): a header line naming the columns
with their units (`time [min]`, `force (µN)`, `F/mN`, `force_uN`: forces converted to the model's
mg with 1 mg = 9.81 µN), comma, semicolon or tab separators, decimal commas where the separator
allows, UTF-8 or Windows-1252; one line says what was detected; a malformed or ambiguous file is
refused with the problem, its line and the fix. A synthetic curve for testing the fit:
`--synthetic KEY=VALUE ...` runs the scene with those values first and fits to its own history
(an experiment: `synthetic = {...}`, with noise).

Every name is checked before any run: each experiment's scene with its overrides, synthetic
values and start values, and its column, by `poroplast columns` (poroplast_tools/runmodel.py,
check_names; the nearest valid name suggested), then the data files and their columns.

Writes STUDY/calibration.json: per parameter (its label, KEY or KEY@NAME) value, sigma,
interval68, interval95 (and profile68, profile95 with --profile: null where no end was found,
profile68_open, profile95_open the reason per end: "grid", "unconverged", "failed", or null;
collinear_with and trust for a near-collinear parameter; at_bound; profile_lower_cost when a profile
point beat the optimum); noise (model, s, chi2_per_dof), experiments (per experiment: noise model,
s, floor, points, rms in the noise model's shape, rms_weighted (residual / sigma), rms_residual in the
data's unit and that unit), intervals (z and dof), correlation, rms, rms_weighted, runs (made by
this command), runs_in_all (with those the case store held); and the
iterations' log. STUDY/calibration.png: data and fit in the data's unit, one column per experiment,
on a linear and a logarithmic axis; STUDY/profile.png the profiles.
"""
import argparse
import json
import math
import sys
from pathlib import Path

import numpy as np

from poroplast_tools import experiments as exps
from poroplast_tools import fitplots, units
from poroplast_tools.cases import rank_options, use_rank_options
from poroplast_tools.fit import LEVELS, FitError, fit, stats
from poroplast_tools.fitstats import MODELS as NOISE_MODELS, Noise, stacked_weights
from poroplast_tools.identify import COLLINEAR, report as identifiability
from poroplast_tools.measured import Curve, DataError, read_curve
from poroplast_tools.profile import ATOL, MULTIPLES, profile
from poroplast_tools.runmodel import Runs, check_names, synthesise
from poroplast_tools.tables import write_rows


def single(a):
    """The one experiment of the single-curve command line."""
    if not a.scene or not a.column:
        sys.exit("calibrate.py: give a scene and --column, or --experiments FILE")
    if not a.data and not a.synthetic:
        sys.exit("calibrate.py: give --data or --synthetic")
    if a.data and a.synthetic:
        sys.exit("calibrate.py: give --data or --synthetic, not both")
    synthetic = {}
    for k, v in exps.overrides(a.synthetic, "--synthetic"):
        try:
            synthetic[k] = float(v)
        except ValueError:
            raise exps.ExperimentError(f"--synthetic `{k}={v}`: `{v}` is not a number")
    if not a.t_min < a.t_max:
        raise exps.ExperimentError(f"--t-min {a.t_min:g} is not below --t-max {a.t_max:g}: no data between")
    return exps.Experiment(
        name=Path(a.scene).stem, scene=a.scene, column=a.column, data=a.data,
        data_column=a.data_column, unit=a.data_unit,
        noise=a.noise or ("relative+floor" if a.noise_floor is not None else None), noise_floor=a.noise_floor,
        t_min=a.t_min, t_max=a.t_max, synthetic=synthetic)


def floor_type(text):
    """--noise-floor's type: exps.floor_value, its message kept by argparse."""
    try:
        return exps.floor_value(text)
    except ValueError as e:
        raise argparse.ArgumentTypeError(str(e))


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", nargs="?", help="the scene (with --experiments: the experiments' default)")
    ap.add_argument("--experiments", metavar="FILE.toml", help="several experiments at once (see above)")
    ap.add_argument("--param", action="append", required=True, metavar="KEY[@EXPERIMENT]=START")
    ap.add_argument("--column", help="history.csv column to fit (e.g. force_total_mg)")
    ap.add_argument("--data", help="CSV with time and the measured value (see the format above)")
    ap.add_argument("--data-column", help="the data's column (default: found from --column's name)")
    ap.add_argument("--data-unit", metavar="UNIT",
                    help="the data value's unit when its column's name has none: a force in mg, N, mN, uN (µN), nN, "
                         "pN (converted with 1 mg = 9.81 µN), a length in um, nm, mm, m, a stress in kPa, Pa, MPa")
    ap.add_argument("--synthetic", action="append", default=[], metavar="KEY=VALUE",
                    help="fit to the scene's own curve with these values (a test of the fit)")
    ap.add_argument("--noise", choices=NOISE_MODELS,
                    help="the noise model (poroplast_tools/fitstats.py): one unknown sigma (absolute), sigma "
                         "proportional to the model's value (relative), each point's sigma from the data file "
                         "(data), or relative above a given floor (relative+floor, --noise-floor); default: data if "
                         "the file has a sigma column, else absolute")
    ap.add_argument("--noise-floor", type=floor_type, metavar="F[UNIT]",
                    help="relative+floor (implied without --noise): the floor's sigma, in the column's unit or with one "
                         "(0.05uN, 0.5nN)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--t-min", type=float, default=-math.inf)
    ap.add_argument("--t-max", type=float, default=math.inf)
    ap.add_argument("--dir", required=True)
    ap.add_argument("--table", metavar="CSV", help="also write the result as a CSV a page can cite: a row per "
                    "parameter (value, sigma, its 68%% and 95%% intervals) and per experiment (its rms residual)")
    rank_options(ap)
    ap.add_argument("--max-it", type=int, default=15)
    ap.add_argument("--jobs", type=int, default=1, help="with --no-sweep: points run at once")
    ap.add_argument("--ftol", type=float, default=1e-3,
                    help="stop when an iteration lowers the sum of squares by less than this fraction")
    ap.add_argument("--profile", action="store_true",
                    help="profile-likelihood intervals (one parameter: one sweep; more: the others re-optimised at "
                         "each point, a few sweeps per grid point)")
    ap.add_argument("--profile-grid", default=",".join(f"{m:g}" for m in MULTIPLES), metavar="M,M,...",
                    help="the profile's points on each side of the optimum, in standard errors (log space)")
    ap.add_argument("--profile-max-it", type=int, default=4,
                    help="the others' re-optimisation at a profile point: at most this many LM steps")
    a = ap.parse_args()
    if a.table and not Path(a.table).resolve().parent.is_dir():
        sys.exit(f"calibrate.py: --table {a.table}: no such directory {Path(a.table).resolve().parent}")
    sweep = use_rank_options(a)["sweep"]
    try:
        if a.experiments:
            given = {"scene": a.scene, "column": a.column, "noise": a.noise, "noise_floor": a.noise_floor,
                     "unit": a.data_unit, "data_column": a.data_column,
                     "t_min": a.t_min if math.isfinite(a.t_min) else None,
                     "t_max": a.t_max if math.isfinite(a.t_max) else None}
            defaults = {k: v for k, v in given.items() if v is not None}
            experiments = exps.read(a.experiments, defaults)
        else:
            experiments = [single(a)]
        params = exps.params(a.param, experiments)
        sets = exps.overrides(a.set, "--set")
        try:
            multiples = [float(m) for m in a.profile_grid.split(",")]
        except ValueError:
            raise exps.ExperimentError(f"--profile-grid `{a.profile_grid}`: expected numbers separated by commas")
    except exps.ExperimentError as e:
        sys.exit(f"calibrate.py: {e}")

    # Every name before any run: the scenes, overrides, start values and columns (the solver's
    # `columns`), then the data files (the synthetic curves from one batch), their noise models.
    try:
        check_names(experiments, params, sets, say=lambda s: print(s, flush=True))
    except FitError as err:
        sys.exit(f"calibrate.py: {err}")
    curves = {}
    for e in experiments:
        if e.data:
            try:
                curves[e.name] = read_curve(e.data, e.column, e.unit, e.data_column)
            except DataError as err:
                sys.exit(f"calibrate.py: {err}")
            print(f"read {curves[e.name].detected}", flush=True)
    Path(a.dir).mkdir(parents=True, exist_ok=True)
    runs = Runs(a.dir, experiments, params, sets, a.ranks, sweep, a.jobs)
    try:
        curves.update({k: (t, v, None) for k, (t, v) in synthesise(runs, experiments).items()})
    except FitError as err:
        sys.exit(f"calibrate.py: {err}")
    runs.data, noises = [], []
    for e in experiments:
        td, vd, sd = curves[e.name]
        keep = [i for i, t in enumerate(td) if e.t_min <= t <= e.t_max and t > 0]
        if not keep:
            sys.exit(f"calibrate.py: {e.data or e.name}: no data point between t_min = {e.t_min:g} and t_max = "
                     f"{e.t_max:g} s (the data's times: {min(td):g} to {max(td):g} s)")
        ts, vs = np.array(td)[keep], np.array(vd)[keep]
        runs.data.append((list(ts), vs))
        e.noise = e.noise or ("data" if sd is not None else "absolute")
        try:
            noises.append(Noise(e.noise, vs, None if sd is None else np.array(sd)[keep], e.noise_floor))
        except ValueError as err:
            sys.exit(f"calibrate.py: {e.name}: --noise {e.noise}: {err}")
    n = sum(len(ts) for ts, _ in runs.data)
    if n <= len(params):
        sys.exit(f"calibrate.py: {n} data points for {len(params)} parameters")
    keys = [p.label for p in params]

    def identifiable(jac, state):
        """Prints the sensitivity table at the start point and the near-collinear pairs; exits
        naming every parameter that moves no data point."""
        values = np.concatenate([vs for _, vs in runs.data])
        column_units = {units.of_column(e.column) for e in experiments}
        unit = units.shown(column_units.pop()) if len(column_units) == 1 and None not in column_units else ""
        lines, refusals, warnings = identifiability(jac, keys, math.sqrt(float(values @ values) / len(values)), unit)
        print("\n".join(lines), flush=True)
        for msg in warnings:
            print(f"calibrate.py: warning: {msg}", flush=True)
        if refusals:
            vm = [float(max(h["max_von_mises"])) for h in state["histories"] if len(h.get("max_von_mises", ()))]

            def why(k):
                return (f" (remodelling flows only where the von Mises stress exceeds sigma_y: its largest value "
                        f"in this run is {max(vm):.4g} kPa; is sigma_y above it?)") if vm and k.split("@")[0].endswith(
                    "lambda_p") else ""
            columns = ", ".join(sorted({e.column for e in experiments}))
            sys.exit("calibrate.py: " + "; ".join(
                f"{k} has no effect on {columns} at the data's times (a 0.1% change moved no data point): "
                f"it cannot be identified from these data{why(k)}" for k in refusals))

    def weigh(d, p):
        return stacked_weights(noises, d, p)[0]

    try:
        opt = fit(runs.evaluate, weigh, np.log([p.start for p in params]), keys, max_it=a.max_it, ftol=a.ftol,
                  say=lambda s: print(s, flush=True), first_jacobian=identifiable)
    except FitError as e:
        sys.exit(f"calibrate.py: {e} (see its log under runs/)")
    except DataError as e:
        sys.exit(f"calibrate.py: {e}")
    st = stats(opt, any(noise.estimated for noise in noises))
    fitted = runs.count()
    before = (runs.asked, runs.ran)
    prof = profile(runs.evaluate, opt, st, keys, multiples, a.profile_max_it, ATOL,
                   say=lambda s: print(s, flush=True)) if a.profile else None
    if prof:
        print(f"the profile took {runs.count(before)}", flush=True)
    # The unit each experiment's curves and residuals are shown in: its file's (the model's for
    # a synthetic curve).
    shown = {e.name: (curves[e.name].unit, curves[e.name].scale) if isinstance(curves[e.name], Curve)
             else (units.of_column(e.column), 1.0) for e in experiments}
    result = report(a, experiments, params, noises, runs, opt, st, prof, shown)
    (Path(a.dir) / "calibration.json").write_text(json.dumps({"result": result, "log": opt.log}, indent=1))
    if a.table:
        write_rows(a.table, table_rows(result, keys), TABLE_FIELDS)
    fitplots.curves(a.dir, experiments, runs.data, opt.state["histories"], result, params, shown)
    if prof:
        fitplots.profiles(a.dir, opt, st, prof, keys)
    print(f"{runs.count()} in all" + (f", the fit's {fitted} and the profile's {runs.count(before)}" if prof else "")
          + f"; {Path(a.dir) / 'calibration.json'}")


TABLE_FIELDS = ["row", "value", "sigma", "rel_sigma", "lo68", "hi68", "lo95", "hi95", "points", "unit"]


def table_rows(result, keys):
    """calibration.json's result as rows: each parameter's value, sigma and intervals, then each
    experiment's rms residual (in its data's unit) and points."""
    rows = [{"row": k, "value": result[k]["value"], "sigma": result[k]["sigma"],
             "rel_sigma": result[k]["sigma"] / result[k]["value"],
             "lo68": result[k]["interval68"][0], "hi68": result[k]["interval68"][1],
             "lo95": result[k]["interval95"][0], "hi95": result[k]["interval95"][1]} for k in keys]
    rows += [{"row": f"rms {e['name']}", "value": e["rms"], "points": e["points"], "unit": e["unit"]}
             for e in result["experiments"]]
    return rows


def report(a, experiments, params, noises, runs, opt, st, prof, shown):
    """calibration.json's result, printed as it is made; `shown`: per experiment the data's
    unit and its factor to the model's (the residuals are printed in the data's unit)."""
    keys = [p.label for p in params]
    _, scales = stacked_weights(noises, opt.d, len(keys))
    result = {}
    wald = {name: st.wald(opt.x, level) for name, level in LEVELS.items()}
    how = f"Student's t, {st.dof} degrees of freedom" if st.estimated else "normal: sigma given"
    for k, key in enumerate(keys):
        value = math.exp(opt.x[k])
        result[key] = {"value": value, "sigma": value * float(st.rel[k]),
                       **{f"interval{name}": wald[name][k] for name in LEVELS}}
        print(f"{key} = {value:.6g} ± {result[key]['sigma']:.2g} (one standard error); "
              + ", ".join(f"{name}%: [{lo:.6g}, {hi:.6g}]" for name, (lo, hi) in
                          ((name, wald[name][k]) for name in LEVELS)) + f" (Wald, {how})")
        if prof and key in prof.curves:
            p = prof[key]
            for name in LEVELS:
                result[key][f"profile{name}"] = p[f"interval{name}"]
                result[key][f"profile{name}_open"] = p[f"why{name}"]
            print(f"  profile: " + ", ".join(
                f"{name}%: [{_end(p[f'interval{name}'][0], p[f'why{name}'][0])}, "
                f"{_end(p[f'interval{name}'][1], p[f'why{name}'][1])}]" for name in LEVELS))
        low = exps.RANGES.get(params[k].key, (None,))[0]
        if low is not None and value < 2 * low:
            result[key]["at_bound"] = low
            print(f"calibrate.py: warning: {key} ended at {value:.4g}, next to {low:g}, the least the scene accepts: the "
                  "data push it towards 0 (not determined by them, or truly near 0)", flush=True)
        partners = [keys[j] for j in range(len(keys)) if j != k and abs(st.corr[k, j]) > COLLINEAR]
        if partners:
            result[key]["collinear_with"] = partners
            result[key]["trust"] = trust = _trust(prof, key)
            print(f"  near-collinear with {', '.join(partners)}: the Wald interval takes their ridge as straight and "
                  "is not to be trusted; " + {
                      "profile": "trust the profile interval",
                      "profile-open": "trust the profile interval: an open end means the data do not bound it "
                                      "within the grid",
                      "neither": "neither interval is reliable: the profile's re-optimisation did not converge "
                                 "where it crosses the threshold",
                      "none": "run with --profile"}[trust])
    shapes, at = [], 0
    result["experiments"] = []
    for e, noise, s, (ts, vs) in zip(experiments, noises, scales, runs.data):
        # In the noise model's shape: the data's unit (absolute), a fraction of the value
        # (relative, and relative+floor above its floor), the stated sigma (data).
        part = slice(at, at + len(ts))
        rel = opt.w[part] * opt.d[part] * (s if noise.estimated and s > 0 else 1.0)
        at += len(ts)
        shapes.append(rel)
        unit, scale = shown[e.name]
        plain = math.sqrt(float(opt.d[part] @ opt.d[part]) / len(ts)) / scale
        weighted = math.sqrt(float((opt.w[part] * opt.d[part]) @ (opt.w[part] * opt.d[part])) / len(ts))
        result["experiments"].append({"name": e.name, "scene": e.scene, "column": e.column, "points": len(ts),
                                      "noise": e.noise, "s": s, "floor": e.noise_floor,
                                      "rms": math.sqrt(float(rel @ rel) / len(ts)),
                                      "rms_weighted": weighted, "rms_residual": plain, "unit": unit})
        print(f"{e.name}: rms residual {plain:.3g}{' ' + units.shown(unit) if unit else ''} (model − data, "
              f"{len(ts)} points); weighted rms {weighted:.3g} (residual / sigma of the noise model)", flush=True)
        print(f"{e.name}: noise model {e.noise}: " + {
            "absolute": f"sigma estimated from the residuals: {s:.3g}",
            "relative": f"sigma/value estimated from the residuals: {s:.3g}",
            "relative+floor": f"sigma/value estimated from the residuals: {s:.3g}, above the floor "
                              f"{e.noise_floor or 0:.3g}",
            "data": "each point's sigma from the data file"}[e.noise])
    if len(experiments) == 1:
        e, s = experiments[0], scales[0]
        result["noise"] = {"model": e.noise, "s": s,
                           "chi2_per_dof": s * s if e.noise in ("absolute", "relative") else st.chi2}
    else:
        result["noise"] = {"model": "per experiment", "s": None, "chi2_per_dof": st.chi2}
    if not any(n.estimated for n in noises):
        print(f"chi2 per degree of freedom {st.chi2:.3g} (near 1 if the model and the stated sigma fit)")
    result["intervals"] = {"dof": st.dof if st.estimated else None,
                           **{f"z{name}": st.z(level) for name, level in LEVELS.items()}}
    result["correlation"] = {"keys": keys, "matrix": [[float(c) for c in row] for row in st.corr]}
    if prof and prof.lower:
        key, delta, cost = prof.lower
        result["profile_lower_cost"] = {"key": key, "delta": delta, "cost": cost, "optimum_cost": opt.cost}
        print(f"calibrate.py: warning: the profile of {key} found a cost {opt.cost - cost:.3g} below the optimum's "
              f"(at {delta:+.3g} in log {key}): the fit stopped early on a flat ridge; the profile intervals are "
              "taken from that lower cost, the Wald ones are centred on the stopped point")
    if len(keys) > 1:
        print("correlations: " + "; ".join(f"{keys[i]} ~ {keys[j]}: {st.corr[i, j]:+.3f}"
                                             for i in range(len(keys)) for j in range(i + 1, len(keys))))
    allr = np.concatenate(shapes)
    result["rms"] = math.sqrt(float(allr @ allr) / len(allr))
    result["rms_weighted"] = math.sqrt(opt.cost / len(opt.d))
    result["runs"] = runs.ran
    result["runs_in_all"] = runs.asked
    return result


def _end(v, why=None):
    if v is not None:
        return f"{v:.6g}"
    return {"grid": "open (beyond the grid)", "unconverged": "unknown (the others' re-optimisation did not converge)",
            "failed": "unknown (a run failed)"}.get(why, "open (beyond the grid)")


def _trust(prof, key):
    """Which interval of a near-collinear parameter to trust: "profile" (both 95% ends found),
    "profile-open" (an end beyond the grid: the data do not bound it), "neither" (an end whose
    re-optimisation did not converge or failed), "none" (no profile)."""
    if not prof or key not in prof.curves:
        return "none"
    whys = prof[key]["why95"]
    if any(w in ("unconverged", "failed") for w in whys):
        return "neither"
    return "profile-open" if any(w == "grid" for w in whys) else "profile"


if __name__ == "__main__":
    main()
