//! Boundary conditions by physical group: constraints (prescribed u components, rollers on
//! axis-aligned planes, prescribed p) and surface loads integrated once into the external load
//! vector: F_ext,u = ∫_Γ t̄ · w dA (reference-configuration traction) and
//! F_ext,p = −∫_Γ q̄ q dA (prescribed outward flux).

use crate::error::{Error, Result};
use crate::fem::dofmap::DofMap;
use crate::fem::element::{tabulate_tri6, tri6_surface};
use crate::fem::quadrature;
use crate::mesh::dist::LocalMesh;
use crate::scene::BoundaryCondition;

/// A constrained local dof and its value.
#[derive(Debug, Clone, Copy)]
pub struct Constraint {
    pub local: usize,
    pub value: f64,
}

/// Local faces of a surface group, or an error naming the group and the available ones.
pub fn face_group<'m>(mesh: &'m LocalMesh, name: &str, context: &str) -> Result<&'m [u32]> {
    lookup(&mesh.face_groups, mesh, name, context, "a surface")
}

/// Local nodes of a point group, or an error naming it and the available groups.
pub fn point_group<'m>(mesh: &'m LocalMesh, name: &str, context: &str) -> Result<&'m [u32]> {
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
pub fn group_nodes(mesh: &LocalMesh, name: &str, context: &str) -> Result<Vec<usize>> {
    if let Some((_, faces)) = mesh.face_groups.iter().find(|(n, _)| n == name) {
        let mut nodes: Vec<usize> =
            faces.iter().flat_map(|&f| mesh.faces[f as usize].iter().map(|&n| n as usize)).collect();
        nodes.sort_unstable();
        nodes.dedup();
        return Ok(nodes);
    }
    if let Some((_, nodes)) = mesh.point_groups.iter().find(|(n, _)| n == name) {
        return Ok(nodes.iter().map(|&n| n as usize).collect());
    }
    Err(missing(mesh, name, context, "a surface or point"))
}

/// Straight-facet normal of a face from its three vertices (orientation is outward).
fn facet_normal(mesh: &LocalMesh, f: usize) -> [f64; 3] {
    let n = &mesh.faces[f];
    let x = |i: usize| mesh.coords[n[i] as usize];
    let (a, b, c) = (x(0), x(1), x(2));
    let u = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let v = [c[0] - a[0], c[1] - a[1], c[2] - a[2]];
    let m = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]];
    let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    [m[0] / l, m[1] / l, m[2] / l]
}

/// Constraints and external loads of this rank's part. Constraints on nodes of this rank's
/// faces only: the caller makes the flags consistent across ranks.
pub fn build(
    bcs: &[BoundaryCondition],
    mesh: &LocalMesh,
    dofs: &DofMap,
    context: &str,
) -> Result<(Vec<Constraint>, Vec<f64>)> {
    let mut cons = Vec::new();
    let mut ext = vec![0.0; dofs.n_local()];
    let q = quadrature::tri(5);
    let tab = tabulate_tri6(&q);
    for (i, bc) in bcs.iter().enumerate() {
        let ctx = format!("{context}: bc #{} (group \"{}\")", i + 1, bc.group);
        if let Some(d) = &bc.displacement {
            let nodes = group_nodes(mesh, &bc.group, &ctx)?;
            for (comp, v) in d {
                let c = match comp.as_str() {
                    "x" => 0,
                    "y" => 1,
                    _ => 2,
                };
                cons.extend(nodes.iter().map(|&n| Constraint { local: dofs.u_local(n, c), value: *v }));
            }
        }
        if bc.roller == Some(true) {
            for &f in face_group(mesh, &bc.group, &ctx)? {
                let n = facet_normal(mesh, f as usize);
                let c = (0..3).find(|&c| n[c].abs() > 0.999).ok_or_else(|| Error::Scene {
                    path: ctx.clone(),
                    msg: format!(
                        "roller needs faces normal to x, y or z; face with normal ({:.3}, {:.3}, {:.3}) is not",
                        n[0], n[1], n[2]
                    ),
                })?;
                cons.extend(
                    mesh.faces[f as usize]
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
                let nodes = mesh.faces[f as usize];
                let coords: [[f64; 3]; 6] = std::array::from_fn(|a| mesh.coords[nodes[a] as usize]);
                for qp in 0..q.weights.len() {
                    let s = tri6_surface(&coords, &tab, qp);
                    let tv = match (t.normal, t.vector) {
                        (Some(v), _) => [v * s.normal[0], v * s.normal[1], v * s.normal[2]],
                        (_, Some(v)) => v,
                        _ => [0.0; 3],
                    };
                    let w = tab.weights[qp] * s.da;
                    for a in 0..6 {
                        for c in 0..3 {
                            ext[dofs.u_local(nodes[a] as usize, c)] += w * tv[c] * tab.n[qp][a];
                        }
                    }
                }
            }
        }
        if let Some(flux) = bc.flux {
            for &f in face_group(mesh, &bc.group, &ctx)? {
                let nodes = mesh.faces[f as usize];
                let coords: [[f64; 3]; 6] = std::array::from_fn(|a| mesh.coords[nodes[a] as usize]);
                for qp in 0..q.weights.len() {
                    let s = tri6_surface(&coords, &tab, qp);
                    let xi = q.points[qp];
                    let l = [1.0 - xi[0] - xi[1], xi[0], xi[1]];
                    for m in 0..3 {
                        let v = mesh.vertex_of_node[nodes[m] as usize] as usize;
                        ext[dofs.p_local(v)] -= tab.weights[qp] * s.da * flux * l[m];
                    }
                }
            }
        }
    }
    Ok((cons, ext))
}
