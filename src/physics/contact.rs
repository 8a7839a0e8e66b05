//! Rigid, flat, impermeable, frictionless plates (model.md §1, §5) as variable bounds on the
//! vertical displacement of the aggregate's surface nodes, and the drainage that follows
//! contact.
//!
//! A surface node at reference height Z has current height Z + u_z, and must satisfy
//! u(t) ≤ Z + u_z ≤ 2R: lower bound u(t) − Z from the moving lower plate (its top face is at
//! z = u(t), the loading (53)), upper bound 2R − Z from the fixed upper plate. These
//! are variable bounds of the active-set Newton (`solver::active_set`; or PETSc's SNESVI),
//! refreshed at every stage time.
//!
//! Fluid: the surface drains into the bath where it is off the plates and is sealed where it
//! touches them (`physics::drainage`); the plates give it their gap ([`Plates::drainage_gap`]).

use crate::fem::dofmap::DofMap;
use crate::mesh::dist::LocalMesh;
pub(crate) use crate::physics::drainage::{Drainage, DrainageGap};
use crate::physics::tools::protocol::ToolProtocol;
use crate::solver::active_set::{Positions, SharedPositions};

/// Lower-plate displacement u(t): linear between the points (t, u) of the plate's path, from
/// (0, 0), the last value after it. The compression–release test (53) (ramp to u_max, hold,
/// release back to 0, rest) is the path of its four corners (`PlatesSpec::path`).
#[derive(Debug, Clone)]
pub(crate) struct PlateLoading {
    /// (t, u) in increasing t, from (0, 0).
    points: Vec<(f64, f64)>,
}

impl PlateLoading {
    /// The table (t, u) (increasing t; the scene checks it).
    pub(crate) fn table(points: Vec<(f64, f64)>) -> PlateLoading {
        PlateLoading { points }
    }

    pub(crate) fn displacement(&self, t: f64) -> f64 {
        let p = &self.points;
        if t <= p[0].0 {
            return p[0].1;
        }
        match p.windows(2).find(|w| t < w[1].0) {
            Some(w) => w[0].1 + (w[1].1 - w[0].1) * (t - w[0].0) / (w[1].0 - w[0].0),
            None => p[p.len() - 1].1,
        }
    }

    /// The points (t, u), from (0, 0).
    pub(crate) fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// The kinks of u(t), the table's times after 0: steps must land on them.
    pub(crate) fn kinks(&self) -> Vec<f64> {
        self.points.iter().map(|p| p.0).filter(|&t| t > 0.0).collect()
    }
}

/// Which plate a surface node touches.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Touch {
    Free,
    Lower,
    Upper,
}

/// Tolerance (relative to R) for "at the bound": Newton iterates are projected onto the bounds,
/// so a node in contact sits on it to round-off.
const AT_BOUND: f64 = 1e-9;

/// The plates and the aggregate surface that can touch them.
pub(crate) struct Plates {
    pub(crate) loading: PlateLoading,
    /// Height of the upper plate's bottom face at its origin (2R).
    z_top: f64,
    /// The upper plate's protocol, and its displacement downwards (position 0 of the shared
    /// positions: an unknown of the solver under force control).
    pub(crate) upper: ToolProtocol,
    pub(crate) positions: SharedPositions,
    /// The upper plate's displacement that the drainage's gaps are taken against, when they are
    /// the predictor's (`DrainageGap::Predicted`: the predictor's plate too, so that a force-
    /// controlled plate's Newton moves do not open the drainage); None: its displacement now.
    pub(crate) drain_d: std::cell::Cell<Option<f64>>,
    /// Local nodes of the contact surface (their vertices only for P1–P1, see `new`) and their
    /// reference heights: the nodes with bounds, the contact nodes of the observables.
    pub(crate) nodes: Vec<usize>,
    z_ref: Vec<f64>,
    /// How the surface drains (`physics::drainage`): its seal distance keeps the predictor's
    /// nodes near a plate on it, and its gap rule says whose gaps the steps drain by.
    pub(crate) drain: Drainage,
    /// Local node (if here) of the bottom pole, which stays on the lower plate (see `new`).
    anchor: Option<usize>,
    tol: f64,
    /// Whether the contact is bounds on the nodes' u_z (else the plates are plane tools of the
    /// general path, `plates.contact = "tools"`, and only the anchor has bounds).
    on_bounds: bool,
}

