"""The inverse question (issue 51, item 6): the paper's quantitative load-share claims treated as
data, each an interval the paper's words allow, and the model's parameters the paper leaves
uncertain fitted to them by the project's own least squares (fit.py, profile.py).

A claim is an interval [lo, hi] of one observable (the paper's value ± its precision, or the
range its words give: "mostly constitutive" is a constitutive share in [0.5, 1]); its residual is
r = (v − mid) / half, v the observable (its log10 for an order-of-magnitude claim), mid and half
the interval's centre and half-width, so that |r| ≤ 1 is "within the paper's precision" and
Σ r² is the fit's cost (fit.py's `data` noise: the weights 1/half are given, not estimated).

A parameter point is four runs of the shipped scenes on the meridian (`RUNS`): `remodel_155`
(the isotropic case: the syringe crossing, p(X_U, 30 s), the peaks and their split), the same
with the remodelling-dependent permeability (c, k0 scaled as the paper's Fig 11 scales it), the
same with λp / 10 (the λp 1 → 0.1 peak changes, as the paper's Figs 7b-8b) and `remodel_40` (σ_VM
after the release, from its fields at 40 s). `observables` reads them; `claim_residuals` turns
them into r. `Model.evaluate` is fit.py's model: a batch of points is one `poroplast sweep`, and a
finite-difference neighbour replays its point's time steps (runmodel.py does the same)."""
import math
from dataclasses import dataclass

import numpy as np

from . import claims, fields
from .cases import run_cases
from .history import at, given_steps, history


@dataclass(frozen=True)
class Claim:
    id: str            # the claims table's row (scripts/data/claims.csv)
    what: str
    observable: str    # a key of `observables`' dict
    paper: float       # the paper's number, in the observable's unit
    lo: float          # the interval the paper's words allow (in the observable's unit)
    hi: float
    log: bool = False  # the residual in log10 (an order of magnitude)
    precision: str = ""

    def bounds(self):
        """(mid, half) of the interval, in the residual's space (log10 for `log`)."""
        lo, hi = (math.log10(self.lo), math.log10(self.hi)) if self.log else (self.lo, self.hi)
        return (lo + hi) / 2, (hi - lo) / 2

    def residual(self, value):
        """(v − mid) / half: |r| ≤ 1 within the claim's interval; NaN where v is not a number
        (or not positive for a log claim)."""
        if value is None or not math.isfinite(value) or (self.log and value <= 0):
            return math.nan
        mid, half = self.bounds()
        return ((math.log10(value) if self.log else value) - mid) / half


# The claims. A claim with a number takes its value and precision from its row of claims.csv (the
# quote's printed number by claims.py's rule: half a unit of its last printed digit; an order of
# magnitude a factor √10 either way), the quote `quote` of the row where it quotes two (P56's
# first: the c = 2 crossing itself, not its difference from the isotropic one). P35's words give
# no number: "mostly constitutive" is a share in [0.5, 1].
def from_claims(id, what, observable, quote=0, rows=None):
    """The Claim of claims.csv's row `id` on `observable`: its (quote-th) quote's number ± precision."""
    row = next((r for r in (rows or claims.load()) if r["id"] == id), None)
    if row is None:
        raise ValueError(f"inverse: claims.csv has no row {id}")
    said = claims.quotes(row["precision_note"])
    if quote >= len(said):
        raise ValueError(f"inverse: claims.csv's {id} quotes the paper {len(said)} times, not {quote + 1}")
    value, precision = claims.printed(said[quote])
    if isinstance(precision, str):    # a factor: "×F"
        factor = float(precision[1:])
        return Claim(id, what, observable, value, value / factor, value * factor, log=True,
                     precision=f'"{said[quote]}": within a factor {factor:g} of {value:g}')
    return Claim(id, what, observable, value, value - precision, value + precision,
                 precision=f'"{said[quote]}": ±{precision:g}')


def _claims():
    rows = claims.load()
    return [
        Claim("P35", "constitutive share of the peak force", "share_constitutive", 0.5, 0.5, 1.0,
              precision='"mostly constitutive": more than half, [0.5, 1]'),
        from_claims("P9", "syringe crossing of p(X_U) (s)", "t_cross", rows=rows),
        from_claims("P56", "c = 2: crossing of p(X_U) (s)", "t_cross_c2", rows=rows),
        from_claims("P58", "c = 2 over isotropic, p(X_U, 30 s)", "p30_ratio", rows=rows),
        from_claims("P38", "λp 1 → 0.1: constitutive-peak change (mg)", "d_peak_constitutive", rows=rows),
        from_claims("P39", "λp 1 → 0.1: total-peak change (mg)", "d_peak_total", rows=rows),
        from_claims("P23b", "σ_VM contact zones over centre at 40 s", "vm_ratio", rows=rows),
    ]


