#!/usr/bin/env python3
"""Pressure at the upper contact edge of a plates run: oscillations would show as negative
pressures or a non-monotone profile p(r) along the contact surface.

For every output step with an upper contact patch, takes the pressure at the surface nodes
touching the upper plate (contact field = 2) and at all other nodes within 15 um below
the plate and 15 um beyond the patch's radius, and prints: the largest pressure, the smallest pressure in contact, the most
negative pressure near the edge (relative to the largest), and how often p increases outward
along the contact patch (binned in r; a smooth profile decreases towards the edge).

    python3 scripts/contact_edge.py RUN_DIR [--until T]
"""
import argparse
import h5py
import numpy as np


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("run")
    ap.add_argument("--until", type=float, default=None, help="last time to look at (e.g. the end of the hold)")
    a = ap.parse_args()
    f = h5py.File(f"{a.run}/fields.h5", "r")
    X = f["mesh/coordinates"][:]
    times = f["time"][:]
    z_top = X[:, 2].max()
    worst = 0.0
    print(f"{'t':>8} {'r_c':>6} {'p_max':>8} {'p_min(contact)':>14} {'p_min(edge)/p_max':>18} {'rises':>5}")
    for k, t in enumerate(times):
        if a.until is not None and t > a.until + 1e-9:
            break
        key = f"{k:06d}"
        c = f["fields/contact"][key][:]
        top = c == 2
        if top.sum() < 3:
            continue
        u = f["fields/u"][key][:]
        p = f["fields/p"][key][:]
        x = X + u
        r = np.hypot(x[:, 0], x[:, 1])
        rc = r[top].max()
        near = (x[:, 2] > z_top - 15.0) & ~top & (r < rc + 15.0)
        pmax = p.max()
        pmin_c = p[top].min()
        pmin_edge = min(p[top].min(), p[near].min() if near.any() else 0.0)
        # Profile along the patch: mean p in radial bins; count increases outward.
        bins = np.linspace(0, rc, 6)
        means = [p[top & (r >= lo) & (r < hi)].mean() for lo, hi in zip(bins[:-1], bins[1:]) if (top & (r >= lo) & (r < hi)).any()]
        rises = sum(1 for m0, m1 in zip(means, means[1:]) if m1 > m0 + 1e-6 * pmax)
        worst = min(worst, pmin_edge / pmax)
        print(f"{t:8.3f} {rc:6.1f} {pmax:8.3f} {pmin_c:14.4f} {pmin_edge / pmax:18.2e} {rises:5d}")
    print(f"most negative edge pressure relative to p_max: {worst:.2e}")


if __name__ == "__main__":
    main()
