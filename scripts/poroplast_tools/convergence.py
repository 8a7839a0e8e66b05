"""A convergence study's design and its extrapolation: mesh levels at one step level and step
levels on one mesh (a cross; or every combination), run as one batch of cases, each observable
extrapolated by `richardson.converge`."""
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
    """Runs the study's cases (completed ones are skipped): {(h, s): (run directory, result)}."""
    cases, fixed = cross(scene, hs, ss, sets, H, S, full)
    ran = run_cases(scene, [ov for _, _, ov in cases], fixed, Path(root), ranks, [], observe)
    return {(h, s): r for (h, s, _), r in zip(cases, ran)}
