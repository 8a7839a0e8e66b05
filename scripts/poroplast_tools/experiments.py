"""The experiments of a calibration: the curves one parameter set must fit, each with its scene,
its overrides, its data and its noise model; and the fitted parameters, shared by all
experiments or one experiment's own.

An experiments file (TOML; paths relative to it):

    scene = "remodel_40"                  # defaults for every experiment (each may override)
    column = "force_total_mg"
    set = ["mesh.geometry=axisymmetric", "material.mu=2.5"]
    noise = "relative+floor"
    noise_floor = "0.05uN"

    [[experiment]]
    name = "r150"                         # letters, digits, _ and -
    data = "aggregate3.csv"
    set = ["mesh.params.R=150", "plates.radius=150"]
    t_max = 70

    [[experiment]]
    name = "r100_hold30"
    set = ["mesh.params.R=100", "plates.radius=100", "plates.t_end=40"]
    synthetic = { "material.remodelling.lambda_p" = 0.002 }   # a curve of the model itself
    synthetic_noise = 0.02                # its Gaussian noise: σ = √((0.02 y)² + floor²)
    synthetic_floor = 0.001               # (in the column's unit)
    synthetic_every = 1.0                 # s between its data times (default: the run's steps)
    seed = 1

An experiment's keys: name, scene, column, set (after the file's), data, data_column, unit,
noise, noise_floor, t_min, t_max, synthetic, synthetic_noise, synthetic_floor,
synthetic_every, seed; the file's: the same but name and data, and [[experiment]]. An unknown
key is refused with the nearest valid one, a value of the wrong kind with the kind expected;
`set` is one override (`set = "time.t_end=2"`) or a list of them. The command
line's scene, --column, --noise, --noise-floor, --data-unit, --data-column, --t-min and --t-max
are defaults below the file's; its --set comes before every `set`.

Parameters (`--param`): `KEY=START` is shared by every experiment; `KEY@NAME=START` is experiment
NAME's own (e.g. each aggregate its own µ: `--param material.mu@r150=2.5 --param
material.mu@r100=2.5`); an experiment without a value of KEY keeps its scene's. The fit works in
log parameters, so a start must be positive: a parameter whose 0 switches its term off (the
surface tension, the yield stress) cannot start there (`ZERO_OFF` says what 0 means). A key
with a range the scene accepts (`RANGES`: the surface tension's 0.01–1000 mN/m, outside which
it is refused as a unit mistake) must start within it, and a fit's point outside it is not run
(`outside`): it counts as a failed step.
"""
import re
from dataclasses import dataclass, field
from pathlib import Path

from . import units
from .fitstats import MODELS
from .measured import nearest

# What 0 means for a parameter that may be 0 in a scene: the reason a fit cannot start there.
ZERO_OFF = {
    "surface.tension": "surface.tension = 0 builds no surface term and log(0) is not a start: start from a positive "
                       "value (tissues measure 1-30 mN/m, e.g. surface.tension=5)",
    "material.remodelling.sigma_y": "sigma_y = 0 is the liquid limit (no threshold) and log(0) is not a start: start "
                                    "from a positive value below the run's von Mises stress (e.g. 0.1 kPa), or keep "
                                    "sigma_y = 0 fixed (--set) and fit the others",
}
# Keys the scene accepts only within a range (lo, hi, unit): the scene refuses the rest as a unit
# mistake (src/scene/surface.rs, PLAUSIBLE).
RANGES = {"surface.tension": (0.01, 1000.0, "mN/m")}

# The keys of an experiment and what each must be (the file's: the same but name and data).
NUMBER = (int, float)
KEYS = {"name": str, "scene": str, "column": str, "set": (str, list), "data": str, "data_column": str, "unit": str,
        "noise": str, "noise_floor": (int, float, str), "t_min": NUMBER, "t_max": NUMBER, "synthetic": dict,
        "synthetic_noise": NUMBER, "synthetic_floor": NUMBER, "synthetic_every": NUMBER, "seed": int}
OWN = {"name", "data"}      # an experiment's own keys, not the file's
NAME = re.compile(r"^[A-Za-z0-9_-]+$")


class ExperimentError(Exception):
    """A malformed experiments file or parameter: the message says what and where."""


