"""Least squares over an abstract model: Levenberg–Marquardt, the noise's re-weighting, and the
statistics of the optimum (standard errors, Wald intervals; the profile likelihood is
poroplast_tools/profile.py, whose inner fits are this module's `iterate`).

The model is `evaluate(points, what, replay=None)`: a batch of points (arrays of the fitted
variables, log-parameters in the calibration) to a list with, per point, (d, state) — d the
differences model − data at the data points, `state` what the run leaves that the next batch may
replay (the calibration: its histories, whose time steps its finite-difference neighbours take) —
or None for a failed run. `what` names each point (printed by the model); `replay` is one state
for every point or a list, one per point. One call is one batch (the calibration: one `poroplast
sweep`).

The LM loop (`iterate`) moves several `Search`es in step, each with its own free variables and
damping: one iteration's finite-difference neighbours of all of them are one batch, their trial
steps one more. The main fit (`fit`) is one search of all variables; the profile's inner fits
are one search per profile point, of all variables but the profiled one.

The noise is `weigh(d, p)`: the per-point weights w that give w d unit variance at the
differences d of a fit of p parameters (poroplast_tools/fitstats.Noise per curve, stacked; a
relative noise's σ_i is a fraction of the model's value there). LM minimises |w d|² with w
fixed; at its optimum the weights are estimated anew, and where they changed other than by a
common factor (a relative noise: the model moved from the start; several curves, each its own
σ; a noise floor) the fit goes on from there with them, until they settle (`rounds`:
iteratively re-weighted least squares, whose fixed point is unbiased where weights by the data
are not: fitstats). A common factor leaves the optimum where it is: one curve with one unknown
absolute σ needs one round.

The statistics (`stats`) linearise at the optimum: the covariance of the variables is (JᵀJ)⁻¹
with J the Jacobian of w d (unit variance), the Wald interval x̂ ± z σ with z Student's t of
n − p degrees of freedom when w was estimated from the residuals, the normal z when σ was given
(fitstats.quantile)."""
import math
from dataclasses import dataclass, field

import numpy as np

from .fitstats import quantile

LEVELS = {"68": math.erf(1 / math.sqrt(2)), "95": 0.95}   # one σ (68.27%) and 95%


class FitError(Exception):
    """A run the fit cannot do without failed (the start point, a finite-difference neighbour)."""


@dataclass
class Optimum:
    x: np.ndarray            # the fitted variables
    d: np.ndarray            # differences model − data there
    state: object            # the model's state there (replayed by its neighbours)
    w: np.ndarray            # the noise weights estimated there (unit variance)
    jac: np.ndarray          # d d / d x there (unweighted)
    log: list = field(default_factory=list)   # one entry per LM iteration

    @property
    def r(self):
        return self.w * self.d

    @property
    def cost(self):
        return float(self.r @ self.r)


@dataclass
class Search:
    """One least-squares search of Levenberg–Marquardt: the variables `free` of x move, the
    others stay (the main fit: all free; a profile point: all but the profiled one)."""
    x: np.ndarray
    d: np.ndarray
    state: object
    free: list
    name: str = ""                    # its runs' labels begin with it
    lam: float = 1e-2                 # the damping
    jac: np.ndarray = None            # d d / d x[free] at jac_at (unweighted)
    jac_at: np.ndarray = None
    its: int = 0                      # iterations done (over all calls of `iterate`)
    done: bool = False
    converged: bool = False           # stopped by a tolerance (not by max_it, a failure, giving up)
    failed: bool = False              # a finite-difference run failed

    def label(self, what):
        return f"{self.name + ', ' if self.name else ''}iteration {self.its + 1}: {what}"


def forward_jacobians(evaluate, searches, keys, what=None, h=1e-3):
    """d d / d x[free] of every search at its x by forward differences: the neighbours x + h e_k
    of all searches ONE batch, each replaying its search's state. A search one of whose
    neighbours failed is marked failed (jac None). `what`: the label (default: the iteration's)."""
    eye = np.eye(len(searches[0].x)) if searches else None
    points, labels, replay, owner = [], [], [], []
    for s in searches:
        for k in s.free:
            points.append(s.x + h * eye[k])
            labels.append(f"{what}: d {keys[k]}" if what else s.label(f"d {keys[k]}"))
            replay.append(s.state)
            owner.append(s)
    got = evaluate(points, labels, replay) if points else []
    for s in searches:
        cols = [out for out, o in zip(got, owner) if o is s]
        if any(c is None for c in cols):
            s.jac, s.failed, s.done = None, True, True
        else:
            s.jac = np.column_stack([(dk - s.d) / h for dk, _ in cols])
        s.jac_at = s.x.copy()


