"""The study runner: one home for what the study scripts share. Run the scripts from the
repository root after `cargo build --release` (or with POROPLAST_BIN set).

  * running: `run_case` (one case under mpirun: a scene, `--set` overrides, PETSc options, into
    CASE/run/, its log in CASE/log.txt and its result in CASE/case.json with the signature of what
    it ran), `run_cases` (many, the completed ones skipped: an interrupted study continues; the
    cases to run go to ONE `mpirun -n RANKS poroplast sweep` — a batch, see `run_batch` — or,
    with `--no-sweep` / POROPLAST_SWEEP=0, one `mpirun` per case); `rank_options` and
    `use_rank_options` (the scripts' --ranks, --ranks-per-case, --no-sweep);
  * grids: `parse_grid` (a `--grid` axis), `grid_cases` (all combinations), `h_levels` (a mesh
    sweep: h with the other sizes scaled in proportion), `refined_steps` (a step sweep);
  * reading a run: `history`, `timings`, `at` (a column at time t), `observe` (max:, last:,
    COL@T, ... of a history);
  * orders: `solve_order` (the observed order of a sequence of levels, Richardson).
"""
import csv
import functools
import hashlib
import itertools
import json
import math
import os
import re
import shutil
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(os.environ.get("POROPLAST_BIN",
                         Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "release" / "poroplast"))
# The defaults of run_cases' `sweep` and `ranks_per_case` (see there): a script's --no-sweep and
# --ranks-per-case, set once by `use_rank_options`; a call that passes them is not affected.
_DEFAULTS = {"sweep": os.environ.get("POROPLAST_SWEEP", "1") != "0", "ranks_per_case": None}

# The converged level of the plates experiment (docs/performance.md): the meridian at h = 10 um
# with the surface and the poles at 2 um, no pressure stabilisation (its error is the largest on
# such meshes); with 1/8 of the scene's steps (`refined_steps(..., 0.125)`), every force within
# 0.1% of the converged value.
CONVERGED_LEVEL = ["mesh.geometry=axisymmetric", "mesh.params.h=10", "mesh.params.h_pole=2", "mesh.params.h_surf=2",
                   "mesh.params.w_surf=30", "fem.stabilisation=0"]
# A case's result (case.json, summary.csv column) <- timings.txt key
COUNTERS = {"wall_s": "total", "steps": "steps", "step_cuts": "step_cuts", "newton_its": "newton_its",
            "ksp_its": "ksp_its", "dofs": "dofs"}
SIZES = ("h_pole", "h_edge", "h_surf")   # mesh sizes besides h, scaled with it by h_levels


SHIPPED_REFERENCES = ROOT / "scripts" / "data" / "references.csv"


def references(path=SHIPPED_REFERENCES):
    """A references.csv (scripts/references.py) as {(case, observable): (extrapolated, error bar)}."""
    with open(path) as f:
        return {(r["case"], r["observable"]): (float(r["extrapolated"]), float(r["error_bar"]))
                for r in csv.DictReader(f)}


def write_rows(path, rows, fields=None):
    """Rows (dicts) as a CSV file with a header: `fields` (default: the first row's keys; keys a row
    has beyond them are left out)."""
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields or list(rows[0]), extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)


def write_atomic(path, text):
    """Writes `text` to `path` through a temporary file and `os.replace`: a reader (or an
    interrupted writer) sees the old file or the new one, never a truncated one."""
    path = Path(path)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    tmp.write_text(text)
    os.replace(tmp, path)


def env():
    e = dict(os.environ)
    if os.geteuid() == 0:
        e.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    e.update(OMPI_MCA_rmaps_base_oversubscribe="1", OMPI_MCA_btl="self,vader", OMPI_MCA_pml="ob1")
    return e


def scene_values(scene):
    """A scene (file or shipped name) as a dict, through `poroplast show` for shipped ones."""
    import tomllib
    p = Path(scene)
    text = p.read_text() if p.exists() else subprocess.run([str(BIN), "show", scene], check=True,
                                                          capture_output=True, text=True).stdout
    return tomllib.loads(text)


