//! The global quadratic tetrahedral mesh (as read from a file), its local node conventions, and face matching.
//!
//! Conventions (gmsh's, verified on a straight-sided order-2 mesh, see `tests::gmsh_tet10_edge_order`):
//! * a tet has 10 nodes: vertices 0..4, then the mid-edge node `4 + k` on edge [`TET10_EDGES`]`[k]`;
//! * every tet is positively oriented: det [x1 - x0, x2 - x0, x3 - x0] > 0;
//! * a boundary face has 6 nodes in gmsh Triangle6 order (3 vertices, then the mid-nodes of edges
//!   01, 12, 20), oriented so that the right-hand rule on the 3 vertices gives the outward normal.

pub mod dist;
pub mod generate;
pub mod gmsh;
pub mod meridian;
pub mod mirror;
pub mod partition;
pub mod source;

#[cfg(test)]
mod tests;

use crate::error::{Error, Result};

/// Mid-edge node `4 + k` of a Tetrahedron10 sits on the edge between vertices `TET10_EDGES[k]` (gmsh order).
pub const TET10_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)];

/// Local faces of a Tetrahedron10: 3 vertex positions then the 3 mid-edge positions (Triangle6 order),
/// ordered so that the right-hand-rule normal points OUT of a positively oriented tet.
/// Face 0 is opposite vertex 3, face 1 opposite vertex 2, face 2 opposite vertex 0, face 3 opposite vertex 1.
pub const TET_FACES: [[usize; 6]; 4] = [[0, 2, 1, 6, 5, 4], [0, 1, 3, 4, 9, 7], [1, 2, 3, 5, 8, 9], [0, 3, 2, 7, 8, 6]];

/// Node permutation that turns a negatively oriented Tetrahedron10 into a positive one
/// (swap vertices 1 and 2; the mid-edge nodes follow their edges).
pub(crate) const TET10_FLIP: [usize; 10] = [0, 2, 1, 3, 6, 5, 4, 7, 9, 8];

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

/// The global mesh: quadratic cells, outward boundary faces and named physical groups.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Node coordinates, compact 0-based numbering.
    pub coords: Vec<[f64; 3]>,
    /// The element family: what a cell and a boundary face are.
    pub family: Family,
    /// Cells, positively oriented, in gmsh node order (Tetrahedron10, or Triangle6 of the meridian);
    /// a cell uses the first [`Family::cell_nodes`] slots (the rest are `u32::MAX`).
    pub cells: Vec<[u32; MAX_CELL_NODES]>,
    /// Boundary (tagged) faces — Triangle6, or Line3 on the meridian — each unique, outward from
    /// their cell; a face uses the first [`Family::face_nodes`] slots.
    pub faces: Vec<[u32; MAX_FACE_NODES]>,
    /// For each face: its cell and that cell's local face index (see [`Family::cell_faces`]).
    pub face_cell: Vec<(u32, u8)>,
    /// Physical volume name -> tet indices (sorted).
    pub volume_groups: Vec<(String, Vec<u32>)>,
    /// Physical surface name -> face indices (sorted; a face may be in several groups).
    pub face_groups: Vec<(String, Vec<u32>)>,
    /// Physical point name -> node indices (sorted).
    pub point_groups: Vec<(String, Vec<u32>)>,
    /// The node is a corner of some tet (carries a P1 pressure dof).
    pub is_vertex: Vec<bool>,
}

impl Mesh {
    /// Face indices of the physical surface `name`.
    pub fn face_group(&self, name: &str) -> Result<&[u32]> {
        find_group(&self.face_groups, name, "surface")
    }

    /// Node indices of the physical point `name`.
    pub fn point_group(&self, name: &str) -> Result<&[u32]> {
        find_group(&self.point_groups, name, "point")
    }

    /// Tet indices of the physical volume `name`.
    pub fn volume_group(&self, name: &str) -> Result<&[u32]> {
        find_group(&self.volume_groups, name, "volume")
    }

