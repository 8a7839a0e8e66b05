//! Scalar observables for `history.csv`: a field at a reference point (located once, by
//! inverting the isoparametric map of the containing element), or a field's mean over a
//! surface group, ∫_Γ f dA / ∫_Γ dA. Values are reduced over ranks.

use crate::error::{Error, Result};
use crate::fem::dofmap::DofMap;
use crate::fem::element::{tabulate_tri6, tet10, tri6_surface, Tabulation};
use crate::fem::kernel::p1_values;
use crate::fem::quadrature;
use crate::mesh::dist::LocalMesh;
use crate::scene::Probe as ProbeSpec;
use mpi::collective::SystemOperation;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// Which scalar a probe reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Quantity {
    Pressure,
    Displacement(usize),
    /// Porosity 1 − Φs/J at the point, with this Φs.
    Porosity(f64),
}

impl Quantity {
    pub fn parse(s: &str) -> Option<Quantity> {
        Some(match s {
            "p" => Quantity::Pressure,
            "ux" => Quantity::Displacement(0),
            "uy" => Quantity::Displacement(1),
            "uz" => Quantity::Displacement(2),
            _ => return None,
        })
    }
}

enum Where {
    /// This rank owns the point: (local element, reference coordinates). None elsewhere.
    Point(Option<(usize, [f64; 3])>),
    /// Local faces of the group and the group's total area.
    Group(Vec<u32>, f64),
}

pub struct Probe {
    pub name: String,
    quantity: Quantity,
    scale: f64,
    at: Where,
}

/// Reference coordinates of X in element `e` if it lies inside (Newton on the isoparametric map).
pub fn locate_in_element(mesh: &LocalMesh, e: usize, x: [f64; 3]) -> Option<[f64; 3]> {
    let t = &mesh.tets[e];
    let c = |i: usize| mesh.coords[t[i] as usize];
    // Quick reject by the vertex bounding box, padded for curved faces.
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for a in 0..10 {
        for d in 0..3 {
            lo[d] = lo[d].min(c(a)[d]);
            hi[d] = hi[d].max(c(a)[d]);
        }
    }
    let pad = 1e-9 * (0..3).map(|d| hi[d] - lo[d]).fold(0.0, f64::max);
    if (0..3).any(|d| x[d] < lo[d] - pad || x[d] > hi[d] + pad) {
        return None;
    }
    let mut xi = [0.25; 3];
    for _ in 0..20 {
        let (n, dn) = tet10(&xi);
        let mut r = x;
        let mut jm = nalgebra::Matrix3::<f64>::zeros();
        for a in 0..10 {
            for d in 0..3 {
                r[d] -= n[a] * c(a)[d];
                for k in 0..3 {
                    jm[(d, k)] += c(a)[d] * dn[a][k];
                }
            }
        }
        let step = jm.try_inverse()? * nalgebra::Vector3::from(r);
        for k in 0..3 {
            xi[k] += step[k];
        }
        if step.norm() < 1e-13 {
            break;
        }
    }
    let l = p1_values(&xi);
    (l.iter().all(|&v| v >= -1e-9)).then_some(xi)
}

impl Probe {
    /// A point probe of `quantity` at reference point `x` (collective), named `name`.
    pub fn at_point(
        name: &str,
        quantity: Quantity,
        x: [f64; 3],
        mesh: &LocalMesh,
        world: &SimpleCommunicator,
        context: &str,
    ) -> Result<Probe> {
        let spec = ProbeSpec { name: name.into(), field: "p".into(), point: Some(x), group: None, scale: 1.0 };
        let mut p = Probe::new(&spec, mesh, world, context)?;
        p.quantity = quantity;
        Ok(p)
    }

    /// Sets up a probe (collective).
    pub fn new(spec: &ProbeSpec, mesh: &LocalMesh, world: &SimpleCommunicator, context: &str) -> Result<Probe> {
        let quantity = Quantity::parse(&spec.field).ok_or_else(|| Error::Scene {
            path: context.into(),
            msg: format!("probe \"{}\": unknown field {}", spec.name, spec.field),
        })?;
        let at = if let Some(x) = spec.point {
            let found = (0..mesh.tets.len()).find_map(|e| locate_in_element(mesh, e, x).map(|xi| (e, xi)));
            let mine = if found.is_some() { world.rank() } else { world.size() };
            let mut owner = 0;
            world.all_reduce_into(&mine, &mut owner, SystemOperation::min());
            if owner == world.size() {
                return Err(Error::Scene {
                    path: context.into(),
                    msg: format!("probe \"{}\": point {:?} is outside the mesh", spec.name, x),
                });
            }
            Where::Point(if owner == world.rank() { found } else { None })
        } else {
            let group = spec.group.as_deref().unwrap_or_default();
            let faces = super::bc::face_group(mesh, group, &format!("{context}: probe \"{}\"", spec.name))?.to_vec();
            let area = reduce_sum(world, integrate(mesh, &faces, |_| 1.0));
            Where::Group(faces, area)
        };
        Ok(Probe { name: spec.name.clone(), quantity, scale: spec.scale, at })
    }