def consolidation_coefficient(scene):
    """c = k (λ + 2µ) of a linear scene's material (µm²/s; λ = 2µν/(1 − 2ν)), from its values."""
    m = scene_values(scene)["material"]
    k = m.get("permeability", m.get("k0"))
    lam = 2 * m["mu"] * m["nu"] / (1 - 2 * m["nu"])
    return k * (lam + 2 * m["mu"])


# ---------------------------------------------------------------- reading a run

def _file(path, name):
    path = Path(path)
    return path / name if path.is_dir() else path


def history(path):
    """history.csv (of a run directory, or the file) as {column: array}; rows that do not parse
    (a run still writing) are dropped; {} without rows."""
    with open(_file(path, "history.csv")) as f:
        r = csv.reader(f)
        head = next(r)
        rows = []
        for row in r:
            try:
                if len(row) == len(head):
                    rows.append([float(x) for x in row])
            except ValueError:
                pass
    if not rows:
        return {}
    a = np.array(rows)
    return {k: a[:, i] for i, k in enumerate(head)}


def timings(path):
    """timings.txt (of a run directory, or the file) as {key: number}; {} without the file."""
    out = {}
    path = _file(path, "timings.txt")
    if not path.exists():
        return out
    for line in open(path):
        if " = " in line:
            k, v = line.split(" = ", 1)
            try:
                out[k.strip()] = float(v)
            except ValueError:
                pass
    return out


def at(h, col, when):
    """Column `col` of a history interpolated linearly at time `when` (NaN outside the run or
    without the column)."""
    if col not in h or len(h.get("time", ())) == 0:
        return float("nan")
    t, v = h["time"], h[col]
    if not t[0] <= when <= t[-1]:
        return float("nan")
    i = max(1, int(np.searchsorted(t, when, side="left")))
    w = (when - t[i - 1]) / (t[i] - t[i - 1]) if t[i] > t[i - 1] else 1.0
    return float(v[i - 1] + w * (v[i] - v[i - 1]))


def observe(h, spec):
    """The observable `spec` of a history (NaN if it does not apply): max:COL, min:COL, last:COL,
    last:A/B, COL@T, zero:COL (the first time COL falls from positive to zero or below),
    err:COL@T (|COL − COL_exact| at T), maxerr:COL@T0:T1 (the largest |COL − COL_exact| over
    T0 ≤ t ≤ T1)."""
    nan = float("nan")
    t = h.get("time", [])
    if spec.startswith(("err:", "maxerr:")):
        kind, rest = spec.split(":", 1)
        col, _, when = rest.partition("@")
        if col not in h or col + "_exact" not in h or not when:
            return nan
        if kind == "err":
            return abs(at(h, col, float(when)) - at(h, col + "_exact", float(when)))
        t0, t1 = (float(x) for x in when.split(":"))
        e = [abs(a - b) for a, b, s in zip(h[col], h[col + "_exact"], t) if t0 <= s <= t1]
        return float(max(e)) if e else nan
    if spec.startswith(("max:", "min:", "last:", "zero:")):
        kind, col = spec.split(":", 1)
        if kind == "last" and "/" in col:
            a, b = col.split("/", 1)
            return float(h[a][-1] / h[b][-1]) if a in h and b in h and h[b][-1] != 0 else nan
        if col not in h:
            return nan
        v = h[col]
        if kind == "zero":
            for i in range(1, len(v)):
                if v[i - 1] > 0 >= v[i]:
                    return float(t[i - 1] + (t[i] - t[i - 1]) * v[i - 1] / (v[i - 1] - v[i]))
            return nan
        return float({"max": max, "min": min, "last": lambda x: x[-1]}[kind](v))
    col, _, when = spec.partition("@")
    return at(h, col, float(when)) if col in h and when else nan


# ---------------------------------------------------------------- running

def slug(overrides):
    return "__".join(f"{k}-{v}" for k, v in overrides).replace("/", "_").replace(" ", "") or "base"


def signature(scene, overrides, sets, petsc):
    """What a case ran: the scene, every --set, the PETSc options (not the rank count)."""
    return [str(scene), *(f"{k}={v}" for k, v in list(sets) + list(overrides)), *petsc]


