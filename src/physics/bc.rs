//! Boundary conditions by physical group: constraints (prescribed u components, rollers on
//! axis-aligned planes — the meridian's axis, x = 0, is one — prescribed p) and surface loads integrated once into the external load
//! vector: F_ext,u = ∫_Γ t̄ · w dA (reference-configuration traction) and
//! F_ext,p = −∫_Γ q̄ q dA (prescribed outward flux).

use crate::error::{Error, Result};
use crate::fem::dofmap::DofMap;
use crate::fem::surface::FaceRule;
use crate::mesh::dist::LocalMesh;
use crate::reference_cell::Family;
use crate::scene::BoundaryCondition;

/// A constrained local dof and its value.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Constraint {
    pub(crate) local: usize,
    pub(crate) value: f64,
}

/// Local faces of a surface group, or an error naming the group and the available ones.
pub(crate) fn face_group<'m>(mesh: &'m LocalMesh, name: &str, context: &str) -> Result<&'m [u32]> {
    lookup(&mesh.face_groups, mesh, name, context, "a surface")
}

/// Local nodes of a point group, or an error naming it and the available groups.
pub(crate) fn point_group<'m>(mesh: &'m LocalMesh, name: &str, context: &str) -> Result<&'m [u32]> {
    lookup(&mesh.point_groups, mesh, name, context, "a point")
}

/// The entry `name` of `groups` (a group list of `mesh`, of `kind` groups); the error lists the
/// mesh's groups by kind, or says that `name` is a group of the other kind.
fn lookup<'m>(
    groups: &'m [(String, Vec<u32>)],
    mesh: &LocalMesh,
    name: &str,
    context: &str,
    kind: &str,
) -> Result<&'m [u32]> {
    groups.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_slice()).ok_or_else(|| missing(mesh, name, context, kind))
}

fn missing(mesh: &LocalMesh, name: &str, context: &str, kind: &str) -> Error {
    let list = |g: &[(String, Vec<u32>)]| g.iter().map(|(n, _)| n.as_str()).collect::<Vec<_>>().join(", ");
    let (faces, points) = (list(&mesh.face_groups), list(&mesh.point_groups));
    let other = mesh.face_groups.iter().chain(&mesh.point_groups).any(|(n, _)| n == name);
    let msg = if other {
        format!("\"{name}\" is not {kind} group (surface groups: {faces}; point groups: {points})")
    } else {
        format!("physical group \"{name}\" not found (surface groups: {faces}; point groups: {points})")
    };
    Error::Mesh { path: context.into(), msg }
}

/// Local nodes touched by a group: all nodes of its faces, or the nodes of a point group.
pub(crate) fn group_nodes(mesh: &LocalMesh, name: &str, context: &str) -> Result<Vec<usize>> {
    if let Some((_, faces)) = mesh.face_groups.iter().find(|(n, _)| n == name) {
        let mut nodes: Vec<usize> =
            faces.iter().flat_map(|&f| mesh.face(f as usize).iter().map(|&n| n as usize)).collect();
        nodes.sort_unstable();
        nodes.dedup();
        return Ok(nodes);
    }
    if let Some((_, nodes)) = mesh.point_groups.iter().find(|(n, _)| n == name) {
        return Ok(nodes.iter().map(|&n| n as usize).collect());
    }
    Err(missing(mesh, name, context, "a surface or point"))
}

