"""Field pictures of a run from its `fields.h5`, without ParaView or a display (matplotlib's Agg):
p, σ_VM, porosity and ‖E_p‖ (or any scalar field the run wrote) at chosen output times, a row
per time and a column per field, in the deformed configuration.

* A meridian run (6-node triangles): the deformed meridian (r, z).
* A 3-D run (10-node tetrahedra, a quarter or the full sphere): the section by the meridional
  plane y = 0 (x = 0 if that misses the mesh), drawn in (x, z); optionally the horizontal
  section through the body's mid-height, in (x, y). The section is cut from the cells with their
  vertices (`slices`): a node field linear between them (p is P1: exact), a cell field constant
  on each cell's part of the cut.

fields.h5 (docs/reference-run-directory.md): /time, /step_mesh (the mesh group of each output),
/mesh[_g]/coordinates and /topology, /fields/NAME/NNNNNN. A field with a value per node of its
mesh is a node field, one per cell a cell field. A file that cannot be opened (a run killed while
writing it) is read from the copy at the last checkpoint, where there is one; outputs or fields
that cannot be read are left out; both are said in the notes."""
from pathlib import Path

import numpy as np

from . import slices

# Field -> label with its unit; DEFAULT: drawn unless the user names others.
LABELS = {"p": "p (kPa)", "von_mises": "σ_VM (kPa)", "porosity": "porosity", "norm_ep": "‖E_p‖",
          "J": "J = det F", "contact": "contact (0 free, 1 lower, 2 upper)", "rank": "MPI rank"}
DEFAULT = ["p", "von_mises", "porosity", "norm_ep"]
# Names a user may give for a field, beside its own.
ALIASES = {"pressure": "p", "vm": "von_mises", "sigma_vm": "von_mises", "ep": "norm_ep", "phi": "porosity"}
# At most this many output times when none are asked for (evenly chosen, first and last kept).
MAX_TIMES = 6
# An output time this close to the one asked for is that time (s, relative).
SAME_TIME = 1e-6


def canonical(name):
    return ALIASES.get(name, name)


def output_times(times, wanted=None):
    """Indices of the output times to draw: the nearest written to each of `wanted` (in that
    order, each once), else at most MAX_TIMES evenly spaced (the first and the last kept)."""
    n = len(times)
    if wanted:
        t = np.asarray(times, float)
        return list(dict.fromkeys(int(np.argmin(np.abs(t - w))) for w in wanted))
    if n <= MAX_TIMES:
        return list(range(n))
    return sorted({int(round(i)) for i in np.linspace(0, n - 1, MAX_TIMES)})


def differs(written, asked):
    return abs(written - asked) > SAME_TIME * max(1.0, abs(asked))


def open_fields(run, notes):
    """fields.h5 open for reading (h5py.File), or the checkpoint's copy when it cannot be opened;
    None (and a note) when neither can."""
    import h5py
    run = Path(run)
    tried = []
    copy = "the copy at the last checkpoint"
    for path, what in [(run / "fields.h5", None), (run / "checkpoints" / "fields.h5", copy)]:
        if not path.exists():
            continue
        try:
            f = h5py.File(path, "r", locking=False)   # a run may be writing it
        except OSError as e:
            tried.append(f"{path.relative_to(run)} cannot be read ({str(e).splitlines()[0][:80]})")
            continue
        if "time" not in f or "mesh/topology" not in f:
            f.close()
            tried.append(f"{path.relative_to(run)} has no /time or /mesh/topology (not a poroplast fields file?)")
            continue
        if what:
            notes.append("; ".join(tried + [f"the fields are drawn from {what}, {path.relative_to(run)}"]))
        else:
            notes.extend(tried)
        return f
    notes.append("; ".join(tried) + ": no field pictures" if tried
                 else "no fields.h5 (output.fields = false): no field pictures")
    return None


class Step:
    """One output of fields.h5: its time, its mesh group's points (deformed by u where the step
    has u) and cells, and its scalar fields on nodes or cells."""

    def __init__(self, f, k):
        self.f, self.k = f, k
        self.t = float(f["time"][k])
        g = int(f["step_mesh"][k]) if "step_mesh" in f and k < len(f["step_mesh"]) else 0
        mesh = f["mesh" if g == 0 else f"mesh_{g}"]
        self.X, self.cells = mesh["coordinates"][:], mesh["topology"][:]
        u = self.field("u")
        self.x = self.X + u if u is not None and u.shape == self.X.shape else self.X

    def field(self, name):
        """The step's values of `name` (None where it has none)."""
        path = f"fields/{name}/{self.k:06d}"
        return self.f[path][:] if path in self.f else None

    def scalar(self, name):
        """(values, on nodes) of a scalar field; None where the step has none."""
        v = self.field(name)
        if v is None or v.ndim != 1:
            return None
        if len(v) == len(self.X):
            return v, True
        if len(v) == len(self.cells):
            return v, False
        return None