impl Plates {
    /// `(loading, upper)`: the lower and upper plates' protocols; `faces`: local faces of the
    /// contact surface; `anchor`: the local node of the bottom
    /// pole, if on this rank; `drain` the surface's drainage (module docs); `on_vertices`:
    /// contact on the faces' vertices only, for equal-order P1–P1, whose mid-edge nodes are
    /// slaves of their edges (`fem::equal_order`): a bound there would contradict the tie row
    /// (on a curved face the mid-edge node of two vertices on a plate lies beyond it by the
    /// face's sagitta).
    ///
    /// The anchor's contact is bilateral (bounds lo = hi = u(t)): gravity keeps the aggregate on
    /// the lower plate throughout, but when the upper contact opens on release, the vertical
    /// rigid motion is held only by the unilateral lower contact against the weight (≈ 40 nN);
    /// any Newton iterate that frees it makes the Jacobian singular. Pinning the pole removes
    /// that mode without changing the converged solution as long as its reaction stays
    /// compressive (reported as `force_lower_mg`).
    pub(crate) fn new(
        (loading, upper): (PlateLoading, ToolProtocol),
        radius: f64,
        mesh: &LocalMesh,
        faces: &[u32],
        anchor: Option<usize>,
        drain: Drainage,
        on_vertices: bool,
    ) -> Plates {
        let per_face = if on_vertices { mesh.family.face_vertices() } else { mesh.family.face_nodes() };
        let mut nodes: Vec<usize> =
            faces.iter().flat_map(|&f| mesh.face(f as usize)[..per_face].iter().map(|&n| n as usize)).collect();
        nodes.sort_unstable();
        nodes.dedup();
        let z_ref = nodes.iter().map(|&n| mesh.coords[n][2]).collect();
        let positions = std::rc::Rc::new(std::cell::RefCell::new(Positions { d: vec![0.0], target: vec![None] }));
        let z_top = 2.0 * radius;
        Plates {
            loading,
            z_top,
            upper,
            positions,
            drain_d: Default::default(),
            nodes,
            z_ref,
            drain,
            anchor,
            tol: AT_BOUND * radius,
            on_bounds: true,
        }
    }

    /// Leaves the contact to the plates' two plane tools (`plates.contact = "tools"`): only the
    /// anchor keeps its bounds. Returns the anchor (local node, if here), which the tools skip.
    pub(crate) fn leave_contact_to_tools(&mut self) -> Option<usize> {
        self.on_bounds = false;
        self.anchor
    }

    /// Height of the lower plate's top face at time t.
    pub(crate) fn z_lower(&self, t: f64) -> f64 {
        self.loading.displacement(t)
    }

    /// How many copies of a body of `volume` (µm³, the meshed part) make the reference sphere:
    /// 1 for a whole sphere (and on the meridian), 4 for a quarter; the full-body forces are
    /// this times the model's.
    pub(crate) fn symmetry(&self, volume: f64) -> f64 {
        symmetry(0.5 * self.z_top, volume)
    }

    /// Height of the upper plate's bottom face now (2R less its displacement).
    pub(crate) fn z_upper(&self) -> f64 {
        self.z_upper_at(self.positions.borrow().d[0])
    }

    /// Height of the upper plate's bottom face at displacement d.
    pub(crate) fn z_upper_at(&self, d: f64) -> f64 {
        self.z_top - d
    }

    /// Writes the bounds of the owned surface u_z dofs at time t (others stay ±∞).
    pub(crate) fn fill_bounds(&self, t: f64, dofs: &DofMap, lo: &mut [f64], hi: &mut [f64]) {
        let (zl, zu) = (self.z_lower(t), self.z_upper());
        for (k, &n) in self.nodes.iter().enumerate() {
            if !self.on_bounds && Some(n) != self.anchor {
                continue;
            }
            if let Some(i) = dofs.local_to_owned(dofs.uz_local(n)) {
                lo[i] = zl - self.z_ref[k];
                hi[i] = if Some(n) == self.anchor { lo[i] } else { zu - self.z_ref[k] };
            }
        }
    }

    /// Contact predictor for a step from t0 to t1: the owned nodes touching the lower plate at
    /// t0 (or within the seal distance of it) move with it to t1 in the initial guess `x`.
    ///
    /// Why: when the plate retreats (release), those nodes are off their bound at the start of
    /// the step, so the active-set test treats them as free and its first Newton step applies the whole
    /// former contact force to a free surface; the elements next to it collapse (J < Φs) however
    /// small the step. Moved with the plate they stay active while the reaction is compressive,
    /// and leave the plate only when it turns tensile.
    /// `x0` is the state at t0 (owned entries), `x` the guess being built.
    pub(crate) fn predict(&self, t0: f64, t1: f64, dofs: &DofMap, x0: &[f64], x: &mut [f64]) {
        let (z0, z1) = (self.z_lower(t0), self.z_lower(t1));
        for (k, &n) in self.nodes.iter().enumerate() {
            if let Some(i) = dofs.local_to_owned(dofs.uz_local(n)) {
                // Nodes on the plate or within the seal distance keep their gap.
                if self.z_ref[k] + x0[i] <= z0 + self.drain.seal_gap.max(self.tol) {
                    x[i] = x0[i] + z1 - z0;
                }
            }
        }
    }

