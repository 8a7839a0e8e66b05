//! Scalar observables for `history.csv`: a field at a reference point (located once, by
//! inverting the isoparametric map of the containing element), or a field's mean over a
//! surface group, ∫_Γ f dA / ∫_Γ dA. Values are reduced over ranks.
//!
//! On a meridian mesh a point (x, y, z) is the point (√(x² + y²), z) of the meridian, "ux" is the
//! radial displacement u_r, and surface means are over the surface of revolution.

use crate::error::{Error, Result};
use crate::fem::dofmap::DofMap;
use crate::fem::surface::FaceRule;
use crate::io::recorder::ColumnDoc;
use crate::mesh::dist::LocalMesh;
use crate::parallel::sum;
use crate::reference_cell::shape::{p1_values as p1, p2_values as shapes};
use crate::reference_cell::Family;
use crate::scene::{Probe as ProbeSpec, ProbeField};
use mpi::collective::SystemOperation;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// Which scalar a probe reads.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Quantity {
    Pressure,
    Displacement(usize),
    /// Porosity 1 − Φs/J at the point, with this Φs.
    Porosity(f64),
}

impl From<ProbeField> for Quantity {
    fn from(f: ProbeField) -> Quantity {
        match f {
            ProbeField::P => Quantity::Pressure,
            ProbeField::Ux => Quantity::Displacement(0),
            ProbeField::Uy => Quantity::Displacement(1),
            ProbeField::Uz => Quantity::Displacement(2),
        }
    }
}

enum Where {
    /// This rank owns the point: (local element, reference coordinates). None elsewhere.
    Point(Option<(usize, [f64; 3])>),
    /// Local faces of the group and the group's total area.
    Group(Vec<u32>, f64),
}

/// The `history.csv` column of each `[[probe]]`, named by the scene.
pub(crate) const COLUMN: ColumnDoc = ColumnDoc::pattern(
    "*probe name*",
    "as the field",
    "a `[[probe]]`: `p` (kPa) or `ux`, `uy`, `uz` (µm) at a point or averaged over a surface group, divided by \
     `scale`",
);

pub(crate) struct Probe {
    pub(crate) name: String,
    quantity: Quantity,
    scale: f64,
    at: Where,
}

/// The point of the mesh's space that stands for the reference point x: itself in 3-D, its
/// meridian point (√(x² + y²), 0, z) on a meridian mesh.
pub(crate) fn mesh_point(family: Family, x: [f64; 3]) -> [f64; 3] {
    match family {
        Family::Tet10 => x,
        Family::Tri6 => [x[0].hypot(x[1]), 0.0, x[2]],
    }
}

/// Reference coordinates of X (a point of the mesh's space, [`mesh_point`]) in element `e` if it
/// lies inside (Newton on the isoparametric map).
pub(crate) fn locate_in_element(mesh: &LocalMesh, e: usize, x: [f64; 3]) -> Option<[f64; 3]> {
    let fam = mesh.family;
    let t = mesh.cell(e);
    let c = |i: usize| mesh.coords[t[i] as usize];
    // Quick reject by the node bounding box, padded for curved faces.
    let (mut lo, mut hi) = ([f64::MAX; 3], [f64::MIN; 3]);
    for a in 0..t.len() {
        for d in 0..3 {
            lo[d] = lo[d].min(c(a)[d]);
            hi[d] = hi[d].max(c(a)[d]);
        }
    }
    let pad = 1e-9 * (0..3).map(|d| hi[d] - lo[d]).fold(0.0, f64::max);
    if (0..3).any(|d| x[d] < lo[d] - pad || x[d] > hi[d] + pad) {
        return None;
    }
    let axes = fam.axes();
    let dim = axes.len();
    let mut xi = if dim == 3 { [0.25; 3] } else { [1.0 / 3.0, 1.0 / 3.0, 0.0] };
    for _ in 0..20 {
        let (n, dn) = shapes(fam, &xi);
        let mut r = nalgebra::DVector::<f64>::zeros(dim);
        let mut jm = nalgebra::DMatrix::<f64>::zeros(dim, dim);
        for (row, &d) in axes.iter().enumerate() {
            r[row] = x[d];
            for a in 0..t.len() {
                r[row] -= n[a] * c(a)[d];
                for k in 0..dim {
                    jm[(row, k)] += c(a)[d] * dn[a][k];
                }
            }
        }
        let step = jm.try_inverse()? * r;
        for k in 0..dim {
            xi[k] += step[k];
        }
        if step.norm() < 1e-13 {
            break;
        }
    }
    let l = p1(fam, &xi);
    (l.iter().all(|&v| v >= -1e-9)).then_some(xi)
}

