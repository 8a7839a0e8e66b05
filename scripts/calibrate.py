"""Calibration: fit scene parameters to a measured curve by least squares over batch runs.

Levenberg–Marquardt on the residuals r_i = model(t_i) − data(t_i) (the model's history column
interpolated at the data's times), the Jacobian by forward differences (one run per parameter,
relative step 1e-3) whose runs take the point's own time steps (`time.steps`: a step cut or an
error rejection in one run and not in the other would make the difference jump), parameters in log space (they are positive and of different scales). A
trial step whose run fails counts as a worse fit (more damping). The residuals are weighted by
the noise model (--noise: absolute, relative, or each point's sigma from the data file;
poroplast_tools/fitstats.py); the standard errors are the square roots of the diagonal of
s² (JᵀJ)⁻¹ with J at the optimum (its own finite-difference runs if the last step moved it),
printed with the correlations, s (the estimated noise level) or χ²/(n − p) (a stated sigma).
Before the first step the start point's sensitivities are printed, near-collinear parameter
pairs warned of, and a parameter that moves no data point refused (poroplast_tools/identify.py).
Every run is a case
of the case store STUDY/runs/cases/ (`poroplast sweep`: a completed one is not run again, so an
interrupted calibration continues): each iteration's n finite-difference neighbours are one
batch (the point is the last accepted trial, complete; the first iteration runs it first),
one `mpirun -n RANKS poroplast sweep` (--ranks 2, --ranks-per-case K: 1 on a meridian, RANKS
for 3-D), and each trial step one more; `--no-sweep` runs one mpirun per run, `--jobs N` of them
at once. STUDY/calibration.png shows the data and the fitted curve. The fit
stops when an iteration lowers the sum of squares by less than `--ftol` (default 0.1%), when
its step is below 1e-5 (log space), or after `--max-it` iterations.

    python3 scripts/calibrate.py remodel_40 --data measured.csv --column force_total_mg \\
        --param material.remodelling.lambda_p=0.001 --param material.remodelling.sigma_y=2.0 \\
        --dir studies/calib [--set KEY=VALUE ...] [--t-min 0 --t-max 40] [--max-it 15]

`--data`: a CSV file, the format of poroplast_tools/measured.py (docs/user-guide.md): a header
line, `time` in s and the value, a force in mg, uN or nN (`force_uN`, or --data-unit), lines
starting with # comments; a malformed file is refused with the problem and its line. A
synthetic curve for testing the fit: `--synthetic KEY=VALUE ...` runs the scene with those
values first and fits to its own history.
"""
import argparse
import json
import math
import sys
import threading
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from poroplast_tools import labels
from poroplast_tools.cases import rank_options, run_cases, use_rank_options
from poroplast_tools.history import at, given_steps, history
from poroplast_tools.fitstats import MODELS as NOISE_MODELS, uncertainty, weights
from poroplast_tools.identify import report as identifiability
from poroplast_tools.measured import DataError, check_within, read_curve