def available(f):
    """The scalar fields of the file (vectors, such as u and darcy_flux, are not drawn)."""
    out = []
    for name in f.get("fields", {}):
        members = list(f["fields"][name])
        if members and f["fields"][name][members[0]].ndim == 1:
            out.append(name)
    return out


class TickLabels:
    """Colour-bar tick labels that carry their own exponent and just the digits that tell the
    ticks apart (0.3999995, 0.4, 0.4000005; 2e-08, 4e-08): no offset or multiplier label
    ("1e−5") at the bar's top, where it overlaps the next panel."""

    def __new__(cls):
        from matplotlib.ticker import Formatter

        class Labels(Formatter):
            ticks = ()

            def set_locs(self, locs):
                self.ticks = locs

            def __call__(self, v, pos=None):
                locs = np.asarray(self.ticks, float)
                steps = np.diff(np.sort(locs))
                step = steps[steps > 0].min() if (steps > 0).any() else 0.0
                if step and abs(v) < 1e-6 * step:
                    return "0"
                big = np.abs(locs).max() if len(locs) else abs(v)
                digits = 3 if not step else max(3, int(np.ceil(np.log10(max(big, step) / step))) + 1)
                return f"{v:.{digits}g}"
        return Labels()


def colorbar(fig, im, ax):
    cb = fig.colorbar(im, ax=ax, shrink=0.85, format=TickLabels())
    cb.ax.tick_params(labelsize=7)
    return cb


def panel(ax, tri, values, on_nodes):
    """A field on a triangulation: filled contours of node values (48 levels: smooth, and no
    seams along thin triangles as Gouraud shading leaves), flat colours of triangle values.
    Triangles with a value that is not finite (a diverged step) are left blank."""
    from matplotlib.tri import Triangulation
    v = np.asarray(values, float)
    bad = (~np.isfinite(v[tri.triangles])).any(1) if on_nodes else ~np.isfinite(v)
    if bad.any():
        tri = Triangulation(tri.x, tri.y, tri.triangles, mask=bad)
        v = np.where(np.isfinite(v), v, 0.0)
    if on_nodes:
        return ax.tricontourf(tri, v, levels=48, cmap="viridis")
    return ax.tripcolor(tri, facecolors=v, cmap="viridis")


class Meridian:
    """The deformed meridian of a 6-node-triangle mesh, in (r, z)."""
    axes = ("r (µm)", "z (µm)")

    def __init__(self, step):
        from matplotlib.tri import Triangulation
        self.tri = Triangulation(step.x[:, 0], step.x[:, 2], step.cells[:, :3])

    def values(self, v, on_nodes):
        return v


class Section:
    """A plane section of a deformed tetrahedral mesh, drawn in two of its coordinates."""

    def __init__(self, step, where):
        from matplotlib.tri import Triangulation
        x = step.x
        if where == "mid":
            z = 0.5 * (x[:, 2].min() + x[:, 2].max())
            self.cut, self.plane = slices.cut(x, step.cells, [0, 0, 1], z), f"z = {z:.4g} µm"
            ij, self.axes = (0, 1), ("x (µm)", "y (µm)")
        else:
            self.cut, self.plane = slices.cut(x, step.cells, [0, 1, 0], 0.0), "y = 0"
            ij, self.axes = (0, 2), ("x (µm)", "z (µm)")
            if self.cut is None:
                self.cut, self.plane = slices.cut(x, step.cells, [1, 0, 0], 0.0), "x = 0"
                ij, self.axes = (1, 2), ("y (µm)", "z (µm)")
        if self.cut is not None:
            p = self.cut.points
            self.tri = Triangulation(p[:, ij[0]], p[:, ij[1]], self.cut.triangles)

    def values(self, v, on_nodes):
        return self.cut.node(v) if on_nodes else self.cut.cell(v)