CLAIMS = _claims()


def claim_residuals(obs, claims=CLAIMS):
    """The residual of every claim (a list, in `claims`' order) from the observables `obs`."""
    return [c.residual(obs.get(c.observable)) for c in claims]


def cost(residuals):
    """Σ r² (NaN where a residual is)."""
    return float(sum(r * r for r in residuals))


def reproduced(residuals):
    """How many claims lie within their interval (|r| ≤ 1)."""
    return sum(1 for r in residuals if math.isfinite(r) and abs(r) <= 1.0)


# ------------------------------------------------------------------ the parameters

@dataclass(frozen=True)
class Param:
    name: str          # the CSV's name
    key: str           # the scene key
    table1: float      # Table 1's value (the scene's unit)
    lo: float          # the physically plausible bounds (the scene's unit)
    hi: float
    paper_unit: float  # factor from the scene's unit to the unit printed
    unit: str
    why: str           # why these bounds


PARAMS = {p.name: p for p in [
    Param("k0", "material.k0", 3.7729, 0.37729, 37.729, 1e-3, "mm⁴/(N s)",
          "a decade either side of Table 1 (the paper itself runs 2.58e-4 to 3.77e-3)"),
    Param("kappa", "material.kappa", 4.638, 0.05, 6.0, 1.0, "",
          "Table 1's κ and its M (0.0848: the two exponents the other way round), ×1.3 and ×0.6"),
    Param("m0", "material.m0", 0.0848, 0.05, 6.0, 1.0, "",
          "Table 1's M and its κ (4.638), ×0.6 and ×1.3"),
    Param("lambda_p", "material.remodelling.lambda_p", 0.001, 0.0001, 0.01, 1e3, "(MPa s)⁻¹",
          "the paper's own range (0.1-1) and a decade faster"),
    Param("sigma_y", "material.remodelling.sigma_y", 2.0, 0.5, 8.0, 1.0, "kPa", "the paper's 1-4 kPa, ×2 wider"),
    Param("c", "material.permeability_c", 2.0, 0.5, 8.0, 1.0, "", "Fig 11's c ~ 2 (fitted by the paper), ×4"),
    Param("nu", "material.nu", 0.2, 0.05, 0.3, 1.0, "",
          "below 1/3, where the law stays elliptic at 30% compression (docs/model.md)"),
]}

# The discrete choices the paper states ambiguously, each as scene overrides (the base: (40b),
# a drained settling under gravity, the scene's fading stabilisation, Table 1's κ and M,
# impermeable plates).
CHOICES = {
    "form_40a": ("(40a)'s flow rule (the rate with the 1/J factor)", [("material.remodelling.form", '"40a"')]),
    "no_settling": ("no settling (gravity off)", [("material.gravity", "[0.0, 0.0, 0.0]")]),
    "stabilisation_off": ("no pressure stabilisation", [("fem.stabilisation", "0")]),
    "exponents_swapped": ("Table 1's κ and M the other way round (κ = 0.0848, M = 4.638)",
                          [("material.kappa", "0.0848"), ("material.m0", "4.638")]),
    "plates_permeable": ("permeable plates: Table 1's k_β through 1 µm",
                         [("plates.permeability", "3.7729e-4"), ("plates.thickness", "1")]),
}

K0_C2 = 2.5779 / 3.7729   # Fig 11's k0 over Table 1's: the c = 2 case's k0 follows k0 by this factor


# ------------------------------------------------------------------ the runs and observables

# name -> (scene, overrides); the parameters are added per point (`case`)
COMMON = [("mesh.geometry", "axisymmetric"), ("output.fields", "false"), ("output.fields_at", "[]")]
RUNS = {
    "iso": ("remodel_155", [("time.t_end", "80")]),
    "c2": ("remodel_155", [("time.t_end", "80")]),
    "lam": ("remodel_155", [("time.t_end", "60")]),
    "r40": ("remodel_40", [("time.t_end", "40"), ("output.fields", "true"), ("output.fields_every", "100000"),
                           ("output.fields_at", "[40.0]")]),
}


def case_values(run, values):
    """The parameter overrides of `run` at `values` ({name: value} of PARAMS, scene units): the c = 2
    run takes k0 × K0_C2 and c, the λp run λp / 10, the others ignore c."""
    v = dict(values)
    out = []
    for name, p in PARAMS.items():
        if name not in v:
            continue
        x = v[name]
        if name == "c":
            if run != "c2":
                continue
        elif name == "k0" and run == "c2":
            x = x * K0_C2
        elif name == "lambda_p" and run == "lam":
            x = x / 10
        out.append((p.key, repr(float(x))))
    if run == "c2" and "c" not in v:
        out.append((PARAMS["c"].key, repr(PARAMS["c"].table1)))
    if run == "c2" and "k0" not in v:
        out.append((PARAMS["k0"].key, repr(PARAMS["k0"].table1 * K0_C2)))
    if run == "lam" and "lambda_p" not in v:
        out.append((PARAMS["lambda_p"].key, repr(PARAMS["lambda_p"].table1 / 10)))
    return out


