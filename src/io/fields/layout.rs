//! What `fields.h5` holds and how it is named (the layout of the parent module's docs): the
//! file names, the cells' XDMF types and node order, the mesh a rank writes ([`OutputMesh`]),
//! the fields of a step ([`Field`], [`FieldKind`]) and the record of a step written.

use crate::reference_cell::Family;

/// Name of the HDF5 file inside the run directory.
pub(crate) const H5_NAME: &str = "fields.h5";
/// Name of the XDMF file inside the run directory.
pub(crate) const XDMF_NAME: &str = "fields.xdmf";
/// XDMF topology type written for 10-node tetrahedra (accepted by ParaView's XDMF 2 and XDMF 3 readers).
pub(crate) const XDMF_TOPOLOGY_TYPE: &str = "Tetrahedron_10";
/// XDMF topology type written for the 6-node triangles of a meridian mesh.
pub(crate) const XDMF_TOPOLOGY_TYPE_TRI6: &str = "Triangle_6";

/// The XDMF topology type and nodes per cell of a family.
pub(super) fn cell_type(family: Family) -> (&'static str, usize) {
    match family {
        Family::Tet10 => (XDMF_TOPOLOGY_TYPE, 10),
        Family::Tri6 => (XDMF_TOPOLOGY_TYPE_TRI6, 6),
    }
}
/// `xdmf[i] = gmsh[GMSH_TO_XDMF_TET10[i]]`: GMSH `Tetrahedron10` order to XDMF/VTK quadratic-tet
/// order (the mid-nodes of edges (2,3) and (1,3) swap places). The permutation is its own inverse.
pub(crate) const GMSH_TO_XDMF_TET10: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];

/// The part of the mesh this rank writes.
pub struct OutputMesh<'a> {
    /// Number of nodes over all ranks.
    pub n_global_nodes: usize,
    /// This rank owns global nodes `[node_offset, node_offset + coords.len())`.
    pub node_offset: usize,
    /// Coordinates of the owned nodes only.
    pub coords: &'a [[f64; 3]],
    /// Number of cells over all ranks.
    pub n_global_cells: usize,
    /// This rank writes cells `[cell_offset, cell_offset + cells.len())`.
    pub cell_offset: usize,
    /// Global node ids of each cell, GMSH `Tetrahedron10` order: 4 vertices, then mid-edge nodes on
    /// edges (0,1),(1,2),(0,2),(0,3),(2,3),(1,3); or GMSH `Triangle6` order in the first 6 slots.
    pub cells: &'a [[u32; 10]],
    /// The cell family.
    pub family: Family,
}

/// Where a field lives and how many components it has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldKind {
    /// One value per node.
    NodeScalar,
    /// Three values per node, interleaved `x y z`.
    NodeVector,
    /// One value per cell.
    CellScalar,
    /// Three values per cell, interleaved `x y z`.
    CellVector,
}

impl FieldKind {
    pub(super) fn on_nodes(self) -> bool {
        matches!(self, FieldKind::NodeScalar | FieldKind::NodeVector)
    }
    pub(super) fn components(self) -> usize {
        match self {
            FieldKind::NodeScalar | FieldKind::CellScalar => 1,
            FieldKind::NodeVector | FieldKind::CellVector => 3,
        }
    }
    pub(super) fn code(self) -> u64 {
        match self {
            FieldKind::NodeScalar => 1,
            FieldKind::NodeVector => 2,
            FieldKind::CellScalar => 3,
            FieldKind::CellVector => 4,
        }
    }
}

/// One field of one step: this rank's values, for its owned nodes (`coords.len()` values, ×3 for
/// vectors, interleaved `x y z`) or its cells (`cells.len()` values, ×3 for vectors).
pub struct Field<'a> {
    /// Name in the file and in ParaView; ASCII letters, digits, `_`, `-`, `.`; not starting with `.`.
    pub name: &'a str,
    /// Node or cell, scalar or vector.
    pub kind: FieldKind,
    /// This rank's values.
    pub data: &'a [f64],
}

/// A step written: its time, its fields and the mesh group its grid uses.
pub(super) struct StepRecord {
    pub(super) time: f64,
    pub(super) fields: Vec<(String, FieldKind)>,
    /// The mesh group its grid uses (0: `/mesh`, g: `/mesh_g`; see [`FieldFile::reopen`](super::FieldFile::reopen)).
    pub(super) mesh: i64,
}

/// Name of mesh group g.
pub(super) fn mesh_group(g: i64) -> String {
    if g == 0 {
        "mesh".into()
    } else {
        format!("mesh_{g}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tet10_permutation_maps_gmsh_edges_to_vtk_edges() {
        let gmsh = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)];
        let vtk = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)];
        assert_eq!(GMSH_TO_XDMF_TET10[..4], [0, 1, 2, 3]);
        for (e, edge) in vtk.iter().enumerate() {
            assert_eq!(gmsh[GMSH_TO_XDMF_TET10[4 + e] - 4], *edge);
        }
        for (i, &j) in GMSH_TO_XDMF_TET10.iter().enumerate() {
            assert_eq!(GMSH_TO_XDMF_TET10[j], i, "an involution");
        }
    }
}
