"""The experiments' model for a fit: runs of their scenes at parameter points, each batch one
`poroplast sweep` (poroplast_tools/cases.py), and the synthetic curves a fit can be tested on.

`Runs.evaluate` is the model of poroplast_tools/fit.py: per point (log-parameters) the stacked
differences model − data of every experiment, each experiment's history column interpolated at
its data's times. A finite-difference neighbour replays the time steps of its point's run
(`time.steps`): a step cut in one run and not in the other would make the difference jump.

`check_names` checks every name of a calibration before any run: each experiment's scene with
its overrides and start values (an unknown key, an implausible value) and its column, through
`poroplast columns` (the scene loaded and validated, no mesh: milliseconds).
"""
import math
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np

from . import cases
from .cases import run_cases
from .experiments import outside
from .fit import FitError
from .history import at, given_steps, history
from .measured import check_within, nearest, write_curve
from .synthetic import noisy

def scene_columns(scene, sets):
    """`cases.scene_columns`, its refusal a FitError."""
    try:
        return cases.scene_columns(scene, sets)
    except cases.SceneError as e:
        raise FitError(str(e))


def check_names(experiments, params, sets=(), say=print):
    """Refuses (FitError) before any run a scene, override, start value or column that the
    solver would not take: per experiment one `poroplast columns` of its scene with the common
    `sets`, its own, its synthetic values and the start values of its parameters (a parameter
    of several experiments is checked with each). A binary without the subcommand: said, and
    the column is checked at the first run instead (`Runs.check`)."""
    for e in experiments:
        given = (list(sets) + list(e.sets) + [(k, repr(v)) for k, v in e.synthetic.items()]
                 + [(p.key, repr(p.start)) for p in params if p.applies(e)])
        try:
            cols = scene_columns(e.scene, given)
        except FitError as err:
            what = " ".join(f"{k}={v}" for k, v in given) or "no overrides"
            single = e.name == Path(e.scene).stem     # the command line's one experiment
            raise FitError((f"{e.scene} with {what}" if single else f"experiment `{e.name}` ({e.scene} with {what})")
                           + f": {err}")
        if cols is None:
            say(f"note: {cases.BIN} has no `columns` subcommand (built before it): the scenes and "
                "columns are checked at the first run instead")
            return
        if e.column not in cols:
            raise FitError(missing_column(e, cols))


def missing_column(e, cols):
    """Why experiment e's column is not one of its history's `cols`."""
    return (f"`{e.column}` (the column to fit, --column) is not a column of the history of {e.scene}"
            + (f" (experiment `{e.name}`)" if e.name != Path(e.scene).stem else "") + f"{nearest(e.column, cols)}; "
            f"its columns: {', '.join(c for c in cols if c not in ('step', 'dt', 'newton_its', 'ksp_its', 'wall_s'))}")


