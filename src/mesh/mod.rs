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

/// The global mesh: quadratic tets, outward boundary faces and named physical groups.
#[derive(Debug, Clone, Default)]
pub struct Mesh {
    /// Node coordinates, compact 0-based numbering.
    pub coords: Vec<[f64; 3]>,
    /// Quadratic tets in gmsh Tetrahedron10 node order, all positively oriented.
    pub tets: Vec<[u32; 10]>,
    /// Boundary (tagged) triangles in Triangle6 order, each unique, outward from their tet.
    pub faces: Vec<[u32; 6]>,
    /// For each face: its tet and that tet's local face index (see [`TET_FACES`]).
    pub face_tet: Vec<(u32, u8)>,
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

    /// Number of tet corner nodes (P1 pressure nodes).
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

/// All tet faces, sorted, each packed in a `u128` as (sorted vertex triple, 4 * tet + local face) so that
/// faces shared by two tets are adjacent entries (see [`unpack_face`]). Sorting packed integers (not
/// hashing) keeps it deterministic, compact and fast. Needs fewer than 2^30 tets.
pub(crate) fn sorted_tet_faces(tets: &[[u32; 10]]) -> Vec<u128> {
    let mut v = Vec::with_capacity(tets.len() * 4);
    for (t, tet) in tets.iter().enumerate() {
        for (f, lf) in TET_FACES.iter().enumerate() {
            let [a, b, c] = face_key(tet[lf[0]], tet[lf[1]], tet[lf[2]]);
            let id = (4 * t + f) as u128;
            v.push(((a as u128) << 96) | ((b as u128) << 64) | ((c as u128) << 32) | id);
        }
    }
    v.sort_unstable();
    v
}

/// (sorted vertex triple, tet, local face) of an entry of [`sorted_tet_faces`].
pub(crate) fn unpack_face(k: u128) -> ([u32; 3], u32, u8) {
    let id = k as u32;
    ([(k >> 96) as u32, (k >> 64) as u32, (k >> 32) as u32], id / 4, (id % 4) as u8)
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
