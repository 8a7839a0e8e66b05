"""The synthetic experiment that checks the calibration: the meridian case a new user
calibrated, its true parameters and the fits' start points, its discretisation levels, and noisy
data sets in the lab's CSV format (poroplast_tools/measured.py).

The case: R = 150 µm, µ = 2.5 kPa, remodelling σy = 0.5 kPa and λp = 0.002 (kPa s)⁻¹, 30%
compression in 10 s, held until 70 s, released by 80 s, at rest until 90 s; `remodel_40` on its
meridian with those overrides. The 1-parameter fit (λp) is that case. For 3 parameters
(µ, λp, σy) it is not: with λp = 0.002 the relaxation time 1/(λp µ) = 200 s is three times the
hold, the hold shows a straight decline, and only a combination of rate and threshold is
determined (corr(λp, σy) = 0.998, standard errors 25-30% at 2% noise); with λp = 0.02 (20 s)
the hold shows the relaxation's curvature and its plateau, and each is determined (0.85;
2.2% and 0.7%). The truth is the model itself at the true values (same mesh and steps as the
fits), so a fit's error is the noise's alone; the model's discretisation error against a finer
level is a separate number (`LEVELS["fine"]`).

A second case, `TST`: tissue surface tensiometry with a yield stress. `tst_hold` (Table 1's
aggregate, R = 100 µm, µ = 20 kPa) with a surface tension γ = 5 mN/m, λp = 0.001 (kPa s)⁻¹ and
σy = 0.2 kPa, as two experiments: aggregates of the same tissue compressed by 15% and by 30% in
5 s and held 1000 s (the data end with the hold: no release, no contact opening). γ, λp and σy
are fitted together. One compression does not separate γ from σy: both hold up the plateau
(the 30% curve alone: cos +0.9997 between their columns, corr(γ, σy) = −0.9997, σ(γ) 20%); at
two compressions their shares differ (a change of γ moves the force at the end of the hold
about 2.5 times as much at 30% as at 15%, one of σy 1.4 times: coverage.py's per-experiment
rows of jitter_tst.csv) and each is determined (corr −0.93; σ/value 1.0%, 0.08%, 0.18% for γ,
λp, σy at 2% noise with data every 1 s; docs/studies.md). Each run about 1.3 s on 1 rank on a
quiet machine (coarse level, 46 steps).
"""
from dataclasses import dataclass, field

import numpy as np

SCENE = "remodel_40"
COLUMN = "force_total_mg"
CASE = [("mesh.geometry", "axisymmetric"), ("mesh.params.R", "150"), ("mesh.params.r_pole", "75"),
        ("plates.radius", "150"), ("plates.t_ramp", "10"), ("plates.t_end", "80"), ("time.t_end", "90"),
        ("output.fields", "false"), ("output.fields_at", "[]"), ("output.checkpoint_every", "0")]
# Mesh and steps. coarse: 249 dofs, 77 steps, about 1.5 s a run on 1 rank (geometric steps: the
# same for every parameter value unless a solve fails, so the curve is smooth in the parameters);
# medium: the mesh of docs/studies.md's smoothness study with the same steps; fine: that mesh
# with remodel_40's own steps, the yardstick of the others' discretisation error.
LEVELS = {
    "coarse": [("mesh.params.h", "75"), ("mesh.params.h_pole", "15"),
               ("time.dt", "0.05"), ("time.growth", "1.5"), ("time.dt_max", "2.0")],
    "medium": [("mesh.params.h", "30"), ("mesh.params.h_pole", "4.5"),
               ("time.dt", "0.05"), ("time.growth", "1.5"), ("time.dt_max", "2.0")],
    "fine": [("mesh.params.h", "30"), ("mesh.params.h_pole", "4.5")],
}
ISSUE = {"material.mu": 2.5, "material.remodelling.lambda_p": 0.002, "material.remodelling.sigma_y": 0.5}
# The fits by their number of parameters: (the fitted keys, the true values of the case).
FITS = {1: (["material.remodelling.lambda_p"], ISSUE),
        3: (["material.mu", "material.remodelling.lambda_p", "material.remodelling.sigma_y"],
            ISSUE | {"material.remodelling.lambda_p": 0.02})}




@dataclass(frozen=True)
class Case:
    """A synthetic case of the calibration: its scene and fitted column, the overrides of every
    run (`common`), its discretisation levels, its fits by number of parameters ({p: (keys,
    truth)}), and its experiments ({name: overrides}; one unnamed experiment, None: the case
    itself, fitted from one --data file; several: an --experiments file). `floor`: data only
    where the true force is above this fraction of its peak (data_times). `tag` names the
    coverage study's folders (TAG{p}) and `suffix` its files (coverage{suffix}.csv)."""
    name: str
    scene: str
    column: str
    common: list
    levels: dict
    fits: dict
    experiments: dict = field(default_factory=lambda: {None: []})
    floor: float = 0.05
    tag: str = "fit"
    suffix: str = ""
    about: str = ""

    def sets(self, level, truth, fitted):
        """The overrides of a run of the case at `level` (every experiment's; each adds its
        own): the case, the level, and the true value of every parameter of `truth` not in
        `fitted`."""
        return self.common + self.levels[level] + [(k, repr(v)) for k, v in truth.items() if k not in fitted]

    @property
    def several(self):
        return list(self.experiments) != [None]


