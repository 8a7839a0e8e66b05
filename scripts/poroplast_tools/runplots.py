"""The figures of a run directory or a sweep directory (`plot_run.py`): the history against
time — force, probe pressure and H/W, with the plate protocol's phases shaded and the summary's
peak and contact opening marked — and, for a meridian run, the fields p, σ_VM and ‖E_p‖ on the
deformed meridian at the output times. A sweep's cases are overlaid on one history figure.

The phases come from the run's resolved `scene.toml` (`plates.ramp`, `hold`, `release`; runs of
earlier versions: ramp to t_ramp, hold to t_end − t_ramp, release to t_end), the marks from its `summary.toml` where there is one (runs of earlier
versions have none)."""
import csv
import tomllib
from pathlib import Path

import numpy as np

from . import history as runs
from . import labels

# The history panels, in order: a column (or the ratio "A/B") and its label's key.
PANELS = ["force_total_mg", "probe_p", "height/width"]
# Columns that are bookkeeping, not observables (a scene without plates plots the rest).
BOOKKEEPING = {"step", "time", "dt", "newton_its", "ksp_its", "wall_s"}
# The meridian fields: (name in fields.h5, label, per node).
FIELDS = [("p", "p (kPa)", True), ("von_mises", "σ_VM (kPa)", False), ("norm_ep", "‖E_p‖", False)]
# At most this many output times in the fields figure (evenly chosen, first and last kept).
MAX_TIMES = 6
PHASE_COLOURS = {"ramp": "tab:orange", "hold": "tab:blue", "release": "tab:green"}


def phases(run):
    """The plate protocol's phases [(name, t0, t1)] from the run's scene.toml; [] without plates."""
    path = Path(run) / "scene.toml"
    if not path.exists():
        return []
    plates = tomllib.loads(path.read_text()).get("plates")
    if not plates:
        return []
    if "ramp" in plates:
        ramp, hold_end = float(plates["ramp"]), float(plates["ramp"]) + float(plates["hold"])
        end = hold_end + float(plates["release"])
    else:
        ramp, end = float(plates["t_ramp"]), float(plates["t_end"])
        hold_end = end - ramp
    return [("ramp", 0.0, ramp), ("hold", ramp, hold_end), ("release", hold_end, end)]


def summary(run):
    """The run's summary.toml as a dict ({} without one)."""
    path = Path(run) / "summary.toml"
    return tomllib.loads(path.read_text()) if path.exists() else {}


def series(h, name):
    """A panel's values: a column, or the ratio of two ("height/width"); None if absent."""
    if "/" in name:
        a, b = name.split("/")
        return h[a] / h[b] if a in h and b in h else None
    return h.get(name)


def panels(h):
    """The panels a history has: PANELS where present, else its observables (a scene without
    plates: its probes and exact columns)."""
    shown = [p for p in PANELS if series(h, p) is not None]
    return shown or [c for c in h if c not in BOOKKEEPING]


def shade(ax, phases_):
    for name, t0, t1 in phases_:
        ax.axvspan(t0, t1, color=PHASE_COLOURS[name], alpha=0.12, lw=0)


def history_figure(cases, out):
    """The history panels of `cases` [(legend label, run directory)] on shared time axes,
    written to `out`; the phases shaded where all cases share them. Returns the figure."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    hs = [(label, runs.history(d), d) for label, d in cases]
    hs = [(label, h, d) for label, h, d in hs if h]
    if not hs:
        raise SystemExit("no history rows to plot")
    names = panels(hs[0][1])
    fig, axes = plt.subplots(len(names), 1, sharex=True, figsize=(7, 2.4 * len(names)), squeeze=False)
    axes = axes[:, 0]
    all_phases = [phases(d) for _, _, d in hs]
    shared = all_phases[0] if all(p == all_phases[0] for p in all_phases) else []
    # The phases the runs reached (a run may end before the release).
    t_max = max(h["time"][-1] for _, h, _ in hs)
    shared = [(n, t0, min(t1, t_max)) for n, t0, t1 in shared if t0 < t_max]
    for ax, name in zip(axes, names):
        shade(ax, shared)
        for label, h, _ in hs:
            ax.plot(h["time"], series(h, name), lw=1.2, label=label)
        ax.set_ylabel(labels.column(name))
        ax.grid(alpha=0.3)
    if len(hs) == 1:
        mark(axes[names.index("force_total_mg")] if "force_total_mg" in names else None, summary(hs[0][2]))
    for name, t0, t1 in shared:
        axes[0].text(0.5 * (t0 + t1), 1.0, name, transform=axes[0].get_xaxis_transform(), ha="center",
                     va="bottom", fontsize=8, color=PHASE_COLOURS[name])
    if len(hs) > 1:
        axes[0].legend(fontsize=7)
    axes[-1].set_xlabel("t (s)")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    return fig


def mark(ax, s):
    """The summary's peak force and contact opening on the force panel."""
    p = s.get("plates", {})
    if ax is None or "peak_force_mg" not in p:
        return
    ax.plot([p["peak_force_time_s"]], [p["peak_force_mg"]], "kv", ms=5,
            label=f"peak {p['peak_force_mg']:.4g} mg = {p['peak_force_uN']:.4g} µN")
    if "contact_opening_time_s" in p:
        ax.axvline(p["contact_opening_time_s"], color="k", ls=":", lw=1,
                   label=f"contact opens, t = {p['contact_opening_time_s']:.4g} s")
    ax.legend(fontsize=7)


