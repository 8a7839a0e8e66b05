#!/usr/bin/env python3
"""Observed convergence orders of the verification problems under h- and Δt-refinement.

Terzaghi (column H = 100 µm): errors of the sealed-bottom pressure and of the settlement at
t* = 10 s (c t*/H² = 0.12) against the exact series.
  * h-study: h = 20, 10, 5 µm with BDF2 and small steps, so the time error is negligible;
  * Δt-study: backward Euler with constant steps Δt = 2, 1, 0.5, 0.25 s on h = 5 µm.
Cryer (R = 100 µm, --cryer): maximum centre-pressure error over 1 s <= t <= 12 s (rise, peak,
decay), h = R/4, R/8, R/12 with BDF2 and Δt <= 0.05 s.
Prints a table per study with the observed order between successive levels.

    python3 scripts/convergence.py [--cryer] [--ranks 2]
"""
import argparse
from _runner import run, at_time, order

BDF2 = ("-ts_type", "bdf", "-ts_bdf_order", "2", "-ts_adapt_type", "none")


def table(title, rows, ratio_key):
    print(f"\n{title}")
    print(" ".join(f"{h:>12}" for h in rows[0].keys()) + "   orders")
    prev = None
    for r in rows:
        line = " ".join(f"{v:>12.4e}" if isinstance(v, float) else f"{v:>12}" for v in r.values())
        if prev:
            errs = [k for k in r if k.startswith("err")]
            ratio = prev[ratio_key] / r[ratio_key]
            line += "   " + " ".join(f"{k}: {order(prev[k], r[k], ratio):.2f}" for k in errs)
        print(line)
        prev = r


def terzaghi(ranks):
    ts = 10.0
    rows = []
    for h in [20.0, 10.0, 5.0]:
        ov = [f"mesh.params.h={h}", f"time.t_end={ts}", "time.dt=1e-3", "time.growth=1.2", "time.dt_max=0.02"]
        hist, tm = run(None, ranks, BDF2, scene="terzaghi", overrides=ov)
        rows.append({"h": h, "dofs": int(tm["dofs"]),
                     "err_p": abs(at_time(hist, ts, "p_bottom") - at_time(hist, ts, "p_bottom_exact")),
                     "err_settl": abs(at_time(hist, ts, "settlement") - at_time(hist, ts, "settlement_exact"))})
    table(f"Terzaghi h-refinement (BDF2, dt <= 0.02 s), errors at t = {ts} s", rows, "h")
    rows = []
    for dt in [2.0, 1.0, 0.5, 0.25]:
        ov = ["mesh.params.h=5.0", "time.t_end=20.0", f"time.dt={dt}", "time.growth=1.0", f"time.dt_max={dt}"]
        hist, tm = run(None, ranks, scene="terzaghi", overrides=ov)
        rows.append({"dt": dt, "steps": len(hist) - 1,
                     "err_p": abs(at_time(hist, 20.0, "p_bottom") - at_time(hist, 20.0, "p_bottom_exact")),
                     "err_settl": abs(at_time(hist, 20.0, "settlement") - at_time(hist, 20.0, "settlement_exact"))})
    table("Terzaghi Δt-refinement (backward Euler, constant Δt, h = 5), errors at t = 20 s", rows, "dt")


def cryer(ranks):
    t0, t1 = 1.0, 12.0
    rows = []
    for n in [4, 8, 12]:
        h = 100.0 / n
        ov = [f"mesh.params.h={h}", f"mesh.params.h_pole={h}", f"time.t_end={t1}", "time.dt=1e-3",
              "time.growth=1.2", "time.dt_max=0.05"]
        hist, tm = run(None, ranks, BDF2, scene="cryer", overrides=ov)
        # The numerical curve crosses the exact one, so errors at a single time are noisy:
        # use the maximum over the window covering the rise, the peak and the decay.
        err = max(abs(float(r["p_center"]) - float(r["p_center_exact"])) for r in hist if t0 <= float(r["time"]) <= t1)
        rows.append({"h": h, "dofs": int(tm["dofs"]), "err_pc": err})
    table(f"Cryer h-refinement (BDF2, dt <= 0.05 s), max centre-pressure error for {t0} <= t <= {t1} s", rows, "h")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cryer", action="store_true", help="also the (slower) Cryer h-study")
    ap.add_argument("--ranks", type=int, default=2)
    a = ap.parse_args()
    terzaghi(a.ranks)
    if a.cryer:
        cryer(a.ranks)
