"""Speed against accuracy from a convergence study: every case's error (against the study's
extrapolated value) against its wall time on 2 ranks, the Pareto front marked, and one case
(the default discretisation) highlighted. Prints the front and the cheapest case within a
target error.

    python3 scripts/speed_accuracy.py studies/conv_reference --observable force_total_mg@35 \\
        [--default-h 20 --default-dt 1] [--target 0.01] [--out docs/figures/speed_accuracy.png]
"""
import argparse
import csv
import math
from pathlib import Path


def pareto(points):
    """The points no other point beats in both time and error (sorted by time)."""
    front, best = [], math.inf
    for p in sorted(points, key=lambda p: (p["wall_s"], p["error"])):
        if p["error"] < best:
            front.append(p)
            best = p["error"]
    return front


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("study")
    ap.add_argument("--observable", required=True)
    ap.add_argument("--default-h", type=float, default=20.0)
    ap.add_argument("--default-dt", type=float, default=1.0)
    ap.add_argument("--target", type=float, default=0.01, help="relative error a user asks for")
    ap.add_argument("--out", default=None)
    a = ap.parse_args()
    study = Path(a.study)
    rows = list(csv.DictReader(open(study / "errors.csv")))
    if a.observable not in rows[0]:
        raise SystemExit(f"speed_accuracy.py: {a.observable} is not in {study / 'errors.csv'}")
    pts = [{"h": float(r["h"]), "dt": float(r["dt_scale"]), "wall_s": float(r["wall_s"]),
            "error": float(r[a.observable])} for r in rows]
    pts = [p for p in pts if math.isfinite(p["error"]) and math.isfinite(p["wall_s"])]
    front = pareto(pts)
    default = next((p for p in pts if p["h"] == a.default_h and p["dt"] == a.default_dt), None)
    print(f"{a.observable}: error against the extrapolated value; Pareto front (h, dt scale, wall s, error):")
    for p in front:
        print(f"  h = {p['h']:g}, dt x {p['dt']:g}: {p['wall_s']:.1f} s, {p['error']:.2e}")
    if default:
        on = any(p is default for p in front)
        print(f"default (h = {a.default_h:g}, dt x {a.default_dt:g}): {default['wall_s']:.1f} s, "
              f"{default['error']:.2e} ({'on' if on else 'off'} the front)")
    ok = [p for p in pts if p["error"] <= a.target]
    if ok:
        c = min(ok, key=lambda p: p["wall_s"])
        print(f"cheapest within {a.target:g}: h = {c['h']:g}, dt x {c['dt']:g}, {c['wall_s']:.1f} s ({c['error']:.2e})")
    else:
        print(f"no case within {a.target:g}")

    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    fig, ax = plt.subplots(figsize=(6, 4))
    for h in sorted({p["h"] for p in pts}, reverse=True):
        sel = sorted((p for p in pts if p["h"] == h), key=lambda p: p["wall_s"])
        ax.loglog([p["wall_s"] for p in sel], [max(p["error"], 1e-6) for p in sel], "o-", alpha=0.7, label=f"h = {h:g} um")
    ax.loglog([p["wall_s"] for p in front], [max(p["error"], 1e-6) for p in front], "k--", lw=1, label="Pareto front")
    if default:
        ax.loglog([default["wall_s"]], [max(default["error"], 1e-6)], "r*", ms=14, label="default")
    ax.axhline(a.target, color="gray", lw=0.8, ls=":")
    ax.set_xlabel("wall time on 2 ranks (s)")
    ax.set_ylabel(f"relative error of {a.observable}")
    ax.grid(alpha=0.3, which="both")
    ax.legend(fontsize=7)
    ax.set_title("points along a line: dt x 1, 1/2, 1/4, 1/8 (left to right)", fontsize=8)
    fig.tight_layout()
    out = Path(a.out) if a.out else study / f"speed_accuracy_{a.observable.replace(':', '_').replace('@', '_at_').replace('/', '_over_')}.png"
    fig.savefig(out, dpi=120)
    print(f"figure: {out}")


if __name__ == "__main__":
    main()