@dataclass
class Experiment:
    name: str
    scene: str
    column: str
    sets: list = field(default_factory=list)      # (key, value) overrides after the common --set
    data: str = None                              # the CSV file (None: synthetic)
    data_column: str = None
    unit: str = None
    noise: str = None                             # None: data if the file has sigma, else absolute
                                                  # (relative+floor if a floor is given)
    noise_floor: float = None                     # in the column's unit (mg for forces)
    t_min: float = float("-inf")
    t_max: float = float("inf")
    synthetic: dict = field(default_factory=dict)  # {key: value} of the synthetic curve's run
    synthetic_noise: float = 0.0
    synthetic_floor: float = 0.0
    synthetic_every: float = None
    seed: int = 0


@dataclass
class Param:
    key: str                 # the scene key
    start: float
    experiment: str = None   # None: shared

    @property
    def label(self):
        return self.key if self.experiment is None else f"{self.key}@{self.experiment}"

    def applies(self, e):
        return self.experiment is None or self.experiment == e.name


def floor_value(text):
    """A noise floor `0.01` (the column's unit) or with a force unit (`0.05uN`) in mg
    (units.force); ValueError naming the problem."""
    try:
        return units.force(text)
    except ValueError as e:
        raise ValueError(f"noise floor {e}" if "`" in str(e) else f"noise floor `{text}`: not a number "
                         "(e.g. 0.005, in the column's unit, or 0.05uN)")


def overrides(items, where):
    """(key, value) pairs of `KEY=VALUE` overrides: `items` one string or a list of them."""
    if isinstance(items, str):
        items = [items]
    if not isinstance(items, (list, tuple)):
        raise ExperimentError(f"{where}: `set` must be a string \"KEY=VALUE\" or a list of them, not {_kind(items)}")
    out = []
    for s in items:
        if not isinstance(s, str):
            raise ExperimentError(f"{where}: `set` entry {s!r} is {_kind(s)}: each must be a string \"KEY=VALUE\"")
        key, eq, value = s.partition("=")
        if not eq or not key.strip():
            raise ExperimentError(f"{where}: `{s}` is not KEY=VALUE")
        out.append((key.strip(), value.strip()))
    return out


def _kind(v):
    return {bool: "a boolean", int: "an integer", float: "a number", str: "a string", list: "a list",
            dict: "a table"}.get(type(v), type(v).__name__)


def _check_keys(table, where, top=False):
    """Refuses an unknown key (with the nearest valid one) or a value of the wrong kind."""
    allowed = {k: t for k, t in KEYS.items() if not (top and k in OWN)}
    for k, v in table.items():
        if k not in allowed:
            if top and k in OWN:
                raise ExperimentError(f"{where}: `{k}` belongs in an [[experiment]], not at the top of the file")
            raise ExperimentError(f"{where}: unknown key `{k}`{nearest(k, allowed)}; the keys: "
                                  f"{', '.join(sorted(allowed))}")
        if isinstance(v, bool) or not isinstance(v, allowed[k]):
            want = {str: "a string", NUMBER: "a number", int: "an integer", dict: "a table {KEY = VALUE, ...}",
                    (str, list): "a string or a list of strings", (int, float, str): "a number or a string"}
            raise ExperimentError(f"{where}: `{k} = {v!r}` is {_kind(v)}: expected {want[allowed[k]]}")
    for k, v in (table.get("synthetic") or {}).items():
        if isinstance(v, bool) or not isinstance(v, NUMBER):
            raise ExperimentError(f"{where}: synthetic `{k} = {v!r}` is {_kind(v)}: expected a number")


