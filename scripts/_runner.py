"""Shared helpers for the study scripts: run poroplast (scene variants by `--set`) under mpirun,
read history.csv. Run the scripts from the repository root after `cargo build --release`."""
import csv
import os
import subprocess
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
BIN = Path(os.environ.get("POROPLAST_BIN", ROOT / "target" / "release" / "poroplast"))

# The converged level of the plates experiment (docs/performance.md): the meridian at h = 10 um
# with the surface and the poles at 2 um, no pressure stabilisation (its error is the largest on
# such meshes); with 1/8 of the scene's steps (`refined_steps(..., 0.125)`), every force within
# 0.1% of the converged value.
CONVERGED_LEVEL = ["mesh.geometry=axisymmetric", "mesh.params.h=10", "mesh.params.h_pole=2", "mesh.params.h_surf=2",
                   "mesh.params.w_surf=30", "fem.stabilisation=0"]


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


def run(text, ranks=2, petsc=(), workdir=None, scene=None, overrides=()):
    """Runs a scene given as TOML text, or the scene `scene` (file or shipped name) with `--set`
    overrides ("key=value"); returns (history rows as dicts, timings dict)."""
    workdir = Path(workdir or tempfile.mkdtemp(prefix="poroplast-study-"))
    workdir.mkdir(parents=True, exist_ok=True)
    if scene is None:
        scene = workdir / "scene.toml"
        scene.write_text(text)
    out = workdir / "run"
    cmd = ["mpirun", "-n", str(ranks), str(BIN), "run", str(scene), "--out", str(out), "--force", "-q"]
    for o in overrides:
        cmd += ["--set", o]
    if petsc:
        cmd += ["--", *petsc]
    subprocess.run(cmd, check=True, env=env(), stdout=subprocess.DEVNULL)
    rows = list(csv.DictReader(open(out / "history.csv")))
    timings = {}
    for line in open(out / "timings.txt"):
        if " = " in line:
            k, v = line.split(" = ")
            timings[k.strip()] = float(v)
    return rows, timings


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


def at_time(rows, t, col):
    r = min(rows, key=lambda r: abs(float(r["time"]) - t))
    if abs(float(r["time"]) - t) > 1e-9 * max(1.0, t):
        raise ValueError(f"no row at t = {t}")
    return float(r[col])


def order(e_coarse, e_fine, ratio):
    import math
    return math.log(e_coarse / e_fine) / math.log(ratio) if e_coarse > 0 and e_fine > 0 else float("nan")
