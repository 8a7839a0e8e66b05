"""The study runner: one home for what the study scripts share. Run the scripts from the
repository root after `cargo build --release` (or with POROPLAST_BIN set).

  * running: `run_case` (one case under mpirun: a scene, `--set` overrides, PETSc options, into
    CASE/run/, its log in CASE/log.txt and its result in CASE/case.json with the signature of what
    it ran), `run_cases` (many, the completed ones skipped: an interrupted study continues);
  * grids: `parse_grid` (a `--grid` axis), `grid_cases` (all combinations), `h_levels` (a mesh
    sweep: h with the other sizes scaled in proportion), `refined_steps` (a step sweep);
  * reading a run: `history`, `timings`, `at` (a column at time t), `observe` (max:, last:,
    COL@T, ... of a history);
  * orders: `solve_order` (the observed order of a sequence of levels, Richardson).
"""
import csv
import itertools
import json
import math
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(os.environ.get("POROPLAST_BIN", ROOT / "target" / "release" / "poroplast"))

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


def write_rows(path, rows, fields=None):
    """Rows (dicts) as a CSV file with a header: `fields` (default: the first row's keys; keys a row
    has beyond them are left out)."""
    with open(path, "w", newline="") as f:
        w = csv.DictWriter(f, fieldnames=fields or list(rows[0]), extrasaction="ignore")
        w.writeheader()
        w.writerows(rows)


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
    tm = timings(case_dir / "run")
    result = {"status": "ok", **{c: tm.get(k, float("nan")) for c, k in COUNTERS.items()}}
    h = history(case_dir / "run")
    result.update({o: observe(h, o) for o in observables})
    result["signature"] = signature(scene, overrides, sets, petsc)
    (case_dir / "case.json").write_text(json.dumps(result, indent=1))
    return result


def run_cases(scene, cases, sets, root, ranks, petsc=(), observables=(), label=None, names=None, weights=None):
    """Runs every case (a list of (key, value) overrides) into root/cases/<name>/ (`names`, default
    the overrides' slug), skipping the ones that completed, with progress and the ETA of the whole
    set. `scene` is one scene for all cases or a list, one per case; `weights` the cases' relative
    costs for the ETA (default equal). Returns (case dir, result) per case, in order.
    `label(case)` names a case in the progress lines (default: its name, else its overrides)."""
    shown = [label(c) for c in cases] if label else list(names) if names else \
        [" ".join(f"{k}={v}" for k, v in c) or "(base scene)" for c in cases]
    scenes = [scene] * len(cases) if isinstance(scene, (str, Path)) else list(scene)
    weights = weights or [1.0] * len(cases)
    dirs = [root / "cases" / n for n in (names or [slug(c) for c in cases])]
    prior = [completed(d, signature(s, c, sets, petsc), observables) for d, s, c in zip(dirs, scenes, cases)]
    todo = sum(1 for r in prior if r is None)
    print(f"{root}: {len(cases)} cases, {len(cases) - todo} already complete, {todo} to run "
          f"on {ranks} rank(s)", flush=True)
    out, t0, done, left = [], time.time(), 0.0, sum(w for w, r in zip(weights, prior) if r is None)
    for n, (case, s, cdir, result, w, name) in enumerate(zip(cases, scenes, dirs, prior, weights, shown), 1):
        if result is not None:
            print(f"[{n}/{len(cases)}] {name}: complete, skipped", flush=True)
        else:
            start = time.time()
            result = run_case(s, case, sets, cdir, ranks, petsc, observables)
            done, left = done + w, left - w
            eta = (time.time() - t0) / done * left
            print(f"[{n}/{len(cases)}] {name}: {result['status']} in {time.time() - start:.1f} s"
                  f"{'' if result['status'] == 'ok' else ' — ' + result['error']}"
                  f"  [{time.time() - t0:.0f} s, eta {eta:.0f} s]", flush=True)
        out.append((cdir, result))
    return out


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
