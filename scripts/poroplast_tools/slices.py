"""A plane section of a tetrahedral mesh: the triangles where the plane n·x = c cuts the cells,
with the cells' linear (vertex) interpolation on them. What a field picture of a 3-D run draws
(`fieldplots`): a node field is interpolated at the cut points from the two vertices of each cut
edge (exact for a field linear on the cell, as p is), a cell field is its cell's value on every
triangle of the cell.

Vertices on the plane (a symmetry face of a quarter mesh lies in it) belong to the side n·x ≤ c:
a face in the plane is then cut from the one cell on its n·x > c side, so it appears once (a
boundary face with no cell on that side: from the other side), and the slivers of cells that
only touch the plane have no area and are dropped."""
from dataclasses import dataclass

import numpy as np

# Signed distances within this share of the mesh's size are on the plane (round-off of the
# coordinates of a face meant to lie in it).
ON_PLANE = 1e-10


@dataclass
class Section:
    """The triangles of a cut: points (m×3, in space), triangles (k×3 indices into them), the
    cell of each triangle (k), and each point on the edge (a, b) of the mesh at a + w (b − a):
    edges (m×2 vertex indices), w (m)."""
    points: np.ndarray
    triangles: np.ndarray
    cells: np.ndarray
    edges: np.ndarray
    w: np.ndarray

    def node(self, values):
        """A node field's values at the cut points (linear along each cut edge)."""
        v = np.asarray(values)
        a, b = v[self.edges[:, 0]], v[self.edges[:, 1]]
        return a + self.w * (b - a)

    def cell(self, values):
        """A cell field's value on each triangle."""
        return np.asarray(values)[self.cells]

    def area(self):
        """The area of each triangle."""
        p = self.points[self.triangles]
        return 0.5 * np.linalg.norm(np.cross(p[:, 1] - p[:, 0], p[:, 2] - p[:, 0]), axis=1)


def _triangles(pattern):
    """The cut of a cell whose vertices i with bit i of `pattern` set lie on the n·x > c side:
    triangles of three edges, each (vertex above, vertex below). One vertex alone on its side:
    the three edges from it; two on each side (a, b | c, d): the quadrilateral (a,c), (a,d),
    (b,d), (b,c) as two triangles; none when all four are on one side."""
    up = [i for i in range(4) if pattern >> i & 1]
    down = [i for i in range(4) if not pattern >> i & 1]
    if len(up) == 1:
        return [[(up[0], j) for j in down]]
    if len(up) == 3:
        return [[(i, down[0]) for i in up]]
    if len(up) == 2:
        (a, b), (c, d) = up, down
        return [[(a, c), (a, d), (b, d)], [(a, c), (b, d), (b, c)]]
    return []


TRIANGLES = [np.array(_triangles(k), int).reshape(-1, 3, 2) for k in range(16)]


def cut(X, tets, normal, c):
    """The section of the cells `tets` (k×4 vertex indices into the points X; further columns
    ignored) by the plane normal·x = c; None where the plane misses the mesh. A boundary face in
    the plane with its cell on the n·x < c side is cut from the other side."""
    s = _cut(X, tets, normal, c)
    return s if s is not None else _cut(X, tets, -np.asarray(normal, float), -c)


def _cut(X, tets, normal, c):
    X, tets = np.asarray(X, float), np.asarray(tets)[:, :4]
    n = np.asarray(normal, float)
    size = max(np.ptp(X, axis=0).max(), 1.0)
    d = X @ n - c
    d[np.abs(d) <= ON_PLANE * size * np.linalg.norm(n)] = 0.0
    pattern = ((d[tets] > 0) * (1 << np.arange(4))).sum(1)
    cells, pairs = [], []
    for k in range(1, 15):
        these = np.nonzero(pattern == k)[0]
        for t in TRIANGLES[k]:
            cells.append(these)
            pairs.append(tets[these][:, t])                  # (n, 3, 2) global (above, below)
    cells = np.concatenate(cells)
    if not len(cells):
        return None
    pairs = np.concatenate(pairs)
    a, b = pairs[..., 0], pairs[..., 1]
    w = d[a] / (d[a] - d[b])                                  # d[a] > 0 >= d[b]: w in (0, 1]
    # A point at a vertex on the plane (w = 1) is that vertex's, whichever edge reached it.
    on = w == 1.0
    key = np.stack([np.where(on, b, np.minimum(a, b)), np.where(on, b, np.maximum(a, b))], -1).reshape(-1, 2)
    _, first, index = np.unique(key, axis=0, return_index=True, return_inverse=True)
    tri = index.reshape(-1, 3)
    edges = np.stack([a.ravel()[first], b.ravel()[first]], 1)
    ws = w.ravel()[first]
    points = X[edges[:, 0]] + ws[:, None] * (X[edges[:, 1]] - X[edges[:, 0]])
    s = Section(points, tri, cells, edges, ws)
    # Cells that only touch the plane (at a vertex or an edge) leave triangles without area.
    keep = s.area() > 1e-12 * size ** 2
    if not keep.any():
        return None
    return Section(points, tri[keep], cells[keep], edges, ws)
