"""The refined drawing of poroplast_tools.maps against fields with known values: the P2 map
reproduces the nodes exactly and a quadratic displacement everywhere (so that a deformed
boundary curves as the P2 solution does), the P1 pressure is exactly linear inside, neighbours
share their edge points, X_U and the table's regions move with a known displacement, and a map
figure drawn from a synthetic run is printed at its width (and so is every paper figure in
docs/figures, each embedded in the docs)."""
import re
import tempfile
import unittest
from pathlib import Path

import numpy as np

from poroplast_tools import maps, paper_figures as pf

DOCS = Path(__file__).resolve().parents[2] / "docs"

# Two straight 6-node triangles on the rectangle [0, 100] × [0, 200] (x, z), mid-edge nodes in
# fields.TRI6_EDGES order; their shared edge is (0, 2).
CORNERS = np.array([[0, 0], [100, 0], [100, 200], [0, 200]], float)
TRI = [(0, 1, 2), (0, 2, 3)]


def mesh():
    X, tri6, mids = [*CORNERS], [], {}
    for t in TRI:
        row = list(t)
        for a, b in ((t[0], t[1]), (t[1], t[2]), (t[2], t[0])):
            k = frozenset((a, b))
            if k not in mids:
                mids[k] = len(X)
                X.append((CORNERS[a] + CORNERS[b]) / 2)
            row.append(mids[k])
        tri6.append(row)
    return np.array(X), np.array(tri6)


def quadratic(P):
    x, z = P[..., 0], P[..., 1]
    return np.stack([1e-3 * x * z + 0.5 * x - 3.0, 2e-4 * x * x - 1e-4 * z * z + 0.1 * z], -1)


class Refinement(unittest.TestCase):
    def test_nodes_and_quadratics_exact(self):
        X, tri6 = mesh()
        u = quadratic(X)
        for n in (2, 4, 6):
            r = maps.refine(X, u, tri6, n)
            # every node of the mesh is a sub-point (n even), at its own deformed position
            for i in range(len(X)):
                k = np.nonzero(np.all(np.abs(r.ref - X[i]) < 1e-9, 1))[0]
                self.assertEqual(len(k), 1, f"node {i}, n = {n}")
                np.testing.assert_allclose(r.cur[k[0]], X[i] + u[i], atol=1e-12)
            # a quadratic displacement is P2: exact at every sub-point, not only at the nodes
            np.testing.assert_allclose(r.cur, r.ref + quadratic(r.ref), atol=1e-10)
            np.testing.assert_allclose(r.p2(tri6, u), quadratic(r.ref), atol=1e-10)

    def test_curved_edge(self):
        """A mid-edge node moved off its chord: the sub-points of that edge lie on the parabola
        through the edge's three nodes (the deformed boundary curves)."""
        X, tri6 = mesh()
        u = np.zeros_like(X)
        u[tri6[0, 3]] = [0.0, 10.0]                     # the mid-node of edge (0, 1), z = 0, raised 10 µm
        r = maps.refine(X, u, tri6, 4)
        on = np.abs(r.ref[:, 1]) < 1e-9                 # the sub-points of that edge
        s = r.ref[on, 0] / 100.0
        np.testing.assert_allclose(r.cur[on, 1], 4 * s * (1 - s) * 10.0, atol=1e-12)
        self.assertEqual(on.sum(), 5)

    def test_p1_exact_inside(self):
        X, tri6 = mesh()
        p = 2.0 - 0.03 * X[:, 0] + 0.011 * X[:, 1]
        p_mid_wrong = p.copy()
        p_mid_wrong[4:] = 99.0                          # mid-edge values are not used: p is P1
        r = maps.refine(X, np.zeros_like(X), tri6, 6)
        exact = 2.0 - 0.03 * r.ref[:, 0] + 0.011 * r.ref[:, 1]
        np.testing.assert_allclose(r.p1(tri6, p_mid_wrong), exact, atol=1e-12)
        # linear on each sub-triangle: exact at any point inside
        import matplotlib.tri as mtri
        tri = mtri.Triangulation(r.ref[:, 0], r.ref[:, 1], r.triangles)
        q = np.random.default_rng(1).uniform([1, 1], [99, 199], (200, 2))
        got = mtri.LinearTriInterpolator(tri, r.p1(tri6, p))(q[:, 0], q[:, 1])
        np.testing.assert_allclose(got, 2.0 - 0.03 * q[:, 0] + 0.011 * q[:, 1], atol=1e-10)

    def test_neighbours_share_points(self):
        X, tri6 = mesh()
        n = 4
        r = maps.refine(X, np.zeros_like(X), tri6, n)
        per = (n + 1) * (n + 2) // 2
        self.assertEqual(len(r.ref), 2 * per - (n + 1))   # the shared edge's n + 1 points once
        self.assertEqual(len(r.triangles), 2 * n * n)
        a, b = (r.ref[r.triangles[:, k]] - r.ref[r.triangles[:, 0]] for k in (1, 2))
        area = 0.5 * np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0])
        self.assertAlmostEqual(area.sum(), 100 * 200, places=6)
        self.assertEqual(len(np.unique(r.parent)), 2)


