#!/usr/bin/env python3
"""Tissue surface tensiometry on the model: when does the lab's Laplace reading equal the
aggregate's true surface tension γ, and how large is its bias?

The lab compresses an aggregate between plates, waits, and reads σ = F / (π R3² (1/R1 + 1/R2))
from the plate force F and the profile (R1, R2 the principal radii at the equator, R3 the contact
radius). Every run writes that reading as `sigma_app` in history.csv at every step, from its
own profile (docs/model.md, "The lab's Laplace analysis"). This script runs the shipped
`tst_hold` scene (meridian, R = 100 µm, µ = 20 kPa, its surface graded for the reading) as the
cases of `cases`:

* the first study (γ = 5 mN/m, 30% held `--hold` s, the scene's weight): the liquid (σy = 0) at
  three flow rates λp, a yield stress σy > 0 with and without the tension, the paper's Table 1,
  two compressions (15%, then 30%: the lab's test of liquid behaviour);
* the domain of the liquid's reading. With σy = 0 the elastic deviator relaxes in 1/(λp µ) and
  the shape then flows to its Young–Laplace equilibrium in the capillary time R/(λp γ); their
  ratio is µR/γ. λp = 0.01, µR/γ = 10 ... 4000 (γ from 200 to 0.5 mN/m), 15% and 30%, without
  the weight and with it (the shipped scenes' full weight, no buoyancy: Bond number ρ g R²/γ),
  each held twice its capillary time; and the new-user trial's liquid (R = 150 µm, γ = 3,
  λp = 0.05, 15% then straight on to 30%, 600 s each).

From the liquid holds without weight, µR/γ ≥ DOMAIN_MIN, `rule` gives the measured domain:
σ_app within 5% of γ once t > a/(λp µ) and t > b R/(λp γ) (docs/studies.md states it, and
scripts/tests/test_tensiometry.py checks it against the table).

    python3 scripts/tensiometry.py [--out runs/tensiometry] [--hold 3000] [--ranks 2] [--docs]
    python3 scripts/tensiometry.py --buoyancy [--out runs/tensiometry] [--docs]

The study's cases weigh the aggregate in air (tst_hold without its [medium] section: the study
measures the reading's bias with the weight, docs/studies.md); `--buoyancy` instead runs the
new-user trial's liquid (γ = 1 mN/m, R = 200 µm, λp = 0.05, 15% held 600 s) in air, in the medium
(tst_hold as shipped) and without gravity, and writes OUT/tensiometry_medium.csv (σ_app / γ at the hold's end;
--docs copies it to docs/figures/data/; docs/model.md, "The medium").

Writes OUT/tensiometry.csv (per hold: σ_app / γ at its end and its range in the hold's second
half, the time from which it stays within 5% of γ, in s and in both time scales, µR/γ, the Bond
number) and OUT/figures/tensiometry_{hold,two,domain}.png; --docs copies them to docs/figures/
(docs/studies.md, "Tissue surface tensiometry").
"""
import argparse
import math
import shutil
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from poroplast_tools import cases as store
from poroplast_tools.history import history
from poroplast_tools.tables import write_rows

ROOT = Path(__file__).resolve().parent.parent
GAMMA, MU, R = 5.0, 20.0, 100.0      # mN/m, kPa (the solid's µ), µm: the tst_hold scene's
RHO_G = 9.81e-6                       # ρ g of the mixture (1000 kg/m³), kPa/µm: the Bond number's
WITHIN = 0.05                         # "equals γ": within 5%
DOMAIN_MIN = 40                       # the rule's µR/γ from here (at 10 the reading's scatter alone is ±5%)
RP = "material.remodelling"
RAMP, REST = 5.0, 290.0               # s: each compression's ramp; rest between release and the next