    /// The contact nodes whose upper bound is the upper plate's, with their owned u_z dof
    /// (owned only; all but the anchor, which is held on the lower plate).
    pub(crate) fn upper_nodes<'a>(&'a self, dofs: &'a DofMap) -> impl Iterator<Item = (usize, usize)> + 'a {
        self.nodes
            .iter()
            .enumerate()
            .filter(|(_, &n)| Some(n) != self.anchor)
            .filter_map(|(k, _)| dofs.local_to_owned(dofs.uz_local(self.nodes[k])).map(|i| (k, i)))
    }

    /// Whether contact node k (index into `nodes`) lies in the upper half (its reaction is the
    /// upper plate's).
    pub(crate) fn upper_half(&self, k: usize) -> bool {
        self.z_ref[k] > 0.5 * self.z_top
    }

    /// This rank's smallest gap between the upper plate at displacement d and the contact
    /// nodes of the state `x0` (owned entries; ∞ without any here).
    pub(crate) fn upper_gap(&self, d: f64, dofs: &DofMap, x0: &[f64]) -> f64 {
        self.upper_nodes(dofs).map(|(k, i)| self.z_top - d - (self.z_ref[k] + x0[i])).fold(f64::INFINITY, f64::min)
    }

    /// Force control's predictor: the owned nodes on the upper plate at its displacement d0 (or
    /// within the seal distance of it) move with it to its displacement now. Nothing when it
    /// stays (bitwise today's predictor).
    pub(crate) fn predict_upper(&self, d0: f64, dofs: &DofMap, x0: &[f64], x: &mut [f64]) {
        let d1 = self.positions.borrow().d[0];
        if d1 == d0 {
            return;
        }
        let zu0 = self.z_top - d0;
        for (k, &n) in self.nodes.iter().enumerate() {
            if let Some(i) = dofs.local_to_owned(dofs.uz_local(n)) {
                if self.z_ref[k] + x0[i] >= zu0 - self.drain.seal_gap.max(self.tol) {
                    x[i] = x0[i] - (d1 - d0);
                }
            }
        }
    }

    /// The isochoric affine guess for a step from t0 to t1: the plates' relative motion as a
    /// uniform vertical compression between them, with the lateral expansion that keeps the
    /// volume (J) of every element to first order, on the state `x0` (owned entries, u of the
    /// owned nodes first, `axes` per node: the Cartesian axis of each component; `coords` their
    /// reference positions). Short steps load the mixture almost undrained, so this guess
    /// respects J > Φs where an extrapolated compaction rate overshoots it.
    pub(crate) fn predict_isochoric(
        &self,
        t0: f64,
        t1: f64,
        coords: &[[f64; 3]],
        axes: &[usize],
        x0: &[f64],
        x: &mut [f64],
    ) {
        let (z0, z1, zu) = (self.z_lower(t0), self.z_lower(t1), self.z_upper());
        let nc = axes.len();
        for (n, c) in coords.iter().enumerate() {
            let mut cur = *c;
            for (k, &a) in axes.iter().enumerate() {
                cur[a] += x0[nc * n + k];
            }
            let du = isochoric_increment(cur, z0, z1, zu);
            for (k, &a) in axes.iter().enumerate() {
                x[nc * n + k] = x0[nc * n + k] + du[a];
            }
        }
    }

    /// Contact state of a surface node at reference height `z_ref` from its u_z.
    fn touch(&self, z_ref: f64, uz: f64, t: f64, zu: f64) -> Touch {
        let z = z_ref + uz;
        if z <= self.z_lower(t) + self.tol {
            Touch::Lower
        } else if z >= zu - self.tol {
            Touch::Upper
        } else {
            Touch::Free
        }
    }

    /// Contact state of every contact-surface node (same order as `nodes`).
    /// The upper plate at displacement `d_upper`.
    pub(crate) fn states(&self, dofs: &DofMap, u_local: &[f64], t: f64, d_upper: f64) -> Vec<Touch> {
        let zu = self.z_upper_at(d_upper);
        self.nodes.iter().zip(&self.z_ref).map(|(&n, &z)| self.touch(z, u_local[dofs.uz_local(n)], t, zu)).collect()
    }

