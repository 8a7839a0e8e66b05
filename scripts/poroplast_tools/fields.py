"""Observables of a finished run that the sweep's observables of its history (`max:COL`,
`COL@T`, ...) do not give: region means of the cell fields, the positive-pressure region
("pressure bubble"), and the events of a history (the upper plate's detachment, the time a decay
settles). Each takes a run directory and returns a float (NaN where it does not apply), so that
`references.py` can extrapolate it like a history observable (`DERIVED`, by name).

Regions, in reference coordinates (the paper's Figs 5-6 text): the centre, cells whose centroid
has r < 30 µm and |z − R| < 30 µm; the contact zones, r < 40 µm and within 30 µm of either plate.
Means are weighted by volume: on the meridian a cell's area times 2π r of its centroid, in 3-D
its volume (straight-sided cells, which is exact for the reference mesh's interior cells)."""
import math
from functools import lru_cache
from pathlib import Path

import numpy as np

from . import history as runs

# The mid-edge nodes of fields.h5's cells, in the order of XDMF's Tetra_10 and Tri_6 (VTK's):
# nodes 4..9 of a tetrahedron, 3..5 of a triangle, on these vertex pairs. The writer permutes
# gmsh's order into this one (src/io/fields/layout.rs).
TET10_EDGES = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)]
TRI6_EDGES = [(0, 1), (1, 2), (2, 0)]
CENTRE_HALF = 30.0    # µm: the centre region's half-size
CONTACT_R = 40.0      # µm: the contact zones' radius
CONTACT_DEPTH = 30.0  # µm: ... and depth from the plate


# A run's history.csv, read once for the several observables of one run.
history = lru_cache(maxsize=4)(runs.history)


class Fields:
    """A run's fields.h5 with the reference cells' centroids (r, z), volume weights and
    time interpolation between the two outputs around a requested time."""

    def __init__(self, run):
        import h5py
        self.f = h5py.File(Path(run) / "fields.h5", "r")
        X, top = self.f["/mesh/coordinates"][:], self.f["/mesh/topology"][:]
        self.meridian = top.shape[1] == 6
        nv = 3 if self.meridian else 4
        v = X[top[:, :nv]]
        c = v.mean(1)
        self.r, self.z = np.hypot(c[:, 0], c[:, 1]), c[:, 2]
        self.radius = 0.5 * (X[:, 2].max() - X[:, 2].min())
        if self.meridian:   # the meridian lies in the plane y = 0: area × 2π r
            a = 0.5 * np.abs((v[:, 1, 0] - v[:, 0, 0]) * (v[:, 2, 2] - v[:, 0, 2])
                             - (v[:, 2, 0] - v[:, 0, 0]) * (v[:, 1, 2] - v[:, 0, 2]))
            self.w = a * 2 * math.pi * self.r
        else:
            self.w = np.abs(np.linalg.det(v[:, 1:] - v[:, :1])) / 6
        self.vertices = top[:, :nv]
        self.times = self.f["/time"][:]

    def at(self, name, t):
        """Field `name` at time t, linear between the outputs around t (exact at an output)."""
        T = self.times
        if not T[0] - 1e-9 <= t <= T[-1] + 1e-9:
            return None
        k = int(np.searchsorted(T, t - 1e-9))
        if abs(T[k] - t) <= 1e-9 * max(1.0, t) or k == 0:
            return self.f[f"/fields/{name}/{k:06d}"][:]
        w = (t - T[k - 1]) / (T[k] - T[k - 1])
        return (1 - w) * self.f[f"/fields/{name}/{k - 1:06d}"][:] + w * self.f[f"/fields/{name}/{k:06d}"][:]

    def regions(self, depth=CONTACT_DEPTH):
        """The centre and the contact zones (to `depth` from the plates) as cell masks."""
        zones = self.zones(depth)
        return zones["centre"], zones["contact"]

    def zones(self, depth=CONTACT_DEPTH):
        """Every region as a cell mask: the centre, the contact zones, and each plate's alone."""
        R = self.radius
        upper = (self.r < CONTACT_R) & (self.z > 2 * R - depth)
        lower = (self.r < CONTACT_R) & (self.z < depth)
        return {"centre": (self.r < CENTRE_HALF) & (abs(self.z - R) < CENTRE_HALF), "contact": upper | lower,
                "contact_upper": upper, "contact_lower": lower}

    def mean(self, values, where):
        return float((values[where] * self.w[where]).sum() / self.w[where].sum())

    def cell_pressure(self, t):
        p = self.at("p", t)
        return None if p is None else p[self.vertices].mean(1)


@lru_cache(maxsize=2)
def fields(run):
    return Fields(run)


def zone_mean(run, name, zone, t, depth=CONTACT_DEPTH):
    """Volume mean of the cell field `name` (von_mises, norm_ep, porosity) over `zone` (centre,
    contact, contact_upper, contact_lower; the contact zones `depth` deep) at t."""
    f = fields(run)
    v = f.at(name, t)
    if v is None:
        return float("nan")
    return f.mean(v, f.zones(depth)[zone])


def zone_ratio(run, name, t, depth=CONTACT_DEPTH):
    """The contact zones' mean of `name` over the centre's at t."""
    return zone_mean(run, name, "contact", t, depth) / zone_mean(run, name, "centre", t)