def iterate(evaluate, searches, w, keys, max_it, ftol=0.0, xtol=1e-5, atol=None, max_trials=None,
            after=None, on_jacobian=None):
    """Levenberg–Marquardt iterations of every search with the weights w, all searches in step:
    each iteration's finite-difference neighbours of all searches still iterating are one batch
    (`forward_jacobians`), their trial steps one more (and one per round of retries). Damping λ
    on diag(JᵀJ), λ/3 after an accepted step, ×4 after a worse or failed trial (at most
    `max_trials` trials, λ < 1e8); an iteration ends after one accepted step. A search stops,
    converged, when an accepted step lowers its cost by less than `ftol` (relative) or moves x
    by less than `xtol` (max norm), or, with `atol`, when the Gauss–Newton step at its current
    Jacobian predicts a decrease below `atol` (absolute: the profile needs the cost, not the
    point; checked once more after the last of `max_it` iterations); unconverged after `max_it`
    iterations of this call, when no trial lowers the cost, or when a run fails. `after(search, cost)` sees each iteration's end; `on_jacobian(search)` each
    new Jacobian."""
    for s in searches:
        s.done = s.converged = False
    count = 0
    while True:
        active = [s for s in searches if not s.done]
        if not active:
            return
        if count >= max_it and atol is None:
            for s in active:
                s.done = True
            return
        forward_jacobians(evaluate, [s for s in active if s.jac_at is None or not np.array_equal(s.jac_at, s.x)],
                          keys)
        pending = []
        for s in active:
            if s.failed:
                continue
            if on_jacobian:
                on_jacobian(s)
            wj, r = w[:, None] * s.jac, w * s.d
            if atol is not None and _predicted_decrease(wj, r) < atol:
                s.done = s.converged = True
                continue
            pending.append(s)
        if count >= max_it:             # with atol: the last point's Jacobian checked, no more steps
            for s in pending:
                s.done = True
            return
        count += 1
        trials = {id(s): 0 for s in pending}
        moved = {}
        while pending:
            steps = []
            for s in pending:
                wj, r = w[:, None] * s.jac, w * s.d
                jtj = wj.T @ wj
                step = np.zeros_like(s.x)
                damped = jtj + s.lam * np.diag(np.diag(jtj))
                try:
                    step[s.free] = np.linalg.solve(damped, -(wj.T @ r))
                except np.linalg.LinAlgError:   # a variable that moves nothing here: no step along it
                    step[s.free] = np.linalg.lstsq(damped, -(wj.T @ r), rcond=None)[0]
                steps.append(step)
            out = evaluate([s.x + step for s, step in zip(pending, steps)],
                           [s.label(f"trial step, damping {s.lam:.3g}") for s in pending])
            still = []
            for s, step, trial in zip(pending, steps, out):
                cost, tcost = _cost(w, s.d), math.inf if trial is None else _cost(w, trial[0])
                trials[id(s)] += 1
                if tcost < cost:
                    s.x, (s.d, s.state), s.lam = s.x + step, trial, s.lam / 3
                    moved[id(s)] = (1 - tcost / cost, np.max(np.abs(step)))
                    continue
                s.lam *= 4
                if s.lam < 1e8 and (max_trials is None or trials[id(s)] < max_trials):
                    still.append(s)
            pending = still
        for s in active:
            if s.failed or s.converged:
                continue
            s.its += 1
            if after:
                after(s, _cost(w, s.d))
            if id(s) not in moved:
                s.done = True           # no trial lowered the cost
                continue
            gain, size = moved[id(s)]
            if size < xtol or gain < ftol:
                s.done = s.converged = True


def _cost(w, d):
    r = w * d
    return float(r @ r)


