"""Which cases a study runs: grid axes of overrides and their combinations, mesh levels (h with
the other sizes scaled in proportion) and step levels (every step scaled), and the converged
level of the plates experiment."""
import itertools
import sys

from .cases import scene_values

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


def h_levels(scene, hs, sets=()):
    """A mesh sweep: for each h of `hs`, the (key, value) overrides mesh.params.h = h and the
    other sizes (SIZES: h_pole, h_edge, h_surf — the scene's, or those of `sets`, "KEY=VALUE",
    at the scene's h) scaled in proportion."""
    mesh = scene_values(scene).get("mesh", {})
    params = dict(mesh.get("params", {}))
    # Sizes given as fractions of R (mesh.relative_sizes) in µm; sizes given in µm win, as in a run.
    radius = params.get("R")
    for k, v in mesh.get("relative_sizes", {}).items():
        if k not in params and radius is not None and (k == "h" or k in SIZES):
            params[k] = v * radius
    h0 = params.get("h")
    if h0 is None:
        sys.exit(f"{scene}: the scene's mesh has no params.h (nor relative_sizes.h with params.R)")
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
