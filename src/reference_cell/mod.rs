//! The reference cells below meshes and elements (deal.II's `ReferenceCell` layer): the cell
//! families, their node numbering (gmsh's), the P1/P2 shape functions on them ([`shape`]) and the
//! check that a curved cell's map does not fold. Meshes use it to build and check cells, elements
//! to integrate on them; it depends on neither.
//!
//! Conventions (gmsh's, verified on a straight-sided order-2 mesh, see `mesh::tests::gmsh_tet10_edge_order`):
//! * a tet has 10 nodes: vertices 0..4, then the mid-edge node `4 + k` on edge [`TET10_EDGES`]`[k]`;
//! * every tet is positively oriented: det [x1 - x0, x2 - x0, x3 - x0] > 0;
//! * a boundary face has 6 nodes in gmsh Triangle6 order (3 vertices, then the mid-nodes of edges
//!   01, 12, 20), oriented so that the right-hand rule on the 3 vertices gives the outward normal;
//! * a meridian triangle has 6 nodes (3 vertices, then the mid-nodes of edges 01, 12, 20) and is
//!   counter-clockwise in (x, z).

pub mod shape;

/// Mid-edge node `4 + k` of a Tetrahedron10 sits on the edge between vertices `TET10_EDGES[k]` (gmsh order).
pub const TET10_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)];

/// Local faces of a Tetrahedron10: 3 vertex positions then the 3 mid-edge positions (Triangle6 order),
/// ordered so that the right-hand-rule normal points OUT of a positively oriented tet.
/// Face 0 is opposite vertex 3, face 1 opposite vertex 2, face 2 opposite vertex 0, face 3 opposite vertex 1.
pub const TET_FACES: [[usize; 6]; 4] = [[0, 2, 1, 6, 5, 4], [0, 1, 3, 4, 9, 7], [1, 2, 3, 5, 8, 9], [0, 3, 2, 7, 8, 6]];

/// Node permutation that turns a negatively oriented Tetrahedron10 into a positive one
/// (swap vertices 1 and 2; the mid-edge nodes follow their edges).
pub const TET10_FLIP: [usize; 10] = [0, 2, 1, 3, 6, 5, 4, 7, 9, 8];

/// Nodes of a Triangle6 cell's sides as Line3 faces (vertex, vertex, mid-edge node), each ordered
/// so that the outward normal of a positively oriented triangle is the tangent turned clockwise
/// in the (x, z) plane (see [`Family::Tri6`]).
pub const TRI6_SIDES: [[usize; 3]; 3] = [[0, 1, 3], [1, 2, 4], [2, 0, 5]];

/// Mid-edge node `3 + k` of a Triangle6 sits on the edge between vertices `TRI6_EDGES[k]` (gmsh order).
pub const TRI6_EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

pub const MAX_CELL_NODES: usize = 10;
pub const MAX_FACE_NODES: usize = 6;

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
    pub const fn face_nodes(self) -> usize {
        match self {
            Family::Tet10 => 6,
            Family::Tri6 => 3,
        }
    }
    /// Vertices per boundary face (the first nodes of a face).
    pub const fn face_vertices(self) -> usize {
        match self {
            Family::Tet10 => 3,
            Family::Tri6 => 2,
        }
    }
    /// Displacement components per node.
    pub const fn components(self) -> usize {
        match self {
            Family::Tet10 => 3,
            Family::Tri6 => 2,
        }
    }
    /// The Cartesian axis (0 = x or r, 1 = y, 2 = z) of each displacement component.
    pub const fn axes(self) -> &'static [usize] {
        match self {
            Family::Tet10 => &[0, 1, 2],
            Family::Tri6 => &[0, 2],
        }
    }
    /// The displacement component along Cartesian `axis`, if the family has one.
    pub fn component(self, axis: usize) -> Option<usize> {
        self.axes().iter().position(|&a| a == axis)
    }
    /// Local faces of a cell (cell node positions, in face node order, outward).
    pub fn cell_faces(self) -> &'static [&'static [usize]] {
        const TET: [&[usize]; 4] = [&TET_FACES[0], &TET_FACES[1], &TET_FACES[2], &TET_FACES[3]];
        const TRI: [&[usize]; 3] = [&TRI6_SIDES[0], &TRI6_SIDES[1], &TRI6_SIDES[2]];
        match self {
            Family::Tet10 => &TET,
            Family::Tri6 => &TRI,
        }
    }
    /// Edges of a cell (vertex pairs) in the order of its mid-edge nodes.
    pub fn edges(self) -> &'static [(usize, usize)] {
        match self {
            Family::Tet10 => &TET10_EDGES,
            Family::Tri6 => &TRI6_EDGES,
        }
    }
    /// Whether the geometry is axisymmetric (weights 2πr, hoop strain u_r / r).
    pub const fn axisymmetric(self) -> bool {
        matches!(self, Family::Tri6)
    }
    /// Short plural of the cells, for logs.
    pub const fn cells_name(self) -> &'static str {
        match self {
            Family::Tet10 => "tets",
            Family::Tri6 => "meridian triangles",
        }
    }
    /// Name of a cell, for messages.
    pub const fn cell_name(self) -> &'static str {
        match self {
            Family::Tet10 => "tetrahedron",
            Family::Tri6 => "triangle",
        }
    }
}

/// Node permutation that turns a clockwise Triangle6 counter-clockwise (swap vertices 1 and 2; the
/// mid-edge nodes follow their edges).
pub const TRI6_FLIP: [usize; 6] = [0, 2, 1, 5, 4, 3];

/// Twice the signed area of the straight triangle in the (x, z) plane.
pub fn area2(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    (b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0])
}

/// The measure of a cell's straight (vertex) simplex, vertex i at `x(i)`: the volume of a
/// tetrahedron, the area of a meridian triangle.
pub fn straight_measure(family: Family, x: impl Fn(usize) -> [f64; 3]) -> f64 {
    match family {
        Family::Tet10 => tet_det(x(0), x(1), x(2), x(3)).abs() / 6.0,
        Family::Tri6 => area2(x(0), x(1), x(2)).abs() / 2.0,
    }
}

/// Determinant of [b - a, c - a, d - a] (6 x signed volume of the straight tet).
pub fn tet_det(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    let u = sub(b, a);
    let v = sub(c, a);
    let w = sub(d, a);
    u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0])
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
