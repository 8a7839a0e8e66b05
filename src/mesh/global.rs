//! The global mesh as read from a file, and its named physical groups.

use crate::error::{Error, Result};
use crate::reference_cell::{Family, MAX_CELL_NODES, MAX_FACE_NODES};

/// The global mesh: quadratic cells, outward boundary faces and named physical groups.
#[derive(Debug, Clone, Default)]
pub(crate) struct Mesh {
    /// Node coordinates, compact 0-based numbering.
    pub(crate) coords: Vec<[f64; 3]>,
    /// The element family: what a cell and a boundary face are.
    pub(crate) family: Family,
    /// Cells, positively oriented, in gmsh node order (Tetrahedron10, or Triangle6 of the meridian);
    /// a cell uses the first [`Family::cell_nodes`] slots (the rest are `u32::MAX`).
    pub(crate) cells: Vec<[u32; MAX_CELL_NODES]>,
    /// Boundary (tagged) faces — Triangle6, or Line3 on the meridian — each unique, outward from
    /// their cell; a face uses the first [`Family::face_nodes`] slots.
    pub(crate) faces: Vec<[u32; MAX_FACE_NODES]>,
    /// For each face: its cell and that cell's local face index (see [`Family::cell_faces`]).
    pub(crate) face_cell: Vec<(u32, u8)>,
    /// Physical volume name -> tet indices (sorted).
    pub(crate) volume_groups: Vec<(String, Vec<u32>)>,
    /// Physical surface name -> face indices (sorted; a face may be in several groups).
    pub(crate) face_groups: Vec<(String, Vec<u32>)>,
    /// Physical point name -> node indices (sorted).
    pub(crate) point_groups: Vec<(String, Vec<u32>)>,
    /// The node is a corner of some cell (carries a P1 pressure dof).
    pub(crate) is_vertex: Vec<bool>,
}

impl Mesh {
    /// Face indices of the physical surface `name`.
    pub(crate) fn face_group(&self, name: &str) -> Result<&[u32]> {
        find_group(&self.face_groups, name, "surface")
    }

    /// Node indices of the physical point `name`.
    #[cfg(test)]
    pub(crate) fn point_group(&self, name: &str) -> Result<&[u32]> {
        find_group(&self.point_groups, name, "point")
    }

    /// Cell indices of the physical volume `name` (a physical surface on the meridian).
    #[cfg(test)]
    pub(crate) fn volume_group(&self, name: &str) -> Result<&[u32]> {
        find_group(&self.volume_groups, name, "volume")
    }

    /// The nodes of cell e.
    pub(crate) fn cell(&self, e: usize) -> &[u32] {
        &self.cells[e][..self.family.cell_nodes()]
    }

    /// Number of cell corner nodes (P1 pressure nodes).
    #[cfg(test)]
    pub(crate) fn n_vertices(&self) -> usize {
        self.is_vertex.iter().filter(|&&v| v).count()
    }
}

/// Look up a named group; the error names the missing group and lists the available ones.
pub(super) fn find_group<'a>(groups: &'a [(String, Vec<u32>)], name: &str, kind: &str) -> Result<&'a [u32]> {
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
