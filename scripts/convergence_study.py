"""Convergence study: mesh levels × time-step levels, Richardson extrapolation.

Runs a scene at mesh sizes h (mesh.params.h, with the other sizes — h_pole, h_edge, h_surf —
scaled in proportion from those a run with the study's --set overrides would mesh with: a size
given in µm, in the scene or by --set, wins over the scene's mesh.relative_sizes, so `--set
mesh.params.h=10 --set mesh.params.h_pole=2` gives h_pole = 2.82 at h = 14.1; the log lists the
sizes each level uses and where they come from) and time-step scales s (every step scaled by s: time.dt,
time.dt_max and time.error_tolerance multiplied by s, time.growth raised to the power s;
`levels.refined_steps`): each mesh level at one step level and each step level on one mesh (a
cross; --full: every combination), as one batch (one `poroplast sweep` on --ranks ranks,
--ranks-per-case each: default 1 on a meridian, all for 3-D; its cases kept in STUDY/cases:
completed ones are skipped, so an interrupted study continues). For each observable (default:
the sweep's list) it estimates

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
  * the error of every case against Q*, as a fraction of |Q*|.

A level that fails is named with its likely cause: when it failed while settling under gravity or
in its first step, or its mesh is much finer than the levels that completed, its sizes (the mesh
level, not the material, is then the likely cause); the study then exits with 1.

The extrapolation is `poroplast_tools/richardson.py`'s. Writes STUDY/summary.csv (h, dt_scale,
status, the counters and observables of each case), STUDY/convergence.csv (observable, Q*, error bar,
p_h, p_t, the finest mesh's value at the mesh sequence's steps), STUDY/errors.csv (every case's relative error per observable, a fraction:
columns `<observable>_relerr_fraction`), STUDY/levels.txt (the sizes of each level, and each failed
level's cause), and
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

from poroplast_tools.cases import SceneError, rank_options, scene_columns, use_rank_options
from poroplast_tools.convergence import cross, failure_cause, run_study
from poroplast_tools.levels import describe_sizes
from poroplast_tools.richardson import converge
from poroplast_tools.tables import write_rows


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene")
    ap.add_argument("--h", required=True, help="mesh sizes, coarse to fine, e.g. 30,25,20,15")
    ap.add_argument("--dt-scale", default="1,0.5,0.25,0.125", help="time-step scales, coarse to fine")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE")
    ap.add_argument("--observe", nargs="+", default=None, help="observables (default: the sweep's list)")
    ap.add_argument("--dir", required=True)
    rank_options(ap)
    ap.add_argument("--formal-h", type=float, default=2.0)
    ap.add_argument("--formal-t", type=float, default=1.0)
    ap.add_argument("--time-mesh", type=float, help="the mesh h of the step sequence (default: the finest)")
    ap.add_argument("--mesh-steps", type=float, help="the step scale of the mesh sequence (default: the finest)")
    ap.add_argument("--full", action="store_true", help="every mesh level at every step level")
    a = ap.parse_args()
    use_rank_options(a)
    hs = [float(x) for x in a.h.split(",")]
    ss = [float(x) for x in a.dt_scale.split(",")]
    if len(hs) < 3 or len(ss) < 3:
        sys.exit("convergence_study.py: need at least 3 mesh and 3 time-step levels")
    H = hs[-1] if a.time_mesh is None else a.time_mesh
    S = ss[-1] if a.mesh_steps is None else a.mesh_steps
    if H not in hs or S not in ss:
        sys.exit(f"convergence_study.py: --time-mesh {H:g} must be one of --h and --mesh-steps {S:g} one of --dt-scale")
    root = Path(a.dir)
    check_scene(a.scene, a.set)
    sizes = describe_sizes(a.scene, hs, a.set)
    print("\n".join(sizes), flush=True)
    root.mkdir(parents=True, exist_ok=True)
    results = {k: r for k, (_, r) in run_study(a.scene, hs, ss, a.set, root, a.ranks, a.observe, H, S,
                                                a.full).items()}
    cases = cross(a.scene, hs, ss, a.set, H, S, a.full)[0]
    completed = [ov for h, s, ov in cases if results[(h, s)]["status"] == "ok"]
    causes = [failure_cause((h, s, ov), results[(h, s)].get("error", ""), completed)
              for h, s, ov in cases if results[(h, s)]["status"] != "ok"]
    errors = {results[(h, s)].get("error", "") for h, s, _ in cases}
    if not completed and len(errors) == 1:
        # One error for every level (a typo in a key, a scene that does not run): said once.
        causes = [f"every level failed: {failure_cause(cases[-1], errors.pop(), completed)}"]
    (root / "levels.txt").write_text("\n".join(sizes + causes) + "\n")
    if causes:
        print("\n".join(causes), file=sys.stderr, flush=True)
    if not completed:
        sys.exit(f"convergence_study.py: no level completed (above; also in {root / 'levels.txt'}): nothing to "
                 f"extrapolate")
    # The summary's numbers: the counters, then the observables (every spec holds ':' or '@').
    numbers = [k for k in next(iter(results.values())) if k not in ("status", "error")]
    observe = [k for k in numbers if ":" in k or "@" in k]

    with open(root / "summary.csv", "w", newline="") as f:
        cols = ["h", "dt_scale", "status"] + numbers
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for (h, s), r in results.items():
            w.writerow({"h": h, "dt_scale": s, **{k: r.get(k, float("nan")) for k in cols[2:]}})

    ok = lambda o: {k: r.get(o, float("nan")) for k, r in results.items() if r["status"] == "ok"}
    rows = [{"observable": o, **converge(ok(o), hs, ss, H, S, a.formal_h, a.formal_t)} for o in observe]
    write_rows(root / "convergence.csv", rows)
    ref = {r["observable"]: r["extrapolated"] for r in rows}
    with open(root / "errors.csv", "w", newline="") as f:
        w = csv.writer(f)
        # Relative errors |Q − Q*| / |Q*|: fractions (0.001 = 0.1%), as the column names say.
        w.writerow(["h", "dt_scale", "wall_s"] + [f"{o}_relerr_fraction" for o in observe])
        for (h, s), r in results.items():
            w.writerow([h, s, r.get("wall_s", float("nan"))]
                       + [abs(r.get(o, float("nan")) - ref[o]) / abs(ref[o]) if ref[o] else float("nan")
                          for o in observe])
    print(f"{'observable':24} {'extrapolated':>14} {'± bar':>10} {'p_h':>6} {'p_t':>6} {'finest':>12}  orders used")
    for r in rows:
        print(f"{r['observable']:24} {r['extrapolated']:14.6g} {r['error_bar']:10.2g} {r['p_h']:6.2f} "
              f"{r['p_t']:6.2f} {r['finest']:12.6g}  h {r['order_h']}, dt {r['order_t']}")
    plot(root, hs, ss, results, observe, ref)
    if causes:
        sys.exit(f"convergence_study.py: {len(causes)} of {len(cases)} levels failed (above; also in "
                 f"{root / 'levels.txt'}): the extrapolation uses the others, NaN where it needs them")


def check_scene(scene, sets):
    """Exits with the binary's message if the scene with the study's overrides does not load
    (an unknown scene or key, a bad value): before any size is read or any case launched."""
    try:
        scene_columns(scene, [tuple(s.split("=", 1)) if "=" in s else (s, "") for s in sets])
    except SceneError as e:
        sys.exit(f"convergence_study.py: {scene} with the study's --set does not load: {e}")


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