/// Straight-facet normal of a face from its vertices (orientation is outward).
fn facet_normal(mesh: &LocalMesh, f: usize) -> [f64; 3] {
    let n = mesh.face(f);
    let x = |i: usize| mesh.coords[n[i] as usize];
    let m = match mesh.family {
        Family::Tet10 => {
            let (a, b, c) = (x(0), x(1), x(2));
            let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
            let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
            [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
        }
        // A side of a counter-clockwise meridian triangle: the tangent turned clockwise.
        Family::Tri6 => [x(1)[2] - x(0)[2], 0.0, x(0)[0] - x(1)[0]],
    };
    let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    [m[0] / l, m[1] / l, m[2] / l]
}

/// The displacement component along Cartesian `axis`, or an error naming the geometry.
fn component(mesh: &LocalMesh, axis: usize, ctx: &str) -> Result<usize> {
    mesh.family.component(axis).ok_or_else(|| Error::Scene {
        path: ctx.to_string(),
        msg: format!(
            "an axisymmetric (meridian) model has no {} displacement: its components are u_r (x) and u_z (z)",
            ["x", "y", "z"][axis]
        ),
    })
}

/// u_r = 0 on the axis (the nodes of a meridian mesh at x = r = 0): the regularity of the hoop
/// strain u_r / R, part of the axisymmetric formulation rather than a boundary condition.
fn axis_constraints(mesh: &LocalMesh, dofs: &DofMap) -> Vec<Constraint> {
    let scale = mesh.coords.iter().map(|x| x[0].abs().max(x[2].abs())).fold(0.0, f64::max);
    (0..mesh.coords.len())
        .filter(|&n| mesh.coords[n][0].abs() <= 1e-9 * scale)
        .map(|n| Constraint { local: dofs.u_local(n, 0), value: 0.0 })
        .collect()
}

/// Constraints and external loads of this rank's part. Constraints on nodes of this rank's
/// faces only: the caller makes the flags consistent across ranks.
pub(crate) fn build(
    bcs: &[BoundaryCondition],
    mesh: &LocalMesh,
    dofs: &DofMap,
    context: &str,
) -> Result<(Vec<Constraint>, Vec<f64>)> {
    let mut cons = Vec::new();
    let mut ext = vec![0.0; dofs.n_local()];
    let rule = FaceRule::new(mesh.family);
    let nc = dofs.nc;
    if mesh.family.axisymmetric() {
        cons.extend(axis_constraints(mesh, dofs));
    }
    for (i, bc) in bcs.iter().enumerate() {
        if bc.geometry.is_some_and(|g| g.family() != mesh.family) {
            continue;
        }
        let ctx = format!("{context}: bc #{} (group \"{}\")", i + 1, bc.group);
        if let Some(d) = &bc.displacement {
            let nodes = group_nodes(mesh, &bc.group, &ctx)?;
            for (axis, v) in d {
                let c = component(mesh, axis.index(), &ctx)?;
                cons.extend(nodes.iter().map(|&n| Constraint { local: dofs.u_local(n, c), value: *v }));
            }
        }
        if bc.roller == Some(true) {
            for &f in face_group(mesh, &bc.group, &ctx)? {
                let n = facet_normal(mesh, f as usize);
                let axis = (0..3).find(|&c| n[c].abs() > 0.999).ok_or_else(|| Error::Scene {
                    path: ctx.clone(),
                    msg: format!(
                        "roller needs faces normal to x, y or z; face with normal ({:.3}, {:.3}, {:.3}) is not",
                        n[0], n[1], n[2]
                    ),
                })?;
                let c = component(mesh, axis, &ctx)?;
                cons.extend(
                    mesh.face(f as usize)
                        .iter()
                        .map(|&n| Constraint { local: dofs.u_local(n as usize, c), value: 0.0 }),
                );
            }
        }
        if let Some(p) = bc.pressure {
            for n in group_nodes(mesh, &bc.group, &ctx)? {
                let v = mesh.vertex_of_node[n];
                if v >= 0 {
                    cons.push(Constraint { local: dofs.p_local(v as usize), value: p });
                }
            }
        }
        if let Some(t) = &bc.traction {
            for &f in face_group(mesh, &bc.group, &ctx)? {
                let nodes = mesh.face(f as usize);
                let coords: Vec<[f64; 3]> = nodes.iter().map(|&n| mesh.coords[n as usize]).collect();
                for p in rule.points(&coords) {
                    let tv = match (t.normal, t.vector) {
                        (Some(v), _) => [v * p.normal[0], v * p.normal[1], v * p.normal[2]],
                        (_, Some(v)) => v,
                        _ => [0.0; 3],
                    };
                    for (a, &node) in nodes.iter().enumerate() {
                        for (c, &axis) in mesh.family.axes().iter().enumerate() {
                            ext[nc * node as usize + c] += p.w * tv[axis] * p.n[a];
                        }
                    }
                }
            }
        }
        if let Some(flux) = bc.flux {
            for &f in face_group(mesh, &bc.group, &ctx)? {
                let nodes = mesh.face(f as usize);
                let coords: Vec<[f64; 3]> = nodes.iter().map(|&n| mesh.coords[n as usize]).collect();
                for p in rule.points(&coords) {
                    for m in 0..mesh.family.face_vertices() {
                        let v = mesh.vertex_of_node[nodes[m] as usize] as usize;
                        ext[dofs.p_local(v)] -= p.w * flux * p.l[m];
                    }
                }
            }
        }
    }
    Ok((cons, ext))
}
