"""Coverage of the calibration's intervals: do its nominal 68% and 95% intervals hold the truth
68% and 95% of the time?

A truth run of the meridian case (poroplast_tools/synthetic.py: R = 150 µm, µ = 2.5 kPa,
σy = 0.5 kPa, λp = 0.002 (kPa s)⁻¹, 30% in 10 s, hold to 70 s, release by 80 s; for the
3-parameter fit λp = 0.02, where µ, λp and σy are each identifiable: synthetic.py says why);
--sets data sets of its force at 1 s intervals with independent Gaussian noise (--noise-level ×
the value, seeded), written as lab CSV files; each fitted by scripts/calibrate.py (its command
line and calibration.json only) for 1 parameter (λp) and 3 (µ, λp, σy), from the truth ×
--start-factor.
`--case tst`: tissue surface tensiometry with a yield stress (synthetic.TST: tst_hold's
aggregate, γ = 5 mN/m, λp = 0.001 (kPa s)⁻¹, σy = 0.2 kPa), two experiments, 15% and 30% held
1000 s, each data set a pair of files fitted together (calibrate.py --experiments) for γ, λp
and σy; its files are DIR/tst3/, DIR/data/tst3/, coverage_tst.csv, coverage_tst.png and
jitter_tst.csv, so that both cases can share a directory (and its store).
Counts how often the intervals hold the truth (calibration.json's `interval68`/`interval95`,
else the same Wald intervals in log space from value and sigma: poroplast_tools/coverage.py).

    python3 scripts/coverage.py --dir studies/coverage [--sets 50] [--params 1 3] [--jobs 2]
    python3 scripts/coverage.py --dir /tmp/cov --sets 5 --params 1        # a quick check
    python3 scripts/coverage.py --case tst --dir studies/coverage [--sets 50] [--linearised 2000] [--docs]
    python3 scripts/coverage.py --dir studies/coverage --sets 0 --linearised 2000   # the linearised study alone

Before the fits, the model's jitter: runs at each fitted parameter × (1 + k/100), k = −3 … 3,
and at each data time the largest deviation from a cubic in the parameter, against the noise
(it must be far below 1 for the intervals to mean anything), with the standard errors and
correlations the linearised model predicts (jitter.csv; several experiments: their data times
stacked, the rows' `experiment` "all", and besides, printed and as rows of their own, what each
experiment alone would predict: its standard errors, its correlations with the cosines of their
columns, and d F/d ln θ at its last data time).
With --linearised N, the same statistics on the case's linearised model F0 + J (ln θ − ln θ0),
J the jitter runs' central differences at the truth: N fits per noise model (absolute,
relative, relative+floor, data; each with data drawn from its own noise) through the fit's own
code (fit.fit, fitstats' weights), no solver runs: coverage_linearised.csv, and a table with
each rate's binomial standard error (poroplast_tools/coverage.linearised_fits).
Writes DIR/coverage.csv (one row per fit: estimates, sigmas, intervals, covered flags, runs,
seconds), DIR/coverage.png (normalised errors against a standard normal; coverage rates with
Wilson 95% error bars) and a table on the console. Resumable: every run is a case of the shared
store DIR/store/cases (each fit's runs/cases links to it; completed runs are not run again,
e.g. the common start point's), and a fit with its calibration.json is not run again. --docs
copies the tables and the figure to docs/figures/ (data/ for the tables).
"""
import argparse
import csv
import json
import math
import os
import shutil
import statistics
import subprocess
import sys
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from poroplast_tools import coverage as cov
from poroplast_tools import synthetic as syn
from poroplast_tools.measured import write_curve
from poroplast_tools.cases import run_cases
from poroplast_tools.history import history

CALIBRATE = Path(__file__).resolve().parent / "calibrate.py"
DOCS = Path(__file__).resolve().parent.parent / "docs" / "figures"
JITTER_STEPS = [k / 100 for k in range(-3, 4)]


