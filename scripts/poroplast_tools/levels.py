"""Which cases a study runs: grid axes of overrides and their combinations, mesh levels (h with
the other sizes scaled in proportion) and step levels (every step scaled), and the converged
level of the plates experiment."""
import itertools
import sys

from .cases import SceneError, resolved_scene

# The converged level of the plates experiment (docs/performance.md): the meridian at h = 10 um
# with the surface and the poles at 2 um, no pressure stabilisation (its error is the largest on
# such meshes); with 1/8 of the scene's steps (`refined_steps(..., 0.125)`), every force within
# 0.1% of the converged value.
CONVERGED_LEVEL = ["mesh.geometry=axisymmetric", "mesh.params.h=10", "mesh.params.h_pole=2", "mesh.params.h_surf=2",
                   "mesh.params.w_surf=30", "fem.stabilisation=0"]
SIZES = ("h_pole", "h_edge", "h_surf")   # mesh sizes besides h, scaled with it by h_levels


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


def base_sizes(scene, sets=()):
    """The bulk size h and the sizes scaled with it (SIZES) that a run of `scene` with the
    overrides `sets` ("KEY=VALUE") meshes with, as {key: (µm, where it comes from)}: the sizes of
    mesh.params as the binary resolves the scene (`poroplast show --explain`: mesh.relative_sizes
    × R, a size given in µm winning, or mesh.grading = "auto"'s chart). Sizes it does not give
    are the .geo's own defaults (h_pole = h/3, h_surf = h_edge = h: they follow h by themselves)."""
    pairs = [tuple(s.split("=", 1)) if "=" in s else (s, "") for s in sets]
    try:
        params = resolved_scene(scene, pairs).get("mesh", {}).get("params", {})
    except SceneError as e:
        sys.exit(f"mesh levels of {scene}: {e}")
    keys = [k.strip() for k, _ in pairs]
    resolved = "resolved from the scene" + (" and the --set values" if keys else "")
    where = lambda k: (f"--set mesh.params.{k}" if f"mesh.params.{k}" in keys
                       else "--set mesh.params" if "mesh.params" in keys else resolved)
    sizes = {k: (float(params[k]), where(k)) for k in ("h",) + SIZES if k in params}
    if "h" not in sizes:
        sys.exit(f"{scene}: the mesh has no size h to scale (neither mesh.params.h nor mesh.relative_sizes.h with "
                 f"mesh.params.R): give one, e.g. --set mesh.params.h=20")
    return sizes


def h_levels(scene, hs, sets=()):
    """A mesh sweep: for each h of `hs`, the (key, value) overrides mesh.params.h = h and the
    other sizes (SIZES: h_pole, h_edge, h_surf, as `base_sizes` finds them for the scene with
    the overrides `sets`) scaled in proportion: a size set with --set is scaled from the h the
    same overrides give, so `--set mesh.params.h=10 --set mesh.params.h_pole=2` keeps h_pole = h/5
    on every level, whatever the scene's relative_sizes say."""
    sizes = base_sizes(scene, sets)
    h0 = sizes["h"][0]
    return [[("mesh.params.h", f"{h:g}")] + [(f"mesh.params.{k}", f"{v * h / h0:g}")
                                            for k, (v, _) in sizes.items() if k != "h"]
            for h in hs]


def describe_sizes(scene, hs, sets=()):
    """Lines for a study's log: the sizes the levels scale (each with where it comes from) and
    each level's sizes."""
    sizes = base_sizes(scene, sets)
    h0 = sizes["h"][0]
    lines = [f"mesh levels: the sizes at h = {h0:g} µm, each level scaled by h/{h0:g}:"]
    lines += [f"  {k} = {v:g} µm ({where})" for k, (v, where) in sizes.items()]
    if set(sizes) == {"h"}:
        lines.append("  (no other size given: those of the .geo follow h by its own defaults)")
    for h, level in zip(hs, h_levels(scene, hs, sets)):
        lines.append(f"  level h = {h:g}: " + ", ".join(f"{k.removeprefix('mesh.params.')} = {v}" for k, v in level))
    return lines


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