def figure(f, rows, names, out, where, asked, title):
    """The pictures of fields `names` at the outputs `rows` of the open file f into `out`; where:
    "meridian" (a meridian run), "axis" or "mid" (a 3-D run's sections). Returns (the figure's
    panels {(k, name): (triangulation, values drawn)}, notes)."""
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    notes, drawn, planes = [], {}, []
    fig, axes = plt.subplots(len(rows), len(names), figsize=(max(3.4 * len(names), 6.0), 3.2 * len(rows) + 0.4),
                             squeeze=False, layout="constrained")
    for r, k in enumerate(rows):
        try:
            step = Step(f, k)
            view = Meridian(step) if where == "meridian" else Section(step, where)
        except (OSError, KeyError, ValueError) as e:
            notes.append(f"output {k} cannot be read ({str(e).splitlines()[0][:80]}): not drawn")
            view = None
        if view is not None and where != "meridian":
            planes.append(view.plane)
        if view is not None and getattr(view, "tri", None) is None:
            notes.append(f"output {k}: the section {view.plane} misses the mesh")
            view = None
        when = f"t = {step.t:.6g} s" if view is not None else f"output {k}"
        if view is not None and asked.get(k) is not None and differs(step.t, asked[k]):
            when += f" (asked {asked[k]:g} s)"
        for c, name in enumerate(names):
            ax = axes[r, c]
            ax.set_title(f"{LABELS.get(name, name)}, {when}", fontsize=8)
            got = None
            if view is not None:
                try:
                    got = step.scalar(name)
                except (OSError, KeyError, ValueError):
                    got = None
            if got is None:
                ax.text(0.5, 0.5, "not written" if view is not None else "not readable", ha="center",
                        va="center", transform=ax.transAxes, fontsize=8, color="0.4")
                ax.set_axis_off()
                if view is not None:
                    notes.append(f"{name} at t = {step.t:.4g} s: not written at that output")
                continue
            v = view.values(*got)
            colorbar(fig, panel(ax, view.tri, v, got[1]), ax)
            drawn[(k, name)] = (view.tri, v)
            ax.set_aspect("equal")
            ax.set_xlabel(view.axes[0], fontsize=7)
            ax.set_ylabel(view.axes[1], fontsize=7)
            ax.tick_params(labelsize=7)
    if planes:
        title = f"{title}: section {' / '.join(dict.fromkeys(planes))} of the deformed body"
    fig.suptitle(title, fontsize=10)
    fig.savefig(out, dpi=110)
    plt.close(fig)
    return drawn, notes


def draw(run, wanted=None, names=None, mid_plane=False, notes=None, title=None):
    """The field pictures of a run directory, into run/plot_fields.png (a 3-D run's mid-height
    section, with `mid_plane`: run/plot_fields_mid.png). `wanted`: times (s), the nearest written
    drawn; `names`: fields (None: DEFAULT's that the run wrote). Returns [(PNG written, what it
    shows)]; what was not drawn is said in `notes`."""
    run = Path(run)
    notes = [] if notes is None else notes
    f = open_fields(run, notes)
    if f is None:
        return []
    with f:
        try:
            return pictures(f, run, wanted, names, mid_plane, notes, title)
        except (OSError, KeyError, ValueError) as e:   # a file still being written, or damaged
            notes.append(f"fields.h5 could not be read to the end ({str(e).splitlines()[0][:80]}): "
                         "no field pictures")
            return []


def pictures(f, run, wanted, names, mid_plane, notes, title):
    """draw()'s work on the open file f."""
    times = f["time"][:]
    if not len(times):
        notes.append("fields.h5 has no output yet: no field pictures")
        return []
    have = available(f)
    if names:
        names = list(dict.fromkeys(canonical(n) for n in names))
        vectors = [n for n in names if n not in have and n in f.get("fields", {})]
        missing = [n for n in names if n not in have and n not in vectors]
        if vectors:
            notes.append(f"{', '.join(vectors)}: a vector field, not drawn (the scalar fields: {', '.join(have)})")
        if missing:
            notes.append(f"fields.h5 has no {', '.join(missing)} (it has {', '.join(have)})")
        names = [n for n in names if n in have]
    else:
        names = [n for n in DEFAULT if n in have]
    if not names:
        notes.append("no field to draw")
        return []
    rows = output_times(times, wanted)
    asked = {}
    for w in wanted or []:
        k = int(np.argmin(np.abs(times - w)))
        asked.setdefault(k, w)
        if differs(times[k], w):
            where = f"after the last output ({times[-1]:.6g} s)" if w > times[-1] else "not an output time"
            notes.append(f"t = {w:g} s is {where}: drawn at the nearest written, {times[k]:.6g} s")
    meridian = f["mesh/topology"].shape[1] == 6
    title = title or run.name
    jobs = [("meridian", run / "plot_fields.png")] if meridian else [("axis", run / "plot_fields.png")]
    if mid_plane and not meridian:
        jobs.append(("mid", run / "plot_fields_mid.png"))
    elif mid_plane:
        notes.append("a meridian run has no mid-height section (--mid-plane is for 3-D runs)")
    written = []
    for where, out in jobs:
        drawn, more = figure(f, rows, names, out, where, asked, title)
        notes.extend(more)
        if drawn:
            shown = list(dict.fromkeys(k for k, _ in drawn))
            on = {"meridian": "the deformed meridian", "axis": "the section y = 0 (through the axis)",
                  "mid": "the section at mid-height"}[where]
            written.append((out, f"{', '.join(dict.fromkeys(n for _, n in drawn))} at t = "
                                 + ", ".join(f"{times[k]:.6g}" for k in shown) + f" s on {on}"))
        else:
            out.unlink(missing_ok=True)
    return written