def short(key):
    return key.split(".")[-1]


def runs_ok(a, cases, sets):
    """The histories of the cases (one sweep in the shared store); exits if one failed."""
    out = run_cases(a.case.scene, cases, sets, Path(a.dir) / "store", a.ranks, ranks_per_case=1)
    bad = [str(d) for d, r in out if r["status"] != "ok"]
    if bad:
        sys.exit(f"coverage.py: runs failed: {', '.join(bad)}")
    return [history(d) for d, _ in out]


def jitter(a, p, data, extra):
    """Per parameter of the p-parameter fit: the largest deviation, over the data times, of the
    curve from a cubic in the parameter (runs at θ (1 + k/100), k = −3 … 3, their own steps), in
    units of the noise; and the standard errors and correlations the linearised model predicts
    at the truth for the noise (central differences of the ±1% runs), and those differences,
    d F/d ln θ (the linearised study's Jacobian). `data`: per experiment (name, times, true
    curve); their points stacked."""
    case = a.case
    keys, truth = case.fits[p]
    m = len(JITTER_STEPS)
    cases = [[(k, repr(v * (1 + s) if k == key else v)) for k, v in truth.items()] + list(case.experiments[name])
             for key in keys for s in JITTER_STEPS for name, _, _ in data]
    hs = runs_ok(a, cases, case.sets(a.level, truth, truth) + extra)
    times = np.concatenate([t for _, t, _ in data])
    where = [name for name, t, _ in data for _ in t]
    noise = a.noise_level * np.abs(np.concatenate([c for _, _, c in data]))
    x = np.array(JITTER_STEPS)
    rows, cols = [], []
    ne = len(data)
    for i, key in enumerate(keys):
        mine = hs[i * m * ne:(i + 1) * m * ne]
        f = np.array([np.concatenate([np.interp(t, h["time"], h[case.column])
                                      for (_, t, _), h in zip(data, mine[k * ne:(k + 1) * ne])]) for k in range(m)])
        dev = f - np.array([np.polyval(np.polyfit(x, f[:, j], 3), x) for j in range(len(times))]).T
        worst = np.max(np.abs(dev), axis=0) / noise
        j = int(np.argmax(worst))
        cols.append((f[4] - f[2]) / math.log(1.01 / 0.99) / noise)   # d F / d ln θ, in noise units
        rows.append({"params": p, "param": key, "jitter_over_noise_max": float(worst[j]), "at_time": float(times[j]),
                     **({"at_experiment": where[j]} if case.several else {}),
                     "jitter_over_noise_median": float(np.median(worst))})
    cv = np.linalg.inv(np.column_stack(cols).T @ np.column_stack(cols))
    sd = np.sqrt(np.diag(cv))
    jac = np.column_stack(cols) * noise[:, None]           # d F / d ln θ in the column's unit
    alone = []
    if case.several:
        # What each experiment alone would tell (the same columns, its rows only): where one
        # experiment cannot separate two parameters and the pair can.
        for name in dict.fromkeys(where):
            mine = [j for j, w in enumerate(where) if w == name]
            c = np.column_stack(cols)[mine]
            last = mine[-1]
            s1 = np.sqrt(np.diag(np.linalg.pinv(c.T @ c)))
            corr = np.linalg.pinv(c.T @ c) / np.outer(s1, s1)
            cos = c.T @ c / np.outer(np.linalg.norm(c, axis=0), np.linalg.norm(c, axis=0))
            pairs = [(i, k) for i in range(len(keys)) for k in range(i + 1, len(keys))]
            print(f"  experiment {name} alone: predicted sigma/value "
                  + ", ".join(f"{short(k)} {s:.3g}" for k, s in zip(keys, s1)) + "; correlations "
                  + ", ".join(f"{short(keys[i])}~{short(keys[k])} {corr[i, k]:+.4f} (cos {cos[i, k]:+.5f})"
                              for i, k in pairs)
                  + f"; d F/d ln θ at its last data time ({times[last]:g} s): "
                  + ", ".join(f"{short(k)} {cols[i][last] * noise[last]:.4g}" for i, k in enumerate(keys))
                  + f" {case.column.rsplit('_', 1)[-1]}", flush=True)
            alone += [{"params": p, "param": key, "experiment": name, "predicted_rel_sigma": float(s1[i]),
                       "predicted_corr": " ".join(f"{v:+.4f}" for v in corr[i]),
                       "cos": " ".join(f"{v:+.5f}" for v in cos[i]),
                       "dF_dlntheta_last": float(cols[i][last] * noise[last])} for i, key in enumerate(keys)]
    for i, r in enumerate(rows):
        r["predicted_rel_sigma"] = float(sd[i])
        r["predicted_corr"] = " ".join(f"{c:+.4f}" for c in cv[i] / (sd[i] * sd))
        if case.several:
            r["experiment"] = "all"
    return rows + alone, jac


