//! The XDMF index of `fields.h5`, as text (the parent module's docs describe it): one `Uniform`
//! grid per step in a `Temporal` collection, each pointing at the mesh group and the field
//! datasets of its step; the bare mesh before the first step. Pure: no file, no MPI.

use super::layout::{mesh_group, StepRecord, H5_NAME};
use crate::io::fmt_real;
use std::fmt::Write as _;

/// The mesh every grid points at: global node and cell counts, XDMF topology type and nodes per
/// cell.
#[derive(Clone, Copy)]
pub(super) struct Shape {
    pub(super) n_nodes: usize,
    pub(super) n_cells: usize,
    pub(super) cell_type: (&'static str, usize),
}

/// A `DataItem` of `fields.h5`'s dataset `h5_object`.
fn data_item(dims: &str, number_type: &str, h5_object: &str) -> String {
    let h5 = xml_escape(H5_NAME);
    format!(
        "<DataItem Dimensions=\"{dims}\" NumberType=\"{number_type}\" Precision=\"8\" Format=\"HDF\">{h5}:{h5_object}</DataItem>"
    )
}

/// The topology and geometry of mesh group `group`.
fn mesh_xml(shape: &Shape, indent: &str, group: i64) -> String {
    let (n, m) = (shape.n_nodes, shape.n_cells);
    let g = mesh_group(group);
    let (ty, npe) = shape.cell_type;
    format!(
        "{indent}<Topology TopologyType=\"{ty}\" NumberOfElements=\"{m}\" NodesPerElement=\"{npe}\">\n\
         {indent}  {}\n\
         {indent}</Topology>\n\
         {indent}<Geometry GeometryType=\"XYZ\">\n\
         {indent}  {}\n\
         {indent}</Geometry>\n",
        data_item(&format!("{m} {npe}"), "Int", &format!("/{g}/topology")),
        data_item(&format!("{n} 3"), "Float", &format!("/{g}/coordinates")),
    )
}

/// The grid of step `k`.
pub(super) fn step_grid(shape: &Shape, k: usize, step: &StepRecord) -> String {
    let mut s = String::new();
    let _ = writeln!(s, "      <Grid Name=\"step_{k:06}\" GridType=\"Uniform\">");
    let _ = writeln!(s, "        <Time Value=\"{}\"/>", fmt_real(step.time));
    s.push_str(&mesh_xml(shape, "        ", step.mesh));
    for (name, kind) in &step.fields {
        let rows = if kind.on_nodes() { shape.n_nodes } else { shape.n_cells };
        let (ty, dims) = match kind.components() {
            1 => ("Scalar", format!("{rows}")),
            c => ("Vector", format!("{rows} {c}")),
        };
        let center = if kind.on_nodes() { "Node" } else { "Cell" };
        let name = xml_escape(name);
        let _ = writeln!(s, "        <Attribute Name=\"{name}\" AttributeType=\"{ty}\" Center=\"{center}\">");
        let _ = writeln!(s, "          {}", data_item(&dims, "Float", &format!("/fields/{name}/{k:06}")));
        let _ = writeln!(s, "        </Attribute>");
    }
    s.push_str("      </Grid>\n");
    s
}

/// The whole index: the temporal collection of the steps' `grids` (from [`step_grid`]), or
/// with no steps yet the bare mesh of group `mesh`.
pub(super) fn xdmf_text(shape: &Shape, n_steps: usize, grids: &str, mesh: i64) -> String {
    let mut s = String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n");
    if n_steps == 0 {
        s.push_str("    <Grid Name=\"mesh\" GridType=\"Uniform\">\n");
        s.push_str(&mesh_xml(shape, "      ", mesh));
        s.push_str("    </Grid>\n");
    } else {
        s.push_str("    <Grid Name=\"fields\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
        s.push_str(grids);
        s.push_str("    </Grid>\n");
    }
    s.push_str("  </Domain>\n</Xdmf>\n");
    s
}

/// `s` with XML's five special characters escaped.
pub(super) fn xml_escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&apos;"),
            _ => o.push(c),
        }
    }
    o
}

#[cfg(test)]
mod tests {
    use super::super::layout::FieldKind;
    use super::*;

    #[test]
    fn escaping() {
        assert_eq!(xml_escape("a<&>\"'"), "a&lt;&amp;&gt;&quot;&apos;");
    }

    #[test]
    fn a_step_points_at_its_mesh_group_and_datasets() {
        let shape = Shape { n_nodes: 14, n_cells: 2, cell_type: ("Tetrahedron_10", 10) };
        let step = StepRecord {
            time: 0.5,
            fields: vec![("u".into(), FieldKind::NodeVector), ("J".into(), FieldKind::CellScalar)],
            mesh: 1,
        };
        let grid = step_grid(&shape, 3, &step);
        for want in [
            "<Grid Name=\"step_000003\" GridType=\"Uniform\">",
            "<Time Value=\"0.5\"/>",
            "NumberOfElements=\"2\" NodesPerElement=\"10\"",
            "Dimensions=\"2 10\" NumberType=\"Int\" Precision=\"8\" Format=\"HDF\">fields.h5:/mesh_1/topology<",
            "Dimensions=\"14 3\" NumberType=\"Float\" Precision=\"8\" Format=\"HDF\">fields.h5:/mesh_1/coordinates<",
            "<Attribute Name=\"u\" AttributeType=\"Vector\" Center=\"Node\">",
            ">fields.h5:/fields/u/000003<",
            "<Attribute Name=\"J\" AttributeType=\"Scalar\" Center=\"Cell\">",
            "Dimensions=\"2\" NumberType=\"Float\"",
        ] {
            assert!(grid.contains(want), "{want} not in\n{grid}");
        }
        let text = xdmf_text(&shape, 1, &grid, 1);
        assert!(text.contains("CollectionType=\"Temporal\"") && text.contains(&grid));
        let bare = xdmf_text(&shape, 0, "", 0);
        assert!(bare.contains("<Grid Name=\"mesh\"") && bare.contains("fields.h5:/mesh/topology"));
    }
}