class Runs:
    """The experiments' model: runs of their scenes at points (log-parameters), one batch per
    call; `evaluate` is the fit's model (poroplast_tools/fit.py)."""

    def __init__(self, study, experiments, params, sets=(), ranks=2, sweep=True, jobs=1):
        self.study, self.experiments, self.params = Path(study), experiments, params
        self.sweep, self.ranks, self.jobs = sweep, ranks, jobs
        self.sets = list(sets)
        self.root = self.study / "runs"
        self.ran = 0                 # the runs the sweeps had to make
        self.asked = 0               # the runs asked for (those the case store held included)
        self.data = None             # per experiment: (times, values) once read
        self.checked = False

    def histories(self, cases, what=None):
        """Runs (scene, overrides) cases — ONE batch, the completed ones skipped — and returns
        their histories (None for a failed run). `what`: lines printed before the batch."""
        for line in what or []:
            print(line, flush=True)
        if not cases:
            return []
        counts = {}
        ran = run_cases([s for s, _ in cases], [c for _, c in cases], self.sets, self.root, self.ranks,
                        counts=counts)
        self.ran += counts.get("ran", 0)
        self.asked += len(cases)
        return [history(d) if r["status"] == "ok" else None for d, r in ran]

    def case(self, e, x, steps=None):
        """Experiment e's case at x: its overrides, the parameters that apply to it, the steps."""
        values = [(p.key, repr(math.exp(v))) for p, v in zip(self.params, x) if p.applies(e)]
        return e.scene, e.sets + values + ([("time.steps", steps)] if steps else [])

    def evaluate(self, points, what, replay=None):
        """Per point (log-parameters) the stacked differences model − data of every experiment
        and the state {"x", "histories"}, or None if a run failed; every experiment's run at
        every point one batch (--no-sweep --jobs N: N points at once), each replaying the steps
        of its experiment's history in the state `replay` (one state for every point, or a list
        with one per point, None: the run's own steps; the profile's inner fits batch the
        neighbours of several points). An experiment whose parameters are those of its replayed
        state (a neighbour that moves another experiment's own parameter) is not run: its
        history is the state's. A point with a parameter outside the range its scene accepts
        (experiments.RANGES: the surface tension below 0.01 mN/m) is not run: None, a failed
        step, with the reason printed."""
        ne = len(self.experiments)
        replays = replay if isinstance(replay, list) else [replay] * len(points)
        runs, keep = [], {}           # the cases to run; (point, experiment) -> replay's history
        bad = {}                      # point -> why it is not run
        for j, (x, rp) in enumerate(zip(points, replays)):
            why = [outside(p.key, math.exp(v)) for p, v in zip(self.params, x)]
            if any(why):
                bad[j] = "; ".join(w for w in why if w)
                continue
            for i, e in enumerate(self.experiments):
                if rp and self.case(e, x) == self.case(e, rp["x"]):
                    keep[j, i] = rp["histories"][i]
                else:
                    runs.append((j, i, self.case(e, x, given_steps(rp["histories"][i]) if rp else None)))
        lines = [f"{name}: " + " ".join(f"{p.label}={math.exp(v):.6g}" for p, v in zip(self.params, x))
                 + (" (the point's steps)" if rp else "")
                 + (f": not run, {bad[j]} (a failed step)" if j in bad else "")
                 for j, (name, x, rp) in enumerate(zip(what, points, replays))]
        cases = [c for _, _, c in runs]
        if self.sweep or self.jobs == 1 or not points:
            hs = self.histories(cases, lines)
        else:
            with ThreadPoolExecutor(max_workers=self.jobs) as pool:
                hs = [h for part in pool.map(lambda j: self.histories([c for k, _, c in runs if k == j], lines[j:j + 1]),
                                             range(len(points))) for h in part]
        got = {**keep, **{(j, i): h for (j, i, _), h in zip(runs, hs)}}
        out = []
        for j, x in enumerate(points):
            if j in bad:
                out.append(None)
                continue
            group = [got[j, i] for i in range(ne)]
            if any(h is None for h in group):
                out.append(None)
                continue
            if not self.checked:
                self.check(group)
            d = [np.array([at(h, e.column, t) for t in ts]) - vs
                 for e, h, (ts, vs) in zip(self.experiments, group, self.data)]
            out.append((np.concatenate(d), {"x": np.array(x), "histories": group}))
        return out

    def count(self, since=(0, 0)):
        """`N runs (R run now, S from the case store)` of the runs asked for since `since`, an
        earlier `(asked, ran)`."""
        asked, ran = self.asked - since[0], self.ran - since[1]
        return f"{asked} runs" + (f" ({ran} run now, {asked - ran} from the case store)" if ran != asked else "")

    def check(self, group):
        """Refuses (once, at the first runs) a column the runs do not write (FitError: a binary
        without `poroplast columns` left it unchecked) and data times after a run's end
        (DataError)."""
        for e, h, (ts, _) in zip(self.experiments, group, self.data):
            if e.column not in h:
                raise FitError(missing_column(e, list(h)))
            check_within(e.data or e.name, ts, float(h["time"][-1]))
        self.checked = True


def synthesise(runs, experiments):
    """The synthetic experiments' data: their runs (one batch) at the `synthetic` values,
    sampled at their steps or every `synthetic_every` s, with Gaussian noise of σ_i =
    √((synthetic_noise y_i)² + synthetic_floor²) (seeded); written to STUDY/synthetic_NAME.csv.
    {name: (times, values)}."""
    todo = [e for e in experiments if e.synthetic]
    if not todo:
        return {}
    cases = [(e.scene, e.sets + [(k, repr(v)) for k, v in e.synthetic.items()]) for e in todo]
    hs = runs.histories(cases, [f"synthetic curve {e.name}: " + " ".join(f"{k}={v}" for k, v in e.synthetic.items())
                                for e in todo])
    out = {}
    for e, h in zip(todo, hs):
        if h is None:
            raise FitError(f"the synthetic run of {e.name} failed")
        if e.column not in h:
            raise FitError(missing_column(e, list(h)))
        t_end = float(h["time"][-1])
        ts = (np.arange(1, int(t_end / e.synthetic_every + 1e-9) + 1) * e.synthetic_every if e.synthetic_every
              else h["time"][h["time"] > 0])
        ys = np.array([at(h, e.column, t) for t in ts])
        ys = noisy(ys, e.synthetic_noise, e.seed, floor=e.synthetic_floor)
        out[e.name] = (list(ts), list(ys))
        write_curve(runs.study / f"synthetic_{e.name}.csv", ts, ys, column=e.column,
                    comment=f"synthetic: {e.scene} {e.synthetic} noise {e.synthetic_noise} floor {e.synthetic_floor} "
                            f"seed {e.seed}")
    return out
