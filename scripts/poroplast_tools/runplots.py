"""The figures of a run directory or a sweep directory (`plot_run.py`): the history against
time — the force (µN, with mg beside it), probe pressure, H/W and, with a surface tension, the
apparent tension σ_app, with the plate protocol's ramps, holds and releases shaded, each hold's end
and the summary's peak and contact opening marked — and the fields (`fieldplots`). A sweep's
cases are overlaid on one history figure.

The protocol comes from the run's resolved `scene.toml`: the plate's path, `plates.table` or the
phases' corners (`plates.ramp`, `hold`, `release`; runs of earlier versions: `t_ramp`, `t_end`),
cut into segments that rise (ramp), stay at ũ > 0 (hold) or fall (release). The marks come from
`summary.toml` where there is one (a completed run of this version).

What a directory lacks or cannot give (a missing or damaged file, a cut last line, a run still
going) is said in the notes `plot` returns; the figures draw what is readable. `Nothing` is
raised when nothing could be drawn."""
import csv
import math
import tomllib
from pathlib import Path

import numpy as np

from . import fieldplots
from . import history as runs
from . import labels

# The history panels of a plate run, in order: a column (or the ratio "A/B"); a force in µN
# comes from its *_uN column, else from its *_mg column × G.
PANELS = ["force_total_uN", "probe_p", "height/width"]
# Columns that are bookkeeping, not observables (a scene without plates plots the rest).
BOOKKEEPING = {"step", "time", "dt", "newton_its", "ksp_its", "wall_s"}
PHASE_COLOURS = {"ramp": "tab:orange", "hold": "tab:blue", "release": "tab:green"}
# A phase narrower than this share of the time axis is shaded but not named (no room).
NAMED_WIDTH = 0.04
# Legend entries longer than this are cut (a sweep over a table would print the table).
LABEL_CHARS = 48


class Nothing(Exception):
    """Nothing of the directory could be drawn; the message says why."""


def read_toml(run, name, notes, why_missing=None):
    """`run/name` as a dict: {} (and a note) when it is missing or not TOML."""
    path = Path(run) / name
    if not path.exists():
        if why_missing:
            notes.append(f"no {name}: {why_missing}")
        return {}
    try:
        return tomllib.loads(path.read_bytes().decode("utf-8", errors="replace"))
    except tomllib.TOMLDecodeError as e:
        notes.append(f"{name} is not readable TOML ({e}): {why_missing or 'not used'}")
        return {}


def status(run):
    """How the run stands, from status.txt: None when completed, else a few words for the title
    ("in progress", "stopped", "failed")."""
    path = Path(run) / "status.txt"
    if not path.exists():
        return "in progress (no status.txt yet)"
    text = path.read_text(errors="replace").strip()
    if text.startswith("completed"):
        return None
    if text.startswith("stopped"):
        return "stopped (resume it: poroplast resume DIR)"
    if text.startswith("failed"):
        return "failed: " + text.split(":", 2)[-1].strip()[:60]
    return text[:60] or "in progress (status.txt empty)"


def plate_path(plates):
    """The plate's path [(t, ũ)] from the resolved [plates] table: `table`, or the phases'
    corners (ramp, hold, release; earlier versions' t_ramp and t_end); None without a protocol.
    Raises KeyError or ValueError when the keys are incomplete."""
    if not plates:
        return None
    if "table" in plates:
        rows = [(float(t), float(u)) for t, u in plates["table"]]
        return rows if rows[0] == (0.0, 0.0) else [(0.0, 0.0)] + rows
    top = float(plates.get("compression", 1.0))
    if "ramp" in plates:
        ramp, hold = float(plates["ramp"]), float(plates["hold"])
        end = ramp + hold + float(plates["release"])
    else:
        ramp, end = float(plates["t_ramp"]), float(plates["t_end"])
        hold = end - 2 * ramp
    return [(0.0, 0.0), (ramp, top), (ramp + hold, top), (end, 0.0)]


def segments(path):
    """The protocol's phases [(kind, t0, t1)] along a path: rising (ramp), at a constant ũ > 0
    (hold; after the path's last row if it stays compressed, to t = inf) or falling (release),
    neighbours of one kind merged; rest at ũ = 0 is no phase."""
    out = []
    legs = list(zip(path, path[1:]))
    if path[-1][1] > 0:
        legs.append((path[-1], (math.inf, path[-1][1])))
    for (t0, u0), (t1, u1) in legs:
        kind = "ramp" if u1 > u0 else "release" if u1 < u0 else "hold" if u0 > 0 else None
        if kind is None or t1 <= t0:
            continue
        if out and out[-1][0] == kind and out[-1][2] == t0:
            out[-1] = (kind, out[-1][1], t1)
        else:
            out.append((kind, t0, t1))
    return out


def phases(run, notes=None):
    """The plate protocol's phases [(kind, t0, t1)] from the run's scene.toml; [] without plates
    (or without a readable scene.toml: said in `notes`)."""
    notes = [] if notes is None else notes
    scene = read_toml(run, "scene.toml", notes, "the protocol's phases are not shaded")
    try:
        path = plate_path(scene.get("plates"))
    except (KeyError, ValueError, TypeError) as e:
        notes.append(f"scene.toml: the plates' protocol is incomplete ({e}): its phases are not shaded")
        return []
    return segments(path) if path else []


