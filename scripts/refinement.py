#!/usr/bin/env python3
"""Mesh refinement of the reference experiment (no remodelling, quarter model, t_end = 40 s):
peak force, force at the end of the hold (t = 35 s), drained plateau (a static solve with no
fluid at the held plate position, the limit of a long hold), max penetration between nodes,
and cost, for a sequence of meshes. Prints the sequence and the changes between meshes; the
peak should change by a shrinking amount.

    python3 scripts/refinement.py [--ranks 2] [--sizes 25:8,20:6,15:5]
"""
import argparse
from _runner import run, at_time


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--sizes", default="25:8,20:6,15:5", help="h:h_pole pairs, coarse to fine")
    a = ap.parse_args()
    print(f"{'h':>5} {'h_pole':>6} {'dofs':>7} {'steps':>5} {'newton':>6} {'ksp':>6} {'wall s':>7} "
          f"{'peak mg':>8} {'F(35) mg':>8} {'drained mg':>10} {'pen um':>7}")
    prev = None
    for pair in a.sizes.split(","):
        h, hp = (float(x) for x in pair.split(":"))
        mesh = [f"mesh.params.h={h}", f"mesh.params.h_pole={hp}"]
        rows, tim = run(None, ranks=a.ranks, scene="reference", overrides=mesh)
        f = [float(r["force_total_mg"]) for r in rows]
        peak = max(f)
        f35 = at_time(rows, 35.0, "force_total_mg")
        pen = max(float(r["max_penetration"]) for r in rows)
        # The drained plateau: no fluid, the plates held (their release after the run's end).
        drained = mesh + ["material.drained=true", "plates.t_end=100000.0", "time.t_end=5.0", "time.dt=0.25"]
        drows, _ = run(None, ranks=a.ranks, scene="reference", overrides=drained)
        fd = float(drows[-1]["force_total_mg"])
        print(f"{h:5.1f} {hp:6.1f} {int(tim['dofs']):7d} {int(tim['steps']):5d} {int(tim['newton_its']):6d} "
              f"{int(tim['ksp_its']):6d} {tim['total']:7.1f} {peak:8.3f} {f35:8.3f} {fd:10.3f} {pen:7.3f}", flush=True)
        if prev:
            print(f"      change of peak {peak - prev[0]:+.3f} mg, F(35) {f35 - prev[1]:+.3f} mg, drained {fd - prev[2]:+.3f} mg")
        prev = (peak, f35, fd)


if __name__ == "__main__":
    main()