@dataclass(frozen=True)
class Case:
    """One run: a liquid (σy = 0) or a yielding aggregate held at each compression of `holds`
    ((compression, seconds), in order), released and rested between them (`release`) or taken
    straight on to the next (the new-user trial's protocol); `gravity` the scene's weight (no
    buoyancy) or none; `dt_max` the hold's largest step; `group` its figure."""
    label: str
    lp: float
    gamma: float
    holds: tuple
    sy: float = 0.0
    r: float = R
    gravity: bool = True
    release: bool = True
    dt_max: float = 50.0
    group: str = "hold"
    medium: bool = False

    @property
    def relaxation_time(self):
        return 1 / (self.lp * MU)

    @property
    def capillary_time(self):
        return self.r / (self.lp * self.gamma) if self.gamma > 0 else math.nan

    @property
    def bond(self):
        # In the medium (ρs = ρf = ρ_m) there is no excess weight.
        return RHO_G * self.r ** 2 / self.gamma if self.gravity and not self.medium and self.gamma > 0 else 0.0

    def table(self):
        """plates.table and the (compression, start, end) of each hold."""
        rows, t, ends = [(0.0, 0.0)], 0.0, []
        for i, (c, hold) in enumerate(self.holds):
            t += RAMP
            rows.append((t, c))
            ends.append((c, t, t + hold))
            t += hold
            rows.append((t, c))
            if self.release and i + 1 < len(self.holds):
                rows += [(t + RAMP, 0.0), (t + RAMP + REST, 0.0)]
                t += RAMP + REST
        return "[" + ", ".join(f"[{a:g}, {b:g}]" for a, b in rows) + "]", ends


def domain_hold(lp, gamma, r=R):
    """A hold of twice the capillary time, at least 100 relaxation times."""
    return float(round(max(2 * r / (lp * gamma), 100 / (lp * MU))))


def cases(hold):
    """name -> Case. The first study (30% held `hold` s; two compressions), then the domain of
    the liquid's reading: λp = 0.01 (kPa s)⁻¹, µR/γ from 10 to 4000, 15% and 30%, without and
    (but at µR/γ = 10, Bo = 0.0005) with the weight, each held twice its capillary time (the steps at most 1/80 of the hold);
    and the new-user trial's liquid (R = 150 µm, γ = 3 mN/m, λp = 0.05, 15% then straight on to
    30%, 600 s each)."""
    out = {
        "liquid_l0.001": Case("liquid, λp = 0.001", 0.001, GAMMA, ((0.3, hold),)),
        "liquid_l0.01": Case("liquid, λp = 0.01", 0.01, GAMMA, ((0.3, hold),)),
        "liquid_l0.1": Case("liquid, λp = 0.1", 0.1, GAMMA, ((0.3, hold),)),
        "yield_0.1": Case("σy = 0.1 kPa, λp = 0.01", 0.01, GAMMA, ((0.3, hold),), sy=0.1),
        "yield_0.1_no_tension": Case("σy = 0.1 kPa, λp = 0.01, γ = 0", 0.01, 0.0, ((0.3, hold),), sy=0.1),
        "table1": Case("Table 1: λp = 0.001, σy = 2 kPa", 0.001, GAMMA, ((0.3, hold),), sy=2.0),
        "two_liquid": Case("two compressions, liquid, λp = 0.01", 0.01, GAMMA, ((0.15, hold), (0.3, hold)),
                           group="two"),
        "two_yield": Case("two compressions, σy = 0.1 kPa, λp = 0.01", 0.01, GAMMA, ((0.15, hold), (0.3, hold)),
                          sy=0.1, group="two"),
    }
    for gamma in DOMAIN_GAMMAS:
        h = domain_hold(0.01, gamma)
        for c in (0.15, 0.3):
            for g in (False, True) if gamma <= 50 else (False,):     # the weight: Bo = 0.0005 at 200
                out[f"domain_g{gamma:g}_c{round(100 * c)}{'_weight' if g else ''}"] = Case(
                    f"liquid, γ = {gamma:g}, {round(100 * c)}%{', weight' if g else ''}", 0.01, gamma, ((c, h),),
                    gravity=g, dt_max=h / 80, group="domain")
    for g in (False, True):
        out[f"trial{'_weight' if g else ''}"] = Case(
            f"trial: R = 150 µm, γ = 3, λp = 0.05{', weight' if g else ''}", 0.05, 3.0,
            ((0.15, 600.0), (0.3, 600.0)),
            r=150.0, gravity=g, release=False, dt_max=20.0, group="trial")
    return out


DOMAIN_GAMMAS = (200.0, 50.0, 10.0, 2.0, 0.5)

# The new-user trial's liquid whose weight in air biased σ_app to 0.19 γ: in air, in the medium,
# without gravity.
BUOYANCY = {
    f"buoyancy_{k}": Case(f"γ = 1, R = 200 µm, λp = 0.05, 15%: {label}", 0.05, 1.0, ((0.15, 600.0),), r=200.0,
                          gravity=g, release=False, group="buoyancy", medium=m)
    for k, label, g, m in (("air", "in air", True, False), ("medium", "in the medium", True, True),
                           ("no_gravity", "without gravity", False, True))
}


