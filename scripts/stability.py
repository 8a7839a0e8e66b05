"""Stability where methods fail: the figures of docs/studies.md (the tests assert the contrasts).

    python3 scripts/stability.py --dir studies/stability [--only undrained remodelling steps]

* undrained: Terzaghi's column after a first step of 1e-6 s (the undrained limit): p against
  depth for P2–P1 and equal-order P1–P1, with and without the projection stabilisation
  (`stability_undrained.png`; test `equal_order_pressure_oscillates_in_the_undrained_limit`).
* remodelling: the homogeneous relaxation scene, σ_zz(t) with the implicit and the explicit
  remodelling update at Δt = 50 and 200 s against Δt = 0.5 s (`stability_remodelling.png`;
  tests `explicit_remodelling_update_fails_at_large_steps`, `relaxation_large_steps_stay_bounded`).
* steps: the remodelling experiment (`remodel_40`) with the hold's steps capped at
  Δt_max = 0.125 s (the seed paper's limit), 2, 5 and 10 s: force against time, and F(35 s) and
  the final H/W against the 0.125 s run (`stability_steps.png`, `stability_steps.csv`).

Every run is a case of the store DIR/<group>/cases (`poroplast sweep`; resumable).
"""
import argparse
import csv
import sys
from pathlib import Path

from poroplast_tools.cases import rank_options, run_cases, use_rank_options
from poroplast_tools.history import at, history


def run(scene, overrides, group, ranks):
    """One case of DIR/<group> (skipped if complete): its run directory, or exits on failure."""
    [(case, r)] = run_cases(scene, [overrides], [], group, ranks)
    if r["status"] != "ok":
        sys.exit(f"stability.py: {case} failed: {r['error']}")
    return case


def finish(fig, ax, path, title, xlabel, ylabel):
    """Labels, legend, and the figure written to `path`."""
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=120)


def undrained(root, plt):
    import h5py
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    # Drawn last on top: the default.
    variants = [("P1-P1", 0, "P1–P1, no stabilisation"), ("P2-P1", 0, "P2–P1, no stabilisation"),
                ("P1-P1", 4, "P1–P1, stabilised"), ("P2-P1", 4, "P2–P1, stabilised (default)")]
    for el, c, label in variants:
        out = run("terzaghi", [("time.t_end", "1e-6"), ("time.dt", "1e-6"), ("fem.element", f'"{el}"'),
                               ("fem.stabilisation", str(c))], root / "undrained", 1)
        with h5py.File(out / "fields.h5", "r") as f:
            z = f["mesh/coordinates"][:, 2]
            p = f["fields/p/000001"][:]
        ax.plot(p, z, ".", ms=3, label=f"{label}: p in [{p.min():.2f}, {p.max():.2f}]")
    ax.axvline(1.0, color="k", lw=0.6, ls="--")
    finish(fig, ax, root / "stability_undrained.png", "Terzaghi, first step 1e-6 s (undrained limit)",
           "p / load after the first step (exact: 1, 0 at the drained top)", "z (µm)")
    plt.close(fig)


def remodelling(root, plt):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ref = history(run("relaxation", [("time.t_end", "1000"), ("time.dt_max", "0.5")], root / "remodelling", 1))
    ax.plot(ref["time"], ref["stress_zz"], "k-", lw=1, label="Δt ≤ 0.5 s (reference)")
    for dt, mark in (("50", "o"), ("200", "s")):
        for integ in ("implicit", "explicit"):
            h = history(run("relaxation", [("time.t_end", "1000"), ("time.dt", dt), ("time.dt_max", dt),
                                           ("time.growth", "1.0"), ("time.land_on", "[]"),
                                           ("material.remodelling.integrator", f'"{integ}"')],
                            root / "remodelling", 1))
            ax.plot(h["time"], h["stress_zz"], mark + ("-" if integ == "implicit" else "--"), ms=4,
                    label=f"{integ}, Δt = {dt} s")
    finish(fig, ax, root / "stability_remodelling.png", "Homogeneous relaxation: remodelling update at large steps",
           "t (s)", "σ_zz (kPa)")
    plt.close(fig)


def steps(root, plt, ranks):
    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    rows, ref = [], None
    for dt_max in ("0.125", "2", "5", "10"):
        h = history(run("remodel_40", [("time.dt_max", dt_max), ("output.fields", "false")], root / "steps", ranks))
        f35, hw = at(h, "force_total_mg", 35.0), h["height"][-1] / h["width"][-1]
        ref = ref or (f35, hw)
        rows.append({"dt_max": dt_max, "steps": len(h["time"]) - 1, "largest_dt": max(h["dt"]),
                     "F35_mg": f35, "F35_error": f35 / ref[0] - 1, "final_HW": hw, "HW_error": hw - ref[1]})
        ax.plot(h["time"], h["force_total_mg"], "-" if dt_max == "0.125" else "o-", ms=3, lw=1,
                label=f"Δt_max = {dt_max} s ({len(h['time']) - 1} steps)")
    with open(root / "stability_steps.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        w.writerows(rows)
    for r in rows:
        print(f"dt_max {r['dt_max']:>5} s: {r['steps']} steps, F(35 s) {r['F35_mg']:.4f} mg "
              f"({100 * r['F35_error']:+.2f}%), final H/W {r['final_HW']:.5f} ({r['HW_error']:+.5f})")
    finish(fig, ax, root / "stability_steps.png", "remodel_40 with long steps in the hold", "t (s)",
           "force on the upper plate (mg)")
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dir", required=True)
    ap.add_argument("--only", nargs="+", choices=["undrained", "remodelling", "steps"],
                    default=["undrained", "remodelling", "steps"])
    rank_options(ap)
    a = ap.parse_args()
    use_rank_options(a)
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    root = Path(a.dir)
    root.mkdir(parents=True, exist_ok=True)
    if "undrained" in a.only:
        undrained(root, plt)
    if "remodelling" in a.only:
        remodelling(root, plt)
    if "steps" in a.only:
        steps(root, plt, a.ranks)
    print(f"figures in {root}")


if __name__ == "__main__":
    main()
