"""The inverse question (issue 51, item 6): can any parameter set within physically plausible
bounds reproduce the paper's load-share claims? The claims are data (each an interval of the
paper's precision, poroplast_tools/inverse.py: CLAIMS), the parameters the paper leaves uncertain
or states ambiguously are fitted to them with the calibration's own Levenberg–Marquardt
(poroplast_tools/fit.py), and the cost profiled over one of them with the others re-fitted by the
same LM (fit.iterate, profile.py's engine).

Every point is four runs on the meridian at the shipped scenes' mesh and steps (the scene level;
its error against the converged references is the `level` stage): `remodel_155` to 80 s, its
c = 2 twin, its λp / 10 twin to 60 s, and `remodel_40` to 40 s with fields at 40 s.

Stages (each writes its CSV; the runs are kept in the case store DIR/cases, so a rerun replays
them):
  level    the Table 1 point at this level against references.csv's converged values:
           scripts/data/inverse_level.csv
  screen   one at a time: each parameter at its two bounds, each discrete choice on its own:
           scripts/data/inverse_screen.csv
  fit      LM from Table 1 over --params: scripts/data/inverse_fit.csv (parameters),
           inverse_claims.csv (each claim at Table 1 and at the optimum), inverse_iterations.csv
  profile  the cost at --profile-factors × Table 1's --profile-param, the other fitted
           parameters re-optimised (fit.py's LM): scripts/data/inverse_profile.csv; every point
           run by the screen, fit and profile (when all three run): scripts/data/inverse_points.csv
  check    the fitted point at the converged level beside this level: scripts/data/inverse_check.csv
  figure   docs/figures/inverse.png from the CSVs
  docs     the section's tables in docs/reproduction.md (between their markers) from the CSVs

    python3 scripts/inverse.py [--stages level screen fit profile figure docs] [--dir studies/inverse]
    python3 scripts/inverse.py --start fit # continue from inverse_fit.csv's optimum (after a claim's
                                           # interval changed) instead of Table 1
    python3 scripts/inverse.py --stages figure --probe k0=1.75,lambda_p=7.8   # a point of your own,
                                           # printed and added to inverse_points.csv
    python3 scripts/inverse.py --stages docs --rescore   # the committed points scored on today's claims
    python3 scripts/inverse.py --quick     # the Table 1 point and one neighbour, nothing written
"""
import argparse
import math
import sys
from pathlib import Path

import numpy as np

from poroplast_tools import inverse as inv
from poroplast_tools.cases import rank_options, run_cases, scene_values, use_rank_options
from poroplast_tools.history import history
from poroplast_tools.levels import CONVERGED_LEVEL, refined_steps
from poroplast_tools.fit import FitError, Search, fit, iterate, stats
from poroplast_tools.profile import conditional
from poroplast_tools.tables import read_rows, write_rows

ROOT = Path(__file__).resolve().parent
DATA = ROOT / "data"
FIGURES = ROOT.parent / "docs" / "figures"
REFERENCES = DATA / "references.csv"

# The observables the level stage compares, with their converged value in references.csv
# (case, observable), or a function of two of them.
def _ref(rows, case, obs):
    return float(next(r for r in rows if r["case"] == case and r["observable"] == obs)["extrapolated"])


LEVEL = {
    "peak_total": lambda R: _ref(R, "remodel_155", "max:force_total_mg"),
    "peak_constitutive": lambda R: _ref(R, "remodel_155", "max:force_constitutive_mg"),
    "t_cross": lambda R: _ref(R, "remodel_155", "zero:probe_p"),
    "p30": lambda R: _ref(R, "remodel_155", "probe_p@30"),
    "t_cross_c2": lambda R: _ref(R, "remodel_155_c2", "zero:probe_p"),
    "p30_c2": lambda R: _ref(R, "remodel_155_c2", "probe_p@30"),
    "p30_ratio": lambda R: _ref(R, "remodel_155_c2", "probe_p@30") / _ref(R, "remodel_155", "probe_p@30"),
    "d_peak_total": lambda R: _ref(R, "combined", "λp 1 → 0.1: total-force peak change (mg)"),
    "d_peak_constitutive": lambda R: _ref(R, "combined", "λp 1 → 0.1: constitutive-force peak change (mg)"),
    "vm_ratio": lambda R: _ref(R, "remodel_40", "vm_contact/centre@40"),
}
OBS = ["peak_total", "peak_constitutive", "share_constitutive", "share_pressure", "t_cross", "t_cross_c2", "p30",
       "p30_c2", "p30_ratio", "d_peak_total", "d_peak_constitutive", "vm_ratio"]