def completed(case_dir, sig, observables=()):
    """The recorded result of a case that completed with the signature `sig`, or None (also for a
    case.json that does not parse). A result recorded before signatures were kept is taken as it
    is. The observables (`observe`; case.json records none, older ones may) are read from its
    history.csv."""
    try:
        result = json.loads((case_dir / "case.json").read_text())
    except (OSError, ValueError):
        return None       # none, or one that does not parse: the case is not complete
    if not isinstance(result, dict) or result.get("signature", sig) != sig:
        return None
    missing = [o for o in observables if o not in result]
    if missing and result.get("status") == "ok" and (case_dir / "run" / "history.csv").exists():
        h = history(case_dir / "run")
        result.update({o: observe(h, o) for o in missing})
    return result


def run_case(scene, overrides, sets, case_dir, ranks, petsc=(), observables=()):
    """Runs one case (always; `run_cases` skips completed ones) into case_dir/run; returns its
    result (status ok or failed, and for ok: the counters of timings.txt and the observables),
    recorded in case_dir/case.json when it completed."""
    case_dir.mkdir(parents=True, exist_ok=True)
    cmd = ["mpirun", "-n", str(ranks), str(BIN), "run", str(scene), "--out", str(case_dir / "run"), "--force", "-q"]
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
    _result(case_dir, scene, overrides, sets, petsc)
    return completed(case_dir, signature(scene, overrides, sets, petsc), observables)


def rank_options(ap, ranks=2):
    """The scripts' rank options: --ranks (the study's MPI ranks), --ranks-per-case, --no-sweep."""
    ap.add_argument("--ranks", type=int, default=ranks,
                    help=f"MPI ranks of the study: the cases to run go to one `mpirun -n RANKS poroplast sweep` "
                         f"(default {ranks})")
    ap.add_argument("--ranks-per-case", type=int, metavar="K",
                    help="ranks of each case, RANKS/K cases at a time (K divides RANKS; default: 1 for "
                         "axisymmetric cases, RANKS for 3-D ones, raised while there are fewer cases than groups)")
    ap.add_argument("--no-sweep", action="store_true",
                    help="one `mpirun -n K` per case, one after another (K: --ranks-per-case, default RANKS), "
                         "as before sweeps (also POROPLAST_SWEEP=0)")


def use_rank_options(a):
    """rank_options' arguments (checked) as the defaults of run_cases' `sweep` and
    `ranks_per_case`; returns them, {"sweep": ..., "ranks_per_case": ...}."""
    if a.ranks < 1 or (a.ranks_per_case is not None and (a.ranks_per_case < 1 or a.ranks % a.ranks_per_case)):
        sys.exit(f"--ranks-per-case {a.ranks_per_case} must divide --ranks {a.ranks}")
    _DEFAULTS["sweep"] = os.environ.get("POROPLAST_SWEEP", "1") != "0" and not a.no_sweep
    _DEFAULTS["ranks_per_case"] = a.ranks_per_case
    return dict(_DEFAULTS)


@functools.lru_cache(maxsize=None)
def _scene_geometry(scene):
    return scene_values(scene).get("mesh", {}).get("geometry", "solid")


def axisymmetric(scene, overrides, sets=()):
    """Whether a case runs on a meridian: its last mesh.geometry override, else its scene's."""
    given = [v for k, v in list(sets) + list(overrides) if k == "mesh.geometry"]
    geometry = given[-1].strip().strip("'\"") if given else _scene_geometry(str(scene))
    return geometry == "axisymmetric"


def choose_ranks_per_case(ranks, scenes, cases, sets, todo, given=None):
    """The ranks of each case of a batch of `todo` cases on `ranks` ranks: `given` if set, else 1
    when every case is axisymmetric (small cases: one per rank is fastest) and all ranks
    otherwise, raised to the next divisor of `ranks` while the groups outnumber the cases."""
    if given:
        return given
    k = 1 if all(axisymmetric(s, c, sets) for s, c in zip(scenes, cases)) else ranks
    while ranks // k > max(todo, 1):
        k = next(d for d in range(k + 1, ranks + 1) if ranks % d == 0)
    return k