def crossing(t, p, after=5.0):
    """The first time after `after` at which p falls from above zero to zero or below (linear
    between rows); NaN if it does not."""
    for i in range(1, len(t)):
        if t[i] > after and p[i - 1] > 0 >= p[i]:
            return float(t[i - 1] + (t[i] - t[i - 1]) * p[i - 1] / (p[i - 1] - p[i]))
    return math.nan


def peak(h, until=60.0):
    """(largest total force, constitutive and pressure forces at it, largest constitutive force)
    up to `until` s."""
    m = h["time"] <= until + 1e-9
    i = int(np.argmax(h["force_total_mg"][m]))
    return (float(h["force_total_mg"][m][i]), float(h["force_constitutive_mg"][m][i]),
            float(h["force_pressure_mg"][m][i]), float(np.max(h["force_constitutive_mg"][m])))


def observables(hs, vm_ratio):
    """The claims' observables from the histories {run: history} of one point and its σ_VM ratio."""
    iso, c2, lam = hs["iso"], hs["c2"], hs["lam"]
    f, fc, fp, fc_max = peak(iso)
    lf, _, _, lfc_max = peak(lam)
    t_c, t_c2 = crossing(iso["time"], iso["probe_p"]), crossing(c2["time"], c2["probe_p"])
    p30, p30_c2 = at(iso, "probe_p", 30.0), at(c2, "probe_p", 30.0)
    return {"peak_total": f, "peak_constitutive": fc_max, "share_constitutive": fc / f, "share_pressure": fp / f,
            "t_cross": t_c, "t_cross_c2": t_c2, "p30": p30, "p30_c2": p30_c2,
            "p30_ratio": p30_c2 / p30 if p30 else math.nan,
            "d_peak_total": lf - f, "d_peak_constitutive": lfc_max - fc_max, "vm_ratio": vm_ratio}


SLACK = 2e-3    # a finite-difference neighbour (log step 1e-3) of a point on a bound stays in


