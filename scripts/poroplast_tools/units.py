"""Units as a lab's column names spell them, and the model's units they convert to.

The model writes forces in milligram-force under g = 9.81 m/s² (`G`, the solver's
src/observe/experiment.rs G: 1 mg = 9.81 µN), lengths in µm, times in s, stresses in kPa
(docs/reference-run-directory.md). Every conversion of a force in scripts/ goes through `G`.

A column name carries its unit as `force [uN]`, `force (µN)`, `force {mN}`, `F/mN` or a suffix
`force_uN`, `time_min`; µ is written `u`, `µ` (U+00B5) or `μ` (U+03BC). `split` reads it."""
import re

G = 9.81   # m/s²: 1 mg-force = 1e-6 kg × G = 9.81 µN

# quantity -> {unit: factor to the model's unit of that quantity}
UNITS = {
    "force": {"mg": 1.0, "N": 1e6 / G, "mN": 1e3 / G, "uN": 1.0 / G, "nN": 1e-3 / G, "pN": 1e-6 / G},
    "length": {"um": 1.0, "nm": 1e-3, "mm": 1e3, "cm": 1e4, "m": 1e6},
    "time": {"s": 1.0, "ms": 1e-3, "min": 60.0, "h": 3600.0},
    "stress": {"kPa": 1.0, "Pa": 1e-3, "MPa": 1e3},
}
MODEL_UNIT = {"force": "mg", "length": "um", "time": "s", "stress": "kPa"}
# Other spellings of the units above.
SPELLINGS = {"µN": "uN", "μN": "uN", "µm": "um", "μm": "um", "micron": "um", "microns": "um", "mgf": "mg", "mg-force": "mg",
             "sec": "s", "secs": "s", "second": "s", "seconds": "s", "mins": "min", "minute": "min",
             "minutes": "min", "hr": "h", "hrs": "h", "hour": "h", "hours": "h", "msec": "ms"}
# The history.csv columns without a unit suffix that have one (docs/reference-run-directory.md).
MODEL_COLUMNS = {
    "force": ("force_total_mg", "force_constitutive_mg", "force_pressure_mg", "force_lower_mg"),
    "length": ("plate_disp", "height", "width", "R1", "R2", "R3", "contact_radius_upper", "contact_radius_lower",
               "max_penetration", "ux", "uy", "uz"),
    "stress": ("probe_p", "stress_xx", "stress_yy", "stress_zz", "max_von_mises"),
}


def unit(text):
    """The unit `text` names, as UNITS spells it (`µN` -> `uN`, `MIN` -> `min`), or None. The
    case is kept where it tells units apart, and ignored where only one unit has that spelling
    (`UN` is uN, `MN` mN: there is no meganewton here)."""
    t = SPELLINGS.get(text, text)
    if any(t in units for units in UNITS.values()):
        return t
    low = t.lower().replace("µ", "u").replace("μ", "u")
    low = SPELLINGS.get(low, low)
    hits = [u for units in UNITS.values() for u in units if u.lower() == low]
    return hits[0] if len(hits) == 1 else None


def quantity(u):
    """The quantity (force, length, time, stress) of a unit of UNITS."""
    return next(q for q, units in UNITS.items() if u in units)


def factor(u):
    """The factor from unit `u` to the model's unit of its quantity (uN -> 1/9.81: to mg)."""
    return UNITS[quantity(u)][u]


def shown(u):
    """A unit as the docs print it (uN -> µN, um -> µm)."""
    return {"uN": "µN", "um": "µm"}.get(u, u)


BRACKETED = re.compile(r"^(.*?)\s*[\[({]\s*([^\])}]*?)\s*[\])}]\s*$")
SLASHED = re.compile(r"^(.+?)\s*/\s*([^/\s]+)$")
SUFFIXED = re.compile(r"^(.+?)[_ ]([A-Za-zµμ]+)$")


def split(name):
    """(base, unit, given) of a column name: `force [uN]` -> ("force", "uN", "uN"); the unit
    None where the name gives none or an unknown one (`given` is the text it gave in brackets
    or after /, else None). A suffix (`force_uN`) counts only when it is a unit (`stress_zz`
    has none)."""
    name = name.strip()
    for pattern in (BRACKETED, SLASHED):
        m = pattern.match(name)
        if m and m.group(1):
            return m.group(1).strip(), unit(m.group(2)), m.group(2)
    m = SUFFIXED.match(name)
    if m and unit(m.group(2)):
        return m.group(1), unit(m.group(2)), None
    return name, None, None


def of_column(column):
    """The model's unit of a history.csv column (`force_total_mg` -> mg, `height` -> um,
    `stress_zz` -> kPa), or None (dimensionless, or not known here)."""
    _, u, _ = split(column)
    if u is not None:
        return u
    for q, names in MODEL_COLUMNS.items():
        if column in names:
            return MODEL_UNIT[q] if q != "force" else "mg"
    return None


def force(text):
    """A force `0.05uN`, `0.5 nN`, `2e-3mg` in mg; a bare number is returned as it is (the
    column's unit). ValueError for another unit or no number."""
    s = str(text).strip()
    m = re.match(r"^([-+0-9.eE]+)\s*([A-Za-zµμ]+)$", s)
    if not m:
        return float(s)
    u = unit(m.group(2))
    if u is None or quantity(u) != "force":
        raise ValueError(f"`{s}`: `{m.group(2)}` is not a force unit ({', '.join(map(shown, UNITS['force']))})")
    return float(m.group(1)) * factor(u)
