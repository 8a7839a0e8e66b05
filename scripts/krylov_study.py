#!/usr/bin/env python3
"""Krylov iterations per linear solve of the default Schur-fieldsplit preconditioner as the
mesh is refined (h halves) and the time step shrinks (Δt 100× smaller), on Cryer's sphere.
Each case takes a few constant steps; the table shows iterations per Newton step (mean over
steps after the first), wall time per step, and DoFs.

    python3 scripts/krylov_study.py [--ranks 2] [--levels 4 8 16]
"""
import argparse
from _runner import run

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("--ranks", type=int, default=2)
ap.add_argument("--levels", type=int, nargs="+", default=[4, 8, 16], help="R/h values")
ap.add_argument("--steps", type=int, default=4)
a = ap.parse_args()

print(f"{'R/h':>5} {'dofs':>8} {'dt [s]':>8} {'c dt/h^2':>9} {'its/solve':>10} {'s/step':>8}")
for n in a.levels:
    h = 100.0 / n
    for dt in [1.0, 0.01]:
        ov = ["solver.preset=fieldsplit", f"mesh.params.h={h}", f"mesh.params.h_pole={h}",
              f"time.t_end={a.steps * dt}", f"time.dt={dt}", "time.growth=1.0", f"time.dt_max={dt}"]
        hist, tm = run(None, a.ranks, scene="cryer", overrides=ov)
        steps = hist[2:]
        its = sum(int(r["ksp_its"]) / max(1, int(r["newton_its"])) for r in steps) / len(steps)
        per = tm["solve_total"] / max(1, len(hist) - 1)
        print(f"{n:>5} {int(tm['dofs']):>8} {dt:>8.2g} {120.7 * dt / h**2:>9.3g} {its:>10.1f} {per:>8.2f}", flush=True)