def row_of(name, what, values, obs, extra=None):
    row = {"point": name, "what": what, **{f"param {n}": values.get(n, p.table1) for n, p in inv.PARAMS.items()}}
    row.update({k: obs[k] for k in OBS})
    inv.scored(row, obs)
    row.update(extra or {})
    return row


def converged_share(root, ranks):
    """The constitutive and pressure shares of the peak force at the converged level (levels.py:
    the meridian at h = 10 µm, surface and poles 2 µm, no stabilisation, ⅛ of the steps; not in
    references.csv), from `remodel_155` run to 6 s: {observable: value}."""
    steps = [(k, f"{v:g}") for k, v in refined_steps(scene_values("remodel_155")["time"], {}, 0.125)]
    level = [tuple(s.split("=", 1)) for s in CONVERGED_LEVEL]
    [(d, r)] = run_cases("remodel_155", [steps + [("time.t_end", "6")]], level + inv.COMMON[1:], root, ranks)
    if r["status"] != "ok":
        sys.exit(f"inverse.py: the converged-level run failed: {r.get('error')}")
    f, fc, fp, _ = inv.peak(history(d))
    return {"share_constitutive": fc / f, "share_pressure": fp / f}


def stage_level(model, out):
    """The Table 1 point at this level against the converged references."""
    [(obs, _)] = model.run([{}])
    walls = dict(model.walls)
    refs = read_rows(REFERENCES)
    conv_share = converged_share(model.root, model.ranks)
    rows = []
    for k in OBS:
        conv = LEVEL[k](refs) if k in LEVEL else conv_share.get(k, math.nan)
        rows.append({"observable": k, "scene_level": obs[k], "converged": conv, "error": obs[k] - conv,
                     "relative_error": (obs[k] - conv) / conv if conv else math.nan})
    rows += [{"observable": f"wall_s {run}", "scene_level": w} for run, w in walls.items()]
    write_rows(out / "inverse_level.csv", rows, ["observable", "scene_level", "converged", "error", "relative_error"])
    for r in rows:
        print(f"{r['observable']:22} {r['scene_level']:10.4g} {r.get('converged', math.nan):10.4g} "
              f"{r.get('error', math.nan):+10.3g}")


def stage_check(args, out):
    """The fitted point (inverse_fit.csv) and Table 1 at the converged level (levels.py: the meridian
    at h = 10 µm, surface and poles 2 µm, no stabilisation, ⅛ of the steps; the remodel_155 runs
    to 60 s): inverse_check.csv, each claim's value and residual at both levels."""
    steps = [f"{k}={v:g}" for k, v in refined_steps(scene_values("remodel_155")["time"], {}, 0.125)]
    level = [tuple(s.split("=", 1)) for s in CONVERGED_LEVEL + steps]
    fitted = {r["param"]: float(r["fitted"]) / inv.PARAMS[r["param"]].paper_unit
              for r in read_rows(out / "inverse_fit.csv")}
    coarse = inv.Model([], args.dir, ranks=args.ranks)
    fine = inv.Model([], args.dir, sets=level, ranks=args.ranks, t_end=60)
    got = fine.run([fitted])
    [(obs_c, _)] = coarse.run([fitted])
    if got[0] is None:
        sys.exit("inverse.py: a run of the fitted point at the converged level failed")
    obs_f = got[0][0]
    rows = []
    for c in inv.CLAIMS:
        rows.append({"claim": c.id, "what": c.what, "scene_level": obs_c[c.observable],
                     "r_scene_level": c.residual(obs_c[c.observable]), "converged_level": obs_f[c.observable],
                     "r_converged_level": c.residual(obs_f[c.observable])})
    for k in ("peak_total", "peak_constitutive", "share_pressure"):
        rows.append({"claim": "", "what": k, "scene_level": obs_c[k], "converged_level": obs_f[k]})
    rc, rf = inv.claim_residuals(obs_c), inv.claim_residuals(obs_f)
    rows.append({"claim": "", "what": "cost (sum of r squared)", "scene_level": inv.cost(rc), "converged_level": inv.cost(rf)})
    rows.append({"claim": "", "what": "claims within the paper's precision", "scene_level": inv.reproduced(rc),
                 "converged_level": inv.reproduced(rf)})
    write_rows(out / "inverse_check.csv", rows)
    for r in rows:
        print(f"{r['claim']:5} {r['what']:45} {r['scene_level']:10.4g} {r['converged_level']:10.4g}")


