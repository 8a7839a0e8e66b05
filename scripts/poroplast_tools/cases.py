"""Running cases: the scripts write a study file and run `poroplast sweep`, which keeps the cases.

The cases of a script's study directory DIR live in the case store DIR/cases (`poroplast sweep
--cases-dir`): each case's run directory is named after what it runs — its scene, every
override, its PETSc options — and holds its outcome, case.toml, once it has ended. `run_cases`
writes the cases as a study file of [[case]] entries (DIR/sweeps/<hash>.toml), runs ONE
`mpirun -n RANKS poroplast sweep` for it, k ranks per case, and reads the results from the
sweep's summary.csv: a case that any earlier study of DIR completed is skipped, an interrupted
one resumes from its checkpoint, a failed one runs again. The sweep's lines go to the console
and to DIR/sweep.log; its directory DIR/sweeps/<hash>/ is removed once every case has ended
(what stays is the store). `--no-sweep`: one `mpirun -n k poroplast sweep` per case, one after
another. Nothing here evaluates observables: the sweep does (`observe`), and the results carry
them as summary.csv has them.

Run the scripts from the repository root after `cargo build --release` (or with POROPLAST_BIN).
"""
import csv
import functools
import hashlib
import json
import math
import os
import re
import shutil
import subprocess
import sys
import threading
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent.parent
BIN = Path(os.environ.get("POROPLAST_BIN",
                         Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target")) / "release" / "poroplast"))
# The defaults of run_cases' `sweep` and `ranks_per_case` (see there): a script's --no-sweep and
# --ranks-per-case, set once by `use_rank_options`; a call that passes them is not affected.
_DEFAULTS = {"sweep": os.environ.get("POROPLAST_SWEEP", "1") != "0", "ranks_per_case": None}
_LOG_LOCK = threading.Lock()   # DIR/sweep.log, shared by the threads of calibrate.py --jobs


def env():
    """The environment of the scripts' mpirun (Open MPI as root, shared memory and TCP only)."""
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


class SceneError(Exception):
    """The solver refused a scene or an override (its message), or could not be run;
    `old_binary`: it does not have the subcommand asked for (built before it)."""

    def __init__(self, message, old_binary=False):
        super().__init__(message)
        self.old_binary = old_binary


NO_SUBCOMMAND = "unrecognized subcommand"    # clap's words for a binary built before a subcommand


def ask(args, what):
    """The standard output of `poroplast ARGS` (a question that needs no MPI: columns, case,
    show --explain); SceneError with the solver's message when it refuses, or when it cannot be
    run. `what`: the command, for the messages."""
    try:
        p = subprocess.run([str(BIN)] + list(args), capture_output=True, text=True, env=env(), timeout=600)
    except FileNotFoundError:
        raise SceneError(f"no poroplast binary at {BIN}: build it (cargo build --release) or set POROPLAST_BIN")
    except OSError as e:
        raise SceneError(f"cannot run {BIN}: {e.strerror}")
    except subprocess.TimeoutExpired:
        raise SceneError(f"`poroplast {what}` did not answer in 600 s")
    if p.returncode != 0:
        if NO_SUBCOMMAND in p.stderr:
            raise SceneError(f"{BIN} has no `{args[0]}` subcommand: rebuild it (cargo build --release)",
                             old_binary=True)
        lines = [ln.strip() for ln in p.stderr.splitlines() if ln.strip()]
        said = [ln for ln in lines if ln.startswith("poroplast: error:")] or lines[-1:]
        raise SceneError(" ".join(ln.removeprefix("poroplast: error:").strip() for ln in said)
                         or f"`poroplast {what}` failed (exit code {p.returncode})")
    return p.stdout


def _set_args(sets):
    return [a for k, v in sets for a in ("--set", f"{k}={v}")]


def scene_columns(scene, sets):
    """The history.csv columns of `scene` under the overrides `sets` ((key, value) pairs), as
    `poroplast columns SCENE --set ...` prints them (one per line, after loading and validating
    the scene: the one check that a scene and its overrides load, without a mesh); None from a
    binary without that subcommand. SceneError with the solver's message when it refuses."""
    try:
        out = ask(["columns", _scene_arg(scene)] + _set_args(sets), f"columns {scene}")
    except SceneError as e:
        if e.old_binary:
            return None
        raise
    return [ln.strip() for ln in out.splitlines() if ln.strip() and " " not in ln.strip()]


def resolved_scene(scene, sets=()):
    """`scene` with the overrides `sets` ((key, value) pairs) as a run resolves it — every value
    a run uses, the mesh sizes in µm among them — as a dict: `poroplast show --explain`'s TOML.
    SceneError with the solver's message when it refuses."""
    import tomllib
    return tomllib.loads(ask(["show", "--explain", _scene_arg(scene)] + _set_args(sets), f"show --explain {scene}"))


def consolidation_coefficient(scene):
    """c = k (λ + 2µ) of a linear scene's material (µm²/s; λ = 2µν/(1 − 2ν)), from its values."""
    m = scene_values(scene)["material"]
    k = m.get("permeability", m.get("k0"))
    lam = 2 * m["mu"] * m["nu"] / (1 - 2 * m["nu"])
    return k * (lam + 2 * m["mu"])


# ---------------------------------------------------------------- the scripts' rank options

def rank_options(ap, ranks=2):
    """The scripts' rank options: --ranks (the study's MPI ranks), --ranks-per-case, --no-sweep."""
    ap.add_argument("--ranks", type=int, default=ranks,
                    help=f"MPI ranks of the study: the cases to run go to one `mpirun -n RANKS poroplast sweep` "
                         f"(default {ranks})")
    ap.add_argument("--ranks-per-case", type=int, metavar="K",
                    help="ranks of each case, RANKS/K cases at a time (K divides RANKS; default: 1 for "
                         "axisymmetric cases, RANKS for 3-D ones, raised while there are fewer cases than groups)")
    ap.add_argument("--no-sweep", action="store_true",
                    help="one `mpirun -n K` per case, one after another (K: --ranks-per-case, default RANKS) "
                         "(also POROPLAST_SWEEP=0)")


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


def choose_ranks_per_case(ranks, scenes, cases, sets, given=None):
    """The ranks of each case of a batch on `ranks` ranks: `given` if set, else 1 when every case
    is axisymmetric (small cases: one per rank is fastest) and all ranks otherwise, raised to the
    next divisor of `ranks` while the groups outnumber the cases."""
    if given:
        return given
    k = 1 if all(axisymmetric(s, c, sets) for s, c in zip(scenes, cases)) else ranks
    while ranks // k > max(len(cases), 1):
        k = next(d for d in range(k + 1, ranks + 1) if ranks % d == 0)
    return k


# ---------------------------------------------------------------- running

def _toml_list(xs):
    return "[" + ", ".join(json.dumps(str(x)) for x in xs) + "]"


def _scene_arg(scene):
    """A scene as the sweep names it: a file as its absolute path, else a shipped scene's name."""
    return str(Path(scene).resolve()) if Path(scene).exists() else str(scene)


def study_text(scenes, cases, sets, petsc=(), observe=None):
    """The STUDY.toml of a batch: a [[case]] list, each case with its scene and overrides
    ((key, value) pairs); the common overrides `sets` and the PETSc options as the study's;
    `observe` the summary's observables (None: the sweep's default list)."""
    lines = ["# cases of a study script (scripts/poroplast_tools/cases.py)", 'name = "cases"',
             f"set = {_toml_list(f'{k}={v}' for k, v in sets)}", f"petsc = {_toml_list(petsc)}"]
    if observe is not None:
        lines.append(f"observe = {_toml_list(observe)}")
    for scene, case in zip(scenes, cases):
        lines += ["", "[[case]]", f"scene = {json.dumps(_scene_arg(scene))}",
                  f"set = {_toml_list(f'{k}={v}' for k, v in case)}"]
    return "\n".join(lines) + "\n"


def check_layout(root):
    """Refuses a study directory of the scripts' earlier layout (DIR/cases/<case>/case.json and
    run/, kept by the scripts themselves): its runs are not reused."""
    old = next(iter(sorted(Path(root).glob("cases/*/case.json"))), None)
    if old is not None:
        sys.exit(f"{root}: holds cases of the scripts' earlier layout ({old.relative_to(root)}: each case in "
                 f"cases/<case>/run/ with case.json); the cases are now kept by `poroplast sweep` "
                 f"(cases/<case>-<key>/ with case.toml) and those are not reused: move {root} aside (its runs "
                 f"stay readable there) or choose another directory")


def run_cases(scene, cases, sets, root, ranks, petsc=(), observe=None, sweep=None, ranks_per_case=None,
              counts=None):
    """Runs every case (a list of (key, value) overrides, after the common `sets`) in the case
    store root/cases, the completed ones skipped; returns (run directory, result) per case, in
    order. `scene` is one scene for all cases or a list, one per case. A result is the case's
    row of the sweep's summary.csv: "status" (ok, failed), "error", and every number after the
    status (the counters wall_s, dofs, steps, step_cuts, newton_its, ksp_its and the observables
    `observe`, default the sweep's list) as a float, NaN where empty. The cases run as ONE sweep
    (`mpirun -n ranks poroplast sweep`, `ranks_per_case` ranks each, default as
    `choose_ranks_per_case` chooses) or, with `sweep` False, one sweep per case on
    `ranks_per_case` (default `ranks`) ranks; both default to the script's --no-sweep and
    --ranks-per-case (`use_rank_options`). `counts`: a dict whose "ran" grows by the number of
    cases the sweeps had to run."""
    root = Path(root)
    check_layout(root)
    sweep = _DEFAULTS["sweep"] if sweep is None else sweep
    fixed = _DEFAULTS["ranks_per_case"] if ranks_per_case is None else ranks_per_case
    scenes = [scene] * len(cases) if isinstance(scene, (str, Path)) else list(scene)
    if sweep:
        k = choose_ranks_per_case(ranks, scenes, cases, sets, fixed)
        rows = _sweep(root, study_text(scenes, cases, sets, petsc, observe), ranks, k, counts)
    else:
        k = fixed or ranks
        rows = [row for s, c in zip(scenes, cases)
                for row in _sweep(root, study_text([s], [c], sets, petsc, observe), k, k, counts)]
    return [_result(row) for row in rows]


def _result(row):
    """(run directory, result) of a summary.csv row (see run_cases)."""
    out = {"status": row["status"], "error": row.get("error", "")}
    numbers = False
    for key, value in row.items():
        if key == "status":
            numbers = True
        elif numbers and key not in ("error", "dir"):
            out[key] = float(value) if value not in ("", None) else math.nan
    return Path(row["dir"]), out


TO_RUN = re.compile(r"^sweep .*: \d+ cases, \d+ already complete, (\d+) to run")


def _sweep(root, text, ranks, k, counts=None):
    """Runs the study `text` as `mpirun -n ranks poroplast sweep -k k` (on 1 rank the binary
    alone) into root/sweeps/<hash>/ with the store root/cases; returns its summary rows (dir
    made absolute)."""
    sweeps = root / "sweeps"
    sweeps.mkdir(parents=True, exist_ok=True)
    name = hashlib.sha1(text.encode()).hexdigest()[:12]
    study, out = sweeps / f"{name}.toml", sweeps / name
    if not study.exists() or study.read_text() != text:
        study.write_text(text)
    # One rank is the binary alone (an MPI singleton): mpirun adds 0.4 s to every sweep, and 2 s
    # more when a case fails (it waits before ending the job).
    launch = [] if ranks == 1 else ["mpirun", "-n", str(ranks)]
    cmd = launch + [str(BIN), "sweep", str(study), "--out", str(out),
                    "--cases-dir", str(root / "cases"), "--ranks-per-case", str(k)]
    errors, lines = [], []
    with subprocess.Popen(cmd, env=env(), stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                          bufsize=1) as p:
        for line in p.stdout:
            if not line.startswith("summary: "):     # the sweep's own summary: read below, then removed
                print(line, end="", flush=True)
            lines.append(line)
            if line.startswith("poroplast: error:"):
                errors.append(line.strip())
            m = TO_RUN.match(line)
            if m and counts is not None:
                counts["ran"] = counts.get("ran", 0) + int(m.group(1))
    with _LOG_LOCK, open(root / "sweep.log", "a") as log:
        log.write(f"\n$ {' '.join(cmd)}\n" + "".join(lines))
    if p.returncode == 75:
        sys.exit(f"{root}: the sweep was stopped by a signal; the same command continues it")
    summary = out / "summary.csv"
    if not summary.exists():
        sys.exit(f"{root}: the sweep ended before running any case"
                 + (f": {errors[-1]}" if errors else f" (exit code {p.returncode}; see {root / 'sweep.log'})"))
    with open(summary) as f:
        rows = list(csv.DictReader(f))
    for r in rows:
        r["dir"] = str(out / r["dir"])
    if all(r["status"] in ("ok", "failed") for r in rows):
        shutil.rmtree(out, ignore_errors=True)
        study.unlink(missing_ok=True)
    return rows


def find_case(root, scene, overrides, sets=(), petsc=()):
    """The run directory of the completed case in the store root/cases, or None: what run_cases
    would return without running anything. The binary finds it (`poroplast case ... --cases-dir`):
    a case is its scene (the text of a file included: a case run before the file was edited is
    another), its overrides (`sets`, then `overrides`) and its PETSc options. SceneError when the
    solver refuses the scene or an override."""
    import tomllib
    store = Path(root) / "cases"
    if not store.is_dir():
        return None
    args = ["case", _scene_arg(scene)] + _set_args(list(sets) + list(overrides)) + ["--cases-dir", str(store)]
    found = tomllib.loads(ask(args + ["--"] + list(petsc), f"case {scene}"))
    return Path(found["dir"]) if found["status"] == "ok" else None