MERIDIAN = Case("meridian", SCENE, COLUMN, CASE, LEVELS, FITS,
                about="meridian case, R = 150 µm, 30% compression held 60 s")

# Tissue surface tensiometry with a yield stress: tst_hold's aggregate at 15% and 30%, each held
# 1000 s, the data to the end of the hold. Mesh sizes as fractions of R (mesh.relative_sizes).
# coarse: 43 cells, 46 geometric steps (the first 0.05 s, ×1.5, at most the scene's 50 s), about
# 1.3 s a run on 1 rank; medium: h = 0.3 R; fine: the scene's own mesh and steps.
TST_TRUTH = {"surface.tension": 5.0, "material.remodelling.lambda_p": 0.001, "material.remodelling.sigma_y": 0.2}
TST_HOLD = 1000.0
TST = Case(
    "tst", "tst_hold", COLUMN,
    [("output.fields", "false"), ("output.fields_at", "[]"), ("output.checkpoint_every", "0")],
    {"coarse": [("mesh.relative_sizes.h", "0.5"), ("mesh.relative_sizes.h_pole", "0.1"),
                ("time.dt", "0.05"), ("time.growth", "1.5")],
     "medium": [("mesh.relative_sizes.h", "0.3"), ("mesh.relative_sizes.h_pole", "0.05"),
                ("time.dt", "0.05"), ("time.growth", "1.5")],
     "fine": []},
    {3: (list(TST_TRUTH), TST_TRUTH)},
    experiments={f"c{round(100 * c)}": [("plates.table", f"[[0.0, 0.0], [5.0, {c}], [{5 + TST_HOLD}, {c}]]"),
                                         ("time.t_end", f"{5 + TST_HOLD}")] for c in (0.15, 0.3)},
    floor=0.0, tag="tst", suffix="_tst",
    about="tensiometry case, R = 100 µm, 15% and 30% each held 1000 s")
CASES = {c.name: c for c in (MERIDIAN, TST)}


def sets(level, truth, fitted, case=MERIDIAN):
    """The overrides of a run of `case` at `level`: Case.sets."""
    return case.sets(level, truth, fitted)


def truth_case(truth):
    """The overrides that give the true values (one case of run_cases)."""
    return [(k, repr(v)) for k, v in truth.items()]


def start(truth, keys, factor):
    """The fit's start point: each parameter's true value times `factor` (near, not at, the truth)."""
    return {k: truth[k] * factor for k in keys}


def calibrate_args(p, level, factor, extra=(), case=MERIDIAN):
    """scripts/calibrate.py's arguments for the p-parameter fit of `case`, from the truth ×
    `factor`, the other parameters at their true values (`extra`: more overrides); the caller
    adds --data (one experiment) or --experiments (several: `experiments_text`), --noise, the
    ranks and --dir."""
    keys, truth = case.fits[p]
    return ([case.scene, "--column", case.column]
            + [f"--param={k}={v!r}" for k, v in start(truth, keys, factor).items()]
            + [f"--set={k}={v}" for k, v in case.sets(level, truth, keys) + list(extra)])


def experiments_text(case, data):
    """The --experiments file of a fit of a case of several experiments: one [[experiment]] per
    experiment, its name, its data file (`data`: {name: path}) and its own overrides; the scene,
    the column and the common overrides come from calibrate_args' command line."""
    def string(s):
        return '"' + str(s).replace("\\", "\\\\").replace('"', '\\"') + '"'
    out = []
    for name, own in case.experiments.items():
        out += ["[[experiment]]", f"name = {string(name)}", f"data = {string(data[name])}",
                "set = [" + ", ".join(string(f"{k}={v}") for k, v in own) + "]", ""]
    return "\n".join(out)


def data_times(time, value, every=1.0, floor=0.05):
    """The data's times: every `every` s from `every` to the run's end, where the true curve is
    above `floor` × its largest value. Below 5% of the peak lies the contact's opening, where
    the runs' adaptive steps differ between nearby parameter values (a step cut in one run and
    not in its neighbour: the curve jumps by 7-21 × 2% noise at 76-77 s on the coarse level);
    after it the force is 0 for every parameter value."""
    time, value = np.asarray(time, dtype=float), np.asarray(value, dtype=float)
    grid = np.arange(every, time[-1] + 1e-9 * time[-1], every)
    f = np.interp(grid, time, value)
    return grid[f > floor * float(np.max(np.abs(value)))]


def noisy(values, rel, seed, index=None, floor=0.0):
    """The values with independent Gaussian noise of standard deviation √((rel value)² + floor²);
    data set `index` of the seed `seed` (an int or a tuple, e.g. (set, experiment); the same
    every time, independent of the others; None: the seed's own generator)."""
    v = np.asarray(values, dtype=float)
    index = () if index is None else tuple(index) if isinstance(index, (tuple, list)) else (index,)
    rng = np.random.default_rng([seed, *index] if index else seed)
    return v + np.hypot(rel * np.abs(v), floor) * rng.standard_normal(v.size)