    /// The nodes of cell e.
    pub fn cell(&self, e: usize) -> &[u32] {
        &self.cells[e][..self.family.cell_nodes()]
    }

    /// The nodes of boundary face f.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.faces[f][..self.family.face_nodes()]
    }

    /// Number of cell corner nodes (P1 pressure nodes).
    pub fn n_vertices(&self) -> usize {
        self.is_vertex.iter().filter(|&&v| v).count()
    }
}

/// Look up a named group; the error names the missing group and lists the available ones.
fn find_group<'a>(groups: &'a [(String, Vec<u32>)], name: &str, kind: &str) -> Result<&'a [u32]> {
    match groups.iter().find(|(n, _)| n == name) {
        Some((_, g)) => Ok(g),
        None => {
            let avail: Vec<String> = groups.iter().map(|(n, _)| format!("\"{n}\"")).collect();
            let avail = if avail.is_empty() { "none".to_string() } else { avail.join(", ") };
            // The mesh does not keep its file name; "physical groups" stands in for the path.
            Err(Error::mesh(
                "physical groups",
                format!("no physical {kind} group named \"{name}\" (available {kind} groups: {avail})"),
            ))
        }
    }
}

/// Sorted vertex triple identifying a triangle independently of orientation.
pub(crate) fn face_key(a: u32, b: u32, c: u32) -> [u32; 3] {
    let mut k = [a, b, c];
    k.sort_unstable();
    k
}

/// All cell faces, sorted, each packed in a `u128` as (sorted vertex key, 4 * cell + local face) so
/// that faces shared by two cells are adjacent entries (see [`unpack_face`]). A line face's key is its
/// vertex pair followed by `u32::MAX`. Sorting packed integers (not hashing) keeps it deterministic,
/// compact and fast. Needs fewer than 2^30 cells.
pub(crate) fn sorted_cell_faces(family: Family, cells: &[[u32; MAX_CELL_NODES]]) -> Vec<u128> {
    let sides = family.cell_faces();
    let mut v = Vec::with_capacity(cells.len() * sides.len());
    for (t, cell) in cells.iter().enumerate() {
        for (f, lf) in sides.iter().enumerate() {
            let [a, b, c] = side_key(family, cell, lf);
            let id = (4 * t + f) as u128;
            v.push(((a as u128) << 96) | ((b as u128) << 64) | ((c as u128) << 32) | id);
        }
    }
    v.sort_unstable();
    v
}

/// The orientation-free key of the side `lf` (local node positions) of a cell.
pub(crate) fn side_key(family: Family, cell: &[u32], lf: &[usize]) -> [u32; 3] {
    match family {
        Family::Tet10 => face_key(cell[lf[0]], cell[lf[1]], cell[lf[2]]),
        Family::Tri6 => face_key(cell[lf[0]], cell[lf[1]], u32::MAX),
    }
}

/// (sorted vertex triple, tet, local face) of an entry of [`sorted_cell_faces`].
pub(crate) fn unpack_face(k: u128) -> ([u32; 3], u32, u8) {
    let id = k as u32;
    ([(k >> 96) as u32, (k >> 64) as u32, (k >> 32) as u32], id / 4, (id % 4) as u8)
}

/// The measure of a cell's straight (vertex) simplex, vertex i at `x(i)`: the volume of a
/// tetrahedron, the area of a meridian triangle.
pub fn straight_measure(family: Family, x: impl Fn(usize) -> [f64; 3]) -> f64 {
    match family {
        Family::Tet10 => tet_det(x(0), x(1), x(2), x(3)).abs() / 6.0,
        Family::Tri6 => meridian::area2(x(0), x(1), x(2)).abs() / 2.0,
    }
}

/// Determinant of [b - a, c - a, d - a] (6 x signed volume of the straight tet).
pub(crate) fn tet_det(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    let u = sub(b, a);
    let v = sub(c, a);
    let w = sub(d, a);
    u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0])
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