def air_scene(out):
    """tst_hold weighed in air (without its [medium] section), in `out`."""
    text = (ROOT / "meshes" / "scenes" / "tst_hold.toml").read_text()
    if "\n[medium]\n" not in text:
        raise SystemExit("tensiometry.py: tst_hold.toml has no [medium] section to take out")
    out.mkdir(parents=True, exist_ok=True)
    path = out / "tst_hold_in_air.toml"
    path.write_text(text.replace("\n[medium]\n", "\n", 1))
    return path


def run(cs, out, ranks):
    """Runs the cases `cs` (name -> Case), each in air or in the medium; name -> run directory."""
    names = list(cs)
    scenes = ["tst_hold" if cs[n].medium else str(air_scene(out)) for n in names]
    results = store.run_cases(scenes, [overrides(cs[n]) for n in names], [], out, ranks)
    bad = [n for n, (_, r) in zip(names, results) if r["status"] != "ok"]
    if bad:
        raise SystemExit(f"tensiometry.py: cases failed: {', '.join(bad)}")
    return {n: d for n, (d, _) in zip(names, results)}


def buoyancy(out, ranks, docs):
    """The BUOYANCY cases' readings at the hold's end into OUT/tensiometry_medium.csv."""
    dirs = run(BUOYANCY, out, ranks)
    rows = []
    for name, case in BUOYANCY.items():
        (c, _, t1), = case.table()[1]
        s = reading(history(dirs[name]), t1)
        rows.append({"case": name, "label": case.label, "R": case.r, "gamma": case.gamma, "lambda_p": case.lp,
                     "compression": c, "time": t1, "gravity": int(case.gravity), "medium": int(case.medium),
                     "bond": case.bond, "sigma_app": s, "sigma_app_over_gamma": s / case.gamma})
        print(f"{case.label}: σ_app / γ = {s / case.gamma:.4g} (Bo = {case.bond:.3g})")
    write_rows(out / "tensiometry_medium.csv", rows)
    if docs:
        dst = ROOT / "docs" / "figures" / "data"
        dst.mkdir(parents=True, exist_ok=True)
        shutil.copy(out / "tensiometry_medium.csv", dst / "tensiometry_medium.csv")
        print(f"copied to {dst}")   # mN/m at R = 100 µm, µ = 20 kPa: µR/γ = 10, 40, 200, 1000, 4000


def overrides(case):
    """The case's --set overrides of tst_hold."""
    table, ends = case.table()
    out = [("plates.table", table), ("time.t_end", f"{ends[-1][2]:g}"), (f"{RP}.lambda_p", repr(case.lp)),
           (f"{RP}.sigma_y", repr(case.sy)), ("surface.tension", repr(case.gamma)), ("output.fields_at", "[]"),
           ("output.fields_every", "0")]
    if case.r != R:
        out.append(("mesh.params.R", f"{case.r:g}"))
    if not case.gravity:
        out.append(("material.gravity", "[0.0, 0.0, 0.0]"))
    if case.dt_max != 50.0:
        out.append(("time.dt_max", f"{case.dt_max:g}"))
    return out


def reading(h, t):
    """σ_app at the history row nearest to time t (the holds' ends are rows: the table's)."""
    i = int(np.argmin(abs(h["time"] - t)))
    return float(h["sigma_app"][i])


def settled_from(h, t0, t1, gamma):
    """The time after t0 from which σ_app stays within WITHIN of γ up to t1 (NaN if never)."""
    m = (h["time"] >= t0) & (h["time"] <= t1)
    t, s = h["time"][m], h["sigma_app"][m] / gamma
    ok = np.abs(s - 1) <= WITHIN
    for i in range(len(t)):
        if ok[i:].all():
            return float(t[i] - t0)
    return math.nan