def series(h, name):
    """A panel's values: a column, the ratio of two ("height/width"), or a force in µN from its
    mg column (× labels.G) when the history has no µN column; None if absent."""
    if "/" in name:
        a, b = name.split("/")
        return h[a] / h[b] if a in h and b in h else None
    if name not in h and name.endswith("_uN") and name[:-3] + "_mg" in h:
        return h[name[:-3] + "_mg"] * labels.G
    return h.get(name)


def tension(scene):
    """The scene's surface tension (mN/m), 0 without one."""
    try:
        return float(scene.get("surface", {}).get("tension", 0.0))
    except (TypeError, ValueError, AttributeError):
        return 0.0


def panels(h, with_sigma_app=False):
    """The panels a history has: PANELS where present (and σ_app with a surface tension, where it
    has a value), else its observables (a scene without plates: its probes and exact columns)."""
    shown = [p for p in PANELS if series(h, p) is not None]
    if shown and with_sigma_app and np.isfinite(h.get("sigma_app", [np.nan])).any():
        shown.append("sigma_app")
    return shown or [c for c in h if c not in BOOKKEEPING]


def shade(ax, phases_, t_max):
    """The phases reached by t_max shaded; each hold's end (within the run) marked."""
    for name, t0, t1 in phases_:
        if t0 >= t_max:
            continue
        ax.axvspan(t0, min(t1, t_max), color=PHASE_COLOURS[name], alpha=0.12, lw=0)
        if name == "hold" and t1 <= t_max:
            ax.axvline(t1, color=PHASE_COLOURS["hold"], ls="--", lw=0.8)


def name_phases(ax, phases_, t_max):
    """The phases' names above the first panel, where there is room; the holds numbered when
    there are several."""
    several = sum(p[0] == "hold" for p in phases_) > 1
    holds = 0
    for name, t0, t1 in phases_:
        holds += name == "hold"
        t1 = min(t1, t_max)
        if t0 >= t_max or t1 - t0 < NAMED_WIDTH * t_max:
            continue
        ax.text(0.5 * (t0 + t1), 1.0, f"hold {holds}" if name == "hold" and several else name,
                transform=ax.get_xaxis_transform(), ha="center", va="bottom", fontsize=8, color=PHASE_COLOURS[name])


def force_axis(ax):
    """The mg beside a µN force axis (1 mg = G µN)."""
    side = ax.secondary_yaxis("right", functions=(lambda f: f / labels.G, lambda m: m * labels.G))
    side.set_ylabel("mg", fontsize=8)
    return side


def history_figure(cases, out, title=None, notes=None, said=None):
    """The history panels of `cases` [(legend label, run directory)] on shared time axes,
    written to `out`; the phases shaded where all cases share them. Returns the figure (what it
    shows in a line appended to `said`); raises Nothing when no case has a row."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    notes = [] if notes is None else notes
    hs = []
    for label, d in cases:
        try:
            h, problems = runs.read(d)
        except OSError as e:
            h, problems = {}, [f"history.csv cannot be read ({e.strerror})"]
        prefix = f"{label}: " if len(cases) > 1 else ""
        notes.extend(prefix + p for p in problems)
        if h and "time" not in h:
            notes.append(prefix + "history.csv has no time column")
        elif h:
            hs.append((label, h, d))
    if not hs:
        raise Nothing("no history rows to draw" + (f" ({'; '.join(notes)})" if notes else ""))
    scene_notes = []
    scenes = [read_toml(d, "scene.toml", scene_notes) for _, _, d in hs]
    all_phases = [phases(d, scene_notes) for _, _, d in hs]
    notes.extend(dict.fromkeys(scene_notes))
    names = panels(hs[0][1], with_sigma_app=any(tension(s) > 0 for s in scenes))
    fig, axes = plt.subplots(len(names), 1, sharex=True, figsize=(7.5, 2.3 * len(names) + 0.5), squeeze=False,
                             layout="constrained")
    axes = axes[:, 0]
    shared = all_phases[0] if all(p == all_phases[0] for p in all_phases) else []
    t_max = max(h["time"][-1] for _, h, _ in hs)
    for ax, name in zip(axes, names):
        shade(ax, shared, t_max)
        for label, h, _ in hs:
            v = series(h, name)
            if v is not None:
                ax.plot(h["time"], v, lw=1.2, label=label if len(hs) > 1 else "_" + label)
        ax.set_ylabel(labels.column(name), fontsize=9)
        ax.grid(alpha=0.3)
        if name.endswith("_uN"):
            force_axis(ax)
    if len(hs) == 1 and "force_total_uN" in names:
        why = "the peak and the contact opening are not marked"
        summary = read_toml(hs[0][2], "summary.toml", notes, why + (" (the run has not completed)"
                                                                    if status(hs[0][2]) else ""))
        mark(axes[names.index("force_total_uN")], summary)
    name_phases(axes[0], shared, t_max)
    if len(hs) > 1:
        axes[0].legend(fontsize=7)
    axes[-1].set_xlabel("t (s)")
    if title:
        fig.suptitle(title, fontsize=10)
    fig.savefig(out, dpi=120)
    plt.close(fig)
    if said is not None:
        rows = sum(len(h["time"]) for _, h, _ in hs)
        phases_ = ", ".join(f"{n} {t0:g}-{t1:g} s" for n, t0, t1 in shared)
        said.append(f"{len(hs)} run(s), {rows} rows to t = {t_max:g} s; panels {', '.join(names)}"
                    + (f"; phases {phases_}" if phases_ else ""))
    return fig


def mark(ax, s):
    """The summary's peak force (µN, and mg) and contact opening on the force panel."""
    p = s.get("plates", {})
    if not isinstance(p, dict) or "peak_force_mg" not in p or "peak_force_time_s" not in p:
        return
    mg = float(p["peak_force_mg"])
    uN = float(p.get("peak_force_uN", mg * labels.G))
    ax.plot([p["peak_force_time_s"]], [uN], "kv", ms=5, label=f"peak {uN:.4g} µN = {mg:.4g} mg")
    if "contact_opening_time_s" in p:
        ax.axvline(p["contact_opening_time_s"], color="k", ls=":", lw=1,
                   label=f"contact opens, t = {p['contact_opening_time_s']:.4g} s")
    ax.legend(fontsize=7)