def _result(case_dir, scene, overrides, sets, petsc):
    """The result of a case that completed into case_dir/run (its counters and signature; the
    observables are computed from its history as it is read, by `completed`), recorded in
    case_dir/case.json."""
    tm = timings(case_dir / "run")
    result = {"status": "ok", **{c: tm.get(k, float("nan")) for c, k in COUNTERS.items()}}
    result["signature"] = signature(scene, overrides, sets, petsc)
    write_atomic(case_dir / "case.json", json.dumps(result, indent=1))
    return result


def run_cases(scene, cases, sets, root, ranks, petsc=(), observables=(), label=None, names=None, weights=None,
              sweep=None, ranks_per_case=None):
    """Runs every case (a list of (key, value) overrides) into root/cases/<name>/ (`names`, default
    the overrides' slug), skipping the ones that completed, with progress and the ETA of the whole
    set. `scene` is one scene for all cases or a list, one per case; `weights` the cases' relative
    costs for the ETA (default equal). Returns (case dir, result) per case, in order.
    `label(case)` names a case in the progress lines (default: its name, else its overrides).
    The cases to run run as one batch (`run_batch`: one `mpirun -n ranks poroplast sweep`,
    `ranks_per_case` ranks each, default as `choose_ranks_per_case` chooses) or, with `sweep` False,
    one `mpirun -n ranks_per_case` (default `ranks`) per case. `sweep` and `ranks_per_case`
    default to the script's --no-sweep and --ranks-per-case (`use_rank_options`)."""
    sweep = _DEFAULTS["sweep"] if sweep is None else sweep
    fixed = _DEFAULTS["ranks_per_case"] if ranks_per_case is None else ranks_per_case
    shown = [label(c) for c in cases] if label else list(names) if names else \
        [" ".join(f"{k}={v}" for k, v in c) or "(base scene)" for c in cases]
    scenes = [scene] * len(cases) if isinstance(scene, (str, Path)) else list(scene)
    weights = weights or [1.0] * len(cases)
    dirs = [root / "cases" / n for n in (names or [slug(c) for c in cases])]
    harvest(root)      # cases an earlier (interrupted) sweep finished, with or without `sweep` now
    prior = [completed(d, signature(s, c, sets, petsc), observables) for d, s, c in zip(dirs, scenes, cases)]
    todo = sum(1 for r in prior if r is None)
    new = [i for i, r in enumerate(prior) if r is None]
    k = choose_ranks_per_case(ranks, [scenes[i] for i in new], [cases[i] for i in new], sets, todo, fixed) \
        if sweep else fixed or ranks
    how = f": one sweep, {ranks // k} case(s) at a time on {k} rank(s) each" if sweep and todo else \
        f", one mpirun -n {k} per case" if todo else ""
    print(f"{root}: {len(cases)} cases, {len(cases) - todo} already complete, {todo} to run "
          f"on {ranks} rank(s){how}", flush=True)
    out, t0, done, left = [], time.time(), 0.0, sum(w for w, r in zip(weights, prior) if r is None)

    def report(n, name, result, secs, w):
        nonlocal done, left
        done, left = done + w, left - w
        eta = (time.time() - t0) / done * left if done else 0.0
        print(f"[{n}/{len(cases)}] {name}: {result['status']} in {secs:.1f} s"
              f"{'' if result['status'] == 'ok' else ' — ' + result['error']}"
              f"  [{time.time() - t0:.0f} s, eta {eta:.0f} s]", flush=True)

    for n, (name, result) in enumerate(zip(shown, prior), 1):
        if result is not None:
            print(f"[{n}/{len(cases)}] {name}: complete, skipped", flush=True)
    if sweep and todo:
        batch = [(scenes[i], cases[i], dirs[i]) for i in new]
        ran = run_batch(root, batch, sets, ranks, k, petsc, observables,
                        lambda j, result, secs: report(new[j] + 1, shown[new[j]], result, secs, weights[new[j]]))
        prior = [r if r is not None else ran[new.index(i)] for i, r in enumerate(prior)]
    for n, (case, s, cdir, result, w, name) in enumerate(zip(cases, scenes, dirs, prior, weights, shown), 1):
        if result is None:
            start = time.time()
            result = run_case(s, case, sets, cdir, k, petsc, observables)
            report(n, name, result, time.time() - start, w)
        out.append((cdir, result))
    return out


