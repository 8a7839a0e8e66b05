"""Calibration: fit scene parameters to a measured curve by least squares over batch runs.

Levenberg–Marquardt on the residuals r_i = model(t_i) − data(t_i) (the model's history column
interpolated at the data's times), the Jacobian by forward differences (one run per parameter,
relative step 1e-3), parameters in log space (they are positive and of different scales). The
uncertainties are the square roots of the diagonal of s² (JᵀJ)⁻¹, s² = Σr²/(n − p), at the
optimum. Every run is a `poroplast run --set ...` on 2 ranks (`--ranks`) in STUDY/runs/.

    python3 scripts/calibrate.py remodel_40 --data measured.csv --column force_total_mg \\
        --param material.remodelling.lambda_p=0.001 --param material.remodelling.sigma_y=2.0 \\
        --dir studies/calib [--set KEY=VALUE ...] [--t-min 0 --t-max 40] [--max-it 15]

`--data`: a CSV with columns `time` and the value (named like --column, or `value`). A
synthetic curve for testing the fit: `--synthetic KEY=VALUE ...` runs the scene with those
values first and fits to its own history.
"""
import argparse
import csv
import json
import math
import subprocess
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _runner import BIN, env  # noqa: E402


class Model:
    def __init__(self, a, keys):
        self.a, self.keys, self.n = a, keys, 0
        self.root = Path(a.dir)

    def history(self, values, tag=None):
        """Runs the scene with the parameter values; returns (time, column) lists."""
        self.n += 1
        out = self.root / "runs" / (tag or f"run{self.n:03d}")
        cmd = ["mpirun", "-n", str(self.a.ranks), str(BIN), "run", self.a.scene, "--out", str(out), "--force", "-q"]
        for s in self.a.set:
            cmd += ["--set", s]
        for k, v in zip(self.keys, values):
            cmd += ["--set", f"{k}={v!r}"]
        p = subprocess.run(cmd, env=env(), stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if p.returncode != 0:
            err = next((l for l in p.stderr.splitlines() if l.startswith("poroplast: error:")), p.stderr[-300:])
            raise RuntimeError(f"run with {dict(zip(self.keys, values))} failed: {err}")
        rows = list(csv.DictReader(open(out / "history.csv")))
        return [float(r["time"]) for r in rows], [float(r[self.a.column]) for r in rows]


def interp(ts, vs, t):
    for i in range(1, len(ts)):
        if ts[i - 1] <= t <= ts[i]:
            w = (t - ts[i - 1]) / (ts[i] - ts[i - 1]) if ts[i] > ts[i - 1] else 1.0
            return vs[i - 1] + w * (vs[i] - vs[i - 1])
    raise ValueError(f"t = {t} outside the run ({ts[0]}..{ts[-1]})")


def solve(a, b):
    """Solves the small dense system a x = b (Gaussian elimination, partial pivoting)."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        piv = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[piv] = m[piv], m[c]
        if m[c][c] == 0:
            raise ZeroDivisionError("singular normal equations")
        for r in range(c + 1, n):
            f = m[r][c] / m[c][c]
            for k in range(c, n + 1):
                m[r][k] -= f * m[c][k]
    x = [0.0] * n
    for r in reversed(range(n)):
        x[r] = (m[r][n] - sum(m[r][k] * x[k] for k in range(r + 1, n))) / m[r][r]
    return x


def inverse(a):
    n = len(a)
    cols = [solve(a, [1.0 if i == j else 0.0 for i in range(n)]) for j in range(n)]
    return [[cols[j][i] for j in range(n)] for i in range(n)]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--param", action="append", required=True, metavar="KEY=INITIAL")
    ap.add_argument("--column", required=True, help="history.csv column to fit (e.g. force_total_mg)")
    ap.add_argument("--data", help="CSV with time and the measured value")
    ap.add_argument("--synthetic", action="append", default=[], metavar="KEY=VALUE",
                    help="fit to the scene's own curve with these values (a test of the fit)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--t-min", type=float, default=-math.inf)
    ap.add_argument("--t-max", type=float, default=math.inf)
    ap.add_argument("--dir", required=True)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--max-it", type=int, default=15)
    a = ap.parse_args()
    keys = [p.split("=", 1)[0] for p in a.param]
    x = [math.log(float(p.split("=", 1)[1])) for p in a.param]
    model = Model(a, keys)
    Path(a.dir).mkdir(parents=True, exist_ok=True)

    if a.synthetic:
        truth = dict(s.split("=", 1) for s in a.synthetic)
        syn = Model(a, list(truth))
        td, vd = syn.history([float(v) for v in truth.values()], tag="synthetic")
    elif a.data:
        rows = list(csv.DictReader(open(a.data)))
        col = a.column if a.column in rows[0] else "value"
        td, vd = [float(r["time"]) for r in rows], [float(r[col]) for r in rows]
    else:
        sys.exit("calibrate.py: give --data or --synthetic")
    data = [(t, v) for t, v in zip(td, vd) if a.t_min <= t <= a.t_max and t > 0]
    if len(data) <= len(keys):
        sys.exit(f"calibrate.py: {len(data)} data points for {len(keys)} parameters")

    def residuals(xs):
        ts, vs = model.history([math.exp(v) for v in xs])
        return [interp(ts, vs, t) - v for t, v in data]

    r = residuals(x)
    cost = sum(v * v for v in r)
    lam, h = 1e-2, 1e-3
    log = []
    for it in range(a.max_it):
        jac = []
        for k in range(len(x)):
            xp = x[:]
            xp[k] += h
            rp = residuals(xp)
            jac.append([(b - c) / h for b, c in zip(rp, r)])  # column k
        jtj = [[sum(jac[i][m] * jac[j][m] for m in range(len(r))) for j in range(len(x))] for i in range(len(x))]
        jtr = [sum(jac[i][m] * r[m] for m in range(len(r))) for i in range(len(x))]
        improved = False
        while lam < 1e8:
            a_mat = [[jtj[i][j] * (1 + lam if i == j else 1) for j in range(len(x))] for i in range(len(x))]
            step = solve(a_mat, [-g for g in jtr])
            xt = [xi + si for xi, si in zip(x, step)]
            rt = residuals(xt)
            ct = sum(v * v for v in rt)
            if ct < cost:
                x, r, cost, lam, improved = xt, rt, ct, lam / 3, True
                break
            lam *= 4
        vals = {k: math.exp(v) for k, v in zip(keys, x)}
        log.append({"iteration": it + 1, "cost": cost, **vals})
        print(f"iteration {it + 1}: rms {math.sqrt(cost / len(r)):.4g}  " + "  ".join(f"{k} = {v:.6g}" for k, v in vals.items()), flush=True)
        if not improved or max(abs(s) for s in step) < 1e-5:
            break
    # Uncertainties at the optimum, from the last Jacobian (log parameters: relative errors).
    dof = max(len(r) - len(x), 1)
    s2 = cost / dof
    try:
        cov = inverse(jtj)
        rel = [math.sqrt(max(cov[i][i] * s2, 0.0)) for i in range(len(x))]
    except ZeroDivisionError:
        rel = [math.nan] * len(x)
    result = {k: {"value": math.exp(v), "sigma": math.exp(v) * e} for k, v, e in zip(keys, x, rel)}
    result["rms"] = math.sqrt(cost / len(r))
    result["runs"] = model.n
    (Path(a.dir) / "calibration.json").write_text(json.dumps({"result": result, "log": log}, indent=1))
    for k in keys:
        print(f"{k} = {result[k]['value']:.6g} ± {result[k]['sigma']:.2g}")
    print(f"rms residual {result['rms']:.3g}, {model.n} runs; {Path(a.dir) / 'calibration.json'}")


if __name__ == "__main__":
    main()