def screen_points():
    """(name, what, values, extra overrides) of the one-at-a-time screen."""
    pts = [("table1", "Table 1 (the base)", {}, [])]
    for n, p in inv.PARAMS.items():
        for side, v in (("lo", p.lo), ("hi", p.hi)):
            pts.append((f"{n}_{side}", f"{n} = {v * p.paper_unit:g} {p.unit}".strip(), {n: v}, []))
    for n, (what, sets) in inv.CHOICES.items():
        pts.append((n, what, {}, sets))
    return pts


def stage_screen(model, out, points=None):
    pts = points or screen_points()
    got = model.run([v for _, _, v, _ in pts], extra=[e for _, _, _, e in pts])
    rows = []
    for (name, what, values, _), g in zip(pts, got):
        if g is None:
            rows.append({"point": name, "what": what, "cost": math.nan, "status": "failed"})
            continue
        rows.append(row_of(name, what, values, g[0], {"status": "ok"}))
    fields = list(next(r for r in rows if r.get("status") == "ok"))
    if out:
        write_rows(out / "inverse_screen.csv", rows, fields)
    ids = [c.id for c in inv.CLAIMS]
    print(f"{'point':20} " + " ".join(f"{i:>6}" for i in ids) + f" {'cost':>8} {'share_c':>8} {'peak':>7}")
    for r in rows:
        if r.get("status") != "ok":
            print(f"{r['point']:20} failed")
            continue
        print(f"{r['point']:20} " + " ".join(f"{r['r ' + i]:+6.2f}" for i in ids)
              + f" {r['cost']:8.2f} {r['share_constitutive']:8.3f} {r['peak_total']:7.2f}")
    return rows


def start_values(names, start, out):
    """The fit's start (scene units): Table 1's values, or ("fit") the optimum inverse_fit.csv holds,
    Table 1's for a parameter it did not fit."""
    values = {n: inv.PARAMS[n].table1 for n in names}
    if start == "fit":
        for r in read_rows(out / "inverse_fit.csv"):
            if r["param"] in values:
                values[r["param"]] = float(r["fitted"]) / inv.PARAMS[r["param"]].paper_unit
    return values