def bubble(run, t):
    """The positive-pressure region at t: its share of the volume, the p⁺-weighted mean distance
    of its cells from the aggregate's centre (relative to R) and their p⁺-weighted mean polar
    angle from the axis (degrees; 0 at the poles, where the plates touch, 90 at the equator),
    in reference coordinates."""
    f = fields(run)
    p = f.cell_pressure(t)
    nan = float("nan")
    if p is None:
        return nan, nan, nan
    pos = np.clip(p, 0, None) * f.w
    rho = np.hypot(f.r, f.z - f.radius) / f.radius
    angle = np.degrees(np.arctan2(f.r, abs(f.z - f.radius)))
    share = float(f.w[p > 0].sum() / f.w.sum())
    if not pos.any():
        return share, nan, nan
    return share, float((pos * rho).sum() / pos.sum()), float((pos * angle).sum() / pos.sum())


def detachment(run, after):
    """The upper plate's detachment after time `after`: (time of the last step in contact, σ_VM max
    at that step, σ_VM max at the next step) from the history."""
    h = history(run)
    t, n, vm = h["time"], h["contact_nodes_upper"], h["max_von_mises"]
    for i in range(1, len(t)):
        if t[i] > after and n[i - 1] > 0 and n[i] == 0:
            return float(t[i - 1]), float(vm[i - 1]), float(vm[i])
    return float("nan"), float("nan"), float("nan")


def settle_time(run, col, t0, t1, fraction):
    """The first time after t0 at which `col` is within `fraction` of its total decay from t0 to
    t1 (linear between rows): e.g. 0.05 for the time 95% of the relaxation has happened."""
    h = history(run)
    t, v = h["time"], h[col]
    v0, v1 = runs.at(h, col, t0), runs.at(h, col, t1)
    target = v1 + fraction * (v0 - v1)
    for i in range(1, len(t)):
        if t[i] > t0 and (v[i - 1] - target) * (v[i] - target) <= 0 and v[i] != v[i - 1]:
            return float(t[i - 1] + (t[i] - t[i - 1]) * (v[i - 1] - target) / (v[i - 1] - v[i]))
    return float("nan")


def hold_min(run, col, t0, t1):
    """The smallest value of `col` over [t0, t1]."""
    h = history(run)
    m = (h["time"] >= t0) & (h["time"] <= t1)
    return float(h[col][m].min()) if m.any() else float("nan")


def peak_time(run, col):
    h = history(run)
    return float(h["time"][h[col].argmax()])


# name -> function of a run directory: the derived observables that references.py's cases name.
DERIVED = {
    **{f"vm_{z}@{t:g}": (lambda z, t: lambda run: zone_mean(run, "von_mises", z, t))(z, t)
       for z in ("centre", "contact") for t in (35.0, 36.0, 37.0, 40.0, 60.0)},
    **{f"vm_contact/centre@{t:g}": (lambda t: lambda run: zone_ratio(run, "von_mises", t))(t) for t in (35.0, 40.0, 60.0)},
    **{f"ep_{z}@60": (lambda z: lambda run: zone_mean(run, "norm_ep", z, 60.0))(z) for z in ("centre", "contact")},
    "ep_contact/centre@60": lambda run: zone_ratio(run, "norm_ep", 60.0),
    # the contact zones 10 µm deep instead of 30: the layer right under the plates
    "ep_contact10/centre@60": lambda run: zone_ratio(run, "norm_ep", 60.0, 10.0),
    "vm_contact10/centre@40": lambda run: zone_ratio(run, "von_mises", 40.0, 10.0),
    # the largest σ_VM anywhere (a point value) over the centre's mean
    **{f"vm_max/centre@{t:g}": (lambda t: lambda run: runs.at(history(run), "max_von_mises", t)
                                / zone_mean(run, "von_mises", "centre", t))(t) for t in (40.0, 60.0)},
    "detach_t": lambda run: detachment(run, 35.0)[0],
    "vm_max_before_detach": lambda run: detachment(run, 35.0)[1],
    "vm_max_after_detach": lambda run: detachment(run, 35.0)[2],
    **{f"bubble_share@{t:g}": (lambda t: lambda run: bubble(run, t)[0])(t) for t in (35.0, 45.0, 60.0)},
    **{f"bubble_where@{t:g}": (lambda t: lambda run: bubble(run, t)[1])(t) for t in (35.0, 45.0, 60.0)},
    **{f"bubble_angle@{t:g}": (lambda t: lambda run: bubble(run, t)[2])(t) for t in (35.0, 45.0, 60.0)},
    # the no-remodelling hold (405 s): when 90% / 95% of the force's relaxation from the peak
    # (5 s) to the end of the hold (400 s) has happened
    "settle90:force_total_mg": lambda run: settle_time(run, "force_total_mg", 5.0, 400.0, 0.10),
    "settle95:force_total_mg": lambda run: settle_time(run, "force_total_mg", 5.0, 400.0, 0.05),
    "min_hold:probe_p": lambda run: hold_min(run, "probe_p", 5.0, 150.0),     # t_end = 155 s
    "min_hold405:probe_p": lambda run: hold_min(run, "probe_p", 5.0, 400.0),  # t_end = 405 s
    "t_max:force_constitutive_mg": lambda run: peak_time(run, "force_constitutive_mg"),
}


def history_observables(observe):
    """The observables `poroplast sweep` evaluates (those of the history): not DERIVED's."""
    return [o for o in observe if o not in DERIVED]


def observed(run, result, observable):
    """An observable of a completed case: DERIVED's from its run directory, else the sweep's
    value in its `result` row."""
    return DERIVED[observable](run) if observable in DERIVED else result.get(observable, float("nan"))