    /// The gap of a surface node to the nearer plate in the local state `u_local` at time t, and
    /// its derivative with respect to the node's displacement components (only u_z: ±1), for the
    /// drainage (`physics::drainage`). The upper plate where the drainage's gaps take it
    /// (`drain_d`).
    pub(crate) fn drainage_gap<'a>(
        &self,
        mesh: &'a LocalMesh,
        dofs: &'a DofMap,
        u_local: &'a [f64],
        t: f64,
    ) -> impl Fn(usize) -> (f64, [f64; 3]) + 'a {
        let zu = self.drain_d.get().map_or_else(|| self.z_upper(), |d| self.z_top - d);
        let zl = self.z_lower(t);
        let z_axis = dofs.nc - 1;
        move |n: usize| {
            let z = mesh.coords[n][2] + u_local[dofs.uz_local(n)];
            let mut dg = [0.0; 3];
            if z - zl <= zu - z {
                dg[z_axis] = 1.0;
                (z - zl, dg)
            } else {
                dg[z_axis] = -1.0;
                (zu - z, dg)
            }
        }
    }
}

/// How many copies of a body of `volume` make the sphere of `radius` (`Plates::symmetry`).
pub(crate) fn symmetry(radius: f64, volume: f64) -> f64 {
    let sphere = 4.0 / 3.0 * std::f64::consts::PI * radius.powi(3);
    (sphere / volume).round().max(1.0)
}

/// The displacement increment at the current position `x` of the affine map that moves the
/// lower plate from z0 to z1 against the fixed upper one at z_upper: vertical strain
/// ε = (z1 − z0)/(z_upper − z0), lateral strain −ε/2 about the z axis, so that
/// det F = (1 + ε/2)² (1 − ε) = 1 + O(ε²).
fn isochoric_increment(x: [f64; 3], z0: f64, z1: f64, z_upper: f64) -> [f64; 3] {
    let strain = (z1 - z0) / (z_upper - z0);
    [0.5 * strain * x[0], 0.5 * strain * x[1], strain * (z_upper - x[2])]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn isochoric_increment_moves_the_plates_and_keeps_volume() {
        let (z0, z1, zu) = (3.0, 5.0, 200.0);
        let eps = (z1 - z0) / (zu - z0);
        // The lower plate's height moves with it, the upper plate's stays.
        assert!((isochoric_increment([7.0, -4.0, z0], z0, z1, zu)[2] - (z1 - z0)).abs() < 1e-12);
        assert_eq!(isochoric_increment([7.0, -4.0, zu], z0, z1, zu)[2], 0.0);
        // F = I + ∂Δu/∂x by central differences (exact for an affine map): the determinant is
        // (1 + ε/2)² (1 − ε), i.e. 1 up to O(ε²).
        let x = [12.0, 30.0, 80.0];
        let h = 1.0;
        let f = nalgebra::Matrix3::from_fn(|i, j| {
            let (mut a, mut b) = (x, x);
            a[j] += h;
            b[j] -= h;
            let d = (isochoric_increment(a, z0, z1, zu)[i] - isochoric_increment(b, z0, z1, zu)[i]) / (2.0 * h);
            d + f64::from(u8::from(i == j))
        });
        let expected = (1.0 + 0.5 * eps).powi(2) * (1.0 - eps);
        assert!((f.determinant() - expected).abs() < 1e-12);
        assert!((f.determinant() - 1.0).abs() < eps * eps);
    }

    #[test]
    fn loading_is_eq_53() {
        let h = PlateLoading::table(vec![(0.0, 0.0), (5.0, 60.0), (35.0, 60.0), (40.0, 0.0)]);
        assert_eq!(h.displacement(0.0), 0.0);
        assert!((h.displacement(2.5) - 30.0).abs() < 1e-12);
        assert_eq!(h.displacement(5.0), 60.0);
        assert_eq!(h.displacement(20.0), 60.0);
        assert!((h.displacement(37.5) - 30.0).abs() < 1e-12);
        assert_eq!(h.displacement(40.0), 0.0);
        assert_eq!(h.displacement(100.0), 0.0);
        assert_eq!(h.kinks(), [5.0, 35.0, 40.0]);
        // Continuous at the kinks.
        for k in h.kinks() {
            assert!((h.displacement(k - 1e-9) - h.displacement(k + 1e-9)).abs() < 1e-6);
        }
    }

    /// A table of two compressions: linear between rows, held after the last.
    #[test]
    fn a_table_is_linear_between_its_rows() {
        let h =
            PlateLoading::table(vec![(0.0, 0.0), (5.0, 30.0), (60.0, 30.0), (65.0, 0.0), (120.0, 0.0), (125.0, 45.0)]);
        assert_eq!(h.kinks(), [5.0, 60.0, 65.0, 120.0, 125.0]);
        for (t, u) in [
            (-1.0, 0.0),
            (0.0, 0.0),
            (1.0, 6.0),
            (30.0, 30.0),
            (62.5, 15.0),
            (100.0, 0.0),
            (124.0, 36.0),
            (500.0, 45.0),
        ] {
            assert!((h.displacement(t) - u).abs() < 1e-12, "u({t}) = {} against {u}", h.displacement(t));
        }
    }
}
