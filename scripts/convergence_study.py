"""Convergence study: mesh levels × time-step levels, Richardson extrapolation.

Runs a scene at mesh sizes h (mesh.params.h, with the other sizes — h_pole, h_edge, from the
scene or --set — scaled in proportion) and time-step scales s (every step scaled by s: time.dt,
time.dt_max and time.error_tolerance multiplied by s, time.growth raised to the power s;
`runner.refined_steps`): each mesh level at one step level and each step level on one mesh (a
cross; --full: every combination), as one batch through `scripts/runner.py` (one `poroplast
sweep` on --ranks ranks, --ranks-per-case each: default 1 on a meridian, all for 3-D; completed
cases are skipped, so an interrupted study continues). For each observable it estimates

  * the observed orders p_h (from the three finest meshes, at the steps --mesh-steps, default the
    finest) and p_t (from the three finest Δt, on the mesh --time-mesh, default the finest),
  * the extrapolated value: with errors additive in h and Δt, Q(h, s) = Q* + E_h(h) + E_t(s),
    Richardson on the mesh sequence gives A = Q* + E_t(S) and on the step sequence
    B = Q* + E_h(H), so Q* = A + B − Q(H, S), with A = Q(h_f, S) + (Q(h_f, S) − Q(h_c, S))/(r_h^p_h − 1)
    and B likewise (f: finest, c: next coarser; H = --time-mesh, S = --mesh-steps). With both at
    the finest levels this is the usual Q_ff + both corrections. The step levels can then be
    refined on a cheaper mesh than the finest (the cross term h^p Δt^q is neglected; docs/studies.md
    measures it). The error bar is 1.25 × the two corrections (Roache's grid convergence index
    with observed orders). Where an
    order is not observed — the differences do not shrink monotonically, or the order falls
    outside [0.5, 4] — the formal order is used instead (--formal-h 2, --formal-t 1: P2–P1 and
    backward Euler), the safety factor is 3, and the bar is at least the spread of the two
    finest levels; convergence.csv says which (`order_h`, `order_t`: observed or formal),
  * the error of every case against Q*.

Writes STUDY/summary.csv (the runner's), STUDY/convergence.csv (observable, Q*, error bar,
p_h, p_t, the finest mesh's value at the mesh sequence's steps), STUDY/errors.csv (every case's error per observable), and
STUDY/conv_<observable>.png (error against h per Δt level, and against Δt per mesh).

    python3 scripts/convergence_study.py reference --h 30,25,20,15 --dt-scale 1,0.5,0.25,0.125 \\
        --dir studies/conv_reference [--time-mesh 20] [--mesh-steps 0.25] [--full]
        [--set KEY=VALUE ...] [--observe ...] [--ranks 2] [--ranks-per-case K] [--no-sweep]
"""
import argparse
import csv
import math
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import study  # noqa: E402
import runner  # noqa: E402
from runner import (SIZES, h_levels, refined_steps, run_cases, scene_values, solve_order,  # noqa: E402,F401
                    write_rows)


def correction(q_coarse, q_fine, ratio, p):
    if math.isnan(p):
        return float("nan")
    return (q_fine - q_coarse) / (ratio ** p - 1)


def extrapolate(qh, qt, q_junction, hs, ss, formal_h, formal_t):
    """Richardson on the mesh sequence qh (levels hs, at the step level S) and the step sequence qt
    (levels ss, on the mesh H), with q_junction = Q(H, S): Q*, its error bar, the observed orders
    and which orders were used (see the module docs)."""
    p_h = solve_order(qh[-3:], (hs[-3] / hs[-2], hs[-2] / hs[-1]))
    p_t = solve_order(qt[-3:], (ss[-3] / ss[-2], ss[-2] / ss[-1]))
    ok = lambda p: 0.5 <= p <= 4.0  # NaN is not
    use_h, use_t = (p_h if ok(p_h) else formal_h), (p_t if ok(p_t) else formal_t)
    c_h = correction(qh[-2], qh[-1], hs[-2] / hs[-1], use_h)
    c_t = correction(qt[-2], qt[-1], ss[-2] / ss[-1], use_t)
    extrap = (qh[-1] + c_h) + (qt[-1] + c_t) - q_junction
    fs_h, fs_t = (1.25 if ok(p_h) else 3.0), (1.25 if ok(p_t) else 3.0)
    bar = fs_h * abs(c_h) + fs_t * abs(c_t)
    if not ok(p_h):
        bar = max(bar, abs(qh[-1] - qh[-2]))
    if not ok(p_t):
        bar = max(bar, abs(qt[-1] - qt[-2]))
    return {"extrapolated": extrap, "error_bar": bar, "p_h": p_h, "p_t": p_t,
            "order_h": "observed" if ok(p_h) else "formal", "order_t": "observed" if ok(p_t) else "formal",
            "finest": qh[-1]}


def cross(scene, hs, ss, sets, H, S, full=False):
    """The cases of a study: (h, s, overrides) for each mesh level at the steps S and each step
    level on the mesh H (every combination with `full`). `sets` are the study's --set values
    ("KEY=VALUE"); sizes and time keys among them are scaled per level (`runner.h_levels`,
    `runner.refined_steps`), the rest returned as the fixed (key, value) overrides of every case."""
    t = scene_values(scene)
    given = {k: v for k, v in (s.split("=", 1) for s in sets) if k.startswith("time.")}   # scaled per level
    scaled = ("time.dt=", "time.dt_max=", "time.error_tolerance=", "time.growth=",
              *(f"mesh.params.{k}=" for k in SIZES))
    fixed = [tuple(s.split("=", 1)) for s in sets if not s.startswith(scaled)]
    cases = []
    for h, mesh in zip(hs, h_levels(scene, hs, sets)):
        for s in ss:
            if not (full or h == H or s == S):
                continue
            cases.append((h, s, mesh + [(k, f"{v:g}") for k, v in refined_steps(t["time"], given, s)]))
    return cases, fixed


