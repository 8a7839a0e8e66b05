"""Speed against accuracy from a convergence study: every case's error (against the study's
extrapolated value) against its wall time (as the study ran it: a case on k ranks, other cases
on the other ranks at the same time when k < --ranks; for times of one case alone on the machine,
run the study with --ranks-per-case equal to --ranks), the Pareto front marked, and one case
(the default discretisation) highlighted. Solver and time-stepping variants run at one
discretisation (a `scripts/study.py` study over `solver.preset`, `time.growth`, ...) join the
chart with `--variants STUDY`: each of its cases is a labelled point, its error taken against
the same extrapolated value. Prints the front and the cheapest case within a target error.

    python3 scripts/speed_accuracy.py studies/conv_reference --observable force_total_mg@35 \\
        [--default-h 20 --default-dt 1] [--target 0.01] [--variants studies/solvers_reference] \\
        [--reference STUDY] [--also [LABEL=]STUDY ...] [--out docs/figures/speed_accuracy.png]

--reference STUDY takes the converged value from another convergence study (e.g. the meridian's,
`scripts/references.py`) instead of the study's own extrapolation; --also STUDY puts another
convergence study's cases on the same chart (e.g. the meridian's beside the 3-D one), errors
against the same value.
"""
import argparse
import csv
import math
from pathlib import Path

from poroplast_tools import labels
from poroplast_tools.tables import pareto


def name(p):
    return p["label"] if "label" in p else f"h = {p['h']:g} µm, steps × {p['dt']:g}"


def read_variants(vdir, ref, observable):
    """The variant study's cases as points: wall time, and the error of `observable` against the
    converged value `ref`."""
    rows = list(csv.DictReader(open(vdir / "summary.csv")))
    if rows and observable not in rows[0]:
        raise SystemExit(f"speed_accuracy.py: {observable} is not in {vdir / 'summary.csv'}")
    keys = list(rows[0])[:list(rows[0]).index("status")] if rows else []
    out = []
    for r in rows:
        if r["status"] != "ok":
            continue
        label = ", ".join(labels.value(k, r[k]) for k in keys if r[k] != "") or "(base scene)"
        out.append({"label": label, "wall_s": float(r["wall_s"]), "error": abs(float(r[observable]) - ref) / abs(ref),
                    "steps": float(r["steps"]), "newton": float(r["newton_its"]), "krylov": float(r["ksp_its"])})
    return out


def extrapolated(study, observable):
    """A convergence study's extrapolated value of `observable` (convergence.csv)."""
    v = next((float(r["extrapolated"]) for r in csv.DictReader(open(study / "convergence.csv"))
              if r["observable"] == observable), None)
    if v is None:
        raise SystemExit(f"speed_accuracy.py: {observable} is not in {study / 'convergence.csv'}")
    return v