class Model:
    """fit.py's model: points in log space of the parameters `names`, each the four RUNS with
    `sets` (the level, the choices) after COMMON; one batch one sweep in the case store `root`."""

    def __init__(self, names, root, sets=(), ranks=2, base=None, t_end=None):
        self.names, self.root, self.sets, self.ranks = list(names), root, list(sets), ranks
        self.t_end = t_end               # the remodel_155 runs' end (s), if not RUNS' own
        self.project = False             # a point outside the bounds: refused (a failed step), or run at its projection
        self.base = dict(base or {})     # the values of the parameters not fitted (scene units)
        self.ran = 0
        self.walls = {}                  # the last point's runs' wall times (s), as their sweep measured them
        self.log = []                    # every point run: (values, its own overrides, observables)

    def values(self, x):
        if self.project:     # the point's projection onto the bounds
            return {**self.base, **{n: min(max(math.exp(min(v, 700.0)), PARAMS[n].lo), PARAMS[n].hi)
                                    for n, v in zip(self.names, x)}}
        # a wild LM trial (a flat direction) can reach any log value: clipped, it is refused as outside
        return {**self.base, **{n: math.exp(min(max(v, -700.0), 700.0)) for n, v in zip(self.names, x)}}

    def outside(self, values):
        """The parameters of `values` outside their bounds (by more than a finite-difference step)."""
        return [n for n, v in values.items() if not PARAMS[n].lo * (1 - SLACK) <= v <= PARAMS[n].hi * (1 + SLACK)]

    def run(self, points, replay=None, extra=None):
        """The observables and state (None: a run failed) of every point ({name: value}), one
        sweep; `replay` a list of states whose steps each point's runs take (None: their own),
        `extra` a list of each point's own overrides (a CHOICES entry's). A run whose overrides
        are its replayed state's (a neighbour in c moves only the c = 2 run) is not run again:
        its history is the state's. The state: {"values", "histories", "vm_ratio"}."""
        replay = replay or [None] * len(points)
        extra = extra or [[]] * len(points)
        scenes, cases, slots = [], [], []
        for j, (values, rp, more) in enumerate(zip(points, replay, extra)):
            for run, (scene, own) in RUNS.items():
                if self.t_end and scene == "remodel_155":
                    own = [(k, str(self.t_end) if k == "time.t_end" else v) for k, v in own]
                if rp and case_values(run, values) == case_values(run, rp["values"]):
                    continue
                steps = [("time.steps", given_steps(rp["histories"][run]))] if rp else []
                scenes.append(scene)
                cases.append(own + list(more) + case_values(run, values) + steps)
                slots.append((j, run))
        counts = {}
        done = run_cases(scenes, cases, COMMON + self.sets, self.root, self.ranks, counts=counts) if cases else []
        self.ran += counts.get("ran", 0)
        got = dict(zip(slots, done))
        out = []
        for j, rp in enumerate(replay):
            group = {run: got.get((j, run)) for run in RUNS}
            if any(g is not None and g[1]["status"] != "ok" for g in group.values()):
                out.append(None)
                continue
            hs = {run: history(g[0]) if g else rp["histories"][run] for run, g in group.items()}
            vm = fields.zone_ratio(group["r40"][0], "von_mises", 40.0) if group["r40"] else rp["vm_ratio"]
            self.walls = {run: g[1].get("wall_s", math.nan) for run, g in group.items() if g}
            obs = observables(hs, vm)
            self.log.append((points[j], list(extra[j]), obs))
            out.append((obs, {"values": points[j], "histories": hs, "vm_ratio": vm}))
        return out

    def evaluate(self, points, what, replay=None):
        """fit.py's model: per point (d, state) with d = r × half (model − mid, unweighted), or None."""
        replays = replay if isinstance(replay, list) else [replay] * len(points)
        vals = [self.values(x) for x in points]
        todo = [j for j, v in enumerate(vals) if not self.outside(v)]
        for j, (w, v) in enumerate(zip(what, vals)):
            bad = self.outside(v)
            print(f"{w}: " + " ".join(f"{n}={v[n]:.5g}" for n in self.names)
                  + (f": not run, {', '.join(bad)} outside the bounds (a failed step)" if bad else ""), flush=True)
        got = self.run([vals[j] for j in todo], [replays[j] for j in todo])
        out = [None] * len(points)
        for j, g in zip(todo, got):
            if g is None:
                continue
            obs, state = g
            r = claim_residuals(obs)
            if not all(math.isfinite(x) for x in r):
                continue
            d = np.array([ri * c.bounds()[1] for ri, c in zip(r, CLAIMS)])
            out[j] = (d, {**state, "x": np.array(points[j])})
        return out


def weigh(d, p):
    """The claims' weights 1 / half (given, fit.py's `data` noise)."""
    return np.array([1.0 / c.bounds()[1] for c in CLAIMS])


def distance(values):
    """Each parameter's factor from Table 1 (value / Table 1's) and the largest |log10| of them."""
    factors = {n: v / PARAMS[n].table1 for n, v in values.items()}
    return factors, max((abs(math.log10(f)) for f in factors.values()), default=0.0)


def point_rows(log):
    """One row per distinct point of Model logs (values, own overrides, observables): its parameters,
    observables, residuals, cost, and the cost of the claims other than P35 (`cost_others`)."""
    rows, seen = [], set()
    for values, extra, obs in log:
        key = (tuple(sorted(values.items())), tuple(extra))
        if key in seen:
            continue
        seen.add(key)
        row = {f"param {n}": values.get(n, p.table1) * p.paper_unit for n, p in PARAMS.items()}
        row["overrides"] = " ".join(f"{k}={v}" for k, v in extra)
        row.update(obs)
        rows.append(scored(row, obs))
    return rows


def scored(row, obs):
    """`row` with the claims' residuals "r ID", "cost", "cost_others" (the claims other than P35)
    and "reproduced" from the observables `obs`."""
    r = claim_residuals(obs)
    row.update({f"r {c.id}": x for c, x in zip(CLAIMS, r)})
    row.update({"cost": cost(r), "cost_others": cost([x for c, x in zip(CLAIMS, r) if c.id != "P35"]),
                "reproduced": reproduced(r)})
    return row


def rescored(rows):
    """Rows of a written CSV (strings) scored again on today's CLAIMS from their own observables:
    the points a study ran stay data when a claim's interval is read anew."""
    out = []
    for row in rows:
        obs = {}
        for c in CLAIMS:
            v = row.get(c.observable, "")
            obs[c.observable] = float(v) if v not in ("", None) else math.nan
        out.append(dict(row) if row.get("status") == "failed" else scored(dict(row), obs))
    return out


def point_key(row):
    """A point's identity in inverse_points.csv: its parameters (10 digits) and own overrides."""
    return tuple(f"{float(row[f'param {n}']):.10g}" for n in PARAMS) + (row.get("overrides", ""),)
