#!/usr/bin/env python3
"""Timing benchmark: runs a scene several times on 1 and 2 ranks (optionally at several mesh
sizes) and prints medians of wall time, assembly and solve time, Newton/Krylov iterations per
step, time per DoF and step, and the 1→2-rank speed-up.

    python3 scripts/bench.py [--scene cryer] [--h 12.5 8.33] [--repeat 3] [--ranks 1 2]
"""
import argparse
import statistics
from _runner import scene_text, edit, run

ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
ap.add_argument("--scene", default="cryer")
ap.add_argument("--h", type=float, nargs="*", default=[], help="mesh sizes (mesh param h and h_pole)")
ap.add_argument("--repeat", type=int, default=3)
ap.add_argument("--ranks", type=int, nargs="+", default=[1, 2])
ap.add_argument("--t-end", type=float, default=None, help="shorten the run")
a = ap.parse_args()

base = scene_text(a.scene)
cases = a.h or [None]
print(f"{'h':>6} {'ranks':>5} {'dofs':>8} {'steps':>5} {'newton/st':>9} {'ksp/newton':>10} "
      f"{'wall[s]':>8} {'assem[s]':>8} {'solve[s]':>8} {'us/dof/st':>9} {'speed-up':>8}")
for h in cases:
    text = base
    if h is not None:
        import re
        m = re.search(r"params = \{([^}]*)\}", text)
        params = dict((k.strip(), float(v)) for k, v in (kv.split("=") for kv in m.group(1).split(",")))
        params["h"] = h
        if "h_pole" in params:
            params["h_pole"] = h
        text = edit(text, params=params)
    if a.t_end:
        text = edit(text, t_end=a.t_end)
    t1 = None
    for n in a.ranks:
        walls, assem, solve = [], [], []
        for _ in range(a.repeat):
            hist, tm = run(text, n)
            walls.append(tm["total"])
            assem.append(tm["residual_assembly"] + tm["jacobian_assembly"])
            solve.append(tm["linear_solve_and_other"])
        steps = len(hist) - 1
        newton = sum(int(r["newton_its"]) for r in hist[1:])
        ksp = sum(int(r["ksp_its"]) for r in hist[1:])
        w = statistics.median(walls)
        t1 = t1 or w
        print(f"{h if h else '-':>6} {n:>5} {int(tm['dofs']):>8} {steps:>5} {newton / steps:>9.2f} {ksp / max(newton, 1):>10.1f} "
              f"{w:>8.2f} {statistics.median(assem):>8.2f} {statistics.median(solve):>8.2f} "
              f"{1e6 * w / (tm['dofs'] * steps):>9.1f} {t1 / w:>8.2f}", flush=True)