def fit_command(a, p, data, fdir, extra):
    """calibrate.py's command line of one fit: `data` the data set's file (one experiment) or
    {experiment: file} (several: written into fdir/experiments.toml)."""
    if a.case.several:
        spec = fdir / "experiments.toml"
        spec.write_text(syn.experiments_text(a.case, {k: Path(v).resolve() for k, v in data.items()}))
        source = ["--experiments", str(spec)]
    else:
        source = ["--data", str(data)]
    return [sys.executable, str(CALIBRATE), *syn.calibrate_args(p, a.level, a.start_factor, extra, a.case),
            *source, "--noise", a.noise, "--ranks", "1", "--ranks-per-case", "1", "--dir", str(fdir),
            "--ftol", repr(a.ftol), "--max-it", str(a.max_it)]


def run_fit(a, p, data, fdir, extra):
    """One calibrate.py fit into fdir (its runs in the shared store); (ok, seconds)."""
    (fdir / "runs").mkdir(parents=True, exist_ok=True)
    link = fdir / "runs" / "cases"
    if not link.exists():
        link.symlink_to(os.path.relpath(Path(a.dir).resolve() / "store" / "cases", link.parent.resolve()))
    t0 = time.time()
    with open(fdir / "fit.log", "w") as log:
        ok = subprocess.run(fit_command(a, p, data, fdir, extra), stdout=log,
                            stderr=subprocess.STDOUT).returncode == 0
    seconds = time.time() - t0
    if ok:
        (fdir / "seconds.txt").write_text(f"{seconds:.3f}\n")
    return ok, seconds


def row_of(case, p, i, fdir, n):
    """The coverage.csv row of a finished fit of `case` (n data points in all)."""
    keys, truth = case.fits[p]
    res = json.loads((fdir / "calibration.json").read_text())["result"]
    secs = fdir / "seconds.txt"
    row = {"params": p, "set": i, "runs": res["runs"],
           "seconds": float(secs.read_text()) if secs.exists() else math.nan,
           "noise_s": res["noise"]["s"], "dof": n - p}
    for k in keys:
        e = res[k]
        iv = cov.intervals(e)
        row |= {f"{short(k)}_truth": truth[k], f"{short(k)}_value": e["value"], f"{short(k)}_sigma": e["sigma"],
                f"{short(k)}_z": cov.normalised_error(e["value"], e["sigma"], truth[k])}
        for name, (lo, hi) in iv.items():
            row |= {f"{short(k)}_lo{name}": lo, f"{short(k)}_hi{name}": hi,
                    f"{short(k)}_covered{name}": int(cov.covers((lo, hi), truth[k]))}
    return row