def output_times(times, wanted=None):
    """Indices of the output times to draw: those nearest `wanted`, else at most MAX_TIMES
    evenly spaced (the first and the last kept)."""
    n = len(times)
    if wanted:
        return sorted({int(np.argmin(np.abs(np.asarray(times) - w))) for w in wanted})
    if n <= MAX_TIMES:
        return list(range(n))
    return sorted({int(round(i)) for i in np.linspace(0, n - 1, MAX_TIMES)})


def fields_figure(run, out, wanted=None):
    """p, σ_VM and ‖E_p‖ (those written) on the deformed meridian at the output times, a row per
    time, written to `out`. Returns the indices of the output times drawn, or None for a 3-D run
    (no figure: a section of the body is ParaView's, fields.xdmf)."""
    import h5py
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.tri import Triangulation
    with h5py.File(Path(run) / "fields.h5", "r") as f:
        if f["mesh/topology"].shape[1] != 6:
            return None
        times = f["time"][:]
        step_mesh = f["step_mesh"][:] if "step_mesh" in f else np.zeros(len(times), int)
        shown = [(n, lab, node) for n, lab, node in FIELDS if n in f["fields"]]
        rows = output_times(times, wanted)
        fig, axes = plt.subplots(len(rows), len(shown), figsize=(3.2 * len(shown), 3.0 * len(rows)),
                                 squeeze=False)
        for r, k in enumerate(rows):
            mesh = "mesh" if step_mesh[k] == 0 else f"mesh_{step_mesh[k]}"
            X, top = f[f"{mesh}/coordinates"][:], f[f"{mesh}/topology"][:]
            x = X + f[f"fields/u/{k:06d}"][:]
            tri = Triangulation(x[:, 0], x[:, 2], top[:, :3])
            for c, (name, label, node) in enumerate(shown):
                ax = axes[r, c]
                v = f[f"fields/{name}/{k:06d}"][:]
                im = ax.tripcolor(tri, v, shading="gouraud" if node else "flat", cmap="viridis")
                fig.colorbar(im, ax=ax, shrink=0.8)
                ax.set_aspect("equal")
                ax.set_title(f"{label}, t = {times[k]:.4g} s", fontsize=9)
                ax.set_xlabel("r (µm)", fontsize=8)
                ax.set_ylabel("z (µm)", fontsize=8)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return rows


def sweep_cases(root):
    """The cases of a sweep directory that ended ok: [(legend label, run directory)], labelled by
    their overrides (summary.csv's columns before `status`)."""
    root = Path(root)
    with open(root / "summary.csv") as f:
        rows = list(csv.DictReader(f))
    out = []
    for row in rows:
        if row.get("status") != "ok":
            continue
        keys = list(row)[1:list(row).index("status")]
        label = labels.case([(k, row[k]) for k in keys if row[k] != ""]) or f"case {row['case']}"
        out.append((label, root / row["dir"]))
    return out


def plot(path, wanted=None):
    """Draws a run directory or a sweep directory (it has summary.csv and cases/); returns the
    PNGs written, and a note for what was not drawn."""
    path = Path(path)
    if (path / "summary.csv").exists() and (path / "cases").is_dir():
        out = path / "plot_history.png"
        history_figure(sweep_cases(path), out)
        return [out], "a sweep: the cases' histories overlaid (their fields: plot_run.py CASE_DIR)"
    if not (path / "history.csv").exists():
        raise SystemExit(f"{path}: neither a run directory (history.csv) nor a sweep directory (summary.csv, cases/)")
    written = [path / "plot_history.png"]
    history_figure([(path.name, path)], written[0])
    note = None
    if (path / "fields.h5").exists():
        out = path / "plot_fields.png"
        if fields_figure(path, out, wanted) is None:
            note = "a 3-D run: no fields figure (open fields.xdmf in ParaView for a section)"
        else:
            written.append(out)
    else:
        note = "no fields.h5 (output.fields = false): no fields figure"
    return written, note