def summarise(dirs, hold):
    """One row per hold of every case: σ_app / γ at its end (of 5 mN/m for γ = 0), its least and
    largest value in the hold's second half (the settled reading's scatter: R3 jumps as the
    contact edge passes a surface node), the time into the hold from which it stays within 5%
    of γ, in s and in both time scales."""
    rows = []
    for name, case in cases(hold).items():
        h = history(dirs[name])
        ref = case.gamma or GAMMA
        for c, t0, t1 in case.table()[1]:
            s = reading(h, t1)
            t5 = settled_from(h, t0, t1, case.gamma) if case.gamma > 0 else math.nan
            late = h["sigma_app"][(h["time"] >= (t0 + t1) / 2) & (h["time"] <= t1)] / ref
            rows.append({"case": name, "group": case.group, "label": case.label, "R": case.r, "lambda_p": case.lp,
                         "sigma_y": case.sy, "gamma": case.gamma, "gravity": int(case.gravity), "bond": case.bond,
                         "compression": c, "hold": t1 - t0, "time": t1, "sigma_app": s,
                         "sigma_app_over_gamma": s / ref, "late_min": float(np.min(late)),
                         "late_max": float(np.max(late)), "within_5pct_from": t5,
                         "relaxation_time": case.relaxation_time, "capillary_time": case.capillary_time,
                         "mu_R_over_gamma": MU * case.r / case.gamma if case.gamma > 0 else math.nan,
                         "within_in_relaxation_times": t5 / case.relaxation_time,
                         "within_in_capillary_times": t5 / case.capillary_time})
    return rows


def liquid_rows(rows):
    """The holds the validity rule is measured on: liquids (σy = 0) with a tension and no weight,
    µR/γ ≥ DOMAIN_MIN."""
    return [r for r in rows if float(r["sigma_y"]) == 0 and float(r["gamma"]) > 0 and int(r["gravity"]) == 0
            and float(r["mu_R_over_gamma"]) >= DOMAIN_MIN]


def rule(rows):
    """The measured domain of the reading over `liquid_rows`: (a, b) such that every hold's
    reading stays within 5% of γ once t > a/(λp µ) and t > b R/(λp γ), i.e. t5 ≤ max(a τ_r,
    b τ_c) for each hold (t5 the time from which it stays within 5%). Of the pairs on that
    front (b one of the holds' t5/τ_c or 0, a the largest t5/τ_r of the holds b leaves), the one
    that overestimates the holds' t5 least (geometric mean of max(a τ_r, b τ_c) / t5); both
    rounded up to 2 significant digits. NaN where a hold never comes within 5%."""
    liq = liquid_rows(rows)
    t5 = [float(r["within_5pct_from"]) for r in liq]
    if not liq or any(math.isnan(t) for t in t5):
        return math.nan, math.nan
    rel = [t / float(r["relaxation_time"]) for t, r in zip(t5, liq)]
    cap = [t / float(r["capillary_time"]) for t, r in zip(t5, liq)]
    front = []
    for b in sorted({0.0, *cap}):
        a = max([x for x, c in zip(rel, cap) if c > b], default=0.0)
        front.append((a, b))
    # max(a τ_r, b τ_c) / t5 = max(a / rel, b / cap) for each hold.
    a, b = min(front, key=lambda ab: sum(math.log(max(ab[0] / x, ab[1] / c)) for x, c in zip(rel, cap)))
    return _up(a), _up(b)


def _up(x):
    """x rounded up to 2 significant digits."""
    if x <= 0:
        return 0.0
    e = math.floor(math.log10(x)) - 1
    return math.ceil(x / 10 ** e - 1e-9) * 10 ** e


