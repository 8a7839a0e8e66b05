"""Parameter studies as batch jobs.

One scene, a grid of `--set` overrides: every combination is a case. The cases go to one
`mpirun -n RANKS poroplast sweep` (RANKS = --ranks, 2 by default; --ranks-per-case K each: by
default 1 on a meridian, RANKS for 3-D; --no-sweep: one mpirun per case), which keeps them in
the case store STUDY/cases: a case that completed with the same scene, `--set` values and PETSc
options is skipped (another `--set` runs it again), so an interrupted study continues where it
stopped (a failed case is tried again), and studies into one STUDY share their cases. Writes

  STUDY/summary.csv      one row per case: the overrides, status, wall time, dofs, steps, step
                         cuts, Newton and Krylov iterations, the observables, error, run directory
  STUDY/<observable>.png each observable against the first grid key (a line per combination
                         of the other keys)
  STUDY/curve_<col>.png  with --curves COL: COL(t) of every case on one figure (the paper's
                         force–time figures)
  STUDY/cases/<case>-<key>/  each case's run directory, with its outcome (case.toml)

    python3 scripts/study.py reference --grid mesh.params.h=20,15 --grid plates.compression=0.2,0.3 \\
        --dir studies/h_u [--set time.t_end=60] [--observe max:force_total_mg force_total_mg@35] \\
        [--ranks 2] [--ranks-per-case K] [--no-sweep] [-- PETSC OPTIONS]

A grid axis is `KEY=V1,V2,...`, or `K1,K2=A1:A2,B1:B2,...` for keys that change together (e.g.
the radius with the mesh and the plates). Observables (columns of history.csv): `max:COL`, `min:COL`, `last:COL`, `last:A/B` (a ratio,
e.g. last:height/width), `COL@T` (interpolated at time T), `zero:COL` (the first time COL falls
from positive to zero or below); against an exact solution (a column COL_exact): `err:COL@T`
(|COL − COL_exact| at T), `maxerr:COL@T0:T1` (the largest over T0 ≤ t ≤ T1); `--orders` prints
the observables along the first grid key with the observed order between successive levels.
The sweep evaluates the observables (the one grammar: src/io/observable.rs); its default, for
the plates experiment: peak force, F(35 s), p(X_U) at 5 and 30 s, its zero crossing, final H/W.
Run from the repository root after `cargo build --release`.
"""
import argparse
import csv
import json
import math
import sys
from pathlib import Path

from poroplast_tools import labels
from poroplast_tools.cases import BIN, rank_options, run_cases, use_rank_options
from poroplast_tools.history import history
from poroplast_tools.levels import grid_cases, parse_grid
from poroplast_tools.richardson import solve_order


def plot(rows, keys, observables, study):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    x_key, others = keys[0], keys[1:]
    try:
        xs = sorted({float(r[x_key]) * labels.axis_factor(x_key) for r in rows})
    except ValueError:
        return []
    files = []
    for obs in observables:
        fig, ax = plt.subplots(figsize=(5.5, 3.8))
        groups = sorted({tuple(r[k] for k in others) for r in rows})
        for g in groups:
            pts = [(float(r[x_key]) * labels.axis_factor(x_key), r[obs]) for r in rows
                   if tuple(r[k] for k in others) == g and r["status"] == "ok" and not math.isnan(r[obs])]
            pts.sort()
            if pts:
                label = labels.case(list(zip(others, g))) or None
                ax.plot([p[0] for p in pts], [p[1] for p in pts], "o-", label=label)
        ax.set_xlabel(labels.key(x_key))
        ax.set_ylabel(labels.observable(obs))
        ax.grid(alpha=0.3)
        if others and groups:
            ax.legend(fontsize=7)
        if len(xs) > 1:
            ax.set_xticks(xs)
        fig.tight_layout()
        name = obs.replace(":", "_").replace("/", "_over_").replace("@", "_at_") + ".png"
        fig.savefig(study / name, dpi=120)
        plt.close(fig)
        files.append(name)
    return files