impl Probe {
    /// A point probe of `quantity` at reference point `x` (collective), named `name`.
    pub(crate) fn at_point(
        name: &str,
        quantity: Quantity,
        x: [f64; 3],
        mesh: &LocalMesh,
        world: &SimpleCommunicator,
        context: &str,
    ) -> Result<Probe> {
        let spec = ProbeSpec { name: name.into(), field: ProbeField::P, point: Some(x), group: None, scale: 1.0 };
        let mut p = Probe::new(&spec, mesh, world, context)?;
        p.quantity = quantity;
        Ok(p)
    }

    /// Sets up a probe (collective).
    pub(crate) fn new(spec: &ProbeSpec, mesh: &LocalMesh, world: &SimpleCommunicator, context: &str) -> Result<Probe> {
        let quantity = Quantity::from(spec.field);
        if let Quantity::Displacement(axis) = quantity {
            if mesh.family.component(axis).is_none() {
                return Err(Error::Scene {
                    path: context.into(),
                    msg: format!(
                        "probe \"{}\": an axisymmetric model has no {} (use ux for u_r)",
                        spec.name, spec.field
                    ),
                });
            }
        }
        let at = if let Some(x) = spec.point {
            let x = mesh_point(mesh.family, x);
            let found = (0..mesh.cells.len()).find_map(|e| locate_in_element(mesh, e, x).map(|xi| (e, xi)));
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
            let faces =
                crate::physics::bc::face_group(mesh, group, &format!("{context}: probe \"{}\"", spec.name))?.to_vec();
            let area = sum(world, integrate(mesh, &faces, |_| 1.0));
            Where::Group(faces, area)
        };
        Ok(Probe { name: spec.name.clone(), quantity, scale: spec.scale, at })
    }

    /// The probe's value (collective); `local` is the owned+ghost state vector.
    pub(crate) fn value(&self, mesh: &LocalMesh, dofs: &DofMap, local: &[f64], world: &SimpleCommunicator) -> f64 {
        let v = match &self.at {
            Where::Point(Some((e, xi))) => {
                let t = mesh.cell(*e);
                match self.quantity {
                    Quantity::Pressure => p1(mesh.family, xi)
                        .iter()
                        .take(mesh.family.cell_vertices())
                        .enumerate()
                        .map(|(m, l)| l * local[dofs.p_local(mesh.vertex_of_node[t[m] as usize] as usize)])
                        .sum(),
                    Quantity::Displacement(axis) => {
                        let c = mesh.family.component(axis).unwrap_or(0);
                        let (n, _) = shapes(mesh.family, xi);
                        (0..t.len()).map(|a| n[a] * local[dofs.u_local(t[a] as usize, c)]).sum()
                    }
                    Quantity::Porosity(phi_s) => {
                        1.0 - phi_s / deformation_gradient(mesh, dofs, *e, xi, local).determinant()
                    }
                }
            }
            Where::Point(None) => 0.0,
            Where::Group(faces, area) => {
                let q = self.quantity;
                let c = match q {
                    Quantity::Displacement(axis) => mesh.family.component(axis).unwrap_or(0),
                    _ => 0,
                };
                integrate(mesh, faces, |(nodes, n, l)| match q {
                    Quantity::Pressure => (0..mesh.family.face_vertices())
                        .map(|m| l[m] * local[dofs.p_local(mesh.vertex_of_node[nodes[m] as usize] as usize)])
                        .sum(),
                    Quantity::Porosity(_) => f64::NAN,
                    Quantity::Displacement(_) => {
                        (0..nodes.len()).map(|a| n[a] * local[dofs.u_local(nodes[a] as usize, c)]).sum()
                    }
                }) / area
            }
        };
        let total = match &self.at {
            Where::Point(_) => sum(world, v),
            Where::Group(..) => sum(world, v),
        };
        total / self.scale
    }
}

