"""Parameter studies as batch jobs.

One scene, a grid of `--set` overrides: every combination is a case, run under mpirun (2 ranks
by default) into its own directory. A case that completed with the same scene, `--set` values and
PETSc options is skipped (another `--set` runs it again), so an interrupted study
continues where it stopped (a failed case is tried again). Writes

  STUDY/summary.csv      one row per case: the overrides, status, wall time, steps, step cuts,
                         Newton and Krylov iterations, dofs, and the observables
  STUDY/<observable>.png each observable against the first grid key (a line per combination
                         of the other keys)
  STUDY/curve_<col>.png  with --curves COL: COL(t) of every case on one figure (the paper's
                         force–time figures)
  STUDY/cases/<case>/    the case's run directory (run/), its log and result (case.json)

    python3 scripts/study.py reference --grid mesh.params.h=20,15 --grid plates.compression=0.2,0.3 \\
        --dir studies/h_u [--set time.t_end=60] [--observe max:force_total_mg force_total_mg@35] \\
        [--ranks 2] [-- PETSC OPTIONS]

A grid axis is `KEY=V1,V2,...`, or `K1,K2=A1:A2,B1:B2,...` for keys that change together (e.g.
the radius with the mesh and the plates). Observables (columns of history.csv): `max:COL`, `min:COL`, `last:COL`, `last:A/B` (a ratio,
e.g. last:height/width), `COL@T` (interpolated at time T), `zero:COL` (the first time COL falls
from positive to zero or below). Default, for the plates experiment: peak force, F(35 s),
p(X_U) at 5 and 30 s, its zero crossing, final H/W. Run from the repository root after
`cargo build --release`.
"""
import argparse
import csv
import itertools
import json
import math
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
import labels  # noqa: E402
from _runner import BIN, env  # noqa: E402

DEFAULT_OBSERVE = ["max:force_total_mg", "force_total_mg@35", "probe_p@5", "probe_p@30", "zero:probe_p",
                   "last:height/width"]
# summary.csv column <- timings.txt key
COUNTERS = {"wall_s": "total", "steps": "steps", "step_cuts": "step_cuts", "newton_its": "newton_its",
            "ksp_its": "ksp_its", "dofs": "dofs"}


def parse_grid(spec):
    """KEY=V1,V2,... or, for keys that vary together, K1,K2=A1:A2,B1:B2,... (one axis)."""
    key, _, values = spec.partition("=")
    keys = [k.strip() for k in key.split(",")]
    if not all(keys) or not values:
        sys.exit(f"study.py: --grid {spec}: expected KEY=V1,V2,... or K1,K2=A1:A2,B1:B2,...")
    points = [[x.strip() for x in v.split(":")] if len(keys) > 1 else [v.strip()] for v in values.split(",")]
    if any(len(p) != len(keys) for p in points):
        sys.exit(f"study.py: --grid {spec}: every value needs {len(keys)} parts separated by ':'")
    return keys, points


def slug(overrides):
    return "__".join(f"{k}-{v}" for k, v in overrides).replace("/", "_").replace(" ", "") or "base"


def history(path):
    rows = list(csv.DictReader(open(path)))
    return {k: [float(r[k]) for r in rows] for k in rows[0]} if rows else {}


def observe(h, spec):
    """The observable `spec` of a history (NaN if it does not apply)."""
    nan = float("nan")
    t = h.get("time", [])
    if spec.startswith(("max:", "min:", "last:", "zero:")):
        kind, col = spec.split(":", 1)
        if kind == "last" and "/" in col:
            a, b = col.split("/", 1)
            return h[a][-1] / h[b][-1] if a in h and b in h and h[b][-1] != 0 else nan
        if col not in h:
            return nan
        v = h[col]
        if kind == "zero":
            for i in range(1, len(v)):
                if v[i - 1] > 0 >= v[i]:
                    return t[i - 1] + (t[i] - t[i - 1]) * v[i - 1] / (v[i - 1] - v[i])
            return nan
        return {"max": max, "min": min, "last": lambda x: x[-1]}[kind](v)
    col, _, when = spec.partition("@")
    return at(h, col, float(when)) if col in h and when else nan


def at(h, col, when):
    """Column `col` of a history interpolated linearly at time `when` (NaN outside the run)."""
    t = h["time"]
    for i in range(1, len(t)):
        if t[i - 1] <= when <= t[i]:
            w = (when - t[i - 1]) / (t[i] - t[i - 1]) if t[i] > t[i - 1] else 1.0
            return h[col][i - 1] + w * (h[col][i] - h[col][i - 1])
    return float("nan")


def timings(path):
    out = {}
    for line in open(path):
        if " = " in line:
            k, v = line.split(" = ", 1)
            try:
                out[k.strip()] = float(v)
            except ValueError:
                pass
    return out


def signature(scene, overrides, sets, petsc):
    """What a case ran: the scene, every --set, the PETSc options (not the rank count)."""
    return [scene, *(f"{k}={v}" for k, v in list(sets) + list(overrides)), *petsc]


def completed(case_dir, sig, observables=()):
    """The recorded result of a case that completed with the signature `sig`, or None. A result
    recorded before signatures were kept is taken as it is. Observables it lacks are read from
    its history.csv."""
    done = case_dir / "case.json"
    if not done.exists():
        return None
    result = json.loads(done.read_text())
    if result.get("signature", sig) != sig:
        return None
    missing = [o for o in observables if o not in result]
    if missing and result.get("status") == "ok" and (case_dir / "run" / "history.csv").exists():
        h = history(case_dir / "run" / "history.csv")
        result.update({o: observe(h, o) for o in missing})
    return result


