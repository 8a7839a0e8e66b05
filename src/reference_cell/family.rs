//! The cell families: their node and face counts, faces, edges and geometry.

use super::{TET10_EDGES, TET_FACES, TRI6_EDGES, TRI6_SIDES};

/// The element family of a mesh, which also fixes its geometry.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Family {
    /// 3-D: 10-node tetrahedra with 6-node triangle faces; displacement (u_x, u_y, u_z).
    #[default]
    Tet10,
    /// Axisymmetric: 6-node triangles of the meridian plane with 3-node line faces. The meridian
    /// lies in the x–z plane (x = r ≥ 0, y = 0, z on the axis); displacement (u_r, u_z).
    /// Positive orientation: counter-clockwise in (x, z), det [x1 − x0, x2 − x0] > 0 with rows (x, z).
    Tri6,
}

impl Family {
    /// Nodes per cell (P2).
    pub const fn cell_nodes(self) -> usize {
        match self {
            Family::Tet10 => 10,
            Family::Tri6 => 6,
        }
    }
    /// Vertices per cell (P1 pressure nodes; the first nodes of a cell).
    pub const fn cell_vertices(self) -> usize {
        match self {
            Family::Tet10 => 4,
            Family::Tri6 => 3,
        }
    }
    /// Nodes per boundary face (P2).
    pub(crate) const fn face_nodes(self) -> usize {
        match self {
            Family::Tet10 => 6,
            Family::Tri6 => 3,
        }
    }
    /// Vertices per boundary face (the first nodes of a face).
    pub(crate) const fn face_vertices(self) -> usize {
        match self {
            Family::Tet10 => 3,
            Family::Tri6 => 2,
        }
    }
    /// Displacement components per node.
    pub(crate) const fn components(self) -> usize {
        match self {
            Family::Tet10 => 3,
            Family::Tri6 => 2,
        }
    }
    /// The Cartesian axis (0 = x or r, 1 = y, 2 = z) of each displacement component.
    pub(crate) const fn axes(self) -> &'static [usize] {
        match self {
            Family::Tet10 => &[0, 1, 2],
            Family::Tri6 => &[0, 2],
        }
    }
    /// The displacement component along Cartesian `axis`, if the family has one.
    pub(crate) fn component(self, axis: usize) -> Option<usize> {
        self.axes().iter().position(|&a| a == axis)
    }
    /// Local faces of a cell (cell node positions, in face node order, outward).
    pub(crate) fn cell_faces(self) -> &'static [&'static [usize]] {
        const TET: [&[usize]; 4] = [&TET_FACES[0], &TET_FACES[1], &TET_FACES[2], &TET_FACES[3]];
        const TRI: [&[usize]; 3] = [&TRI6_SIDES[0], &TRI6_SIDES[1], &TRI6_SIDES[2]];
        match self {
            Family::Tet10 => &TET,
            Family::Tri6 => &TRI,
        }
    }
    /// Edges of a cell (vertex pairs) in the order of its mid-edge nodes.
    pub(crate) fn edges(self) -> &'static [(usize, usize)] {
        match self {
            Family::Tet10 => &TET10_EDGES,
            Family::Tri6 => &TRI6_EDGES,
        }
    }
    /// Whether the geometry is axisymmetric (weights 2πr, hoop strain u_r / r).
    pub(crate) const fn axisymmetric(self) -> bool {
        matches!(self, Family::Tri6)
    }
    /// Short plural of the cells, for logs.
    pub(crate) const fn cells_name(self) -> &'static str {
        match self {
            Family::Tet10 => "tets",
            Family::Tri6 => "meridian triangles",
        }
    }
    /// Name of a cell, for messages.
    pub(crate) const fn cell_name(self) -> &'static str {
        match self {
            Family::Tet10 => "tetrahedron",
            Family::Tri6 => "triangle",
        }
    }
}