def _predicted_decrease(wj, r):
    """The cost decrease the undamped Gauss–Newton step predicts: |r projected on J's columns|²."""
    coef = np.linalg.lstsq(wj, r, rcond=None)[0]
    proj = wj @ coef
    return float(proj @ proj)


def fit(evaluate, weigh, x0, keys, max_it=15, ftol=1e-3, xtol=1e-5, rounds=6, say=print,
        first_jacobian=None):
    """The optimum (`Optimum`) of |w d(x)|² from x0 (variables named `keys`): the iterations of
    one `Search` of all variables (`iterate`: LM, stopping when an iteration lowers the cost by
    less than `ftol` (relative), moves x by less than `xtol` (max norm), or after `max_it`
    iterations), then re-weighting (see the module). `first_jacobian(jac, state)` sees the
    start's Jacobian (the identifiability report)."""
    x = np.asarray(x0, dtype=float)
    [start] = evaluate([x], ["the start point"])
    if start is None:
        raise FitError("the run at the initial parameters failed")
    s = Search(x, start[0], start[1], list(range(len(x))))
    w = weigh(s.d, len(x))
    log = []

    def after(s, cost):
        log.append({"iteration": len(log) + 1, "cost": cost, **{k: math.exp(v) for k, v in zip(keys, s.x)}})
        say(f"iteration {len(log)}: weighted rms {math.sqrt(cost / len(s.d)):.4g} (residual / sigma)  "
            + "  ".join(f"{k} = {math.exp(v):.6g}" for k, v in zip(keys, s.x)))

    def on_jacobian(s):
        if first_jacobian and not log:
            first_jacobian(s.jac, s.state)

    for rnd in range(rounds):
        iterate(evaluate, [s], w, keys, max_it, ftol, xtol, after=after, on_jacobian=on_jacobian)
        if s.failed:
            raise FitError(f"a finite-difference run ({s.label('')[:-2]}) failed")
        new = weigh(s.d, len(x))
        ratio = new / w
        w = new
        if np.ptp(ratio) <= 0.02 * np.mean(ratio):   # a common factor: the optimum stays
            break
        say(f"the noise weights changed by up to {100 * (np.max(ratio) / np.min(ratio) - 1):.3g}% "
            "between the data points: fitting on with the new ones")
    if not np.array_equal(s.jac_at, s.x):
        forward_jacobians(evaluate, [s], keys, "at the optimum")
        if s.failed:
            raise FitError("a finite-difference run (at the optimum) failed")
    return Optimum(s.x, s.d, s.state, w, s.jac, log)


@dataclass
class Stats:
    rel: np.ndarray          # standard errors of the variables (relative errors of log-parameters)
    corr: np.ndarray         # their correlation matrix
    dof: int                 # n − p
    estimated: bool          # σ estimated from the residuals (t quantiles) or given (normal)
    chi2: float              # |w d|² / (n − p)

    def z(self, level):
        return quantile(level, self.dof if self.estimated else None)

    def wald(self, x, level):
        """[lo, hi] of each parameter exp(x) at `level`: exp(x ± z σ), NaN where σ is; an end
        beyond the floats (an unidentified parameter's σ of hundreds in log space) is 0 or inf."""
        z = self.z(level)
        return [[_exp(v - z * e), _exp(v + z * e)] if math.isfinite(e) else [math.nan, math.nan]
                for v, e in zip(x, self.rel)]


def stats(opt, estimated):
    """The statistics of the optimum `opt` (`estimated`: whether its weights were estimated from
    the residuals)."""
    wj = opt.w[:, None] * opt.jac
    n, p = wj.shape
    dof = max(n - p, 1)
    try:
        cov = np.linalg.inv(wj.T @ wj)
        rel = np.sqrt(np.maximum(np.diag(cov), 0.0))
        with np.errstate(invalid="ignore", divide="ignore"):
            corr = cov / np.outer(rel, rel)
    except np.linalg.LinAlgError:
        rel, corr = np.full(p, math.nan), np.full((p, p), math.nan)
    return Stats(rel, corr, dof, estimated, opt.cost / dof)


def _exp(v):
    """exp(v), inf where it overflows."""
    return math.exp(v) if v < 709.0 else math.inf
