#!/usr/bin/env python3
"""Krylov iterations per linear solve of the default Schur-fieldsplit preconditioner as the
mesh is refined (h halves) and the time step shrinks (Δt 100× smaller), on Cryer's sphere.
Each case takes a few constant steps; the table shows iterations per Newton step (mean over
steps after the first), wall time per step, DoFs, and c Δt/h² (c = k (λ + 2µ), the scene's
consolidation coefficient). The cases are a grid (a mesh sweep by `levels.h_levels` × the step
sizes), one `poroplast sweep`, kept in the store DIR/cases/ and skipped when complete.

    python3 scripts/krylov_study.py [--ranks 2] [--levels 4 8 16] [--dt 1 0.01] [--dir studies/krylov]
"""
import argparse
from pathlib import Path

from poroplast_tools.cases import consolidation_coefficient, rank_options, run_cases, scene_values, use_rank_options
from poroplast_tools.history import history, timings
from poroplast_tools.levels import h_levels

SCENE = "cryer"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    rank_options(ap)
    ap.add_argument("--levels", type=int, nargs="+", default=[4, 8, 16], help="R/h values")
    ap.add_argument("--dt", type=float, nargs="+", default=[1.0, 0.01], help="the constant step sizes (s)")
    ap.add_argument("--steps", type=int, default=4)
    ap.add_argument("--dir", default="studies/krylov")
    a = ap.parse_args()
    use_rank_options(a)
    radius = scene_values(SCENE)["mesh"]["params"]["R"]
    c = consolidation_coefficient(SCENE)
    hs = [radius / n for n in a.levels]
    grid = [(n, h, dt, mesh + [("time.t_end", f"{a.steps * dt:g}"), ("time.dt", f"{dt:g}"),
                               ("time.growth", "1.0"), ("time.dt_max", f"{dt:g}")])
            for n, h, mesh in zip(a.levels, hs, h_levels(SCENE, hs)) for dt in a.dt]
    done = run_cases(SCENE, [ov for *_, ov in grid], [("solver.preset", "fieldsplit")], Path(a.dir), a.ranks)
    print(f"c = k (λ + 2µ) = {c:.4g} µm²/s ({SCENE})")
    print(f"{'R/h':>5} {'dofs':>8} {'dt [s]':>8} {'c dt/h^2':>9} {'its/solve':>10} {'s/step':>8}")
    for (n, h, dt, _), (cdir, r) in zip(grid, done):
        if r["status"] != "ok":
            print(f"{n:>5} failed: {r['error']}")
            continue
        hist, tm = history(cdir), timings(cdir)
        steps = list(zip(hist["ksp_its"][2:], hist["newton_its"][2:]))
        its = sum(k / max(1, nw) for k, nw in steps) / len(steps)
        per = tm["solve_total"] / max(1, len(hist["time"]) - 1)
        print(f"{n:>5} {int(tm['dofs']):>8} {dt:>8.2g} {c * dt / h**2:>9.3g} {its:>10.1f} {per:>8.2f}", flush=True)


if __name__ == "__main__":
    main()
