"""Figure labels in the units the docs use (kPa, (MPa s)⁻¹, mm⁴/(N s), µm, mg), not raw scene
keys: a scene key and its value, a history column, an observable of `study.py`."""

# m/s²: the g of the solver's milligram-force, one value for every script (units.G).
from .units import G  # noqa: F401

# scene key -> (symbol, unit, factor from the scene's unit to the unit shown)
KEYS = {
    "material.remodelling.lambda_p": ("λp", "(MPa s)⁻¹", 1e3),    # scene: (kPa s)⁻¹
    "material.remodelling.sigma_y": ("σy", "kPa", 1.0),
    "material.remodelling.form": ("flow rule", "", None),
    "material.k0": ("k0", "mm⁴/(N s)", 1e-3),                      # scene: µm⁴/(nN s)
    "material.permeability_c": ("c", "", 1.0),
    "material.mu": ("µ", "kPa", 1.0),
    "material.nu": ("ν", "", 1.0),
    "plates.compression": ("ũ_max", "", 1.0),
    "plates.t_end": ("t_end", "s", 1.0),
    "plates.radius": ("R", "µm", 1.0),
    "plates.seal_gap": ("seal gap", "µm", 1.0),
    "mesh.params.R": ("R", "µm", 1.0),
    "mesh.params.h": ("h", "µm", 1.0),
    "time.t_end": ("end of the run", "s", 1.0),
    "fem.stabilisation": ("stabilisation c", "", 1.0),
}
# history column -> label with its unit
COLUMNS = {
    "force_total_mg": "total force (mg)",
    "force_constitutive_mg": "constitutive force (mg)",
    "force_pressure_mg": "pressure force (mg)",
    "force_lower_mg": "lower plate's force (mg)",
    "force_total_uN": "total force (µN)",
    "force_constitutive_uN": "constitutive force (µN)",
    "force_pressure_uN": "pressure force (µN)",
    "force_lower_uN": "lower plate's force (µN)",
    "sigma_app": "σ_app (mN/m)",
    "probe_p": "p(X_U) (kPa)",
    "probe_porosity": "porosity at X_U",
    "height": "height (µm)",
    "width": "width (µm)",
    "height/width": "H/W",
    "max_von_mises": "largest σ_VM (kPa)",
    "max_norm_ep": "largest ‖E_p‖",
    "contact_radius_upper": "upper contact radius (µm)",
}


def _number(v):
    return f"{v:.5g}"


def value(key, v):
    """`key = v` in the text's units, e.g. material.remodelling.lambda_p = 0.001 -> λp = 1 (MPa s)⁻¹."""
    if key not in KEYS:
        return f"{key.split('.')[-1]} = {v}"
    sym, unit, factor = KEYS[key]
    try:
        shown = _number(float(v) * factor) if factor is not None else str(v).strip('"')
    except ValueError:
        shown = str(v).strip('"')
    return f"{sym} = {shown}" + (f" {unit}" if unit else "")


def key(k):
    """An axis label for a scene key, e.g. plates.t_end -> t_end (s)."""
    if k not in KEYS:
        return k
    sym, unit, _ = KEYS[k]
    return f"{sym} ({unit})" if unit else sym


def axis_factor(k):
    """The factor that turns the key's scene values into the values shown on an axis."""
    return KEYS.get(k, (None, None, 1.0))[2] or 1.0


def column(c):
    return COLUMNS.get(c, c)


def observable(spec):
    """A study.py observable, e.g. max:force_total_mg -> peak of total force (mg)."""
    kinds = {"max": "peak of ", "min": "minimum of ", "last": "final ", "zero": "zero crossing (s) of ",
             "err": "error against the exact solution of ", "maxerr": "largest error against the exact solution of "}
    if ":" in spec:
        kind, col = spec.split(":", 1)
        if kind == "zero":
            return f"time (s) at which {column(col).split(' (')[0]} crosses 0"
        return kinds.get(kind, kind + " ") + column(col)
    col, _, t = spec.partition("@")
    return f"{column(col)} at t = {t} s" if t else column(col)


def case(overrides):
    """A legend entry for a case's (key, value) overrides: the known keys in the text's units,
    each shown once (keys that change together, e.g. the radius of the mesh and of the plates,
    repeat each other); all keys if none is known."""
    known = [value(k, v) for k, v in overrides if k in KEYS]
    shown = known or [value(k, v) for k, v in overrides]
    return ", ".join(dict.fromkeys(shown))