    /// The probe's value (collective); `local` is the owned+ghost state vector.
    pub fn value(&self, mesh: &LocalMesh, dofs: &DofMap, local: &[f64], world: &SimpleCommunicator) -> f64 {
        let v = match &self.at {
            Where::Point(Some((e, xi))) => {
                let t = &mesh.tets[*e];
                match self.quantity {
                    Quantity::Pressure => p1_values(xi)
                        .iter()
                        .enumerate()
                        .map(|(m, l)| l * local[dofs.p_local(mesh.vertex_of_node[t[m] as usize] as usize)])
                        .sum(),
                    Quantity::Displacement(c) => {
                        let (n, _) = tet10(xi);
                        (0..10).map(|a| n[a] * local[dofs.u_local(t[a] as usize, c)]).sum()
                    }
                    Quantity::Porosity(phi_s) => {
                        1.0 - phi_s / deformation_gradient(mesh, dofs, *e, xi, local).determinant()
                    }
                }
            }
            Where::Point(None) => 0.0,
            Where::Group(faces, area) => {
                let q = self.quantity;
                integrate(mesh, faces, |(nodes, n, l)| match q {
                    Quantity::Pressure => (0..3)
                        .map(|m| l[m] * local[dofs.p_local(mesh.vertex_of_node[nodes[m] as usize] as usize)])
                        .sum(),
                    Quantity::Porosity(_) => f64::NAN,
                    Quantity::Displacement(c) => (0..6).map(|a| n[a] * local[dofs.u_local(nodes[a] as usize, c)]).sum(),
                }) / area
            }
        };
        let total = match &self.at {
            Where::Point(_) => reduce_sum(world, v),
            Where::Group(..) => reduce_sum(world, v),
        };
        total / self.scale
    }
}

/// F = I + Grad u at reference coordinates ξ of local element e (isoparametric map).
pub fn deformation_gradient(
    mesh: &LocalMesh,
    dofs: &DofMap,
    e: usize,
    xi: &[f64; 3],
    local: &[f64],
) -> nalgebra::Matrix3<f64> {
    let t = &mesh.tets[e];
    let (_, dn) = tet10(xi);
    let mut jm = nalgebra::Matrix3::<f64>::zeros();
    for a in 0..10 {
        let x = mesh.coords[t[a] as usize];
        for d in 0..3 {
            for k in 0..3 {
                jm[(d, k)] += x[d] * dn[a][k];
            }
        }
    }
    let jinv = jm.try_inverse().unwrap_or_else(nalgebra::Matrix3::zeros);
    let mut f = nalgebra::Matrix3::<f64>::identity();
    for a in 0..10 {
        // ∇_X N_a = J⁻ᵀ ∇_ξ N_a
        let g = jinv.transpose() * nalgebra::Vector3::from(dn[a]);
        for i in 0..3 {
            let ui = local[dofs.u_local(t[a] as usize, i)];
            for j in 0..3 {
                f[(i, j)] += ui * g[j];
            }
        }
    }
    f
}

/// ∫ over local faces of f(face nodes, P2 face shape values, P1 face shape values).
fn integrate(mesh: &LocalMesh, faces: &[u32], f: impl Fn((&[u32; 6], &[f64; 6], [f64; 3])) -> f64) -> f64 {
    let q = quadrature::tri(5);
    let tab: Tabulation<6> = tabulate_tri6(&q);
    let mut sum = 0.0;
    for &fi in faces {
        let nodes = &mesh.faces[fi as usize];
        let coords: [[f64; 3]; 6] = std::array::from_fn(|a| mesh.coords[nodes[a] as usize]);
        for qp in 0..q.weights.len() {
            let s = tri6_surface(&coords, &tab, qp);
            let xi = q.points[qp];
            sum += tab.weights[qp] * s.da * f((nodes, &tab.n[qp], [1.0 - xi[0] - xi[1], xi[0], xi[1]]));
        }
    }
    sum
}

fn reduce_sum(world: &SimpleCommunicator, v: f64) -> f64 {
    let mut t = 0.0;
    world.all_reduce_into(&v, &mut t, SystemOperation::sum());
    t
}
