#!/usr/bin/env python3
"""Tissue surface tensiometry on the model: when does the lab's Laplace reading equal the
aggregate's true surface tension γ, and how large is its bias?

The lab compresses an aggregate between plates, waits, and reads σ = F / (π R3² (1/R1 + 1/R2))
from the plate force F and the profile (R1, R2 the principal radii at the equator, R3 the contact
radius). Every run writes that reading as `sigma_app` in history.csv at every step, from its
own profile (docs/model.md, "The lab's Laplace analysis"). This script runs the shipped
`tst_hold` scene (meridian, R = 100 µm, 30% compression held, γ = 5 mN/m) as the cases below and
draws σ_app(t) / γ:

* liquid (σy = 0) at three flow rates λp: residual elasticity relaxes in 1/(λp µ), the shape
  reaches its Young–Laplace equilibrium in the capillary time R / (λp γ);
* a yield stress σy > 0 (stress the flow cannot relax), and σy > 0 without any tension (γ = 0:
  the reading of a tension that is not there);
* the paper's Table 1 parameters (λp = 0.001 (kPa s)⁻¹, σy = 2 kPa) with γ = 5 mN/m;
* two compressions (15%, then 30%: `tst_two_compressions`): the lab's test of liquid behaviour
  is that both give the same σ.

    python3 scripts/tensiometry.py [--out runs/tensiometry] [--hold 3000] [--docs]

Writes OUT/tensiometry.csv (per case: σ_app / γ at the end of each hold, the time from which it
stays within 5% of γ, the relaxation and capillary times) and OUT/figures/tensiometry_*.png;
--docs copies them to docs/figures/ (docs/studies.md, "Tissue surface tensiometry").
"""
import argparse
import math
import shutil
from pathlib import Path

import numpy as np

from poroplast_tools import cases as store
from poroplast_tools.history import history
from poroplast_tools.tables import write_rows

ROOT = Path(__file__).resolve().parent.parent
GAMMA, MU, R = 5.0, 20.0, 100.0      # mN/m, kPa (the solid's µ), µm: the tst_hold scene's
WITHIN = 0.05                         # "equals γ": within 5%
RP = "material.remodelling"


def hold_table(hold):
    """One 30% compression in 5 s, held `hold` s, released in 5 s."""
    return f"[[0.0, 0.0], [5.0, 0.3], [{5 + hold:g}, 0.3], [{10 + hold:g}, 0.0]]"


def two_table(hold):
    """15% held `hold` s, released, rest 300 s, 30% held `hold` s, released."""
    t = [0.0, 5.0, 5 + hold, 10 + hold, 300 + hold, 305 + hold, 305 + 2 * hold, 310 + 2 * hold]
    u = [0.0, 0.15, 0.15, 0.0, 0.0, 0.3, 0.3, 0.0]
    return "[" + ", ".join(f"[{a:g}, {b:g}]" for a, b in zip(t, u)) + "]"


def cases(hold):
    """name -> (label, λp, σy, γ, two compressions?)."""
    return {
        "liquid_l0.001": ("liquid, λp = 0.001", 0.001, 0.0, GAMMA, False),
        "liquid_l0.01": ("liquid, λp = 0.01", 0.01, 0.0, GAMMA, False),
        "liquid_l0.1": ("liquid, λp = 0.1", 0.1, 0.0, GAMMA, False),
        "yield_0.1": ("σy = 0.1 kPa, λp = 0.01", 0.01, 0.1, GAMMA, False),
        "yield_0.1_no_tension": ("σy = 0.1 kPa, λp = 0.01, γ = 0", 0.01, 0.1, 0.0, False),
        "table1": ("Table 1: λp = 0.001, σy = 2 kPa", 0.001, 2.0, GAMMA, False),
        "two_liquid": ("two compressions, liquid, λp = 0.01", 0.01, 0.0, GAMMA, True),
        "two_yield": ("two compressions, σy = 0.1 kPa, λp = 0.01", 0.01, 0.1, GAMMA, True),
    }


def overrides(hold, lp, sy, gamma, two):
    """The case's --set overrides of tst_hold."""
    table = two_table(hold) if two else hold_table(hold)
    end = (310 + 2 * hold) if two else (5 + hold)
    return [("plates.table", table), ("time.t_end", f"{end:g}"), (f"{RP}.lambda_p", repr(lp)),
            (f"{RP}.sigma_y", repr(sy)), ("surface.tension", repr(gamma)), ("output.fields_at", "[]"),
            ("output.fields_every", "0")]


def hold_ends(hold, two):
    """(compression, time) of the end of each hold."""
    return [(0.15, 5 + hold), (0.3, 305 + 2 * hold)] if two else [(0.3, 5 + hold)]