def plot_curves(cases, done, study, columns):
    """COL(t) of every completed case, one figure per column."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    files = []
    for col in columns:
        fig, ax = plt.subplots(figsize=(6, 3.8))
        for case, (cdir, result) in zip(cases, done):
            if result["status"] != "ok":
                continue
            h = history(cdir)
            if col in h:
                ax.plot(h["time"], h[col], label=labels.case(case) or "base")
        ax.set_xlabel("time (s)")
        ax.set_ylabel(labels.column(col))
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
        fig.tight_layout()
        name = f"curve_{col.replace('/', '_')}.png"
        fig.savefig(study / name, dpi=120)
        plt.close(fig)
        files.append(name)
    return files


def print_orders(rows, keys, observables):
    """The observables as errors along the first grid key (a table per combination of the other
    keys), with the observed order between successive levels: log(e_i / e_i+1) / log(x_i / x_i+1)
    (`richardson.solve_order` with the limit 0)."""
    x_key, others = keys[0], keys[1:]
    for g in sorted({tuple(r[k] for k in others) for r in rows}):
        sel = [r for r in rows if tuple(r[k] for k in others) == g and r["status"] == "ok"]
        print(f"\n{x_key} levels" + (f" at {labels.case(list(zip(others, g)))}" if others else ""))
        print(f"{x_key:>16} " + " ".join(f"{o:>24}" for o in observables) + "   orders")
        for i, r in enumerate(sel):
            line = f"{r[x_key]:>16} " + " ".join(f"{r[o]:>24.4e}" for o in observables)
            if i:
                ratio = float(sel[i - 1][x_key]) / float(r[x_key])
                line += "   " + " ".join(f"{solve_order([sel[i - 1][o], r[o]], [ratio], limit=0.0):.2f}"
                                         for o in observables)
            print(line)


def main():
    argv = sys.argv[1:]
    petsc = []
    if "--" in argv:
        i = argv.index("--")
        argv, petsc = argv[:i], argv[i + 1:]
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", help="scene file or shipped scene name")
    ap.add_argument("--grid", action="append", default=[], metavar="KEY=V1,V2,...",
                    help="a grid axis (repeatable: the cases are all combinations)")
    ap.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="an override for every case")
    ap.add_argument("--dir", required=True, help="study directory (created; reused to continue)")
    ap.add_argument("--observe", nargs="+", default=None,
                    help="summary observables (default: the sweep's list, for the plates experiment)")
    rank_options(ap)
    ap.add_argument("--no-plots", action="store_true")
    ap.add_argument("--curves", nargs="+", default=[], metavar="COL",
                    help="history columns to plot against time, one line per case")
    ap.add_argument("--orders", action="store_true",
                    help="print each observable (an error: err:, maxerr:) per level of the first grid axis "
                         "with the observed order between successive levels")
    a = ap.parse_args(argv)
    use_rank_options(a)
    if not BIN.exists():
        sys.exit(f"study.py: {BIN} not found: run `cargo build --release` first")
    study = Path(a.dir)
    study.mkdir(parents=True, exist_ok=True)
    axes = [parse_grid(g) for g in a.grid]
    sets = [tuple(s.split("=", 1)) for s in a.set]
    keys = [k for ks, _ in axes for k in ks]
    cases = grid_cases(axes)
    (study / "study.json").write_text(json.dumps(
        {"scene": a.scene, "grid": a.grid, "set": a.set, "observe": a.observe, "ranks": a.ranks,
         "petsc": petsc}, indent=1))

    done = run_cases(a.scene, cases, sets, study, a.ranks, petsc, a.observe)
    # The summary's numbers: the counters, then the observables (every spec holds ':' or '@').
    numbers = [k for k in done[0][1] if k not in ("status", "error")] if done else []
    observables = [k for k in numbers if ":" in k or "@" in k]
    rows = []
    for case, (cdir, result) in zip(cases, done):
        row = dict(case)
        row.update(result)
        row["dir"] = cdir.relative_to(study.resolve()) if cdir.is_relative_to(study.resolve()) else cdir
        rows.append(row)

    cols = keys + ["status"] + numbers + ["error", "dir"]
    with open(study / "summary.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for r in rows:
            w.writerow({k: r[k] for k in cols})
    # One line per axis: the first key of a linked axis stands for it.
    figs = [] if a.no_plots or not keys else plot(rows, [ks[0] for ks, _ in axes], observables, study)
    if not a.no_plots:
        figs += plot_curves(cases, done, study, a.curves)
    if a.orders and axes:
        print_orders(rows, [ks[0] for ks, _ in axes], observables)
    failed = sum(r["status"] != "ok" for r in rows)
    print(f"summary: {study / 'summary.csv'} ({len(rows)} cases, {failed} failed)"
          + (f"; figures: {', '.join(figs)}" if figs else ""))
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