def synthetic_run(d, shift):
    """A meridian fields.h5 on the rectangle mesh: u = shift everywhere, p linear, at t = 0, 30 s."""
    import h5py
    X, tri6 = mesh()
    X3 = np.c_[X[:, 0], np.zeros(len(X)), X[:, 1]]
    with h5py.File(Path(d) / "fields.h5", "w") as f:
        f["/mesh/coordinates"], f["/mesh/topology"], f["/time"] = X3, tri6, np.array([0.0, 30.0])
        for k in (0, 1):
            f[f"/fields/u/{k:06d}"] = np.tile([shift[0], 0.0, shift[1]], (len(X), 1))
            f[f"/fields/p/{k:06d}"] = (1.0 - 0.02 * X[:, 0]) * (k + 1)
            f[f"/fields/von_mises/{k:06d}"] = np.array([1.0, 2.0])
    return X, tri6


class Panels(unittest.TestCase):
    def test_regions_and_probe_move_with_u(self):
        with tempfile.TemporaryDirectory() as d:
            shift = (3.0, -7.0)
            synthetic_run(d, shift)
            s = maps.Section("synthetic", d)
            self.assertEqual(s.radius, 100.0)
            panel = s.panel(s.index(30.0)[0], ["p", "von_mises"])
            self.assertIn("p", panel.node)
            self.assertIn("von_mises", panel.cell)
            np.testing.assert_allclose(maps.probe(panel), (40.0 + shift[0], 190.0 + shift[1]), atol=1e-9)
            for name, poly in maps.regions(100.0).items():
                pts = maps.densify(poly, 2.0)
                self.assertLessEqual(np.diff(pts, axis=0).__abs__().max(), 2.0 + 1e-9)
                np.testing.assert_allclose(panel.current(pts), pts + shift, atol=1e-9, err_msg=name)
            up = maps.regions(100.0)["contact_upper"]
            self.assertTrue(np.allclose(np.hypot(up[2:, 0], up[2:, 1] - 100.0), 100.0))   # along the sphere
            self.assertEqual(tuple(up[1]), (40.0, 170.0))

    def test_3d_face_in_the_plane(self):
        """A 10-node tetrahedron with a face in y = 0: the section is that face with its own
        mid-edge nodes (a quadratic u is reproduced only if each lands on its edge)."""
        import h5py
        from poroplast_tools.fields import TET10_EDGES
        V = np.array([[0, 0, 0], [100, 0, 0], [0, 0, 200], [0, 50, 0]], float)
        X = np.vstack([V, [(V[a] + V[b]) / 2 for a, b in TET10_EDGES]])
        q = quadratic(X[:, [0, 2]])
        with tempfile.TemporaryDirectory() as d:
            with h5py.File(Path(d) / "fields.h5", "w") as f:
                f["/mesh/coordinates"], f["/mesh/topology"], f["/time"] = X, np.arange(10)[None, :], np.array([1.0])
                f["/fields/u/000000"] = np.c_[q[:, 0], np.zeros(10), q[:, 1]]
                f["/fields/p/000000"] = np.zeros(10)
            s = maps.Section("tet", d)
            self.assertEqual(s.tri6.shape, (1, 6))
            r = s.panel(0, ["p"]).refined
            self.assertAlmostEqual(np.abs(r.ref[:, 1]).max(), 200.0)
            np.testing.assert_allclose(r.cur, r.ref + quadratic(r.ref), atol=1e-10)

    def test_map_figure_printed_at_its_width(self):
        with tempfile.TemporaryDirectory() as d:
            run, out = Path(d) / "run", Path(d) / "out"
            run.mkdir()
            synthetic_run(run, (0.0, -5.0))
            name = "fig11c_pressure.png"
            made = pf.fig_pressure({"a": run, "b": run}, out, {}, ["a", "b"], [30.0], name, ("a", "b"))
            self.assertEqual(made, name)
            from PIL import Image
            with Image.open(out / "figures" / name) as im:
                w, h = im.size
            self.assertEqual(w, expected_px(pf.WIDTHS[name]))
            rows = (out / "figures" / "data" / "fig11c_pressure.csv").read_text().splitlines()
            self.assertEqual(len(rows), 3)
            self.assertIn("40,185", rows[1])             # X_U moved by u = (0, −5)
            nodes = (out / "figures" / "data" / "fig11c_pressure_nodes.csv").read_text().splitlines()
            self.assertEqual(len(nodes), 1 + 2 * len(mesh()[0]))