def run_case(scene, overrides, sets, case_dir, ranks, petsc, observables=()):
    """Runs one case; returns its result (status ok or failed, and for ok: the counters of
    timings.txt and the observables), recorded in case_dir/case.json when it completed."""
    case_dir.mkdir(parents=True, exist_ok=True)
    cmd = ["mpirun", "-n", str(ranks), str(BIN), "run", scene, "--out", str(case_dir / "run"), "--force", "-q"]
    for k, v in list(sets) + list(overrides):
        cmd += ["--set", f"{k}={v}"]
    if petsc:
        cmd += ["--", *petsc]
    with open(case_dir / "log.txt", "w") as log:
        log.write(" ".join(cmd) + "\n")
        log.flush()
        p = subprocess.run(cmd, env=env(), stdout=log, stderr=subprocess.PIPE, text=True)
        log.write(p.stderr)
    if p.returncode != 0:
        err = next((l for l in p.stderr.splitlines() if l.startswith("poroplast: error:")), p.stderr.strip()[-300:])
        return {"status": "failed", "error": err}
    tm = timings(case_dir / "run" / "timings.txt")
    result = {"status": "ok", **{c: tm.get(k, float("nan")) for c, k in COUNTERS.items()}}
    h = history(case_dir / "run" / "history.csv")
    result.update({o: observe(h, o) for o in observables})
    result["signature"] = signature(scene, overrides, sets, petsc)
    (case_dir / "case.json").write_text(json.dumps(result, indent=1))
    return result


def run_cases(scene, cases, sets, root, ranks, petsc, observables=(), label=None):
    """Runs every case (a list of (key, value) overrides) into root/cases/<slug>/, skipping the
    ones that completed, with progress and the ETA of the whole set. Returns (case dir, result)
    per case, in order. `label(case)` names a case in the progress lines."""
    label = label or (lambda case: " ".join(f"{k}={v}" for k, v in case) or "(base scene)")
    dirs = [root / "cases" / slug(c) for c in cases]
    prior = [completed(d, signature(scene, c, sets, petsc), observables) for d, c in zip(dirs, cases)]
    todo = sum(1 for r in prior if r is None)
    print(f"{root}: {len(cases)} cases, {len(cases) - todo} already complete, {todo} to run "
          f"on {ranks} rank(s)", flush=True)
    out, ran, t0 = [], 0, time.time()
    for n, (case, cdir, result) in enumerate(zip(cases, dirs, prior), 1):
        if result is not None:
            print(f"[{n}/{len(cases)}] {label(case)}: complete, skipped", flush=True)
        else:
            start = time.time()
            result = run_case(scene, case, sets, cdir, ranks, petsc, observables)
            ran += 1
            eta = (time.time() - t0) / ran * (todo - ran)
            print(f"[{n}/{len(cases)}] {label(case)}: {result['status']} in {time.time() - start:.1f} s"
                  f"{'' if result['status'] == 'ok' else ' — ' + result['error']}"
                  f"  [{time.time() - t0:.0f} s, eta {eta:.0f} s]", flush=True)
        out.append((cdir, result))
    return out


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


def plot_curves(cases, study, columns):
    """COL(t) of every completed case, one figure per column."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    files = []
    for col in columns:
        fig, ax = plt.subplots(figsize=(6, 3.8))
        for case in cases:
            cdir = study / "cases" / slug(case)
            if not (cdir / "case.json").exists():
                continue
            h = history(cdir / "run" / "history.csv")
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
    ap.add_argument("--observe", nargs="+", default=DEFAULT_OBSERVE)
    ap.add_argument("--ranks", type=int, default=2)
    ap.add_argument("--no-plots", action="store_true")
    ap.add_argument("--curves", nargs="+", default=[], metavar="COL",
                    help="history columns to plot against time, one line per case")
    a = ap.parse_args(argv)
    if not BIN.exists():
        sys.exit(f"study.py: {BIN} not found: run `cargo build --release` first")
    study = Path(a.dir)
    study.mkdir(parents=True, exist_ok=True)
    axes = [parse_grid(g) for g in a.grid]
    sets = [tuple(s.split("=", 1)) for s in a.set]
    keys = [k for ks, _ in axes for k in ks]
    cases = [[kv for (ks, _), point in zip(axes, combo) for kv in zip(ks, point)]
             for combo in itertools.product(*[points for _, points in axes])]
    (study / "study.json").write_text(json.dumps(
        {"scene": a.scene, "grid": a.grid, "set": a.set, "observe": a.observe, "ranks": a.ranks,
         "petsc": petsc}, indent=1))

    rows = []
    for case, (_, result) in zip(cases, run_cases(a.scene, cases, sets, study, a.ranks, petsc, a.observe)):
        row = dict(case)
        row.update({"status": result["status"], "error": result.get("error", "")})
        for k in COUNTERS:
            row[k] = result.get(k, float("nan"))
        for o in a.observe:
            row[o] = result.get(o, float("nan"))
        rows.append(row)

    cols = keys + ["status"] + list(COUNTERS) + a.observe + ["error"]
    with open(study / "summary.csv", "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=cols)
        w.writeheader()
        for r in rows:
            w.writerow({k: r[k] for k in cols})
    # One line per axis: the first key of a linked axis stands for it.
    figs = [] if a.no_plots or not keys else plot(rows, [ks[0] for ks, _ in axes], a.observe, study)
    if not a.no_plots:
        figs += plot_curves(cases, study, a.curves)
    failed = sum(r["status"] != "ok" for r in rows)
    print(f"summary: {study / 'summary.csv'} ({len(rows)} cases, {failed} failed)"
          + (f"; figures: {', '.join(figs)}" if figs else ""))
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
