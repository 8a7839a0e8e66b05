"""Plane sections of a tetrahedral mesh against what geometry says they are: the unit cube in
6 × 27 tetrahedra cut by a plane y = c has area 1 wherever c lies in [0, 1] (inside cells,
along their faces, on the cube's two boundary faces), by z = 1/2 too, and by x + y + z = 3/2 in
the regular hexagon of side √2/2 (area 3√3/4); a linear field is interpolated exactly (its
integral over the section is the field at the section's centroid times the area), neighbouring
triangles share their corners, and every triangle lies in the cell whose value it carries."""
import itertools
import math
import unittest

import numpy as np

from poroplast_tools import slices


def cube(n=3, side=1.0):
    """The cube [0, side]³ in n³ cubes of 6 tetrahedra each (Kuhn's: the paths from a cube's
    corner 0 to corner 7 along its edges): (points, k×4 vertices)."""
    g = np.linspace(0, side, n + 1)
    X = np.array([[x, y, z] for z in g for y in g for x in g])
    at = lambda i, j, k: i + (n + 1) * (j + (n + 1) * k)
    tets = []
    for i, j, k in itertools.product(range(n), repeat=3):
        corner = [at(i + (c & 1), j + (c >> 1 & 1), k + (c >> 2 & 1)) for c in range(8)]
        for axes in itertools.permutations(range(3)):
            path = [0]
            for a in axes:
                path.append(path[-1] | 1 << a)
            tets.append([corner[c] for c in path])
    return X, np.array(tets)


def linear(P):
    return 2.0 * P[:, 0] - 3.0 * P[:, 1] + 5.0 * P[:, 2] + 1.0


class Slices(unittest.TestCase):
    def setUp(self):
        self.X, self.tets = cube()
        vol = np.abs(np.linalg.det(self.X[self.tets[:, 1:]] - self.X[self.tets[:, :1]])).sum() / 6
        self.assertAlmostEqual(vol, 1.0, places=12)

    def check(self, s, area, centroid):
        """The section's area, the exact interpolation of the linear field at its points, its
        integral (the field at the centroid times the area), and each triangle inside its cell."""
        a = s.area()
        self.assertAlmostEqual(a.sum(), area, places=12)
        # one point per place: neighbouring triangles share their corners (a continuous picture)
        used = s.points[np.unique(s.triangles)]
        self.assertEqual(len(np.unique(np.round(used, 9), axis=0)), len(used))
        v = s.node(linear(self.X))
        self.assertLess(np.abs(v - linear(s.points)).max(), 1e-12)
        mean = (a * v[s.triangles].mean(1)).sum() / a.sum()
        self.assertAlmostEqual(mean, linear(np.array([centroid]))[0], places=12)
        # barycentric coordinates of the triangles' centroids in their cells: all in [0, 1]
        T = self.X[self.tets[s.cells]]
        c = s.points[s.triangles].mean(1)
        lam = np.linalg.solve(np.transpose(T[:, 1:] - T[:, :1], (0, 2, 1)), (c - T[:, 0])[..., None])[..., 0]
        self.assertGreater(lam.min(), -1e-12)
        self.assertLess(lam.sum(1).max(), 1 + 1e-12)
        self.assertTrue((s.cell(np.arange(len(self.tets))) == s.cells).all())

    def test_planes_y_through_cells_faces_and_boundaries(self):
        for c in (0.0, 0.4, 1 / 3, 0.5, 1.0):
            with self.subTest(y=c):
                s = slices.cut(self.X, self.tets, [0, 1, 0], c)
                self.assertLess(np.abs(s.points[:, 1] - c).max(), 1e-15)
                self.check(s, 1.0, [0.5, c, 0.5])

    def test_a_horizontal_and_an_oblique_plane(self):
        self.check(slices.cut(self.X, self.tets, [0, 0, 2], 1.0), 1.0, [0.5, 0.5, 0.5])
        hexagon = slices.cut(self.X, self.tets, [1, 1, 1], 1.5)
        self.check(hexagon, 3 * math.sqrt(3) / 4, [0.5, 0.5, 0.5])

    def test_a_plane_that_misses_the_mesh(self):
        self.assertIsNone(slices.cut(self.X, self.tets, [0, 1, 0], 1.5))
        self.assertIsNone(slices.cut(self.X, self.tets, [0, 1, 0], -0.1))

    def test_round_off_off_the_plane_is_on_it(self):
        # A symmetry face written with -2e-14 for 0 (the 3-D reference mesh has such): still
        # the face, once.
        X = self.X.copy()
        X[X[:, 1] == 0, 1] = -2.4e-14
        self.check(slices.cut(X, self.tets, [0, 1, 0], 0.0), 1.0, [0.5, 0.0, 0.5])


if __name__ == "__main__":
    unittest.main()
