//! The medium the aggregate sits in (model.md: The medium): its pressure field p_m(x) on the
//! current configuration, which loads the whole boundary group with the traction −p_m n (free
//! faces and faces on a plate alike, so the plates' reactions are the excess over the medium)
//! and is the pressure the drained surface drains towards (`problem::contact_stage`).
//!
//! The field is p_m(x, t) = g_f ρ_m a_g·x − Σ_r Δp_r(t) χ_r(x): the medium's hydrostatic
//! pressure, g_f the gravity factor of the settling ramp (the excess weight is what settles),
//! less each pipette's suction in its bore (`suction`); the reference level is irrelevant: a
//! uniform shift of every pressure changes no displacement (incompressible constituents). The
//! medium's viscous drag −ζ_d u̇ (`drag`) loads the same faces.
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
use crate::physics::drag::Drag;
use crate::physics::suction::Suction;
use crate::physics::surface_geometry::{face_state, orientation, point_normal, Rule, MAX};
use mpi::topology::SimpleCommunicator;

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
    /// The rule's coordinates are the meridian's (r, z).
    meridian: bool,
    /// The pipettes' suctions.
    suctions: Vec<Suction>,
    /// The viscous drag, if the medium has a viscosity.
    drag: Option<Drag>,
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
        let meridian = mesh.family.axes().len() == 2;
        Medium { weight, factor: 1.0, faces: faces.to_vec(), outward, rule, meridian, suctions: Vec::new(), drag: None }
    }

    /// With the pipettes' `suctions`.
    pub(crate) fn with_suctions(mut self, suctions: Vec<Suction>) -> Medium {
        self.suctions = suctions;
        self
    }

    /// With the viscous drag of a medium of viscosity `viscosity` (Pa s, > 0) on the body, its
    /// radius R₀ that of the sphere of the meshed volume (collective; a quarter model's is the
    /// quarter's, which overestimates ζ_d by 4^{1/3}: the pipettes are on the meridian).
    pub(crate) fn with_drag(
        mut self,
        viscosity: f64,
        mesh: &LocalMesh,
        dofs: &DofMap,
        world: &SimpleCommunicator,
    ) -> Medium {
        let radius = (3.0 * mesh.volume(world) / (4.0 * std::f64::consts::PI)).cbrt();
        self.drag = Some(Drag::new(viscosity, radius, &self.rule, mesh, dofs, &self.faces));
        self
    }

    /// The suctions.
    pub(crate) fn suctions(&self) -> &[Suction] {
        &self.suctions
    }

    /// The faces the medium wets (local).
    pub(crate) fn faces(&self) -> &[u32] {
        &self.faces
    }

    /// Whether the rule's coordinates are the meridian's.
    pub(crate) fn meridian(&self) -> bool {
        self.meridian
    }

    /// Moves the suctions to time t, the tools at `positions` (the scene's tools, in order).
    pub(crate) fn move_to(&mut self, t: f64, positions: &[f64]) {
        for s in &mut self.suctions {
            s.move_to(t, positions.get(s.tool_index).copied().unwrap_or(0.0));
        }
    }

    /// The times the suction tables kink at (steps land on them).
    pub(crate) fn kinks(&self) -> Vec<f64> {
        self.suctions.iter().flat_map(Suction::kinks).collect()
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
        for s in &self.suctions {
            p = p + s.pressure(x, self.meridian);
        }
        p
    }

    /// Local node n's current position (local displacement `u`), the rule's coordinates.
    fn node_position(&self, mesh: &LocalMesh, dofs: &DofMap, n: usize, u: &[f64]) -> [f64; 3] {
        let mut x = [0.0; 3];
        for (c, &axis) in mesh.family.axes().iter().enumerate() {
            x[c] = mesh.coords[n][axis] + u[dofs.u_local(n, c)];
        }
        x
    }

    /// p_m at local node n's current position (local displacement `u`): what the drained
    /// surface drains towards.
    pub(crate) fn at_node(&self, mesh: &LocalMesh, dofs: &DofMap, n: usize, u: &[f64]) -> f64 {
        self.pressure(&self.node_position(mesh, dofs, n, u))
    }

    /// ∇p_m at local node n's current position (the rule's coordinates), by duals.
    pub(crate) fn gradient_at(&self, mesh: &LocalMesh, dofs: &DofMap, n: usize, u: &[f64]) -> [f64; 3] {
        let x = self.node_position(mesh, dofs, n, u);
        self.pressure(&std::array::from_fn::<Dual<3>, 3, _>(|i| Dual::var(x[i], i))).d
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

    /// Adds the load and the drag to the residual `f` (local layout) at the local displacement
    /// `u` and rate `udot`.
    pub(crate) fn add_residual(&self, mesh: &LocalMesh, dofs: &DofMap, u: &[f64], udot: &[f64], f: &mut [f64]) {
        for (k, (&face, &outward)) in self.faces.iter().zip(&self.outward).enumerate() {
            let (idx, x, n) = face_state(&self.rule, mesh, dofs, face, u);
            let mut r = self.face_load(&x[..n], outward);
            if let Some(drag) = &self.drag {
                drag.add_face(k, &idx[..n], udot, &mut r[..n]);
            }
            for (k, &l) in idx[..n].iter().enumerate() {
                f[l] += r[k];
            }
        }
    }

    /// The drag's total force on the local faces at the rates `udot` (nN, the rule's
    /// coordinates; 0 without drag).
    pub(crate) fn drag_force(&self, mesh: &LocalMesh, dofs: &DofMap, udot: &[f64]) -> [f64; 3] {
        let mut total = [0.0; 3];
        let Some(drag) = &self.drag else { return total };
        let d = self.rule.layout().0;
        for (k, &face) in self.faces.iter().enumerate() {
            let (idx, _, n) = face_state(&self.rule, mesh, dofs, face, udot);
            let mut r = [0.0; MAX];
            drag.add_face(k, &idx[..n], udot, &mut r[..n]);
            for (i, v) in r[..n].iter().enumerate() {
                total[i % d] += v;
            }
        }
        total
    }

    /// Calls `add` with each face's local dofs and its block ∂r/∂x (+ `shift` ∂r/∂ẋ, the drag),
    /// row-major.
    pub(crate) fn for_each_block(
        &self,
        mesh: &LocalMesh,
        dofs: &DofMap,
        u: &[f64],
        shift: f64,
        mut add: impl FnMut(&[usize], &[f64]) -> crate::error::Result<()>,
    ) -> crate::error::Result<()> {
        for (k, (&face, &outward)) in self.faces.iter().zip(&self.outward).enumerate() {
            let (idx, x, n) = face_state(&self.rule, mesh, dofs, face, u);
            let h = self.face_block(&x[..n], outward);
            let mut block: Vec<f64> = (0..n * n).map(|k| h[k / n][k % n]).collect();
            if let Some(drag) = &self.drag {
                drag.add_face_block(k, n, shift, &mut block);
            }
            add(&idx[..n], &block)?;
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "medium_tests.rs"]
mod tests;