# ---------------------------------------------------------------- batches: one sweep for many cases

MOVED = "moved.txt"     # in a batch's case directory whose run has been moved to the runner's place
SWEEP_LINE = re.compile(r"^sweep: case (\d+) .* (ok|FAILED) in ([0-9.]+) s")


def _toml_list(xs):
    return "[" + ", ".join(json.dumps(str(x)) for x in xs) + "]"


def batch_study(batch, sets, petsc):
    """The STUDY.toml of a batch: a [[case]] list, each case with its scene (a file as an absolute
    path) and overrides; the common --set values and PETSc options as the study's. No observables
    (`observe = []`): the runner computes them from each case's history (`observe`, one grammar),
    so they are neither part of the batch nor of what it is continued for."""
    arg = lambda s: str(Path(s).resolve()) if Path(s).exists() else str(s)
    lines = ["# A batch of scripts/runner.py: the cases of this study directory not yet complete.",
             "name = \"batch\"", f"set = {_toml_list(f'{k}={v}' for k, v in sets)}",
             f"petsc = {_toml_list(petsc)}", "observe = []"]
    for scene, case, _ in batch:
        lines += ["", "[[case]]", f"scene = {json.dumps(arg(scene))}",
                  f"set = {_toml_list(f'{k}={v}' for k, v in case)}"]
    return "\n".join(lines) + "\n"


def _sweep_case_dirs(out):
    """{case index: its run directory} of a sweep directory."""
    cases = out / "cases"
    return {int(d.name.split("_", 1)[0]): d for d in cases.iterdir()} if cases.is_dir() else {}


def _outcome(case_toml):
    import tomllib
    try:
        return tomllib.loads(case_toml.read_text())
    except (OSError, ValueError):
        return None


def _entries(meta):
    """A batch's case entries, the arguments of each as (scene, overrides, sets, petsc) (batches
    written before observables left them carry those fifth: dropped); None if it does not parse."""
    try:
        entries = json.loads(meta.read_text())["cases"]
        return [{"dir": e["dir"], "args": e["args"][:4]} for e in entries]
    except (OSError, ValueError, KeyError, TypeError):
        return None


def _batches(root):
    """The batches of root/sweeps/: (meta file, its case entries or None if it does not parse)."""
    return [(m, _entries(m)) for m in sorted((root / "sweeps").glob("batch-*.json"))]


def _drop_batch(meta):
    shutil.rmtree(meta.with_suffix(""), ignore_errors=True)
    meta.unlink(missing_ok=True)
    meta.with_suffix(".toml").unlink(missing_ok=True)


_HARVEST_LOCK = threading.RLock()   # run_cases of threads (calibrate.py --jobs) harvest one at a time
HARVESTING = "harvesting.txt"   # in a case directory while a sweep's run is moved there: where from


def _stub(run):
    """Whether a sweep's case directory holds only the outcome (what `harvest` leaves behind)."""
    names = {f.name for f in run.iterdir() if not f.name.endswith(".tmp")} if run.is_dir() else None
    return names is not None and names <= {"case.toml", MOVED}     # (.tmp: write_atomic's, interrupted)


def _same_file(a, b):
    try:
        return a.read_bytes() == b.read_bytes()
    except OSError:
        return False


