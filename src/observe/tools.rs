//! What a lab reads of each rigid tool (issue 53): its position along its axis, the force on it,
//! the nodes in contact, the contact radius about its axis and the largest penetration of the
//! surface's nodes into it — five `history.csv` columns per tool, named after it.

use crate::fem::dofmap::DofMap;
use crate::io::recorder::ColumnDoc;
use crate::parallel::{max, sum};
use crate::physics::tools::ToolSet;
use mpi::topology::SimpleCommunicator;

/// A node is in contact within this gap (µm): the Newton iterates are projected onto the tools,
/// so a node on one sits on it to round-off.
const IN_CONTACT: f64 = 1e-8;

/// The columns of each tool, `*tool*` its name.
pub(crate) const COLUMNS: [ColumnDoc; 5] = [
    ColumnDoc::pattern(
        "*tool*_position",
        "µm",
        "a `[[tools]]` entry's displacement along its axis (its protocol's; under force control the position reached)",
    ),
    ColumnDoc::pattern(
        "*tool*_force_uN",
        "µN",
        "the force on the tool along its axis, positive pushing the body: the sum of the contact reactions of the \
         surface nodes nearest to it and within two cells of it (the whole body on the meridian; the meshed part in \
         3-D)",
    ),
    ColumnDoc::pattern("*tool*_contact_nodes", "–", "surface nodes on the tool (gap ≤ 1e-8 µm, pushed)"),
    ColumnDoc::pattern(
        "*tool*_contact_radius",
        "µm",
        "the largest distance from the tool's axis of a node in contact (the node's resolution)",
    ),
    ColumnDoc::pattern(
        "*tool*_penetration",
        "µm",
        "the largest depth of a surface node inside the tool (0 when none; round-off under exact contact)",
    ),
];

/// The column names of the tools named `names`, in order.
pub(crate) fn column_names<'a>(names: impl Iterator<Item = &'a str>) -> Vec<String> {
    names.flat_map(|n| COLUMNS.iter().map(move |c| format!("{n}{}", c.name.trim_start_matches("*tool*")))).collect()
}

/// The five values of every tool at the positions `position` (collective): `local` the local
/// state, `reaction` the owned residual without the contact (`Post::reaction`).
pub(crate) fn read(
    set: &ToolSet,
    position: &[f64],
    dofs: &DofMap,
    local: &[f64],
    reaction: &[f64],
    world: &SimpleCommunicator,
) -> Vec<f64> {
    let n = set.tools().len();
    let nc = dofs.nc;
    let (mut force, mut nodes, mut radius, mut depth) = (vec![0.0; n], vec![0.0; n], vec![0.0f64; n], vec![0.0f64; n]);
    // The nodes within the band of a tool: the others are free (no reaction) or held elsewhere
    // (a constraint's reaction is not the tool's).
    for (node, x, near) in set.owned_gaps(local, position).filter(|(_, _, n)| n.phi <= set.band()) {
        let tool = &set.tools()[near.tool];
        let a = tool.axis;
        // The axis in the node's components ((r, z) on the meridian: tools lie on the z axis).
        let along: f64 =
            if nc == 2 { a[2] * reaction[nc * node + 1] } else { (0..3).map(|c| a[c] * reaction[nc * node + c]).sum() };
        force[near.tool] += along;
        depth[near.tool] = depth[near.tool].max(-near.phi);
        if near.phi <= IN_CONTACT && along > 0.0 {
            nodes[near.tool] += 1.0;
            radius[near.tool] = radius[near.tool].max(tool.radial_distance(x, position[near.tool]));
        }
    }
    let mut out = Vec::with_capacity(5 * n);
    for k in 0..n {
        out.extend([
            position[k],
            1e-3 * sum(world, force[k]),
            sum(world, nodes[k]),
            max(world, radius[k]),
            max(world, depth[k]),
        ]);
    }
    out
}
