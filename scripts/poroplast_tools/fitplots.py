"""The figures of a fit: each experiment's data and fitted curve, and the parameters' profiles."""
import math
from pathlib import Path

import numpy as np

from . import labels
from .fit import LEVELS


def curves(study, experiments, data, histories, result, keys):
    """STUDY/calibration.png: each experiment's data and fitted curve, one panel each."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    ne = len(experiments)
    fig, axes = plt.subplots(1, ne, figsize=(6.4 if ne == 1 else 4.2 * ne, 4.2), squeeze=False)
    for ax, e, h, (ts, vs), info in zip(axes[0], experiments, histories, data, result["experiments"]):
        mine = [p for p in keys if "@" not in p or p.endswith("@" + e.name)]
        ax.plot(h["time"], h[e.column], "-", label="fit: " + ", ".join(
            labels.value(k.split("@")[0], result[k]["value"]) for k in mine))
        ax.plot(ts, vs, "o", ms=3, label="data")
        ax.set_xlabel("t (s)")
        ax.set_ylabel(labels.column(e.column))
        ax.set_title(f"{e.name}: rms residual {info['rms']:.3g}" if ne > 1 else
                     f"{e.scene}: rms residual {result['rms']:.3g}", fontsize=9)
        ax.legend(fontsize=7)
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
