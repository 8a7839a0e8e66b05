"""The figures of a fit: each experiment's data and fitted curve, and the parameters' profiles."""
import math
from pathlib import Path

import numpy as np

from . import labels, units
from .fit import LEVELS

# A fitted parameter's symbol and unit as the scene takes it (the unit of --param's start).
SCENE_UNITS = {
    "material.remodelling.lambda_p": ("λp", "(kPa s)⁻¹"), "material.remodelling.sigma_y": ("σy", "kPa"),
    "material.mu": ("µ", "kPa"), "material.drained_shear_modulus": ("G", "kPa"),
    "material.drained_youngs_modulus": ("E", "kPa"), "surface.tension": ("γ", "mN/m"),
    "material.k0": ("k0", "µm⁴/(nN s)"), "material.nu": ("ν", ""), "material.permeability_c": ("c", ""),
    "surface.adhesion": ("w", "mN/m"),
}


def plus_minus(v, s):
    """`v ± s` with s to two significant digits and v to the same place (scientific below 1e-3
    and from 1e5): 1.5019711 ± 0.0052 -> 1.5020 ± 0.0052."""
    if not (math.isfinite(s) and s > 0):
        return f"{v:.4g}"
    if v and s < 1e-5 * abs(v):            # a σ below the sixth digit: six digits, σ apart
        return f"{v:.6g} ± {s:.2g}"
    k = math.floor(math.log10(abs(v))) if v and (abs(v) < 1e-3 or abs(v) >= 1e5) else 0
    v, s = v / 10 ** k, s / 10 ** k
    digits = max(0, 1 - math.floor(math.log10(s)))
    text = f"{v:.{digits}f} ± {s:.{digits}f}"
    return f"({text})e{k}" if k else text


def legend(key, value, sigma):
    """A fitted parameter for a legend, in the scene's unit: `λp = 0.002010 ± 0.000028 (kPa s)⁻¹`."""
    base, _, name = key.partition("@")
    sym, unit = SCENE_UNITS.get(base, (base.split(".")[-1], ""))
    return f"{sym}{'@' + name if name else ''} = {plus_minus(value, sigma)}" + (f" {unit}" if unit else "")


def curves(study, experiments, data, histories, result, params, shown):
    """STUDY/calibration.png: each experiment's data and fitted curve, one column each, in the
    data's unit (`shown`: per experiment the unit and its factor to the model's): above on a
    linear axis, below on a logarithmic one, where a long hold's small forces can be read."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ne = len(experiments)
    rows = 2 if any(np.any(np.asarray(vs) > 0) for _, vs in data) else 1    # a log panel: positive data
    fig, axes = plt.subplots(rows, ne, figsize=(6.4 if ne == 1 else 4.4 * ne, 3.6 * rows + 0.6), squeeze=False)
    for j, (e, h, (ts, vs), info) in enumerate(zip(experiments, histories, data, result["experiments"])):
        unit, scale = shown[e.name]
        what = labels.column(e.column).split(" (")[0]
        ylabel = f"{what} ({units.shown(unit)})" if unit else labels.column(e.column)
        mine = [p.label for p in params if p.applies(e)]
        fit_label = "fit: " + ", ".join(legend(k, result[k]["value"], result[k]["sigma"]) for k in mine)
        model, measured = np.asarray(h[e.column]) / scale, np.asarray(vs) / scale
        for row, ax in enumerate(axes[:, j]):
            ax.plot(h["time"], model, "-", label=fit_label)
            ax.plot(ts, measured, "o", ms=3, label="data")
            ax.set_xlabel("t (s)")
            ax.set_ylabel(ylabel)
            if row == 0:
                ax.set_title(f"{e.name}: rms residual {info['rms_residual']:.3g}"
                             f"{' ' + units.shown(unit) if unit else ''}, weighted {info['rms_weighted']:.3g}",
                             fontsize=9)
                ax.legend(fontsize=7)
            elif np.any(measured > 0):
                positive = measured[measured > 0]
                ax.set_yscale("log")
                ax.set_ylim(positive.min() / 2, max(positive.max(), np.nanmax(model)) * 2)
                ax.set_title("the same, logarithmic axis (values > 0)", fontsize=8)
            else:
                ax.set_visible(False)
    fig.tight_layout()
    fig.savefig(Path(study) / "calibration.png", dpi=120)
    plt.close(fig)


def profiles(study, opt, st, prof, keys):
    """STUDY/profile.png: each parameter's profile (cost rise) against the Wald parabola, the
    68% and 95% thresholds and both intervals."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, axes = plt.subplots(1, len(keys), figsize=(4.2 * len(keys), 3.8), squeeze=False)
    for k, (ax, key) in enumerate(zip(axes[0], keys)):
        if key not in prof.curves:
            continue
        p = prof[key]
        rows = sorted([(d, c, s) for d, c, s in zip(p["delta"], p["cost"], p["status"]) if math.isfinite(c)]
                      + [(0.0, opt.cost, "ok")])     # with the optimum
        ax.plot([math.exp(opt.x[k] + d) for d, _, _ in rows], [c - prof.cost0 for _, c, _ in rows], "o-", ms=3,
                label="profile")
        bad = [(d, c) for d, c, s in rows if s != "ok"]
        if bad:
            ax.plot([math.exp(opt.x[k] + d) for d, _ in bad], [c - prof.cost0 for _, c in bad], "x", color="C3",
                    label="re-optimisation unconverged")
        fine = np.linspace(min(p["delta"] + [0.0]), max(p["delta"] + [0.0]), 100)
        ax.plot(np.exp(opt.x[k] + fine), (fine / st.rel[k]) ** 2, ":", label="Wald (linear)")
        for name, level in LEVELS.items():
            ax.axhline(st.z(level) ** 2, color="grey", lw=0.6)
            for end in p[f"interval{name}"]:
                if end is not None:
                    ax.axvline(end, color="C3", lw=0.6, ls="--")
        ax.axvline(math.exp(opt.x[k]), color="k", lw=0.6)
        if max(abs(d) for d in p["delta"] + [0.0]) > 1:     # the grid spans more than a factor e
            ax.set_xscale("log")
        ax.set_xlabel(key, fontsize=8)
        ax.tick_params(axis="x", labelrotation=30, labelsize=7)
        ax.set_ylabel("cost rise (weighted, unit variance)")
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(Path(study) / "profile.png", dpi=120)
    plt.close(fig)
