"""Profile-likelihood intervals of a fit's parameters: for each parameter θ_k on a grid about the
optimum, the others re-optimised (the profile), and the interval where the cost has risen by z².

The grid: x_k = x̂_k ± m σ_k (m in `multiples`, σ_k the standard error). With one parameter
there is nothing to re-optimise: every grid point is one run, all ONE batch. With more, each
side of each parameter walks outward from the optimum (continuation): at grid point m the others
start from the better of two runs, the previous point's optimum extrapolated along the path (the
first point: the linearisation at the optimum, `conditional`) and the previous point's optimum
unchanged; from there `fit.iterate` re-optimises them (LM, the same code as the main fit), the
points of all sides still walking in step, each inner iteration's finite-difference neighbours
of all of them one batch (each replaying its own point's steps) and their trial steps one more.
An inner fit is converged when the Gauss–Newton step at its last Jacobian predicts a cost
decrease below `atol` (0.02: the 95% end moves by < 0.3% of its distance from the optimum, the
68% end by < 1%); after `max_it` steps without that it is flagged unconverged. A side stops once
its cost rise reaches the 95% threshold (or an inner fit fails); where √rise jumps by more than
z95 from the last point below the threshold to the first above (a flat stretch and then a wall,
as along the yield stress's ridge: the linear interpolation would put the end too close), that
bracket is bisected, continuing from the point below, at most `REFINE` times per side.

Honesty: a side whose crossing point's inner fit did not converge (or failed) has no end (None,
`why` "unconverged"/"failed"): its cost there is only an upper bound of the profile, the interval
could be longer. A side the grid never takes over the threshold has none either (`why` "grid").
If a profile point's cost is below the optimum's (the fit stopped early on a flat ridge), the
rises are taken from that lowest cost and `Profile.lower` says where it was."""
import math
from dataclasses import dataclass

import numpy as np

from .fit import LEVELS, Search, _cost, iterate

MULTIPLES = (1, 2, 3, 4.5, 6)      # the default grid, in standard errors
ATOL = 0.02
REFINE = 3          # bisections of a side's crossing bracket where √rise jumps by more than z95


@dataclass
class Profile:
    curves: dict           # per key: delta, cost, status ("ok", "unconverged", "failed"), intervalNN, whyNN
    cost0: float           # the cost the rises are taken from (the least found)
    lower: tuple = None    # (key, delta, cost) where a profile point beat the optimum by > atol

    def __getitem__(self, key):
        return self.curves[key]


def conditional(opt, k, delta):
    """The point with variable k at x̂_k + delta and the others where the linearisation at the
    optimum puts their minimum: δ_o = −J_o⁺ (r̂ + J_k δ) (weighted J and r)."""
    wj = opt.w[:, None] * opt.jac
    others = [j for j in range(len(opt.x)) if j != k]
    x = opt.x.copy()
    x[k] += delta
    if others:
        x[others] -= np.linalg.lstsq(wj[:, others], opt.r + wj[:, k] * delta, rcond=None)[0]
    return x


def profile(evaluate, opt, st, keys, multiples=MULTIPLES, max_it=4, atol=ATOL, say=print):
    """The `Profile` of every variable with a finite standard error (see the module); the
    weights are the optimum's."""
    ms = sorted(set(abs(m) for m in multiples if m))
    ks = [k for k in range(len(keys)) if math.isfinite(st.rel[k]) and st.rel[k] > 0]
    rows = {k: [] for k in ks}                        # (delta, cost, status)
    if len(keys) == 1:
        grid = [(k, s * m * st.rel[k]) for k in ks for s in (-1, 1) for m in ms]
        got = evaluate([opt.x + np.eye(1)[k] * d for k, d in grid],
                       [f"profile of {keys[k]}: {d:+.3g}" for k, d in grid])
        for (k, d), out in zip(grid, got):
            rows[k].append((d, math.inf, "failed") if out is None else (d, _cost(opt.w, out[0]), "ok"))
    else:
        _walk(evaluate, opt, st, keys, ks, ms, rows, max_it, atol, say)
    found = [(c, k, d) for k in ks for d, c, status in rows[k] if status == "ok"]
    least = min(found, default=(math.inf, None, None))
    cost0 = min(opt.cost, least[0])
    lower = (keys[least[1]], least[2], least[0]) if least[0] < opt.cost - atol else None
    curves = {}
    for k in ks:
        curve = {"delta": [d for d, _, _ in rows[k]], "cost": [c for _, c, _ in rows[k]],
                 "status": [s for _, _, s in rows[k]]}
        for name, level in LEVELS.items():
            curve[f"interval{name}"], curve[f"why{name}"] = interval(opt.x[k], cost0, rows[k], st.z(level))
        curves[keys[k]] = curve
    return Profile(curves, cost0, lower)