def figures(dirs, hold, out, ab):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    (out / "figures").mkdir(parents=True, exist_ok=True)
    cs = cases(hold)
    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for name, case in cs.items():
        if case.group != "hold":
            continue
        h = history(dirs[name])
        m = (h["time"] >= RAMP) & (h["time"] <= RAMP + hold)
        ax.plot(h["time"][m] - RAMP, h["sigma_app"][m] / GAMMA, label=case.label)
    ax.axhline(1, color="k", lw=0.8)
    ax.axhspan(1 - WITHIN, 1 + WITHIN, color="0.9")
    ax.set(xscale="log", yscale="log", xlabel="time in the hold (s)", ylabel="σ_app / γ  (γ = 5 mN/m)",
           title="The Laplace reading during a 30% hold")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "figures" / "tensiometry_hold.png", dpi=120)
    plt.close(fig)
    fig, ax = plt.subplots(figsize=(7.5, 4.2))
    for name, case in cs.items():
        if case.group != "two":
            continue
        h = history(dirs[name])
        t = h["time"]
        m = np.zeros(len(t), bool)       # the holds
        for _, t0, t1 in case.table()[1]:
            m |= (t >= t0) & (t <= t1)
        ax.plot(t[m], h["sigma_app"][m] / GAMMA, ".", ms=3, label=case.label)
    ax.axhline(1, color="k", lw=0.8)
    ax.set(yscale="log", xlabel="t (s)", ylabel="σ_app / γ", title="Two compressions (15%, then 30%): the liquid test")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(out / "figures" / "tensiometry_two.png", dpi=120)
    plt.close(fig)
    # The domain: every liquid hold without weight, against both time scales.
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.6), sharey=True)
    for name, case in cs.items():
        if case.sy > 0 or case.gamma <= 0 or case.gravity:
            continue
        h = history(dirs[name])
        for c, t0, t1 in case.table()[1]:
            m = (h["time"] > t0) & (h["time"] <= t1)
            t, y = h["time"][m] - t0, h["sigma_app"][m] / case.gamma
            label = (f"µR/γ = {MU * case.r / case.gamma:g}, {round(100 * c)}%"
                     + (", trial" if case.group == "trial" else ""))
            # A colour per µR/γ (the trial its own), dashed at 15%.
            colour = "k" if case.group == "trial" else f"C{DOMAIN_GAMMAS.index(case.gamma)}"
            style = dict(ls="--" if c < 0.2 else "-", lw=1.2, color=colour)
            axes[0].plot(t / case.capillary_time, y, label=label, **style)
            axes[1].plot(t / case.relaxation_time, y, **style)
    a, b = ab
    for ax, x, what in ((axes[0], b, "t λp γ / R  (capillary times)"), (axes[1], a, "t λp µ  (relaxation times)")):
        ax.axhspan(1 - WITHIN, 1 + WITHIN, color="0.9")
        ax.axhline(1, color="k", lw=0.8)
        if math.isfinite(x):
            ax.axvline(x, color="k", ls=":", lw=1)
        ax.set(xscale="log", xlabel=what, ylim=(0.6, 1.6))
    axes[0].set_ylabel("σ_app / γ  (liquid, no weight)")
    axes[0].set_title(f"within 5% once t > {b:g} R/(λp γ) …", fontsize=10)
    axes[1].set_title(f"… and t > {a:g} /(λp µ)", fontsize=10)
    axes[0].legend(fontsize=7, ncol=2)
    fig.tight_layout()
    fig.savefig(out / "figures" / "tensiometry_domain.png", dpi=120)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", default="runs/tensiometry")
    ap.add_argument("--hold", type=float, default=3000.0, help="the first study's hold (s)")
    ap.add_argument("--docs", action="store_true", help="also copy the figures and table to docs/figures/")
    ap.add_argument("--buoyancy", action="store_true",
                    help="only the trial's liquid in air, in the medium and without gravity (tensiometry_medium.csv)")
    store.rank_options(ap)
    a = ap.parse_args()
    store.use_rank_options(a)
    out = Path(a.out)
    if a.buoyancy:
        buoyancy(out, a.ranks, a.docs)
        return
    dirs = run(cases(a.hold), out, a.ranks)
    rows = summarise(dirs, a.hold)
    write_rows(out / "tensiometry.csv", rows)
    print("\n| case | compression | σ_app / γ at the hold's end | within 5% after (s into the hold) | "
          "in 1/(λp µ) | in R/(λp γ) | µR/γ | Bo |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['label']} | {r['compression']:.2f} | {r['sigma_app_over_gamma']:.4g} | "
              f"{r['within_5pct_from']:.4g} | {r['within_in_relaxation_times']:.3g} | "
              f"{r['within_in_capillary_times']:.3g} | {r['mu_R_over_gamma']:.4g} | {r['bond']:.3g} |")
    ab = rule(rows)
    print(f"\nliquid, no weight ({len(liquid_rows(rows))} holds): within 5% of γ once t > {ab[0]:g}/(λp µ) "
          f"and t > {ab[1]:g} R/(λp γ)")
    figures(dirs, a.hold, out, ab)
    if a.docs:
        dst = ROOT / "docs" / "figures"
        (dst / "data").mkdir(parents=True, exist_ok=True)
        shutil.copy(out / "tensiometry.csv", dst / "data" / "tensiometry.csv")
        for f in (out / "figures").glob("tensiometry_*.png"):
            shutil.copy(f, dst / f.name)
        print(f"copied to {dst}")


if __name__ == "__main__":
    main()
