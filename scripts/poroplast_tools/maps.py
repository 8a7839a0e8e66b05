"""Field maps of the mid-plane y = 0 as a journal prints them: every 6-node triangle of the
section split into n × n sub-triangles whose points go through the P2 displacement (so that the
deformed boundary curves), the pressure P1-linear from the triangle's vertices, cell fields (σ_VM,
‖E_p‖) constant on their cell as stored; the regions of the reproduction table (fields.py: the
centre and the contact zones, in the reference configuration) and X_U drawn in the current one.

A map panel shows one run mirrored about the axis, or two runs side by side (the left one
mirrored to x < 0): the experiment is axisymmetric, so each half is the whole meridian."""
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import matplotlib.tri as mtri
from matplotlib import patheffects

from . import fields

PROBE = (40.0, 0.0, 190.0)   # X_U, µm (reference configuration)
HALO = [patheffects.withStroke(linewidth=2.2, foreground="w")]   # dashed outlines legible on any colour


# ---------------------------------------------------------------- the P2 triangle

def lattice(n):
    """The barycentric points (L0, L1, L2) = (1 − i/n − j/n, i/n, j/n), i + j ≤ n, and the n²
    sub-triangles between them (indices into the points, counter-clockwise as the parent)."""
    ij = [(i, j) for j in range(n + 1) for i in range(n + 1 - j)]
    at = {p: k for k, p in enumerate(ij)}
    L = np.array([(1 - (i + j) / n, i / n, j / n) for i, j in ij])
    sub = []
    for i, j in ij:
        if i + j < n:
            sub.append((at[i, j], at[i + 1, j], at[i, j + 1]))
        if i + j < n - 1:
            sub.append((at[i + 1, j], at[i + 1, j + 1], at[i, j + 1]))
    return L, np.array(sub)


def p2_shape(L):
    """The 6 quadratic shape functions at barycentric points L (k×3): vertices 0-2, then the
    mid-edge nodes of edges (0,1), (1,2), (2,0) (fields.TRI6_EDGES)."""
    a, b, c = L.T
    return np.stack([a * (2 * a - 1), b * (2 * b - 1), c * (2 * c - 1), 4 * a * b, 4 * b * c, 4 * c * a], 1)


@dataclass
class Refined:
    """A section refined: reference and current positions of the sub-points (N×2, (x, z)),
    sub-triangles (M×3), the parent triangle of each sub-triangle (M), and of each sub-point its
    parent and barycentric coordinates (to evaluate P1 fields)."""
    ref: np.ndarray
    cur: np.ndarray
    triangles: np.ndarray
    parent: np.ndarray
    point_parent: np.ndarray
    point_L: np.ndarray

    def p2(self, tri6, values):
        """A P2 node field (one value per node of tri6) at the sub-points."""
        N = p2_shape(self.point_L)
        return np.einsum("kj,kj...->k...", N, np.asarray(values)[tri6[self.point_parent]])

    def p1(self, tri6, values):
        """A P1 node field at the sub-points, from the parent's vertices only (p is P1: the
        mid-edge values are not used)."""
        return np.einsum("kj,kj->k", self.point_L, np.asarray(values)[tri6[self.point_parent, :3]])

    def cell(self, values):
        """A cell field on each sub-triangle: its parent's value."""
        return np.asarray(values)[self.parent]