def _walk(evaluate, opt, st, keys, ks, ms, rows, max_it, atol, say, refine=REFINE):
    """The continuation outward on both sides of every variable in ks, all sides in step: each
    side goes to the next grid multiple until its rise passes the 95% threshold; where √rise
    jumps by more than z95 between the last point below and the point above (a flat stretch, then
    a wall: the linear interpolation would put the end too close), the bracket is bisected, at
    most `refine` times per side."""
    z95 = max(st.z(level) for level in LEVELS.values())
    sides = [{"k": k, "sign": sign, "path": [(0.0, 0.0, opt.x.copy(), 0.0)], "next": ms[0], "above": None,
              "refined": 0} for k in ks for sign in (-1, 1)]
    while True:
        walking = [s for s in sides if s["next"] is not None]
        if not walking:
            return
        points, labels, owner = [], [], []
        for side in walking:
            k, m = side["k"], side["next"]
            delta = side["sign"] * m * st.rel[k]
            side["delta"] = delta
            _, d1, x1, _ = side["path"][-1]
            if len(side["path"]) == 1:
                guess = conditional(opt, k, delta)
            else:
                _, d0, x0, _ = side["path"][-2]
                guess = x1 + (x1 - x0) * (delta - d1) / (d1 - d0)
            kept = x1.copy()
            kept[k] = opt.x[k] + delta
            guess[k] = kept[k]
            side["name"] = name = f"profile of {keys[k]} {side['sign'] * m:+g} sigma"
            for x, how in ((guess, "start (extrapolated)"), (kept, "start (the previous point's others)")):
                points.append(x)
                labels.append(f"{name}: {how}")
                owner.append(side)
        got = evaluate(points, labels)
        searches = []
        for side in walking:
            starts = [(_cost(opt.w, out[0]), x, out) for x, out, o in zip(points, got, owner)
                      if o is side and out is not None]
            if not starts:
                rows[side["k"]].append((side["delta"], math.inf, "failed"))
                side["next"] = None
                continue
            _, x, (d, state) = min(starts, key=lambda t: t[0])
            search = Search(x.copy(), d, state, [j for j in range(len(keys)) if j != side["k"]], side["name"])
            side["search"] = search
            searches.append(search)
        iterate(evaluate, searches, opt.w, keys, max_it, ftol=0.0, xtol=1e-7, atol=atol, max_trials=4)
        for side in walking:
            search = side.pop("search", None)
            if search is None:
                continue
            m, cost = side["next"], _cost(opt.w, search.d)
            status = "failed" if search.failed else "ok" if search.converged else "unconverged"
            rows[side["k"]].append((side["delta"], cost, status))
            say(f"{side['name']}: cost rise {cost - opt.cost:.3g}"
                + ("" if status == "ok" else f" ({status}: the others' re-optimisation did not finish)"))
            root = math.sqrt(max(cost - opt.cost, 0.0))
            if search.failed:
                side["next"] = None
                continue
            if root < z95:
                side["path"].append((m, side["delta"], search.x.copy(), root))
                if side["above"] is None:
                    side["next"] = next((g for g in ms if g > m), None)
                    continue
            else:
                side["above"] = (m, root)
            (m_lo, _, _, r_lo), (m_hi, r_hi) = side["path"][-1], side["above"]
            if r_hi - r_lo > z95 and side["refined"] < refine:
                side["next"], side["refined"] = (m_lo + m_hi) / 2, side["refined"] + 1
            else:
                side["next"] = None


def interval(x, cost0, rows, z):
    """([lo, hi] in exp(x), [why_lo, why_hi]): on each side of x the δ where the signed root
    ±√(cost − cost0) of the profile (rows of (δ, cost, status)) reaches z, interpolated linearly
    from the last point below it (exact for a linear model; an unconverged point below it
    too: the crossing lies beyond a point whose upper bound is below z). None where the grid does
    not reach it (why "grid") or where the point that reaches it is not converged ("unconverged",
    "failed": its cost is only an upper bound of the profile)."""
    ends, whys = [], []
    for sign in (-1, 1):
        side = sorted([(abs(d), c, s) for d, c, s in rows if d * sign > 0], key=lambda t: t[0])
        prev = (0.0, 0.0)
        end, why = None, "grid"
        for a, c, status in side:
            root = math.sqrt(max(c - cost0, 0.0)) if math.isfinite(c) else math.inf
            if status != "ok" and root >= z:
                why = status
                break
            # An unconverged point below the threshold counts too: its cost is an upper bound of
            # the profile, so the crossing lies beyond it.
            if root >= z:
                a0, r0 = prev
                end, why = a0 + (a - a0) * (z - r0) / (root - r0) if root > r0 else a, None
                break
            prev = (a, max(prev[1], root))
        ends.append(None if end is None else math.exp(x + sign * end))
        whys.append(why)
    return ends, whys