def _harvest_case(root, sweep_dir, i, e, run):
    """Moves case i of a batch (entry `e`), which ended in the sweep's directory `run`, to its case
    directory; returns its result, or None if there is nothing to harvest. Safe to interrupt and
    to repeat: the run moves in ONE `os.replace`, the case's own place CASE/run is removed only
    while the sweep still holds the run that replaces it, the journal CASE/harvesting.txt names
    the sweep's directory until the bookkeeping is done (the result, the outcome left in the
    batch, MOVED last), and a repeat finishes what is missing."""
    cdir = root / e["dir"]
    dest, journal = cdir / "run", cdir / HARVESTING
    pending = journal.exists() and journal.read_text().strip() == str(run)     # moved, bookkeeping not done
    # Not to move: the outcome stub left in the batch (MOVED), or the stub of a failed case that a
    # continued batch is to run again (MOVED removed) while its run is still CASE/run.
    stub = _stub(run) and ((run / MOVED).exists() or _same_file(run / "case.toml", dest / "case.toml"))
    if run.is_dir() and not stub and not (pending and _stub(run)):   # the sweep's run, not moved yet
        outcome = _outcome(run / "case.toml")
        if outcome is None:
            return None                             # still running
        if _stub(run) and outcome.get("status") == "ok":   # its moved run is gone (CASE removed):
            shutil.rmtree(run)                              # a continued sweep runs it again
            return None
        cdir.mkdir(parents=True, exist_ok=True)
        (cdir / "case.json").unlink(missing_ok=True)
        write_atomic(journal, f"{run}\n")
        if dest.exists():
            shutil.rmtree(dest)                     # an earlier run of the case: the sweep's replaces it
        os.replace(run, dest)
    elif (run / MOVED).exists() and not pending:
        return None                                 # harvested already
    outcome = _outcome(dest / "case.toml")
    if outcome is None:                             # the moved run is gone (the case directory removed)
        if run.is_dir():
            shutil.rmtree(run)                      # so that a continued sweep runs the case again
        journal.unlink(missing_ok=True)
        return None
    ok = outcome.get("status") == "ok"
    error = f"poroplast: error: {outcome.get('error', '')}"
    (cdir / "log.txt").write_text(f"case {i} of the sweep {sweep_dir} (its output: "
                                  f"{root / 'sweeps' / 'sweep.log'})\n" + ("" if ok else error + "\n"))
    if ok:
        scene, overrides, sets, petsc = e["args"]
        result = _result(cdir, scene, [tuple(x) for x in overrides], [tuple(x) for x in sets], petsc)
    else:
        result = {"status": "failed", "error": error}
    run.mkdir(parents=True, exist_ok=True)          # the outcome stays in the batch: a continued sweep skips it
    write_atomic(run / "case.toml", (dest / "case.toml").read_text())
    write_atomic(run / MOVED, f"moved to {dest}\n")
    journal.unlink(missing_ok=True)
    return result


def harvest(root, only=None, remove=True, index=None):
    """Moves the cases that ended in the batches of root/sweeps/ (all, or the batch `only`) to the
    runner's places: a case's run directory to CASE/run and, if it completed, its result to
    CASE/case.json (with the signature of what it ran); its outcome (case.toml) stays in the
    batch, so that a sweep continued there skips it. Safe to interrupt and repeat
    (`_harvest_case`). With `remove`, a batch all of whose cases ended is removed; one with
    unfinished cases stays, for a run_cases that wants exactly those to continue it. `index`:
    only that case of the batch (while its sweep runs: the one it has just reported). Returns
    {case dir: result} of the cases moved."""
    with _HARVEST_LOCK:
        return _harvest(root, only, remove, index)


def _harvest(root, only, remove, index):
    out = {}
    for meta, entries in _batches(root) if only is None else [(only, _entries(only))]:
        if entries is None:
            continue
        sweep_dir = meta.with_suffix("")
        runs = _sweep_case_dirs(sweep_dir)
        ended = 0
        for i, e in enumerate(entries):
            if index not in (None, i):
                continue
            journal = root / e["dir"] / HARVESTING
            run = runs.get(i)
            if run is None and journal.exists():    # interrupted between the move and the bookkeeping
                run = Path(journal.read_text().strip())
                if run.parent != sweep_dir / "cases":
                    continue
            if run is None:
                continue
            result = _harvest_case(root, sweep_dir, i, e, run)
            if result is not None:
                out[root / e["dir"]] = result
            if _outcome(run / "case.toml") is not None and (run / MOVED).exists():
                ended += 1
        if remove and index is None and ended == len(entries):
            _drop_batch(meta)
    return out