def study_points(study, observable, ref):
    """A convergence study's cases (summary.csv) as points: wall time, error against `ref`."""
    rows = [r for r in csv.DictReader(open(study / "summary.csv")) if r["status"] == "ok"]
    if rows and observable not in rows[0]:
        raise SystemExit(f"speed_accuracy.py: {observable} is not in {study / 'summary.csv'}")
    pts = [{"h": float(r["h"]), "dt": float(r["dt_scale"]), "wall_s": float(r["wall_s"]),
            "error": abs(float(r[observable]) - ref) / abs(ref)} for r in rows]
    return [p for p in pts if math.isfinite(p["error"]) and math.isfinite(p["wall_s"])]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("study")
    ap.add_argument("--observable", required=True)
    ap.add_argument("--default-h", type=float, default=20.0)
    ap.add_argument("--default-dt", type=float, default=1.0)
    ap.add_argument("--target", type=float, default=0.01, help="relative error a user asks for")
    ap.add_argument("--variants", action="append", default=[], metavar="STUDY",
                    help="a study.py directory of solver/time-stepping variants at one discretisation (repeatable)")
    ap.add_argument("--reference", default=None, metavar="STUDY",
                    help="take the converged value from this convergence study (default: the study's own)")
    ap.add_argument("--also", action="append", default=[], metavar="[LABEL=]STUDY",
                    help="another convergence study's cases on the same chart (repeatable)")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    study = Path(a.study)
    ref = extrapolated(Path(a.reference) if a.reference else study, a.observable)
    pts = study_points(study, a.observable, ref)
    others = {}
    for spec in a.also:   # LABEL=STUDY or STUDY
        label, _, d = spec.rpartition("=")
        others[label or Path(d).name] = study_points(Path(d), a.observable, ref)
    variants = [v for d in a.variants for v in read_variants(Path(d), ref, a.observable)]
    for label, extra in others.items():
        for p in extra:
            p["label"] = f"{label}: h = {p['h']:g} µm, steps × {p['dt']:g}"
    front = pareto(pts + variants + [p for extra in others.values() for p in extra])
    default = next((p for p in pts if p["h"] == a.default_h and p["dt"] == a.default_dt), None)
    print(f"{a.observable}: error against the extrapolated value; Pareto front (case, wall s, error):")
    for p in front:
        print(f"  {name(p)}: {p['wall_s']:.1f} s, {p['error']:.2e}")
    for v in variants:
        print(f"variant {v['label']}: {v['wall_s']:.1f} s, {v['error']:.2e}"
              f" ({v['steps']:.0f} steps, {v['newton']:.0f} Newton, {v['krylov']:.0f} Krylov)")
    if default:
        on = any(p is default for p in front)
        print(f"default (h = {a.default_h:g}, dt x {a.default_dt:g}): {default['wall_s']:.1f} s, "
              f"{default['error']:.2e} ({'on' if on else 'off'} the front)")
    ok = [p for p in pts + variants + [p for extra in others.values() for p in extra] if p["error"] <= a.target]
    if ok:
        c = min(ok, key=lambda p: p["wall_s"])
        print(f"cheapest within {a.target:g}: {name(c)}, {c['wall_s']:.1f} s ({c['error']:.2e})")
    else:
        print(f"no case within {a.target:g}")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for h in sorted({p["h"] for p in pts}, reverse=True):
        sel = sorted((p for p in pts if p["h"] == h), key=lambda p: p["wall_s"])
        ax.loglog([p["wall_s"] for p in sel], [max(p["error"], 1e-6) for p in sel], "o-", alpha=0.7, label=f"h = {h:g} µm")
    for label, extra in others.items():
        for h in sorted({p["h"] for p in extra}, reverse=True):
            sel = sorted((p for p in extra if p["h"] == h), key=lambda p: p["wall_s"])
            ax.loglog([p["wall_s"] for p in sel], [max(p["error"], 1e-6) for p in sel], "s--", mfc="none",
                      alpha=0.8, label=f"{label}: h = {h:g} µm")
    for v, marker in zip(variants, "sD^vP<>Xhp" * 3):
        ax.loglog([v["wall_s"]], [max(v["error"], 1e-6)], marker, ms=7, mfc="none", label=v["label"])
    ax.loglog([p["wall_s"] for p in front], [max(p["error"], 1e-6) for p in front], "k--", lw=1, label="Pareto front")
    if default:
        ax.loglog([default["wall_s"]], [max(default["error"], 1e-6)], "r*", ms=14, label="default")
    ax.axhline(a.target, color="gray", lw=0.8, ls=":")
    ax.set_xlabel("wall time of the case (s)")
    ax.set_ylabel(f"relative error of {a.observable}")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax.set_title("points along a line: steps × 1, 1/2, 1/4, 1/8 (left to right)", fontsize=8)
    fig.tight_layout()
    out = Path(a.out) if a.out else study / f"speed_accuracy_{a.observable.replace(':', '_').replace('@', '_at_').replace('/', '_over_')}.png"
    fig.savefig(out, dpi=120)
    print(f"figure: {out}")


if __name__ == "__main__":
    main()