def stage_fit(names, args, out):
    model = inv.Model(names, args.dir, ranks=args.ranks)
    # A trial step outside the bounds runs at its projection onto them (as the profile's do): a
    # parameter that sits on its bound (κ at the ±5 s fit's optimum) would otherwise refuse every
    # step that pushes it out, and LM would stall with the others unmoved.
    model.project = True
    start = start_values(names, args.start, out)
    print("fit from " + ("Table 1" if args.start == "table1" else "inverse_fit.csv's optimum") + ": "
          + ", ".join(f"{n} = {start[n] * inv.PARAMS[n].paper_unit:.4g}" for n in names), flush=True)
    x0 = np.log([start[n] for n in names])
    opt = fit(model.evaluate, inv.weigh, x0, names, max_it=args.max_it, ftol=1e-3)
    st = stats(opt, estimated=False)
    values = model.values(opt.x)
    [(obs, _)] = model.run([values])
    [(obs0, _)] = model.run([{}])
    factors, far = inv.distance(values)
    prows = []
    for k, n in enumerate(names):
        p = inv.PARAMS[n]
        prows.append({"param": n, "key": p.key, "unit": p.unit, "table1": p.table1 * p.paper_unit,
                      "fitted": values[n] * p.paper_unit, "factor": factors[n], "lo": p.lo * p.paper_unit,
                      "hi": p.hi * p.paper_unit, "at_bound": _at_bound(values[n], p),
                      "sigma_log": st.rel[k], "bounds_why": p.why})
    write_rows(out / "inverse_fit.csv", prows)
    crows = []
    r0, r1 = inv.claim_residuals(obs0), inv.claim_residuals(obs)
    for c, a, b in zip(inv.CLAIMS, r0, r1):
        crows.append({"claim": c.id, "what": c.what, "paper": c.paper, "lo": c.lo, "hi": c.hi,
                      "precision": c.precision, "table1": obs0[c.observable], "r_table1": a,
                      "fitted": obs[c.observable], "r_fitted": b})
    for k in ("peak_total", "peak_constitutive", "share_pressure"):
        crows.append({"claim": "", "what": k, "table1": obs0[k], "fitted": obs[k]})
    crows.append({"claim": "", "what": "cost (sum of r squared)", "table1": inv.cost(r0), "fitted": inv.cost(r1)})
    crows.append({"claim": "", "what": "claims within the paper's precision", "table1": inv.reproduced(r0),
                  "fitted": inv.reproduced(r1)})
    crows.append({"claim": "", "what": "largest factor from Table 1 (log10)", "table1": 0.0, "fitted": far})
    write_rows(out / "inverse_claims.csv", crows)
    write_rows(out / "inverse_iterations.csv", [{"start": args.start, **r} for r in opt.log])
    print(f"optimum: cost {inv.cost(r1):.3g} (Table 1: {inv.cost(r0):.3g}), {inv.reproduced(r1)} of "
          f"{len(inv.CLAIMS)} claims within their precision; "
          + ", ".join(f"{n} = {values[n] * inv.PARAMS[n].paper_unit:.4g}" for n in names)
          + f"; {model.ran} runs made")
    return model, opt, st


def _at_bound(v, p):
    return "lo" if v <= p.lo * (1 + inv.SLACK) else "hi" if v >= p.hi * (1 - inv.SLACK) else ""


def parse_point(text):
    """A --probe point, "k0=1.5,lambda_p=7.8" (factors of Table 1's), as scene values."""
    values = {}
    for part in text.split(","):
        name, _, factor = part.partition("=")
        if name.strip() not in inv.PARAMS:
            sys.exit(f"inverse.py: --probe {text}: {name.strip()!r} is not a parameter (one of {', '.join(inv.PARAMS)})")
        try:
            values[name.strip()] = float(factor) * inv.PARAMS[name.strip()].table1
        except ValueError:
            sys.exit(f"inverse.py: --probe {text}: {factor!r} is not a number")
    return values


def probe(texts, root, ranks):
    """The --probe points, run and printed: the Model's log (for inverse_points.csv)."""
    model = inv.Model([], root, ranks=ranks)
    points = [parse_point(t) for t in texts]
    for t, g in zip(texts, model.run(points)):
        if g is None:
            print(f"probe {t}: a run failed")
            continue
        r = inv.claim_residuals(g[0])
        print(f"probe {t}: cost {inv.cost(r):.4g}, constitutive share {g[0]['share_constitutive']:.3f}, peak "
              f"{g[0]['peak_total']:.2f} mg; r " + " ".join(f"{c.id} {x:+.2f}" for c, x in zip(inv.CLAIMS, r)))
    return model.log


def rescore(out):
    """inverse_screen.csv and inverse_points.csv scored again on today's CLAIMS (inv.rescored)."""
    for name in ("inverse_screen.csv", "inverse_points.csv"):
        rows = read_rows(out / name)
        fields = list(rows[0])
        new = inv.rescored(rows)
        fields += [k for k in new[0] if k not in fields]
        write_rows(out / name, new, fields)
        print(f"{name}: {len(new)} rows scored on today's claims")


def merge_points(path, new):
    """inverse_points.csv with the rows `new` (this run's points) added, a point run before
    (inv.point_key) replaced by this run's."""
    keys = {inv.point_key(r) for r in new}
    old = [r for r in inv.rescored(read_rows(path)) if inv.point_key(r) not in keys]
    write_rows(path, old + new, list(new[0]))
    print(f"{path.name}: {len(new)} points of this run beside {len(old)} committed")