def refine(X, u, tri6, n=6):
    """The section (X, u: node positions and displacements in (x, z), tri6: m×6 node indices)
    split into n² sub-triangles per triangle; points shared by neighbours (vertices, edge
    points) are merged, so that contours run across the triangles' edges."""
    X, u, tri6 = np.asarray(X, float), np.asarray(u, float), np.asarray(tri6)
    L, sub = lattice(n)
    N = p2_shape(L)                                        # G×6
    m, G = len(tri6), len(L)
    ref = np.einsum("gj,mjd->mgd", N, X[tri6]).reshape(-1, 2)
    cur = ref + np.einsum("gj,mjd->mgd", N, u[tri6]).reshape(-1, 2)
    scale = max(np.ptp(X, axis=0).max(), 1.0)
    _, first, inverse = np.unique(np.round(ref / scale, 9), axis=0, return_index=True, return_inverse=True)
    inverse = inverse.ravel()
    triangles = inverse[(sub[None, :, :] + G * np.arange(m)[:, None, None]).reshape(-1, 3)]
    return Refined(ref[first], cur[first], triangles, np.repeat(np.arange(m), len(sub)),
                   first // G, np.tile(L, (m, 1))[first])


# ---------------------------------------------------------------- a run's section

class Section:
    """The mid-plane y = 0 of a run's fields.h5 as 6-node triangles: every cell of a meridian
    run, the faces in the plane of a 3-D run's cells (3 vertices on it) with their mid-edge nodes."""

    def __init__(self, case, d):
        import h5py
        self.case = case
        self.f = h5py.File(Path(d) / "fields.h5", "r")
        X = self.f["/mesh/coordinates"][:]
        top = self.f["/mesh/topology"][:]
        self.times = self.f["/time"][:]
        if top.shape[1] == 6:
            tri6, cells = top, np.arange(len(top))
        else:
            on = np.abs(X[top[:, :4], 1]) < 1e-9
            tri6, cells = [], []
            for c in np.nonzero(on.sum(1) == 3)[0]:
                a, b, e = np.nonzero(on[c])[0]
                mid = {frozenset(pair): top[c, 4 + k] for k, pair in enumerate(fields.TET10_EDGES)}
                tri6.append([top[c, a], top[c, b], top[c, e], mid[frozenset((a, b))], mid[frozenset((b, e))],
                             mid[frozenset((e, a))]])
                cells.append(c)
            tri6, cells = np.array(tri6), np.array(cells)
        used = np.unique(tri6)                            # the section's own nodes, renumbered
        self.nodes = used
        self.tri6 = np.searchsorted(used, tri6)
        self.cells = cells
        self.X = X[used][:, [0, 2]]
        self.radius = 0.5 * np.ptp(self.X[:, 1])

    def index(self, t):
        k = int(np.argmin(np.abs(self.times - t)))
        if abs(self.times[k] - t) > 0.05:            # e.g. a run older than its scene's fields_at
            print(f"  warning: {self.case} has no output at t = {t:g} s; nearest is {self.times[k]:.4g} s")
        return k, float(self.times[k])

    def field(self, name, k):
        """A field at output k restricted to the section, and whether it is a node field: node
        fields on the section's nodes (u as (x, z)), cell fields on its triangles."""
        v = self.f[f"/fields/{name}/{k:06d}"][:]
        if len(v) == len(self.f["/mesh/coordinates"]):
            return (v[self.nodes][:, [0, 2]] if name == "u" else v[self.nodes]), True
        return v[self.cells], False

    def panel(self, k, names, n=6):
        """The map data at output k: a Panel with the fields `names`."""
        node, cell = {}, {}
        for name in names:
            v, on_nodes = self.field(name, k)
            (node if on_nodes else cell)[name] = v
        return Panel(self.case, float(self.times[k]), self.X, self.field("u", k)[0], self.tri6, node, cell,
                     self.radius, n)


@dataclass
class Panel:
    """One run's section at one time: reference positions X and displacements u of its nodes
    ((x, z), µm), its 6-node triangles, P1 node fields and cell fields by name."""
    case: str
    t: float
    X: np.ndarray
    u: np.ndarray
    tri6: np.ndarray
    node: dict
    cell: dict
    radius: float
    n: int = 6

    def __post_init__(self):
        self.refined = refine(self.X, self.u, self.tri6, self.n)
        r = self.refined
        self._ref = mtri.Triangulation(r.ref[:, 0], r.ref[:, 1], r.triangles)
        self._u = [mtri.LinearTriInterpolator(self._ref, r.p2(self.tri6, self.u)[:, i]) for i in (0, 1)]

    def values(self, name):
        """(values, on the sub-points?) of a field: P1 node fields at the sub-points, cell fields
        per sub-triangle."""
        if name in self.node:
            return self.refined.p1(self.tri6, self.node[name]), True
        return self.refined.cell(self.cell[name]), False

    def current(self, points):
        """Reference points (k×2, (x ≥ 0, z)) in the current configuration: u interpolated on the
        refined reference section. A point on the curved boundary that falls just outside the
        sub-triangles' chords is moved 0.1-3% of R towards the centre first."""
        pts = np.atleast_2d(np.asarray(points, float))
        out = np.full_like(pts, np.nan)
        centre = np.array([0.0, self.radius])
        for shrink in (0.0, 1e-3, 3e-3, 1e-2, 3e-2):
            todo = np.isnan(out[:, 0])
            if not todo.any():
                break
            q = centre + (pts[todo] - centre) * (1 - shrink)
            d = np.stack([np.ma.filled(f(q[:, 0], q[:, 1]), np.nan) for f in self._u], 1)
            out[todo] = q + d
        return out


def read_panels(nodes_csv, cells_csv):
    """The panels of a map figure's data (paper_figures.write_panels: <figure>_nodes.csv and
    _cells.csv), in their order: what the figure was drawn from, without the runs."""
    import csv
    with open(nodes_csv, newline="") as f:
        nodes = list(csv.DictReader(f))
    with open(cells_csv, newline="") as f:
        cells = list(csv.DictReader(f))
    fixed_n, fixed_c = {"case", "t_s", "node", "x_ref_um", "z_ref_um", "ux_um", "uz_um"}, \
        {"case", "t_s", "cell", *(f"n{k}" for k in range(6))}
    by_n, by_c = {}, {}
    for rows, by in ((nodes, by_n), (cells, by_c)):
        for r in rows:
            by.setdefault((r["case"], r["t_s"]), []).append(r)
    col = lambda rows, k: np.array([float(r[k]) for r in rows])
    panels = []
    for key, rn in by_n.items():
        rc = by_c[key]
        X = np.c_[col(rn, "x_ref_um"), col(rn, "z_ref_um")]
        u = np.c_[col(rn, "ux_um"), col(rn, "uz_um")]
        tri6 = np.array([[int(r[f"n{k}"]) for k in range(6)] for r in rc])
        panels.append(Panel(key[0], float(key[1]), X, u, tri6,
                            {k: col(rn, k) for k in rn[0] if k not in fixed_n},
                            {k: col(rc, k) for k in rc[0] if k not in fixed_c}, 0.5 * np.ptp(X[:, 1])))
    return panels


# ---------------------------------------------------------------- the table's regions

def regions(R, n=40):
    """The reference-configuration outlines (x ≥ 0, z; polylines, µm) of the regions the
    reproduction table averages over (fields.py): the centre (r < 30 µm, |z − R| < 30 µm) and the
    contact zones (r < 40 µm, within 30 µm of either plate), the latter closed along the sphere."""
    a, d, c = fields.CONTACT_R, fields.CONTACT_DEPTH, fields.CENTRE_HALF
    arc = np.linspace(np.arcsin(a / R), 0.0, n)        # polar angle from the axis, from r = a to r = 0
    upper = np.r_[[[0.0, 2 * R - d], [a, 2 * R - d]], np.c_[R * np.sin(arc), R + R * np.cos(arc)]]
    lower = upper * [1, -1] + [0, 2 * R]
    centre = np.array([[0.0, R - c], [c, R - c], [c, R + c], [0.0, R + c]])
    return {"centre": centre, "contact_upper": upper, "contact_lower": lower}


def densify(poly, step=1.0):
    """A polyline with points at most `step` apart (so that its image under u is curved)."""
    out = [poly[:1]]
    for p, q in zip(poly[:-1], poly[1:]):
        k = max(1, int(np.ceil(np.linalg.norm(q - p) / step)))
        out.append(p + (q - p) * (np.arange(1, k + 1) / k)[:, None])
    return np.concatenate(out)


# ---------------------------------------------------------------- drawing

def triangulation(panel, side):
    """The refined current section on one side of the axis (side = +1, or −1: mirrored)."""
    r = panel.refined
    return mtri.Triangulation(side * r.cur[:, 0], r.cur[:, 1], r.triangles)


def draw(ax, panel, name, side, **kw):
    """A field of one panel on one side of the axis: P1 fields Gouraud-shaded on the
    sub-triangles (linear on each: exact for p), cell fields flat."""
    v, on_points = panel.values(name)
    tri = triangulation(panel, side)
    if on_points:
        return ax.tripcolor(tri, v, shading="gouraud", **kw)
    return ax.tripcolor(tri, facecolors=v, edgecolors="face", linewidth=0.3, **kw)   # no seams


def isobars(ax, panel, side, levels, fmt="%g"):
    """Labelled isobars of the pressure at `levels` that it crosses (p = 0 bold where p changes
    sign by more than 0.01 kPa: the drained surface's p ≈ 0 is not an isobar); returns the levels
    drawn."""
    v, _ = panel.values("p")
    tri = triangulation(panel, side)
    inside = [x for x in levels if v.min() < x < v.max() and x != 0]
    if inside:
        cs = ax.tricontour(tri, v, levels=inside, colors="k", linewidths=0.5)
        ax.clabel(cs, fmt=fmt, fontsize=8, inline_spacing=2)
    if v.min() < -0.01 < 0.01 < v.max():
        cs = ax.tricontour(tri, v, levels=[0.0], colors="k", linewidths=1.3)
        ax.clabel(cs, fmt=fmt, fontsize=8, inline_spacing=2)
        inside.append(0.0)
    return sorted(inside)


def outline(ax, panel, side):
    """The table's regions (dashed, haloed) and X_U, mapped to the current configuration, on one
    side."""
    for poly in regions(panel.radius).values():
        xz = panel.current(densify(poly))
        ax.plot(side * xz[:, 0], xz[:, 1], color="k", lw=0.9, ls=(0, (3, 1.5)), path_effects=HALO)
    x, z = probe(panel)
    ax.plot(side * x, z, "o", ms=4, mfc="k", mec="w", mew=0.8)


def probe(panel):
    """X_U's current position (x, z), scaled with the aggregate (X_U = (0.4 R, 1.9 R))."""
    s = panel.radius / 100.0
    return tuple(panel.current([[PROBE[0] * s, PROBE[2] * s]])[0])
