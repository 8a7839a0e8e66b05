//! The scene's rigid tools as the contact sees them at set-up: the tool set (the `[[tools]]`, and
//! the plates as plane tools under `plates.contact = "tools"`), the note on pipette rims finer
//! than the surface, and the refusal of a tool overlapping the body at t = 0.

use crate::error::{Error, Result};
use crate::fem::dofmap::DofMap;
use crate::mesh::dist::LocalMesh;
use crate::parallel::agree;
use crate::physics::bc::{self, Constraint};
use crate::physics::contact::Plates;
use crate::physics::tools::protocol::ToolProtocol;
use crate::physics::tools::{Profile, Tool, ToolSet};
use crate::scene::tools::ToolSpec;
use crate::scene::LoadedScene;
use mpi::topology::SimpleCommunicator;

/// The scene's tools and the surface nodes that can touch them (None without tools): nodes
/// within two mean cell sizes of a tool get a frame. With `plates.contact = "tools"` the plates
/// are two more, plane tools with the plates' paths (their anchor keeps its bounds).
pub(super) fn tools(
    world: &SimpleCommunicator,
    scene: &LoadedScene,
    local: &LocalMesh,
    dofs: &DofMap,
    cons: &[Constraint],
    plates: Option<&mut Plates>,
) -> Result<Option<ToolSet>> {
    let s = &scene.scene;
    let plate_tools = s.plates.as_ref().map_or(&[][..], |p| p.tool_names());
    if s.tools.is_empty() && plate_tools.is_empty() {
        return Ok(None);
    }
    let ctx = format!("{}: [[tools]]", scene.source);
    let mut faces: Vec<u32> = Vec::new();
    let (mut tools, mut protocols) = (Vec::new(), Vec::new());
    for spec in &s.tools {
        faces.extend_from_slice(agree(world, bc::face_group(local, &spec.group, &ctx))?);
        tools.push(Tool::from_spec(spec, &ctx)?);
        protocols.push(ToolProtocol::from_rows(&spec.rows()));
    }
    let mut pinned = Vec::new();
    if let (Some(ps), Some(p), [lower, upper]) = (&s.plates, plates, plate_tools) {
        faces.extend_from_slice(agree(world, bc::face_group(local, &ps.group, &ctx))?);
        // The plates' own gaps seal the surface (the drainage stays the plates').
        let plane = |name, z, a| Tool { seals: false, ..Tool::new(name, Profile::Plane, [0.0, 0.0, z], [0.0, 0.0, a]) };
        tools.push(plane(lower, 0.0, 1.0));
        protocols.push(ToolProtocol::displacements(p.loading.points()));
        tools.push(plane(upper, p.z_upper_at(0.0), -1.0));
        protocols.push(p.upper.clone());
        pinned.extend(p.leave_contact_to_tools());
    }
    faces.sort_unstable();
    faces.dedup();
    let mut constrained = vec![false; dofs.n_local()];
    for c in cons {
        constrained[c.local] = true;
    }
    let band = 2.0 * local.mean_size(world);
    let set =
        ToolSet::new(world, tools, protocols, local, dofs, &faces, s.fem.equal_order(), &constrained, &pinned, band);
    refuse_overlap(world, &set, dofs, &ctx)?;
    // Force control from the start: the tool must touch the body at t = 0 (later switches are
    // checked when they are reached, `PoroProblem::predict`).
    set.check_start(&vec![0.0; dofs.n_local()]).map_err(|e| match e {
        Error::Scene { path, msg } => Error::Scene { path: format!("{}: {path}", scene.source), msg },
        e => e,
    })?;
    Ok(Some(set))
}

/// A pipette's rim rounded below the surface's cell size can pass between two surface nodes (the
/// contact holds at the nodes): a note for each such pipette, with the largest surface edge within
/// its outer radius of its axis.
pub(super) fn coarse_rims(
    world: &SimpleCommunicator,
    set: &ToolSet,
    local: &LocalMesh,
    specs: &[ToolSpec],
) -> Vec<String> {
    let mut notes = Vec::new();
    for (tool, spec) in set.tools().iter().zip(specs) {
        let (Some(rim), Some(inner), Some(wall)) = (spec.rim_radius, spec.inner_radius, spec.wall) else { continue };
        let reach = inner + wall + rim;
        let rho = |x: [f64; 3]| tool.radial_distance(x, 0.0);
        let mut longest = 0.0f64;
        let faces = local.face_groups.iter().find(|(n, _)| *n == spec.group).map_or(&[][..], |(_, f)| f);
        for &f in faces {
            let nodes = &local.face(f as usize)[..local.family.face_vertices()];
            let x: Vec<[f64; 3]> = nodes.iter().map(|&n| local.coords[n as usize]).collect();
            if x.iter().all(|&p| rho(p) > reach) {
                continue;
            }
            for (i, a) in x.iter().enumerate() {
                for b in &x[i + 1..] {
                    longest = longest.max((0..3).map(|k| (a[k] - b[k]).powi(2)).sum::<f64>().sqrt());
                }
            }
        }
        let longest = crate::parallel::max(world, longest);
        if longest > rim {
            notes.push(format!(
                "tools: \"{}\" has a rim of radius {rim} µm, below the surface cells within its reach ({longest:.3} \
                 µm): the rim can pass between two surface nodes; refine the surface there to h ≤ {rim} µm",
                tool.name
            ));
        }
    }
    notes
}

/// A tool must not reach into the body at t = 0 (beyond round-off of the body's size): the
/// contact would start by pushing the surface out of it in one step.
fn refuse_overlap(world: &SimpleCommunicator, set: &ToolSet, dofs: &DofMap, ctx: &str) -> Result<()> {
    let zero = vec![0.0; dofs.n_local()];
    let position = set.positions();
    let mut depth = vec![0.0f64; set.tools().len()];
    for (_, _, near) in set.owned_gaps(&zero, &position) {
        depth[near.tool] = depth[near.tool].max(-near.phi);
    }
    let depth = crate::parallel::max_slice(world, &depth);
    for (tool, d) in set.tools().iter().zip(depth) {
        let tol = 1e-9 * tool.profile.size().max(1.0);
        if d > tol {
            return Err(Error::Scene {
                path: ctx.to_string(),
                msg: format!(
                    "tool \"{}\" overlaps the body by {d:.4} µm at t = 0 (its origin {:?}, axis {:?}): place it touching \
                     or clear of the surface, and move it in with tools.protocol",
                    tool.name, tool.origin, tool.axis
                ),
            });
        }
    }
    Ok(())
}
