//! The medium the aggregate sits in (model.md: The medium): its pressure field p_m(x) on the
//! current configuration, which loads the whole boundary group with the traction −p_m n (free
//! faces and faces on a plate alike, so the plates' reactions are the excess over the medium)
//! and is the pressure the drained surface drains towards (`problem::contact_stage`).
//!
//! Today the field is the medium's hydrostatic pressure p_m(x) = g_f ρ_m a_g·x, g_f the gravity
//! factor of the settling ramp (the excess weight is what settles); the reference level is
//! irrelevant: a uniform shift of every pressure changes no displacement (incompressible
//! constituents). Pressure by region (a pipette's bore) is a further term of [`Medium::pressure`].
//!
//! The load's residual on a face is r_b = Σ_q p_m(x_q) N_b(ξ_q) (n da)_q (added to node b's u
//! rows: the external work −∮ p_m n·δx da moved to the left), its block the exact derivative by
//! duals: the follower-load stiffness p_m ∂(n da)/∂x and the pressure-gradient term
//! (∇p_m·δx) n da. On a closed surface ∮ p_m n·δx da = δ∫_V p_m dv, so the assembled tangent
//! is symmetric (one face's is not), and ∮ p_m n da = ∫_V ∇p_m dv: with the face rule exact for
//! the integrand (`Rule::exact_for_linear_fields`: degree 6 on the 6-node triangles, 7 on the
//! meridian's edges) the load of the hydrostatic part is ρ_m a_g V_h with the same discrete volume V_h as the bulk's ∫ J dV, so a
//! settled aggregate's plate force is its excess weight (ρ_mix − ρ_m) g V_h to round-off.

use crate::fem::dofmap::DofMap;
use crate::material::dual::{Dual, Scalar};
use crate::mesh::dist::LocalMesh;
use crate::physics::biphasic::KG_M3_M_S2_TO_KPA_PER_UM;
use crate::physics::surface_geometry::{face_state, orientation, point_normal, Rule, MAX};

/// The medium on this rank's faces of the boundary group.
pub(crate) struct Medium {
    /// ρ_m a_g in the face rule's coordinates (x, y, z, or r, z on the meridian), kPa/µm.
    weight: [f64; 3],
    /// The settling's gravity factor g_f (1 after settling).
    factor: f64,
    faces: Vec<u32>,
    /// Per face, +1 if its node order gives the outward normal, −1 if the inward.
    outward: Vec<f64>,
    rule: Rule,
}

impl Medium {
    /// The medium of density `density` (kg/m³) under the gravity `gravity` (m/s², Cartesian)
    /// on the local `faces` of the boundary group.
    pub(crate) fn new(density: f64, gravity: [f64; 3], mesh: &LocalMesh, faces: &[u32]) -> Medium {
        let rule = Rule::exact_for_linear_fields(mesh.family);
        let mut weight = [0.0; 3];
        for (c, &axis) in mesh.family.axes().iter().enumerate() {
            weight[c] = density * gravity[axis] * KG_M3_M_S2_TO_KPA_PER_UM;
        }
        let outward = faces.iter().map(|&f| orientation(&rule, mesh, f)).collect();
        Medium { weight, factor: 1.0, faces: faces.to_vec(), outward, rule }
    }

    /// Scales the hydrostatic part with the settling's gravity factor (as the bulk's weight).
    pub(crate) fn set_gravity_factor(&mut self, factor: f64) {
        self.factor = factor;
    }

    /// p_m at the current position `x` (the rule's coordinates), kPa.
    pub(crate) fn pressure<T: Scalar>(&self, x: &[T; 3]) -> T {
        let mut p = T::cst(0.0);
        for (xi, &w) in x.iter().zip(&self.weight) {
            p = p + xi.scale(self.factor * w);
        }
        p
    }

    /// p_m at local node n's current position (local displacement `u`): what the drained
    /// surface drains towards.
    pub(crate) fn at_node(&self, mesh: &LocalMesh, dofs: &DofMap, n: usize, u: &[f64]) -> f64 {
        let mut x = [0.0; 3];
        for (c, &axis) in mesh.family.axes().iter().enumerate() {
            x[c] = mesh.coords[n][axis] + u[dofs.u_local(n, c)];
        }
        self.pressure(&x)
    }

    /// ∇p_m (the rule's coordinates; constant: the hydrostatic part).
    pub(crate) fn gradient(&self) -> [f64; 3] {
        self.weight.map(|w| self.factor * w)
    }

    /// The load of one face with node coordinates `x` (rule layout): Σ_q p_m(x_q) N_b (n da)_q.
    fn face_load<T: Scalar>(&self, x: &[T], outward: f64) -> [T; MAX] {
        let (d, nn) = self.rule.layout();
        let mut r = [T::cst(0.0); MAX];
        for q in 0..self.rule.w.len() {
            let p = self.pressure(&self.rule.point(q, x));
            let nda = point_normal(&self.rule, q, x, outward);
            for node in 0..nn {
                let pn = p.scale(self.rule.n[q][node]);
                for i in 0..d {
                    r[d * node + i] = r[d * node + i] + pn * nda[i];
                }
            }
        }
        r
    }

    /// ∂r/∂x of one face: [`Self::face_load`] differentiated by duals (row-major).
    fn face_block(&self, x: &[f64], outward: f64) -> [[f64; MAX]; MAX] {
        let xd: Vec<Dual<MAX>> = x.iter().enumerate().map(|(i, &v)| Dual::var(v, i)).collect();
        let r = self.face_load(&xd, outward);
        std::array::from_fn(|i| r[i].d)
    }

    /// Adds the load to the residual `f` (local layout) at the local displacement `u`.
    pub(crate) fn add_residual(&self, mesh: &LocalMesh, dofs: &DofMap, u: &[f64], f: &mut [f64]) {
        for (&face, &outward) in self.faces.iter().zip(&self.outward) {
            let (idx, x, n) = face_state(&self.rule, mesh, dofs, face, u);
            let r = self.face_load(&x[..n], outward);
            for (k, &l) in idx[..n].iter().enumerate() {
                f[l] += r[k];
            }
        }
    }

    /// Calls `add` with each face's local dofs and its block ∂r/∂x, row-major.
    pub(crate) fn for_each_block(
        &self,
        mesh: &LocalMesh,
        dofs: &DofMap,
        u: &[f64],
        mut add: impl FnMut(&[usize], &[f64]) -> crate::error::Result<()>,
    ) -> crate::error::Result<()> {
        for (&face, &outward) in self.faces.iter().zip(&self.outward) {
            let (idx, x, n) = face_state(&self.rule, mesh, dofs, face, u);
            let h = self.face_block(&x[..n], outward);
            let block: Vec<f64> = (0..n * n).map(|k| h[k / n][k % n]).collect();
            add(&idx[..n], &block)?;
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "medium_tests.rs"]
mod tests;