def read(path, defaults):
    """The experiments of the file `path`; `defaults` (a dict of Experiment fields, from the
    command line) below the file's own."""
    import tomllib
    path = Path(path)
    try:
        top = tomllib.loads(path.read_text())
    except FileNotFoundError:
        raise ExperimentError(f"{path}: no such file")
    except OSError as e:
        raise ExperimentError(f"{path}: cannot be read: {e.strerror}")
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as e:
        raise ExperimentError(f"{path}: not TOML: {e}")
    runs = top.pop("experiment", None)
    if isinstance(runs, dict):
        raise ExperimentError(f"{path}: `[experiment]` is one table: write each experiment as [[experiment]]")
    if not isinstance(runs, list) or not runs or not all(isinstance(r, dict) for r in runs):
        raise ExperimentError(f"{path}: no [[experiment]] table" + nearest("experiment", top))
    _check_keys(top, path, top=True)
    common = overrides(defaults.get("set", []), "--set") + overrides(top.get("set", []), path)
    out = []
    for i, entry in enumerate(runs):
        where = f"{path}, experiment {i + 1}"
        _check_keys(entry, where)
        merged = {**defaults, **top, **entry}
        name = entry.get("name")
        if not isinstance(name, str) or not NAME.match(name):
            raise ExperimentError(f"{where}: a `name` of letters, digits, _ and - is needed")
        if name in (e.name for e in out):
            raise ExperimentError(f"{where}: the name `{name}` is taken")
        where = f"{path}, experiment `{name}`"
        for k in ("scene", "column"):
            if not merged.get(k):
                raise ExperimentError(f"{where}: no `{k}` (in the experiment, the file, or the command line)")
        if ("data" in entry) == bool(entry.get("synthetic")):
            raise ExperimentError(f"{where}: give either `data` (a CSV file) or `synthetic` (a table of values)")
        if merged.get("noise") is not None and merged["noise"] not in MODELS:
            raise ExperimentError(f"{where}: noise `{merged['noise']}`: expected one of {', '.join(MODELS)}"
                                  f"{nearest(merged['noise'], MODELS)}")
        try:
            e = Experiment(
                name=name, scene=str(merged["scene"]), column=str(merged["column"]),
                sets=common + overrides(entry.get("set", []), where),
                data=str(path.parent / entry["data"]) if "data" in entry else None,
                data_column=merged.get("data_column"), unit=merged.get("unit"),
                noise=merged.get("noise") or ("relative+floor" if merged.get("noise_floor") is not None else None),
                noise_floor=None if merged.get("noise_floor") is None else floor_value(merged["noise_floor"]),
                t_min=float(merged.get("t_min", float("-inf"))), t_max=float(merged.get("t_max", float("inf"))),
                synthetic={k: float(v) for k, v in (entry.get("synthetic") or {}).items()},
                synthetic_noise=float(merged.get("synthetic_noise", 0.0)),
                synthetic_floor=float(merged.get("synthetic_floor", 0.0)),
                synthetic_every=None if merged.get("synthetic_every") is None else float(merged["synthetic_every"]),
                seed=int(merged.get("seed", i)))
        except (TypeError, ValueError) as err:
            raise ExperimentError(f"{where}: {err}")
        if e.synthetic_every is not None and not e.synthetic_every > 0:
            raise ExperimentError(f"{where}: synthetic_every = {e.synthetic_every:g}: the time between data points "
                                  "must be positive (s)")
        if not e.t_min < e.t_max:
            raise ExperimentError(f"{where}: t_min = {e.t_min:g} is not below t_max = {e.t_max:g}: no data between")
        out.append(e)
    return out


def params(items, experiments):
    """The `--param KEY=START` / `KEY@NAME=START` items as Params, checked against the
    experiments' names."""
    out = []
    names = [e.name for e in experiments]
    for item in items:
        if "=" not in item:
            raise ExperimentError(f"--param `{item}`: expected KEY=START or KEY@EXPERIMENT=START")
        key, start = item.split("=", 1)
        key, _, name = key.strip().partition("@")
        if not key:
            raise ExperimentError(f"--param `{item}`: no key before `=` (expected KEY=START, e.g. material.mu=2.5)")
        if name and name not in names:
            raise ExperimentError(f"--param `{item}`: no experiment `{name}`{nearest(name, names)} (the experiments: "
                                  f"{', '.join(names)})")
        try:
            p = Param(key, float(start), name or None)
        except ValueError:
            raise ExperimentError(f"--param `{item}`: `{start}` is not a number")
        if p.start == 0 and key in ZERO_OFF:
            raise ExperimentError(f"--param `{item}`: {ZERO_OFF[key]}")
        if not p.start > 0:
            raise ExperimentError(f"--param `{item}`: the fit works in log parameters; the start must be positive")
        if outside(key, p.start):
            raise ExperimentError(f"--param `{item}`: {outside(key, p.start)}")
        if p.label in (q.label for q in out) or any(
                q.key == p.key and (q.experiment is None) != (p.experiment is None) for q in out):
            raise ExperimentError(f"--param `{item}`: {key} is given twice (shared and per experiment, or repeated)")
        out.append(p)
    return out



def outside(key, value):
    """Why `value` of `key` is outside the range the scene accepts (RANGES), or None."""
    if key not in RANGES:
        return None
    lo, hi, unit = RANGES[key]
    if value < lo:
        return f"{key} = {value:.4g} is below {lo:g} {unit}, the least the scene accepts"
    if value > hi:
        return f"{key} = {value:.4g} is above {hi:g} {unit}, the most the scene accepts"
    return None
