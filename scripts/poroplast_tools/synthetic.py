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
"""
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


def sets(level, truth, fitted):
    """The overrides of a run of the case at `level`: the case, the level, and the true value of
    every parameter of `truth` not in `fitted`."""
    return CASE + LEVELS[level] + [(k, repr(v)) for k, v in truth.items() if k not in fitted]


def truth_case(truth):
    """The overrides that give the true values (one case of run_cases)."""
    return [(k, repr(v)) for k, v in truth.items()]


def start(truth, keys, factor):
    """The fit's start point: each parameter's true value times `factor` (near, not at, the truth)."""
    return {k: truth[k] * factor for k in keys}


def calibrate_args(p, level, factor, extra=()):
    """scripts/calibrate.py's arguments for the p-parameter fit of this case, from the truth ×
    `factor`, the other parameters at their true values (`extra`: more overrides); the caller
    adds --data, --noise, the ranks and --dir."""
    keys, truth = FITS[p]
    return ([SCENE, "--column", COLUMN] + [f"--param={k}={v!r}" for k, v in start(truth, keys, factor).items()]
            + [f"--set={k}={v}" for k, v in sets(level, truth, keys) + list(extra)])


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
    data set `index` of the seed `seed` (the same every time, independent of the others; None:
    the seed's own generator)."""
    v = np.asarray(values, dtype=float)
    rng = np.random.default_rng(seed if index is None else [seed, index])
    return v + np.hypot(rel * np.abs(v), floor) * rng.standard_normal(v.size)
