//! The global mesh as read from a file: quadratic cells of one family (10-node tetrahedra, or
//! 6-node triangles of a meridian), their outward boundary faces, named physical groups, and the
//! face matching the partitioner and the distribution use. The node numbering of a cell and of a
//! face is the reference cell's ([`crate::reference_cell`]).

pub mod dist;
pub mod generate;
pub mod gmsh;
pub mod mirror;
pub mod partition;
pub mod source;

#[cfg(test)]
pub(crate) mod test_util;
#[cfg(test)]
mod tests;

use crate::error::{Error, Result};
use crate::reference_cell::{Family, MAX_CELL_NODES, MAX_FACE_NODES};

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
    /// The node is a corner of some cell (carries a P1 pressure dof).
    pub is_vertex: Vec<bool>,
}

impl Mesh {
    /// Face indices of the physical surface `name`.
    pub fn face_group(&self, name: &str) -> Result<&[u32]> {
        find_group(&self.face_groups, name, "surface")
    }

    /// Node indices of the physical point `name`.
    #[cfg(test)]
    pub fn point_group(&self, name: &str) -> Result<&[u32]> {
        find_group(&self.point_groups, name, "point")
    }

    /// Cell indices of the physical volume `name` (a physical surface on the meridian).
    #[cfg(test)]
    pub fn volume_group(&self, name: &str) -> Result<&[u32]> {
        find_group(&self.volume_groups, name, "volume")
    }

    /// The nodes of cell e.
    pub fn cell(&self, e: usize) -> &[u32] {
        &self.cells[e][..self.family.cell_nodes()]
    }

    /// Number of cell corner nodes (P1 pressure nodes).
    #[cfg(test)]
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