def experiment(a, p, extra):
    """The truth runs of the p-parameter fit's case (one per experiment), their data times and
    true curves, the jitter rows, and the data sets' files (written once: the same seed gives the
    same files): (points in all, jitter rows, per set its file or {experiment: file}, the true
    curves and the Jacobian of the linearised model (None with --no-jitter))."""
    case = a.case
    keys, truth = case.fits[p]
    names = list(case.experiments)
    hs = runs_ok(a, [syn.truth_case(truth) + list(case.experiments[name]) for name in names],
                 case.sets(a.level, truth, truth) + extra)
    data = []
    for name, h in zip(names, hs):
        times = syn.data_times(h["time"], h[case.column], a.every, a.floor)
        curve = np.interp(times, h["time"], h[case.column])
        data.append((name, times, curve))
        print(f"{p}-parameter case ({', '.join(f'{short(k)} = {v:g}' for k, v in truth.items())})"
              + (f", experiment {name}" if name else "")
              + f": {len(times)} data times {times[0]:g} ... {times[-1]:g} s, peak {curve.max():.4g} mg, "
              f"last {curve[-1]:.4g} mg", flush=True)
    jit, jac = ([], None) if a.no_jitter else jitter(a, p, data, extra)
    for r in jit:
        if r.get("experiment", "all") != "all":
            continue
        print(f"  {short(r['param'])}: jitter (largest deviation from a cubic over ±3%) "
              f"{r['jitter_over_noise_max']:.2e} × the noise (t = {r['at_time']:g} s"
              + (f" of {r['at_experiment']}" if "at_experiment" in r else "") + "), median "
              f"{r['jitter_over_noise_median']:.1e}; predicted sigma/value {r['predicted_rel_sigma']:.3g}, "
              f"correlations {r['predicted_corr']}", flush=True)
    folder = Path(a.dir) / "data" / f"{case.tag}{p}"
    folder.mkdir(parents=True, exist_ok=True)
    files = []
    for i in range(a.sets):
        one = {}
        for j, (name, times, curve) in enumerate(data):
            # One experiment: data set i of the seed (as before there were several); several:
            # (i, j + 1), every experiment's noise independent of the others' (not (i, 0): numpy's
            # SeedSequence ignores trailing zeros, so it would be data set i's).
            path = folder / (f"set_{i:03d}_{name}.csv" if name else f"set_{i:03d}.csv")
            if not path.exists():
                sig = a.noise_level * np.abs(curve) if a.noise == "data" else None
                index = (i, j + 1) if case.several else i
                write_curve(path, times, syn.noisy(curve, a.noise_level, a.seed + p, index), sig,
                            f"synthetic: {case.column} of the truth{f', experiment {name}' if name else ''}, "
                            f"{100 * a.noise_level:g}% Gaussian noise, seed {a.seed + p}, set {index}")
            one[name] = path
        files.append(one if case.several else one[None])
    return sum(len(t) for _, t, _ in data), jit, files, ([c for _, _, c in data], jac)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dir", required=True)
    ap.add_argument("--sets", type=int, default=50, help="synthetic data sets (5: a quick check)")
    ap.add_argument("--case", choices=list(syn.CASES), default="meridian",
                    help="meridian: the meridian case (µ, λp, σy); tst: tensiometry at 15%% and 30%% (γ, λp, σy)")
    ap.add_argument("--params", type=int, nargs="+",
                    help="meridian: fits of 1 parameter (λp) and/or 3 (µ, λp, σy), default both; tst: 3 (γ, λp, σy)")
    ap.add_argument("--noise-level", type=float, default=0.02, help="the noise's sigma / value")
    ap.add_argument("--noise", choices=["relative", "data"], default="relative",
                    help="the fits' noise model: relative (sigma estimated from the residuals; Student t "
                         "intervals) or data (the files state each point's sigma; normal intervals)")
    ap.add_argument("--seed", type=int, default=38)
    ap.add_argument("--start-factor", type=float, default=1.1, help="the fits start at the truth times this")
    ap.add_argument("--level", choices=list(syn.LEVELS), default="coarse", help="mesh and steps")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                    help="more overrides of every run (e.g. a shorter experiment for a test)")
    ap.add_argument("--every", type=float, default=1.0, help="seconds between data points")
    ap.add_argument("--floor", type=float,
                    help="data only where the true force is above this fraction of its peak (at the contact's "
                         "opening the runs' steps differ between nearby parameter values: jitter.csv); default: "
                         "the case's, 0.05 on the meridian, 0 for tst (its data end with the hold)")
    ap.add_argument("--jobs", type=int, default=2, help="fits side by side (each on 1 rank)")
    ap.add_argument("--ranks", type=int, default=2, help="ranks of the truth and jitter runs' sweeps")
    ap.add_argument("--ftol", type=float, default=1e-3, help="calibrate.py --ftol")
    ap.add_argument("--max-it", type=int, default=15, help="calibrate.py --max-it")
    ap.add_argument("--no-jitter", action="store_true", help="skip the jitter check")
    ap.add_argument("--docs", action="store_true",
                    help="also copy the tables and the figure to docs/figures/ (docs/studies.md's numbers)")
    ap.add_argument("--linearised", type=int, default=0, metavar="N",
                    help="also N fits per noise model of the case's linearised model (the jitter runs' Jacobian "
                         "at the truth): the coverage of every noise model's intervals without solver runs")
    a = ap.parse_args()
    if a.linearised and a.no_jitter:
        sys.exit("coverage.py: --linearised needs the jitter runs' Jacobian: leave out --no-jitter")
    if a.sets < 0 or a.linearised < 0:
        sys.exit("coverage.py: --sets and --linearised count data sets: give 0 or more")
    a.case = syn.CASES[a.case]
    a.params = a.params or sorted(a.case.fits)
    if not set(a.params) <= set(a.case.fits):
        sys.exit(f"coverage.py: --case {a.case.name} has fits of {', '.join(map(str, sorted(a.case.fits)))} "
                 "parameters")
    a.floor = a.case.floor if a.floor is None else a.floor
    t_start = time.time()
    root = Path(a.dir)
    root.mkdir(parents=True, exist_ok=True)
    extra = [tuple(s.split("=", 1)) for s in a.set]
    out = {"csv": root / f"coverage{a.case.suffix}.csv", "png": root / f"coverage{a.case.suffix}.png",
           "jitter": root / f"jitter{a.case.suffix}.csv",
           "linearised": root / f"coverage_linearised{a.case.suffix}.csv"}

    cases = {p: experiment(a, p, extra) for p in a.params}
    jit = [r for p in a.params for r in cases[p][1]]
    if jit:
        with open(out["jitter"], "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(dict.fromkeys(k for r in jit for k in r)))
            w.writeheader()
            w.writerows(jit)
        to_docs(a, out["jitter"])

    if a.linearised:
        lin = [r for p in a.params for r in linearised(a, p, *cases[p][3])]
        with open(out["linearised"], "w", newline="") as f:
            w = csv.DictWriter(f, fieldnames=list(lin[0]))
            w.writeheader()
            w.writerows(lin)
        print(f"{out['linearised']}", flush=True)
        to_docs(a, out["linearised"])
    if not a.sets:
        return

    jobs = [(p, i, root / f"{a.case.tag}{p}" / f"set_{i:03d}") for p in a.params for i in range(a.sets)]
    todo = [(p, i, d) for p, i, d in jobs if not (d / "calibration.json").exists()]
    print(f"{len(jobs)} fits, {len(jobs) - len(todo)} done, {len(todo)} to run, {a.jobs} at a time", flush=True)
    failed = []

    def one(job):
        p, i, d = job
        ok, s = run_fit(a, p, cases[p][2][i], d, extra)
        print(f"fit of {p} parameter(s), set {i}: " + (f"{s:.1f} s" if ok else f"FAILED ({d / 'fit.log'})"),
              flush=True)
        if not ok:
            failed.append(job)

    with ThreadPoolExecutor(max_workers=a.jobs) as pool:
        list(pool.map(one, todo))

    rows = [row_of(a.case, p, i, d, cases[p][0]) for p, i, d in jobs if (d / "calibration.json").exists()]
    fields = ["params", "set", "runs", "seconds", "noise_s", "dof"]
    order = [k for p in sorted(a.case.fits) for k in a.case.fits[p][1]]
    for k in sorted({k for p in a.params for k in a.case.fits[p][0]}, key=order.index):
        fields += [f"{short(k)}_{c}" for c in ("truth", "value", "sigma", "z", "lo68", "hi68", "covered68",
                                                "lo95", "hi95", "covered95")]
    with open(out["csv"], "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields)
        w.writeheader()
        w.writerows(rows)
    summary = table(rows, a)
    plot(out["png"], rows, summary, a)
    to_docs(a, out["csv"], out["png"])
    print(f"\n{out['csv']}, {out['png']}; this invocation {time.time() - t_start:.0f} s"
          + (f"; {len(failed)} fit(s) failed" if failed else ""))
    if failed:
        sys.exit(1)


def to_docs(a, *files):
    """With --docs: the study's tables to docs/figures/data/, its figure to docs/figures/."""
    if not a.docs:
        return
    for f in files:
        dst = DOCS / ("data" if f.suffix == ".csv" else "") / f.name
        dst.parent.mkdir(parents=True, exist_ok=True)
        shutil.copy(f, dst)
        print(f"copied to {dst}", flush=True)


def linearised(a, p, curves, jac):
    """The linearised study of the p-parameter fit (poroplast_tools/coverage.linearised_fits):
    --linearised fits per noise model, printed and returned as rows, one per (noise model,
    parameter): the covered counts and rates, their binomial standard errors and Wilson
    intervals, the normalised errors' mean and sd, and the estimated noise scale over its truth
    (σ for absolute, the fraction for the relative ones, 1 for data; the experiments' mean)."""
    keys = a.case.fits[p][0]
    n = a.linearised
    rows = []
    print(f"\nlinearised model, {p}-parameter fit, {n} fits per noise model, {100 * a.noise_level:g}% noise "
          f"(relative+floor: a floor of {cov.FLOOR:g} × the relative noise at each curve's largest value):")
    print("| noise model | parameter | 68% covered | 95% covered | mean z | sd z | s / its truth |")
    print("|---|---|---|---|---|---|---|")
    for model in cov.NOISES:
        fits = cov.linearised_fits(curves, jac, model, a.noise_level, n, a.seed + p, a.start_factor, a.ftol, a.max_it)
        z = np.array([f["z"] for f in fits])
        truth = [cov.noise_sigmas(model, c, a.noise_level)[0][0] if model == "absolute" else
                 1.0 if model == "data" else a.noise_level for c in curves]
        ratio = float(np.mean([np.mean(np.array(f["s"]) / truth) for f in fits]))
        for k, key in enumerate(keys):
            row = {"params": p, "noise": model, "param": short(key), "fits": n}
            cells = []
            for name in cov.LEVELS:
                kk, _, frac, (lo, hi) = cov.rate([f[f"covered{name}"][k] for f in fits])
                se = math.sqrt(frac * (1 - frac) / n)
                row |= {f"covered{name}": kk, f"rate{name}": frac, f"se{name}": se,
                        f"wilson{name}_lo": lo, f"wilson{name}_hi": hi}
                cells.append(f"{kk}/{n} = {100 * frac:.1f} ± {100 * se:.1f}% [{100 * lo:.1f}, {100 * hi:.1f}]")
            row |= {"mean_z": float(z[:, k].mean()), "sd_z": float(z[:, k].std(ddof=1)), "s_over_truth": ratio}
            rows.append(row)
            print(f"| {model} | {short(key)} | {cells[0]} | {cells[1]} | {row['mean_z']:+.3f} | {row['sd_z']:.3f} | "
                  f"{ratio:.4f} |", flush=True)
    return rows


def table(rows, a):
    """Prints the coverage table; returns its entries, (p, key) -> {name: rate}."""
    out = {}
    print(f"\n| fit | parameter | n | 68% covered | 95% covered | mean z | sd z | runs per fit | s per fit |")
    print("|---|---|---|---|---|---|---|---|---|")
    for p in a.params:
        mine = [r for r in rows if r["params"] == p]
        if not mine:
            continue
        for k in a.case.fits[p][0]:
            s = short(k)
            rates = {name: cov.rate([r[f"{s}_covered{name}"] for r in mine]) for name in cov.LEVELS}
            out[p, k] = rates
            z = [r[f"{s}_z"] for r in mine]
            cells = []
            for name, (kk, n, frac, (lo, hi)) in rates.items():
                cells.append(f"{kk}/{n} = {100 * frac:.0f}% [{100 * lo:.0f}, {100 * hi:.0f}]"
                             + ("" if cov.on_target(name, frac) else " (off target)"))
            print(f"| {p} | {s} | {len(mine)} | {cells[0]} | {cells[1]} | {statistics.mean(z):+.2f} | "
                  f"{statistics.stdev(z) if len(z) > 1 else math.nan:.2f} | "
                  f"{statistics.median(r['runs'] for r in mine):.0f} | "
                  f"{statistics.median(r['seconds'] for r in mine):.1f} |")
    print("(coverage: covered/n = rate [Wilson 95% interval]; z = ln(estimate/truth) / (sigma/estimate), "
          "standard normal for honest intervals; targets 68 ± 10%, 95 ± 5%)")
    return out


def plot(path, rows, summary, a):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from statistics import NormalDist
    fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(11, 4.3))
    labels = []
    for (p, k), rates in summary.items():
        z = sorted(r[f"{short(k)}_z"] for r in rows if r["params"] == p)
        q = [NormalDist().inv_cdf((j + 0.5) / len(z)) for j in range(len(z))]
        ax1.plot(q, z, "o", ms=3, label=f"{p}-parameter fit: {short(k)}")
        labels.append(f"{p}p: {short(k)}")
    lim = 3.5
    ax1.plot([-lim, lim], [-lim, lim], "k-", lw=0.8, label="standard normal")
    ax1.set_xlabel("standard normal quantile")
    ax1.set_ylabel("(ln estimate − ln truth) / (σ / estimate), sorted")
    ax1.set_title("normalised errors")
    ax1.legend(fontsize=7)
    for m, name in enumerate(cov.LEVELS):
        nominal = 0.68 if name == "68" else 0.95
        ax2.axhspan(nominal - cov.TARGETS[name], min(nominal + cov.TARGETS[name], 1.0), color=f"C{m}", alpha=0.12)
        ax2.axhline(nominal, color=f"C{m}", lw=0.8)
        xs = np.arange(len(summary)) + (m - 0.5) * 0.15
        fr = [r[name][2] for r in summary.values()]
        lo = [r[name][2] - r[name][3][0] for r in summary.values()]
        hi = [r[name][3][1] - r[name][2] for r in summary.values()]
        ax2.errorbar(xs, fr, yerr=[lo, hi], fmt="o", color=f"C{m}", capsize=3, label=f"{name}% intervals")
    ax2.set_xticks(range(len(summary)))
    ax2.set_xticklabels(labels, fontsize=8)
    ax2.set_ylabel("fraction of fits whose interval holds the truth")
    n = max((r["68"][1] for r in summary.values()), default=0)
    ax2.set_title(f"coverage over {n} data sets (bands: targets; bars: Wilson 95%)")
    ax2.set_ylim(0.4, 1.02)
    ax2.legend(fontsize=7, loc="lower right")
    fig.suptitle(f"{a.case.about}, {a.level} level, {100 * a.noise_level:g}% noise, --noise {a.noise}", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


if __name__ == "__main__":
    main()