def stage_profile(model, opt, names, which, factors, max_it, out):
    """The profile of the cost over `which` at `factors` × its Table 1 value: at each, the other
    fitted parameters re-optimised by fit.py's LM (`iterate`, the engine of profile.py; all grid
    points in step, each iteration's neighbours one sweep), each from the better of two starts
    as in profile.py: where the linearisation at the optimum puts them (profile.conditional,
    held within the bounds) and the optimum's values kept. profile.py's own walk stops
    at the 95% threshold, a rise of 3.84; this one goes to the bound, because the question is how
    far the cost rises where the constitutive share passes 0.5. A point is "converged" when an
    iteration lowers its cost by less than 0.1% (the main fit's rule), else "unconverged" after
    `max_it` iterations: its cost is then an upper bound of the profile."""
    k = names.index(which)
    p = inv.PARAMS[which]
    # Refused trial steps stall LM here (its steps leave the bounds along ν and σy): a point
    # outside is run at its projection onto the bounds instead.
    model.project = True
    starts, labels = [], []
    for f in factors:
        delta = math.log(f * p.table1) - opt.x[k]
        guess = conditional(opt, k, delta)
        for j, n in enumerate(names):
            guess[j] = min(max(guess[j], math.log(inv.PARAMS[n].lo)), math.log(inv.PARAMS[n].hi))
        kept = opt.x.copy()
        kept[k] += delta
        starts += [guess, kept]
        labels += [f"profile of {which} × {f:g}: start (linearised)", f"profile of {which} × {f:g}: start (the others kept)"]
    got = model.evaluate(starts, labels)
    # A parameter the fit left at a bound stays there (its bound is active: along it the cost is
    # flat or rising, and LM's steps in a flat direction leave the bounds).
    values = model.values(opt.x)
    free = [j for j, n in enumerate(names) if j != k and not _at_bound(values[n], inv.PARAMS[n])]
    searches = []
    for i, f in enumerate(factors):     # each point from the better of its two starts (as profile.py)
        tried = [(float(g[0] @ (opt.w ** 2 * g[0])), x, g) for x, g in zip(starts[2 * i:2 * i + 2], got[2 * i:2 * i + 2])
                 if g is not None]
        if not tried:
            continue
        _, x, g = min(tried, key=lambda t: t[0])
        searches.append(Search(x.copy(), g[0], g[1], free, f"profile of {which} × {f:g}"))
    iterate(model.evaluate, searches, opt.w, names, max_it, ftol=1e-3, xtol=1e-5, max_trials=6)
    rows = []
    for s in [None] + searches:
        x = opt.x if s is None else s.x
        model.project = True              # every point as it ran: projected onto the bounds (the fit's too)
        values = model.values(x)
        obs = next(o for v, _, o in reversed(model.log) if all(abs(v.get(n, math.nan) / values[n] - 1) < 1e-12 for n in names))
        r = inv.claim_residuals(obs)
        status = "optimum" if s is None else "failed" if s.failed else "converged" if s.converged else "unconverged"
        rows.append({"param": which, "factor": values[which] / p.table1, "value": values[which] * p.paper_unit,
                     "cost": inv.cost(r), "rise": inv.cost(r) - opt.cost, "status": status,
                     **{f"at {n}": values[n] * inv.PARAMS[n].paper_unit for n in names},
                     **{o: obs[o] for o in OBS}, **{f"r {c.id}": v for c, v in zip(inv.CLAIMS, r)}})
    rows.sort(key=lambda r: r["factor"])
    write_rows(out / "inverse_profile.csv", rows)
    for r in rows:
        print(f"{which} × {r['factor']:.3g}: cost {r['cost']:.4g} ({r['status']}), constitutive share "
              f"{r['share_constitutive']:.3f}, peak {r['peak_total']:.2f} mg")
    return rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dir", type=Path, default=Path("studies/inverse"))
    ap.add_argument("--stages", nargs="+", default=["level", "screen", "fit", "profile", "check", "figure", "docs"],
                    choices=["level", "screen", "fit", "profile", "check", "figure", "docs"])
    ap.add_argument("--params", nargs="+", default=["k0", "lambda_p", "sigma_y", "c", "nu", "kappa"],
                    choices=list(inv.PARAMS), help="the parameters fitted")
    ap.add_argument("--max-it", type=int, default=10)
    ap.add_argument("--start", choices=["table1", "fit"], default="table1",
                    help="the fit's start: Table 1 (default), or the optimum scripts/data/inverse_fit.csv holds "
                         "(to continue a fit after a claim's interval changed)")
    ap.add_argument("--rescore", action="store_true",
                    help="score the committed screen and points CSVs again on today's claims (no run)")
    ap.add_argument("--profile-param", default="k0", choices=list(inv.PARAMS))
    ap.add_argument("--profile-factors", default="1.5,2,3",
                    help="the profiled parameter's values, as factors of Table 1's (default 1.5,2,3: where the constitutive share passes 0.5)")
    ap.add_argument("--profile-max-it", type=int, default=4)
    ap.add_argument("--probe", action="append", default=[], metavar="NAME=FACTOR,...",
                    help="also run this point (parameters as factors of Table 1's, the others at Table 1's) "
                         "and add it to inverse_points.csv; repeatable")
    ap.add_argument("--quick", action="store_true", help="the Table 1 point and k0 × 2 at this level, "
                    "printed, nothing written (a test of the pipeline)")
    rank_options(ap)
    a = ap.parse_args()
    if "profile" in a.stages and a.profile_param not in a.params:
        sys.exit(f"inverse.py: --profile-param {a.profile_param} is not fitted: add it to --params "
                 f"({' '.join(a.params)})")
    try:
        factors = [float(f) for f in a.profile_factors.split(",")]
    except ValueError:
        sys.exit(f"inverse.py: --profile-factors {a.profile_factors}: expected numbers separated by commas, e.g. 3,10")
    if not all(f > 0 for f in factors):
        sys.exit(f"inverse.py: --profile-factors {a.profile_factors}: the factors must be positive")
    needs = {"check": "inverse_fit.csv", "figure": "inverse_screen.csv", "docs": "inverse_screen.csv"}
    for stage, name in needs.items():
        made = {"inverse_fit.csv": "fit", "inverse_screen.csv": "screen"}[name]
        if stage in a.stages and made not in a.stages and not (DATA / name).exists():
            sys.exit(f"inverse.py: the {stage} stage needs scripts/data/{name}: run the {made} stage first "
                     f"(--stages {made} {stage})")
    use_rank_options(a)
    a.dir.mkdir(parents=True, exist_ok=True)
    try:
        if a.quick:
            stage_screen(inv.Model([], a.dir, ranks=a.ranks), None,
                         [("table1", "Table 1", {}, []), ("k0_x2", "k0 × 2", {"k0": 2 * inv.PARAMS["k0"].table1}, [])])
            return
        logs = []        # every point run by the stages: inverse_points.csv
        if "level" in a.stages:
            stage_level(inv.Model([], a.dir, ranks=a.ranks), DATA)
        if "screen" in a.stages:
            m = inv.Model([], a.dir, ranks=a.ranks)
            stage_screen(m, DATA)
            logs.append(m.log)
        if "fit" in a.stages or "profile" in a.stages:
            model, opt, st = stage_fit(a.params, a, DATA)
            logs.append(model.log)
            if "profile" in a.stages:
                stage_profile(model, opt, a.params, a.profile_param, factors, a.profile_max_it, DATA)
        if a.probe:
            logs.append(probe(a.probe, a.dir, a.ranks))
        if a.rescore:
            rescore(DATA)
        if "screen" in a.stages and "profile" in a.stages:   # every point of the screen, fit and profile
            rows = inv.point_rows([e for log in logs for e in log])
            write_rows(DATA / "inverse_points.csv", rows)
        elif logs and (DATA / "inverse_points.csv").exists():   # the new points beside the committed ones
            merge_points(DATA / "inverse_points.csv", inv.point_rows([e for log in logs for e in log]))
        if "check" in a.stages:
            stage_check(a, DATA)
        if "figure" in a.stages:
            from poroplast_tools.inverse_report import figure
            figure(DATA, FIGURES / "inverse.png")
        if "docs" in a.stages:
            from poroplast_tools.inverse_report import write_tables
            page = ROOT.parent / "docs" / "reproduction.md"
            page.write_text(write_tables(page.read_text(encoding="utf-8"), DATA), encoding="utf-8")
            print(f"{page}: the inverse tables written")
    except FitError as e:
        sys.exit(f"inverse.py: {e}")


if __name__ == "__main__":
    main()