def reading(h, t):
    """σ_app at the history row nearest to time t (the holds' ends are rows: the table's)."""
    i = int(np.argmin(abs(h["time"] - t)))
    return float(h["sigma_app"][i])


def settled_from(h, t0, t1):
    """The time after t0 from which σ_app stays within WITHIN of γ up to t1 (NaN if never)."""
    m = (h["time"] >= t0) & (h["time"] <= t1)
    t, s = h["time"][m], h["sigma_app"][m] / GAMMA
    ok = np.abs(s - 1) <= WITHIN
    for i in range(len(t)):
        if ok[i:].all():
            return float(t[i] - t0)
    return math.nan


def summarise(dirs, hold):
    rows = []
    for name, (label, lp, sy, gamma, two) in cases(hold).items():
        h = history(dirs[name])
        for c, t in hold_ends(hold, two):
            s = reading(h, t)
            rows.append({"case": name, "label": label, "lambda_p": lp, "sigma_y": sy, "gamma": gamma,
                         "compression": c, "time": t, "sigma_app": s, "sigma_app_over_gamma": s / GAMMA,
                         "within_5pct_from": settled_from(h, t - hold, t) if gamma > 0 else math.nan,
                         "relaxation_time": 1 / (lp * MU), "capillary_time": R / (lp * GAMMA)})
    return rows


def figures(dirs, hold, out):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    (out / "figures").mkdir(parents=True, exist_ok=True)
    cs = cases(hold)
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for name, (label, lp, sy, gamma, two) in cs.items():
        if two:
            continue
        h = history(dirs[name])
        m = (h["time"] >= 5) & (h["time"] <= 5 + hold)
        ax.plot(h["time"][m] - 5, h["sigma_app"][m] / GAMMA, label=label)
    ax.axhline(1, color="k", lw=0.8)
    ax.axhspan(1 - WITHIN, 1 + WITHIN, color="0.9")
    ax.set(xscale="log", yscale="log", xlabel="time in the hold (s)", ylabel="σ_app / γ  (γ = 5 mN/m)",
           title="The Laplace reading during a 30% hold")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "figures" / "tensiometry_hold.png", dpi=120)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    for name, (label, lp, sy, gamma, two) in cs.items():
        if not two:
            continue
        h = history(dirs[name])
        t = h["time"]
        m = np.zeros(len(t), bool)       # the holds
        for (_, end) in hold_ends(hold, two):
            m |= (t >= end - hold) & (t <= end)
        ax.plot(t[m], h["sigma_app"][m] / GAMMA, ".", ms=3, label=label)
    ax.axhline(1, color="k", lw=0.8)
    ax.set(yscale="log", xlabel="t (s)", ylabel="σ_app / γ", title="Two compressions (15%, then 30%): the liquid test")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "figures" / "tensiometry_two.png", dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="runs/tensiometry")
    ap.add_argument("--hold", type=float, default=3000.0, help="hold duration (s)")
    ap.add_argument("--docs", action="store_true", help="also copy the figures and table to docs/figures/")
    store.rank_options(ap)
    a = ap.parse_args()
    store.use_rank_options(a)
    out = Path(a.out)
    cs = cases(a.hold)
    names = list(cs)
    results = store.run_cases("tst_hold", [overrides(a.hold, *cs[n][1:]) for n in names], [], out, a.ranks)
    bad = [n for n, (_, r) in zip(names, results) if r["status"] != "ok"]
    if bad:
        raise SystemExit(f"tensiometry.py: cases failed: {', '.join(bad)}")
    dirs = {n: d for n, (d, _) in zip(names, results)}
    rows = summarise(dirs, a.hold)
    write_rows(out / "tensiometry.csv", rows)
    print("\n| case | compression | σ_app / γ at the hold's end | within 5% after (s into the hold) | 1/(λp µ) (s) | R/(λp γ) (s) |")
    print("|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['label']} | {r['compression']:.2f} | {r['sigma_app_over_gamma']:.4g} | "
              f"{r['within_5pct_from']:.4g} | {r['relaxation_time']:.3g} | {r['capillary_time']:.3g} |")
    figures(dirs, a.hold, out)
    if a.docs:
        dst = ROOT / "docs" / "figures"
        (dst / "data").mkdir(parents=True, exist_ok=True)
        shutil.copy(out / "tensiometry.csv", dst / "data" / "tensiometry.csv")
        for f in (out / "figures").glob("tensiometry_*.png"):
            shutil.copy(f, dst / f.name)
        print(f"copied to {dst}")


if __name__ == "__main__":
    main()
