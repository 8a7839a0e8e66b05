"""A convergence study's design: mesh levels at one step level and step levels on one mesh (a
cross; or every combination), run as one batch of cases (each observable then extrapolated by
`richardson.converge`), and what to say of a level that failed."""
import re
from pathlib import Path

from .cases import run_cases, scene_values
from .levels import SIZES, h_levels, refined_steps


def cross(scene, hs, ss, sets, H, S, full=False):
    """The cases of a study: (h, s, overrides) for each mesh level at the steps S and each step
    level on the mesh H (every combination with `full`). `sets` are the study's --set values
    ("KEY=VALUE"); sizes and time keys among them are scaled per level (`levels.h_levels`,
    `levels.refined_steps`), the rest returned as the fixed (key, value) overrides of every case."""
    t = scene_values(scene)
    given = {k: v for k, v in (s.split("=", 1) for s in sets) if k.startswith("time.")}   # scaled per level
    scaled = ("time.dt=", "time.dt_max=", "time.error_tolerance=", "time.growth=", "mesh.params.h=",
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
    """Runs the study's cases (completed ones are skipped): {(h, s): (run directory, result)}."""
    cases, fixed = cross(scene, hs, ss, sets, H, S, full)
    ran = run_cases(scene, [ov for _, _, ov in cases], fixed, Path(root), ranks, [], observe)
    return {(h, s): r for (h, s, _), r in zip(cases, ran)}


def mesh_sizes(overrides):
    """The mesh sizes a case's overrides set: {"h": µm, "h_pole": µm, ...}."""
    return {k.removeprefix("mesh.params."): float(v) for k, v in overrides if k.startswith("mesh.params.")}


def failure_stage(error):
    """Where a run failed, from its error line: "settling" (under gravity, before t = 0),
    "first step" (the step from t = 0), or "at t = T"."""
    if "settling" in error:
        return "settling"
    m = re.search(r"from t = ([-+0-9.eE]+)", error)
    if m is None:
        return "unknown"
    try:
        t = float(m.group(1).rstrip("."))
    except ValueError:
        return "unknown"
    return "first step" if t == 0 else f"at t = {t:.6g} s"


def failure_cause(case, error, completed):
    """What to tell the user of a failed level: `case` is its (h, s, overrides), `error` the
    run's error line, `completed` the overrides of the levels that ran to the end. A level
    that failed while settling under gravity or in its first step, or whose mesh is much finer
    (smallest size below half the smallest of any completed level), most likely failed for its
    mesh: the message names its sizes before the solver's words, which speak of the material."""
    h, s, overrides = case
    sizes = mesh_sizes(overrides)
    stage = failure_stage(error)
    where = {"settling": "while settling under gravity (before t = 0)", "first step": "in its first step",
             "unknown": ""}.get(stage, stage)
    head = f"level h = {h:g}, steps × {s:g} failed {where}".rstrip()
    smallest = min(sizes.values(), default=float("nan"))
    done = [min(mesh_sizes(o).values(), default=float("nan")) for o in completed]
    finest_done = min(done, default=None)
    finer = finest_done is not None and smallest < 0.5 * finest_done
    if not (finer or stage in ("settling", "first step")):
        return f"{head}: {error}"
    shown = ", ".join(f"{k} = {v:g}" for k, v in sizes.items())
    # Another level of the same scene completed: the material carries its weight there.
    blame = "its mesh, not the material" if finest_done is not None else "its mesh"
    lines = [f"{head}. Likely cause: {blame}: the level's sizes are {shown} µm."]
    if finer:
        lines.append(f"  Its smallest size, {smallest:g} µm, is {finest_done / smallest:.2g}× finer than that of any "
                     f"level that completed ({finest_done:g} µm).")
    if smallest <= 1.0:
        lines.append("  Elements of a micrometre or less at the poles are crushed by the weight before a contact "
                     "patch forms.")
    if finest_done is None:
        lines.append("  No level completed: run one level alone (`poroplast check SCENE --set ...` with its sizes) "
                     "to see whether the scene runs at all.")
    lines.append("  Check the sizes the levels scale (the 'mesh levels' lines above) and --h.")
    lines.append(f"  The run said: {error}")
    return "\n".join(lines)