class CommittedMapData(unittest.TestCase):
    """The maps' committed data (docs/figures/data/<figure>_nodes.csv, _cells.csv) holds what the
    refined drawing needs, and agrees with the numbers computed from the runs' fields.h5 apart
    (the figures' summary rows; fig5_6_zones.csv's largest σ_VM cell, from fields.py)."""

    def panels(self, name):
        d = DOCS / "figures" / "data"
        return maps.read_panels(d / f"{name}_nodes.csv", d / f"{name}_cells.csv")

    def test_pressure_maps(self):
        import csv
        for name in ("fig3_pressure", "fig3_later_pressure", "fig11c_pressure", "fig_soft_pressure"):
            panels = {(p.case, p.t): p for p in self.panels(name)}
            with open(DOCS / "figures" / "data" / f"{name}.csv", newline="") as f:
                rows = list(csv.DictReader(f))
            self.assertEqual(len(rows), len(panels), name)
            for r in rows:
                p = panels[(r["case"], float(r["t_s"]))]
                self.assertEqual(p.radius, 100.0)
                for got, col in ((p.node["p"].min(), "p_min_kPa"), (p.node["p"].max(), "p_max_kPa"),
                                 (maps.probe(p)[0], "x_U_um"), (maps.probe(p)[1], "z_U_um")):
                    self.assertAlmostEqual(got, float(r[col]), delta=1e-5 * max(1.0, abs(got)), msg=f"{name} {col}")

    def test_midplane_maps(self):
        import csv
        with open(DOCS / "figures" / "data" / "fig5_6_zones.csv", newline="") as f:
            zones = {r["row"]: r for r in csv.DictReader(f)}
        panels = self.panels("fig5_6_midplane")
        self.assertEqual([p.t for p in panels], pf.MIDPLANE_TIMES)
        for p in panels:
            vm = float(zones[f"{p.case}@{p.t:g}"]["vm_max_kPa"])
            self.assertAlmostEqual(p.cell["von_mises"].max(), vm, delta=1e-5 * vm)


def expected_px(width_cm):
    """matplotlib's pixel width of a figure `width_cm` wide at DPI (it truncates)."""
    return int(width_cm / 2.54 * pf.DPI)


class PaperFigures(unittest.TestCase):
    def test_small_text_is_refused(self):
        import matplotlib.pyplot as plt
        with tempfile.TemporaryDirectory() as d:
            fig, ax = plt.subplots()
            ax.set_title("fine", fontsize=8)
            ax.text(0.5, 0.5, "too small", fontsize=6)
            with self.assertRaisesRegex(ValueError, "too small"):
                pf.save(fig, Path(d), "x.png")
            self.assertFalse((Path(d) / "figures" / "x.png").exists())
            plt.close(fig)

    def test_docs_figures_printed_at_their_width_and_embedded(self):
        """Every paper figure in docs/figures is as wide as its printed width at DPI, no taller
        than a page (24 cm), and embedded in docs/reproduction.md."""
        from PIL import Image
        page = (DOCS / "reproduction.md").read_text()
        embedded = set(re.findall(r"\]\(figures/([^)]+\.png)\)", page))
        for name, width in pf.WIDTHS.items():
            with Image.open(DOCS / "figures" / name) as im:
                w, h = im.size
            self.assertEqual(w, expected_px(width), name)
            self.assertLessEqual(h, expected_px(24.0), name)
            self.assertIn(name, embedded)
        # no figure of the paper is embedded that the script does not make
        papers = {n for n in embedded if re.match(r"fig\d|fig_", n)}
        self.assertEqual(papers - set(pf.WIDTHS), set())


if __name__ == "__main__":
    unittest.main()