def run_study(scene, hs, ss, sets, root, ranks, observe, H, S, full=False):
    """Runs the study's cases (completed ones are skipped): {(h, s): (case dir, result)}."""
    cases, fixed = cross(scene, hs, ss, sets, H, S, full)
    names = {tuple(ov): f"h = {h:g}, dt x {s:g}" for h, s, ov in cases}
    ran = run_cases(scene, [ov for _, _, ov in cases], fixed, Path(root), ranks, [], observe,
                          label=lambda ov: names[tuple(ov)])
    return {(h, s): r for (h, s, _), r in zip(cases, ran)}


def converge(values, hs, ss, H, S, formal_h=2.0, formal_t=1.0):
    """Extrapolates one observable from {(h, s): value} (NaN for a failed case) of a cross."""
    q = lambda h, s: values.get((h, s), float("nan"))
    return extrapolate([q(h, S) for h in hs], [q(H, s) for s in ss], q(H, S), hs, ss, formal_h, formal_t)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--h", required=True, help="mesh sizes, coarse to fine, e.g. 30,25,20,15")
    ap.add_argument("--dt-scale", default="1,0.5,0.25,0.125", help="time-step scales, coarse to fine")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--observe", nargs="+", default=study.DEFAULT_OBSERVE)
    ap.add_argument("--dir", required=True)
    runner.rank_options(ap)
    ap.add_argument("--formal-h", type=float, default=2.0)
    ap.add_argument("--formal-t", type=float, default=1.0)
    ap.add_argument("--time-mesh", type=float, help="the mesh h of the step sequence (default: the finest)")
    ap.add_argument("--mesh-steps", type=float, help="the step scale of the mesh sequence (default: the finest)")
    ap.add_argument("--full", action="store_true", help="every mesh level at every step level")
    a = ap.parse_args()
    runner.use_rank_options(a)
    hs = [float(x) for x in a.h.split(",")]
    ss = [float(x) for x in a.dt_scale.split(",")]
    if len(hs) < 3 or len(ss) < 3:
        sys.exit("convergence_study.py: need at least 3 mesh and 3 time-step levels")
    H = hs[-1] if a.time_mesh is None else a.time_mesh
    S = ss[-1] if a.mesh_steps is None else a.mesh_steps
    if H not in hs or S not in ss:
        sys.exit(f"convergence_study.py: --time-mesh {H:g} must be one of --h and --mesh-steps {S:g} one of --dt-scale")
    root = Path(a.dir)
    root.mkdir(parents=True, exist_ok=True)
    results = {k: r for k, (_, r) in run_study(a.scene, hs, ss, a.set, root, a.ranks, a.observe, H, S,
                                                a.full).items()}

    with open(root / "summary.csv", "w", newline="") as f:
        cols = ["h", "dt_scale", "status"] + list(study.COUNTERS) + a.observe
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for (h, s), r in results.items():
            w.writerow({"h": h, "dt_scale": s, **{k: r.get(k, float("nan")) for k in cols[2:]}})

    ok = lambda o: {k: r.get(o, float("nan")) for k, r in results.items() if r["status"] == "ok"}
    rows = [{"observable": o, **converge(ok(o), hs, ss, H, S, a.formal_h, a.formal_t)} for o in a.observe]
    write_rows(root / "convergence.csv", rows)
    ref = {r["observable"]: r["extrapolated"] for r in rows}
    with open(root / "errors.csv", "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["h", "dt_scale", "wall_s"] + a.observe)
        for (h, s), r in results.items():
            w.writerow([h, s, r.get("wall_s", float("nan"))]
                       + [abs(r.get(o, float("nan")) - ref[o]) / abs(ref[o]) if ref[o] else float("nan")
                          for o in a.observe])
    print(f"{'observable':24} {'extrapolated':>14} {'± bar':>10} {'p_h':>6} {'p_t':>6} {'finest':>12}  orders used")
    for r in rows:
        print(f"{r['observable']:24} {r['extrapolated']:14.6g} {r['error_bar']:10.2g} {r['p_h']:6.2f} "
              f"{r['p_t']:6.2f} {r['finest']:12.6g}  h {r['order_h']}, dt {r['order_t']}")
    plot(root, hs, ss, results, a.observe, ref)


def plot(root, hs, ss, results, observe, ref):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    for o in observe:
        if not ref[o] or math.isnan(ref[o]):
            continue
        fig, (ax1, ax2) = plt.subplots(1, 2, figsize=(9, 3.6))
        err = lambda h, s: abs(results[(h, s)].get(o, float("nan")) - ref[o]) / abs(ref[o])
        for s in ss:
            x = [h for h in hs if (h, s) in results]
            if len(x) > 1:
                ax1.loglog(x, [err(h, s) for h in x], "o-", label=f"steps × {s:g}")
        for h in hs:
            x = [s for s in ss if (h, s) in results]
            if len(x) > 1:
                ax2.loglog(x, [err(h, s) for s in x], "s-", label=f"h = {h:g} µm")
        ax1.set_xlabel("h (µm)")
        ax2.set_xlabel("step scale (× the scene's steps)")
        for ax in (ax1, ax2):
            ax.set_ylabel(f"relative error of {o}")
            ax.grid(alpha=0.3, which="both")
            ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(root / ("conv_" + o.replace(":", "_").replace("/", "_over_").replace("@", "_at_") + ".png"), dpi=110)
        plt.close(fig)


if __name__ == "__main__":
    main()