/// F = I + Grad u at reference coordinates ξ of local element e (isoparametric map; with the
/// hoop stretch 1 + u_r / R on the meridian).
pub(crate) fn deformation_gradient(
    mesh: &LocalMesh,
    dofs: &DofMap,
    e: usize,
    xi: &[f64; 3],
    local: &[f64],
) -> nalgebra::Matrix3<f64> {
    let fam = mesh.family;
    let t = mesh.cell(e);
    let (n, dn) = shapes(fam, xi);
    let axes = fam.axes();
    // jm[(d, k)] = ∂x_d/∂ξ_k over the spanned axes (identity elsewhere, so its inverse is too).
    let mut jm = nalgebra::Matrix3::<f64>::identity();
    for &d in axes {
        for (k, _) in axes.iter().enumerate() {
            jm[(d, k)] = 0.0;
        }
    }
    for a in 0..t.len() {
        let x = mesh.coords[t[a] as usize];
        for &d in axes {
            for k in 0..axes.len() {
                jm[(d, k)] += x[d] * dn[a][k];
            }
        }
    }
    // Columns of jm are indexed by ξ_k; map them onto the spanned axes.
    let mut jx = nalgebra::Matrix3::<f64>::identity();
    for (k, &ak) in axes.iter().enumerate() {
        for &d in axes {
            jx[(d, ak)] = jm[(d, k)];
        }
    }
    let jinv = jx.try_inverse().unwrap_or_else(nalgebra::Matrix3::zeros);
    let mut f = nalgebra::Matrix3::<f64>::identity();
    let mut r = 0.0;
    for a in 0..t.len() {
        let x = mesh.coords[t[a] as usize];
        r += n[a] * x[0];
        // ∇_X N_a = J⁻ᵀ ∇_ξ N_a, with ∇_ξ placed on the spanned axes.
        let mut g_ref = nalgebra::Vector3::zeros();
        for (k, &ak) in axes.iter().enumerate() {
            g_ref[ak] = dn[a][k];
        }
        let g = jinv.transpose() * g_ref;
        for (c, &i) in fam.axes().iter().enumerate() {
            let ui = local[dofs.u_local(t[a] as usize, c)];
            for j in 0..3 {
                f[(i, j)] += ui * g[j];
            }
        }
    }
    if fam.axisymmetric() {
        let ur: f64 = (0..t.len()).map(|a| n[a] * local[dofs.u_local(t[a] as usize, 0)]).sum();
        f[(1, 1)] += ur / r;
    }
    f
}

/// ∫ over local faces of f(face nodes, P2 face shape values, P1 face shape values).
fn integrate(mesh: &LocalMesh, faces: &[u32], f: impl Fn((&[u32], &[f64; 6], [f64; 3])) -> f64) -> f64 {
    let rule = FaceRule::new(mesh.family);
    let mut sum = 0.0;
    for &fi in faces {
        let nodes = mesh.face(fi as usize);
        let coords: Vec<[f64; 3]> = nodes.iter().map(|&n| mesh.coords[n as usize]).collect();
        for p in rule.points(&coords) {
            sum += p.w * f((nodes, &p.n, p.l));
        }
    }
    sum
}