def short(label):
    return label if len(label) <= LABEL_CHARS else label[:LABEL_CHARS - 1] + "…"


def sweep_cases(root, notes=None):
    """The cases of a sweep directory to draw: [(legend label, run directory)], labelled by
    their overrides (summary.csv's columns before `status`). Cases that ended ok, and those
    running or interrupted (their rows so far, "in progress" in the label); the others are
    named in `notes`."""
    root = Path(root)
    notes = [] if notes is None else notes
    with open(root / "summary.csv", newline="", encoding="utf-8", errors="replace") as f:
        rows = list(csv.DictReader(f))
    out = []
    for row in rows:
        state = row.get("status") or "unknown (a cut row)"
        case = row.get("case") or "?"
        header = list(row)
        keys = header[1:header.index("status")] if "status" in header else []
        label = short(labels.case([(k, row[k]) for k in keys if row.get(k)]) or f"case {case}")
        d = root / row["dir"] if row.get("dir") else None
        if state in ("running", "interrupted") and d is not None and (d / "history.csv").exists():
            label += f" ({state})"
        elif state != "ok" or d is None:
            why = f": {row['error']}" if row.get("error") else ""
            notes.append(f"case {case} ({state}{why}) not drawn")
            continue
        if not (d / "history.csv").exists():
            notes.append(f"case {case}: no history.csv in {d}: not drawn")
            continue
        out.append((label, d))
    return out


def is_run(path):
    return (path / "history.csv").exists()


def is_sweep(path):
    return (path / "summary.csv").exists() and (path / "cases").is_dir()


def plot(path, wanted=None, fields=None, mid_plane=False):
    """Draws a run directory or a sweep directory (it has summary.csv and cases/) into PNGs in
    it; returns ([(PNG written, what it shows)], notes on what was not drawn or differs from what
    was asked).
    `wanted`: the times of the field pictures (s; the nearest written are drawn); `fields`: their
    names (None: all of fieldplots.DEFAULT the run wrote); `mid_plane`: a 3-D run's horizontal
    section too. Raises Nothing when nothing could be drawn."""
    path = Path(path)
    notes = []
    if not path.is_dir():
        raise Nothing("no such directory" if not path.exists() else
                      f"a file, not a directory: give the run or sweep directory (e.g. {path.parent})")
    if is_sweep(path):
        out = path / "plot_history.png"
        cases = sweep_cases(path, notes)
        if not cases:
            raise Nothing("a sweep without a case to draw (" + "; ".join(notes) + ")")
        said = []
        history_figure(cases, out, f"sweep {path.name}: {len(cases)} case(s)", notes, said)
        notes.append("a sweep: the cases' histories overlaid (their fields: plot_run.py CASE_DIR)")
        return [(out, said[0])], notes
    if not is_run(path) and (path / "cases").is_dir():
        raise Nothing("a sweep directory without its summary.csv yet: plot a case, plot_run.py "
                      f"{path / 'cases' / 'CASE'}")
    if not is_run(path):
        raise Nothing("neither a run directory (history.csv) nor a sweep directory (summary.csv and cases/)")
    state = status(path)
    title = path.name + (f": {state}" if state else "")
    if state:
        notes.append(f"the run is {state}: drawn as far as it got")
    written, said = [], []
    try:
        history_figure([(path.name, path)], path / "plot_history.png", title, notes, said)
        written.append((path / "plot_history.png", said[0]))
    except Nothing as e:
        notes.append(f"no history figure: {e}")
    written += fieldplots.draw(path, wanted, fields, mid_plane, notes, title)
    if not written:
        raise Nothing("; ".join(notes))
    return written, notes