def run_batch(root, batch, sets, ranks, k, petsc, observables, report):
    """Runs the cases of `batch` ((scene, overrides, case dir) each) as one study under ONE
    `mpirun -n ranks poroplast sweep --ranks-per-case k` in root/sweeps/batch-<hash>/, then moves
    them to their case directories (`harvest`). A batch an earlier call left unfinished with
    exactly these cases to run is continued (its interrupted cases resume from their checkpoints);
    other unfinished batches are removed. The observables are not part of a batch (`batch_study`):
    they are computed from the histories as the results are read. `report(j, result, secs)` is called as the j-th case of
    `batch` ends. The sweep's output goes to root/sweeps/sweep.log. Returns the results in batch
    order."""
    sweeps = root / "sweeps"
    sweeps.mkdir(parents=True, exist_ok=True)
    entries = [{"dir": str(d.relative_to(root)), "args": [str(s), [list(x) for x in c], [list(x) for x in sets],
                                                          list(petsc)]} for s, c, d in batch]
    meta = None
    for m, old in _batches(root):
        if old is None:
            _drop_batch(m)
            continue
        runs = _sweep_case_dirs(m.with_suffix(""))
        left = [e for i, e in enumerate(old)
                if not (i in runs and (_outcome(runs[i] / "case.toml") or {}).get("status") == "ok")]
        if meta is None and sorted(left, key=json.dumps) == sorted(entries, key=json.dumps):
            meta, order = m, [e["dir"] for e in old]      # continued: its failed cases run again
            for i, run in runs.items():
                if (_outcome(run / "case.toml") or {}).get("status") != "ok":
                    (run / MOVED).unlink(missing_ok=True)
        else:
            _drop_batch(m)
    if meta is None:
        text = batch_study(batch, sets, petsc)
        meta = sweeps / f"batch-{hashlib.sha1(text.encode()).hexdigest()[:12]}.json"
        write_atomic(meta.with_suffix(".toml"), text)
        write_atomic(meta, json.dumps({"cases": entries}, indent=1))
        order = [e["dir"] for e in entries]
    position = {d: j for j, (_, _, d) in enumerate(batch)}
    of_index = lambda i: position.get(root / order[i])      # sweep case index -> batch position
    cmd = ["mpirun", "-n", str(ranks), str(BIN), "sweep", str(meta.with_suffix(".toml")),
           "--out", str(meta.with_suffix("")), "--ranks-per-case", str(k)]
    with open(sweeps / "sweep.log", "a") as log:
        log.write(f"\n# {time.strftime('%Y-%m-%d %H:%M:%S')}: {' '.join(cmd)}\n")
        log.flush()
        start = log.tell()
        p = subprocess.Popen(cmd, env=env(), stdout=subprocess.PIPE, stderr=log, text=True, bufsize=1)
        ended, seen = {}, set()      # case dir -> result, as the cases are moved; batch positions reported
        try:
            for line in p.stdout:
                log.write(line)
                log.flush()
                m = SWEEP_LINE.match(line)
                if m and of_index(int(m.group(1))) is not None and of_index(int(m.group(1))) not in seen:
                    j = of_index(int(m.group(1)))
                    seen.add(j)
                    ended.update(harvest(root, meta, remove=False, index=int(m.group(1))))
                    report(j, ended.get(batch[j][2]) or {"status": "failed", "error": line.strip()},
                           float(m.group(3)))
        finally:
            p.wait()
    harvest(root, meta)
    results = []
    for s, c, d in batch:
        r = completed(d, signature(s, c, sets, petsc), observables)
        if r is None:
            log = (d / "log.txt").read_text().splitlines() if (d / "log.txt").exists() else []
            err = next((line for line in log if line.startswith("poroplast: error:")), None) or \
                _last_error(sweeps / "sweep.log", start) or \
                f"the sweep exited with {p.returncode} before this case ended"
            r = {"status": "failed", "error": err}
        results.append(r)
    if p.returncode == 75:
        sys.exit(f"{root}: the sweep was stopped by a signal; the same command continues it")
    return results


def _last_error(log, start):
    """The last error line of a log from byte `start` on."""
    with open(log) as f:
        f.seek(start)
        lines = [line for line in f.read().splitlines() if line.startswith("poroplast: error:")]
    return lines[-1] if lines else None