class Model:
    def __init__(self, a, keys):
        self.a, self.keys = a, keys
        self.counts = {"ran": 0}       # the runs the sweeps had to make
        self.lock = threading.Lock()
        self.root = Path(a.dir) / "runs"
        self.sets = [tuple(s.split("=", 1)) for s in a.set]

    @property
    def n(self):
        return self.counts["ran"]

    def histories(self, points, what=None, steps=None):
        """Runs the scene at each point (parameter values) — ONE batch, the completed runs
        skipped (the store knows a run by its values), so an interrupted calibration continues —
        and returns their histories (None for a failed run). `what`: a name per point, printed
        before the batch; `steps`: the `time.steps` every run takes (None: its own)."""
        given = [("time.steps", steps)] if steps else []
        cases = [[(k, repr(v)) for k, v in zip(self.keys, values)] + given for values in points]
        for name, case in zip(what or [], cases):
            print(f"{name}: " + " ".join(f"{k}={v}" for k, v in case[:len(self.keys)])
                  + (" (the point's steps)" if steps else ""), flush=True)
        counts = {}
        ran = run_cases(self.a.scene, cases, self.sets, self.root, self.a.ranks, counts=counts)
        with self.lock:
            self.counts["ran"] += counts.get("ran", 0)
        return [history(d) if r["status"] == "ok" else None for d, r in ran]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--param", action="append", required=True, metavar="KEY=INITIAL")
    ap.add_argument("--column", required=True, help="history.csv column to fit (e.g. force_total_mg)")
    ap.add_argument("--data", help="CSV with time and the measured value (see the format above)")
    ap.add_argument("--data-column", help="the data's column (default: found from --column's name)")
    ap.add_argument("--data-unit", choices=["mg", "uN", "nN"],
                    help="the data's force unit (default: the column name's suffix, else mg)")
    ap.add_argument("--synthetic", action="append", default=[], metavar="KEY=VALUE",
                    help="fit to the scene's own curve with these values (a test of the fit)")
    ap.add_argument("--noise", choices=NOISE_MODELS,
                    help="the noise model (poroplast_tools/fitstats.py): one unknown sigma (absolute), sigma "
                         "proportional to the value (relative), or each point's sigma from the data file (data); "
                         "default: data if the file has a sigma column, else absolute")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--t-min", type=float, default=-math.inf)
    ap.add_argument("--t-max", type=float, default=math.inf)
    ap.add_argument("--dir", required=True)
    rank_options(ap)
    ap.add_argument("--max-it", type=int, default=15)
    ap.add_argument("--jobs", type=int, default=1, help="with --no-sweep: finite-difference runs at once")
    ap.add_argument("--ftol", type=float, default=1e-3,
                    help="stop when an iteration lowers the sum of squares by less than this fraction")
    a = ap.parse_args()
    sweep = use_rank_options(a)["sweep"]
    keys = [p.split("=", 1)[0] for p in a.param]
    x = [math.log(float(p.split("=", 1)[1])) for p in a.param]
    model = Model(a, keys)
    Path(a.dir).mkdir(parents=True, exist_ok=True)

    if a.synthetic:
        truth = dict(s.split("=", 1) for s in a.synthetic)
        syn = Model(a, list(truth))
        [h] = syn.histories([[float(v) for v in truth.values()]], ["synthetic curve"])
        if h is None:
            sys.exit("calibrate.py: the synthetic run failed")
        td, vd, sd = h["time"], h[a.column], None
    elif a.data:
        try:
            td, vd, sd = read_curve(a.data, a.column, a.data_unit, a.data_column)
        except DataError as e:
            sys.exit(f"calibrate.py: {e}")
    else:
        sys.exit("calibrate.py: give --data or --synthetic")
    kept = [(t, v, None if sd is None else sd[i]) for i, (t, v) in enumerate(zip(td, vd))
            if a.t_min <= t <= a.t_max and t > 0]
    data = [(t, v) for t, v, _ in kept]
    if len(data) <= len(keys):
        sys.exit(f"calibrate.py: {len(data)} data points for {len(keys)} parameters")
    noise = a.noise or ("data" if sd is not None else "absolute")
    try:
        w = weights(noise, [v for _, v in data], None if sd is None else [e for _, _, e in kept])
    except ValueError as e:
        sys.exit(f"calibrate.py: --noise {noise}: {e}")

    def residuals(points, what, steps=None):
        """The residuals and history of a run at each point (log-parameters), one batch, each
        run taking `steps` if given; (None, None) for a failed run. Without sweeps and with
        --jobs N, N runs at a time."""
        vals = [[math.exp(v) for v in xs] for xs in points]
        if sweep or a.jobs == 1:
            hs = model.histories(vals, what, steps)
        else:
            with ThreadPoolExecutor(max_workers=a.jobs) as pool:
                hs = [h for [h] in pool.map(lambda vw: model.histories([vw[0]], [vw[1]], steps), zip(vals, what))]
        return [(None, None) if h is None else (w * np.array([at(h, a.column, t) - v for t, v in data]), h)
                for h in hs]

    def jacobian(x, r, it, hist):
        """d r / d x at x (residuals r, history hist) by forward differences: x's neighbours
        x + h e_k, one batch, taking the steps of x's run."""
        shifted = residuals([x + h * np.eye(len(x))[k] for k in range(len(x))],
                            [f"iteration {it}: d {k}" for k in keys], given_steps(hist))
        if any(rk is None for rk, _ in shifted):
            sys.exit(f"calibrate.py: a finite-difference run ({it}) failed (see its log under runs/)")
        return np.column_stack([(rk - r) / h for rk, _ in shifted])

    def identifiable(jac, hist):
        """Prints the sensitivity table at the start point and the near-collinear pairs; exits
        naming every parameter that moves no data point."""
        scale = math.sqrt(sum(v * v for _, v in data) / len(data))
        lines, refusals, warnings = identifiability(jac, keys, scale)
        print("\n".join(lines), flush=True)
        for msg in warnings:
            print(f"calibrate.py: warning: {msg}", flush=True)
        if refusals:
            def why(k):
                vm = hist.get("max_von_mises") if k.endswith("lambda_p") else None
                return (f" (remodelling flows only where the von Mises stress exceeds sigma_y: its largest value "
                        f"in this run is {max(vm):.4g} kPa; is sigma_y above it?)") if vm is not None and len(vm) else ""
            sys.exit("calibrate.py: " + "; ".join(
                f"{k} has no effect on {a.column} at the data's times (a {100 * h:g}% change moved no data point): "
                f"it cannot be identified from these data{why(k)}" for k in refusals))

    x = np.array(x)
    lam, h = 1e-2, 1e-3
    log = []
    # The point of each iteration: the start, then the last accepted trial (r, best).
    [(r, best)] = residuals([x], ["the start point"])
    if r is None:
        sys.exit("calibrate.py: the run at the initial parameters failed")
    if a.data:
        try:
            check_within(a.data, [t for t, _ in data], float(best["time"][-1]))
        except DataError as e:
            sys.exit(f"calibrate.py: {e}")
    cost = float(r @ r)
    for it in range(a.max_it):
        jac, jac_at = jacobian(x, r, it + 1, best), x.copy()
        if it == 0:
            identifiable(jac / w[:, None], best)   # in the data's units
        jtj, jtr = jac.T @ jac, jac.T @ r
        improved = False
        while lam < 1e8:
            step = np.linalg.solve(jtj + lam * np.diag(np.diag(jtj)), -jtr)
            [(rt, ht)] = residuals([x + step], [f"iteration {it + 1}: trial step, damping {lam:.3g}"])
            if rt is not None and float(rt @ rt) < cost:
                gain = 1 - float(rt @ rt) / cost
                x, r, best, cost, lam, improved = x + step, rt, ht, float(rt @ rt), lam / 3, True
                break
            lam *= 4
        vals = {k: math.exp(v) for k, v in zip(keys, x)}
        log.append({"iteration": it + 1, "cost": cost, **vals})
        print(f"iteration {it + 1}: rms {math.sqrt(cost / len(r)):.4g}  "
              + "  ".join(f"{k} = {v:.6g}" for k, v in vals.items()), flush=True)
        if not improved or np.max(np.abs(step)) < 1e-5 or gain < a.ftol:
            break
    # Uncertainties from the Jacobian at the optimum (the last accepted step moved x: once more
    # there), in log parameters: relative errors.
    if not np.array_equal(jac_at, x):
        jac = jacobian(x, r, "at the optimum", best)
    rel, corr, s2, chi2 = uncertainty(jac, r, noise)
    result = {k: {"value": math.exp(v), "sigma": math.exp(v) * float(e)} for k, v, e in zip(keys, x, rel)}
    result["noise"] = {"model": noise, "s": math.sqrt(s2), "chi2_per_dof": chi2}
    result["correlation"] = {"keys": keys, "matrix": [[float(c) for c in row] for row in corr]}
    result["rms"] = math.sqrt(cost / len(r))
    result["runs"] = model.n
    (Path(a.dir) / "calibration.json").write_text(json.dumps({"result": result, "log": log}, indent=1))
    for k in keys:
        print(f"{k} = {result[k]['value']:.6g} ± {result[k]['sigma']:.2g} (one standard error)")
    print({"absolute": f"noise model: absolute, sigma estimated from the residuals: {math.sqrt(s2):.3g}",
           "relative": f"noise model: relative, sigma/value estimated from the residuals: {math.sqrt(s2):.3g}",
           "data": f"noise model: each point's sigma from the data file; chi2 per degree of freedom {chi2:.3g} "
                   "(near 1 if the model and the stated sigma fit)"}[noise])
    if len(keys) > 1:
        print("correlations: " + "; ".join(f"{keys[i]} ~ {keys[j]}: {corr[i, j]:+.3f}"
                                             for i in range(len(keys)) for j in range(i + 1, len(keys))))
    plot(a, data, best, result, keys)
    print(f"rms residual {result['rms']:.3g}, {model.n} runs; {Path(a.dir) / 'calibration.json'}")


def plot(a, data, h, result, keys):
    """STUDY/calibration.png: the data and the fitted run's curve."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6.4, 4.2))
    ax.plot(h["time"], h[a.column], "-", label="fit: " + ", ".join(
        labels.value(k, result[k]['value']) for k in keys))
    ax.plot([t for t, _ in data], [v for _, v in data], "o", ms=3, label="data")
    ax.set_xlabel("t (s)")
    ax.set_ylabel(labels.column(a.column))
    ax.set_title(f"{a.scene}: rms residual {result['rms']:.3g}")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(Path(a.dir) / "calibration.png", dpi=120)
    plt.close(fig)


if __name__ == "__main__":
    main()