# ---------------------------------------------------------------- grids

def parse_grid(spec):
    """A grid axis: KEY=V1,V2,... or, for keys that vary together, K1,K2=A1:A2,B1:B2,...;
    returns (keys, points)."""
    key, _, values = spec.partition("=")
    keys = [k.strip() for k in key.split(",")]
    if not all(keys) or not values:
        sys.exit(f"--grid {spec}: expected KEY=V1,V2,... or K1,K2=A1:A2,B1:B2,...")
    points = [[x.strip() for x in v.split(":")] if len(keys) > 1 else [v.strip()] for v in values.split(",")]
    if any(len(p) != len(keys) for p in points):
        sys.exit(f"--grid {spec}: every value needs {len(keys)} parts separated by ':'")
    return keys, points


def grid_cases(axes):
    """Every combination of the axes' points (parse_grid's), each a list of (key, value)."""
    return [[kv for (ks, _), point in zip(axes, combo) for kv in zip(ks, point)]
            for combo in itertools.product(*[points for _, points in axes])]


def h_levels(scene, hs, sets=()):
    """A mesh sweep: for each h of `hs`, the (key, value) overrides mesh.params.h = h and the
    other sizes (SIZES: h_pole, h_edge, h_surf — the scene's, or those of `sets`, "KEY=VALUE",
    at the scene's h) scaled in proportion."""
    params = scene_values(scene).get("mesh", {}).get("params", {})
    h0 = params.get("h")
    if h0 is None:
        sys.exit(f"{scene}: the scene's mesh has no params.h")
    sizes = {k: v for k, v in params.items() if k in SIZES}
    for s in sets:
        k, v = s.split("=", 1)
        if k.startswith("mesh.params.") and k[12:] in SIZES:
            sizes[k[12:]] = float(v)
    return [[("mesh.params.h", f"{h:g}")] + [(f"mesh.params.{k}", f"{v * h / h0:g}") for k, v in sizes.items()]
            for h in hs]


def refined_steps(scene_time, given, s):
    """("time.KEY", value) overrides that scale every step of a scene by s: dt, dt_max and
    error_tolerance times s, and the growth factor raised to the power s, so that the geometric
    sequence is refined too (scaling dt alone, the growth kept, only shifts the sequence: with
    growth 1.3 the ramp keeps about as many steps). `scene_time` is the scene's [time] table,
    `given` the "time.KEY" overrides that replace its values."""
    out = []
    for key in ("dt", "dt_max", "error_tolerance"):
        v = given.get(f"time.{key}", scene_time.get(key))
        if v is not None:
            out.append((f"time.{key}", float(v) * s))
    g = given.get("time.growth", scene_time.get("growth"))
    if g is not None:
        out.append(("time.growth", float(g) ** s))
    return out


# ---------------------------------------------------------------- orders

def solve_order(q, r, limit=None):
    """Observed order of convergence of the values q (coarse → fine) on levels with ratios r
    (h_i / h_{i+1}), errors C h^p assumed. Without `limit`: from three values (Richardson: the
    limit unknown), NaN if the differences do not shrink monotonically. With the limit known
    (an exact solution): from the last two values' errors against it."""
    if limit is not None:
        e0, e1 = abs(q[-2] - limit), abs(q[-1] - limit)
        return math.log(e0 / e1) / math.log(r[-1]) if e0 > 0 and e1 > 0 else float("nan")
    d1, d2 = q[0] - q[1], q[1] - q[2]
    if d1 == 0 or d2 == 0 or d1 * d2 < 0 or abs(d2) >= abs(d1) * 1.0:
        return float("nan")
    # (r1^p − 1) r2^p / (r2^p − 1) = d1/d2 (constant C h^p errors); bisection in p.
    f = lambda p: (r[0] ** p - 1) * r[1] ** p / (r[1] ** p - 1) - abs(d1 / d2)
    lo, hi = 0.05, 8.0
    if f(lo) > 0 or f(hi) < 0:
        return float("nan")
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if f(mid) < 0 else (lo, mid)
    return 0.5 * (lo + hi)
