//! Surface tension on the aggregate's boundary: the energy Π = γ ∫ da over its current surface,
//! whose first variation is the residual γ ∂A/∂x of the surface's nodes and whose second is the
//! consistent tangent γ ∂²A/∂x². For a sphere of radius r the residual is the Laplace pressure
//! 2γ/r on its surface (∫ div_s δx da = ∫ 2/r δx·n da on a closed surface).
//!
//! A face's area is a quadrature of its current geometry: on a 6-node triangle (3-D)
//! A = Σ_q w_q |x_ξ × x_η|; on a 3-node meridian edge, the area of the surface it sweeps,
//! A = Σ_q w_q 2π r |x_s| (the hoop term: r itself varies). The gradient is written out
//! ([`area_gradient`]); the Hessian is that gradient differentiated by forward-mode duals, so it
//! is the exact derivative of the residual.

use crate::fem::dofmap::DofMap;
use crate::material::dual::{Dual, Scalar};
use crate::mesh::dist::LocalMesh;
use crate::physics::surface_geometry::{face_state, meridian_point, orientation, point_area, tangents, Rule, MAX};
use crate::reference_cell::Family;

/// The face's area from its node coordinates `x` (node-major, [`Rule::layout`]): what the
/// gradient differentiates (the tests check it against this).
#[cfg(test)]
fn area<T: Scalar>(rule: &Rule, x: &[T]) -> T {
    use crate::physics::surface_geometry::{cross, norm};
    let (d, nn) = rule.layout();
    let mut a = T::cst(0.0);
    for q in 0..rule.w.len() {
        match rule.family {
            Family::Tet10 => {
                let (t1, t2) = tangents(rule, q, x, d, nn);
                let m = cross(&t1, &t2);
                a = a + norm(&m).scale(rule.w[q]);
            }
            Family::Tri6 => {
                let (r, t) = meridian_point(rule, q, x, nn);
                a = a + (r * (t[0] * t[0] + t[1] * t[1]).sqrt()).scale(2.0 * std::f64::consts::PI * rule.w[q]);
            }
        }
    }
    a
}

/// ∂A/∂x of the face (the same layout as `x`).
fn area_gradient<T: Scalar>(rule: &Rule, x: &[T]) -> [T; MAX] {
    let mut g = [T::cst(0.0); MAX];
    for q in 0..rule.w.len() {
        let (_, dq) = point_area(rule, q, x);
        for (gk, dk) in g.iter_mut().zip(dq) {
            *gk = *gk + dk;
        }
    }
    g
}

/// The plates' faces at the residual's time: the lower plate's top at z = `lower`, the upper's
/// bottom at z = `upper`.
#[derive(Debug, Clone, Copy)]
pub(crate) struct PlatePlanes {
    pub(crate) lower: f64,
    pub(crate) upper: f64,
}

/// The work of adhesion w to the plates and its range g_a (model.md: Surface tension).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Adhesion {
    pub(crate) work: f64,
    pub(crate) range: f64,
}

/// S(x) = 10x³ − 15x⁴ + 6x⁵ on [0, 1], 0 below, 1 above, and S'(x) = 30x²(1 − x)²: C², so that
/// the residual's ψ' S' term is C¹ and its tangent continuous where a face lies on a plate
/// (g = 0) and at the range's end (the drainage's C¹ step would put a jump w·6/g_a² into the
/// tangent of every point exactly on a plate).
pub(crate) fn smoothstep<T: Scalar>(x: T) -> (T, T) {
    if x.re() <= 0.0 {
        (T::cst(0.0), T::cst(0.0))
    } else if x.re() >= 1.0 {
        (T::cst(1.0), T::cst(0.0))
    } else {
        let (x2, y) = (x * x, T::cst(1.0) - x);
        (x2 * x * (T::cst(10.0) - x.scale(15.0) + x2.scale(6.0)), x2 * y * y.scale(30.0))
    }
}

/// Point q's gap g to the nearer plate, ∂g/∂z_b = ±N_b (node b's z is its last coordinate), and
/// which plate: +1 the lower (its normal into the aggregate +e_z), −1 the upper.
fn point_gap<T: Scalar>(rule: &Rule, q: usize, x: &[T], planes: PlatePlanes) -> (T, [f64; 6], f64) {
    let (d, nn) = rule.layout();
    let mut z = T::cst(0.0);
    for node in 0..nn {
        z = z + x[d * node + d - 1].scale(rule.n[q][node]);
    }
    let n = rule.n[q];
    if z.re() - planes.lower <= planes.upper - z.re() {
        (z - T::cst(planes.lower), n, 1.0)
    } else {
        (T::cst(planes.upper) - z, n.map(|v| -v), -1.0)
    }
}

/// Point q's share of the face's area projected onto the plate with normal σ e_z (σ = ±1),
/// P_q = −σ (n_z da)_q with n the outward normal (`outward` = ±1: the face's node order gives
/// n or −n), and ∂P_q/∂x: on a plate facing it P_q = a_q; on a vertical face 0; on a face
/// turned away from it (the top of a wedge over a wetted patch) negative. In 3-D
/// n_z da = w_q (x_ξ × x_η)_z, on the meridian n = (t_z, −t_r)/|t| and
/// n_z da = −2π w_q r t_r (the ring's area).
fn point_projection<T: Scalar>(rule: &Rule, q: usize, x: &[T], sigma: f64, outward: f64) -> (T, [T; MAX]) {
    let (d, nn) = rule.layout();
    let mut g = [T::cst(0.0); MAX];
    let c = -sigma * outward * rule.w[q];
    match rule.family {
        Family::Tet10 => {
            let (t1, t2) = tangents(rule, q, x, d, nn);
            for node in 0..nn {
                let [a, b] = rule.dn[q][node];
                g[3 * node] = (t2[1].scale(a) - t1[1].scale(b)).scale(c);
                g[3 * node + 1] = (t1[0].scale(b) - t2[0].scale(a)).scale(c);
            }
            ((t1[0] * t2[1] - t1[1] * t2[0]).scale(c), g)
        }
        Family::Tri6 => {
            let (r, t) = meridian_point(rule, q, x, nn);
            let c = -2.0 * std::f64::consts::PI * c;
            for node in 0..nn {
                let (nb, db) = (rule.n[q][node], rule.dn[q][node][0]);
                g[2 * node] = (t[0].scale(nb) + r.scale(db)).scale(c);
            }
            ((r * t[0]).scale(c), g)
        }
    }
}

/// The adhesion's weight at gap g, −w (1 − S(g/g_a)), and its derivative w S'(g/g_a)/g_a.
fn weight<T: Scalar>(ad: Adhesion, g: T) -> (T, T) {
    let (s, ds) = smoothstep(g.scale(1.0 / ad.range));
    ((s - T::cst(1.0)).scale(ad.work), ds.scale(ad.work / ad.range))
}

/// ∂E/∂x of the face's energy with adhesion, E = Σ_q γ a_q − w (1 − S(g_q/g_a)) P_q (the area,
/// and the area projected onto the nearer plate, [`point_projection`]):
/// Σ_q γ ∂a_q/∂x + ω ∂P_q/∂x + P_q ω' ∂g_q/∂x with ω the adhesion's [`weight`].
fn energy_gradient<T: Scalar>(
    rule: &Rule,
    x: &[T],
    gamma: f64,
    outward: f64,
    ad: Adhesion,
    planes: PlatePlanes,
) -> [T; MAX] {
    let (d, nn) = rule.layout();
    let mut g = [T::cst(0.0); MAX];
    for q in 0..rule.w.len() {
        let (_, da) = point_area(rule, q, x);
        let (gap, dgap, sigma) = point_gap(rule, q, x, planes);
        let (p, dp) = point_projection(rule, q, x, sigma, outward);
        let (om, dom) = weight(ad, gap);
        for k in 0..x.len() {
            g[k] = g[k] + da[k].scale(gamma) + om * dp[k];
        }
        let pull = p * dom;
        for node in 0..nn {
            let k = d * node + d - 1;
            g[k] = g[k] + pull.scale(dgap[node]);
        }
    }
    g
}

/// ∂²E/∂x² with adhesion: [`energy_gradient`] differentiated by duals.
fn energy_hessian(
    rule: &Rule,
    x: &[f64],
    gamma: f64,
    outward: f64,
    ad: Adhesion,
    planes: PlatePlanes,
) -> [[f64; MAX]; MAX] {
    let xd: Vec<Dual<MAX>> = x.iter().enumerate().map(|(i, &v)| Dual::var(v, i)).collect();
    let g = energy_gradient(rule, &xd, gamma, outward, ad, planes);
    std::array::from_fn(|i| g[i].d)
}

/// ∂²A/∂x² of the face: the gradient differentiated by duals (row-major, MAX × MAX).
fn area_hessian(rule: &Rule, x: &[f64]) -> [[f64; MAX]; MAX] {
    let xd: Vec<Dual<MAX>> = x.iter().enumerate().map(|(i, &v)| Dual::var(v, i)).collect();
    let g = area_gradient(rule, &xd);
    std::array::from_fn(|i| g[i].d)
}

/// The tension γ on this rank's faces of the boundary group, lowered to γ − w on the plates by
/// the work of adhesion w.
pub(crate) struct SurfaceTension {
    gamma: f64,
    adhesion: Option<Adhesion>,
    faces: Vec<u32>,
    /// Per face, +1 if its node order gives the outward normal, −1 if the inward (with adhesion).
    outward: Vec<f64>,
    rule: Rule,
}

impl SurfaceTension {
    /// `adhesion`: the work of adhesion to the plates (None or w = 0: none, the tension alone).
    pub(crate) fn new(gamma: f64, adhesion: Option<Adhesion>, mesh: &LocalMesh, faces: &[u32]) -> SurfaceTension {
        let adhesion = adhesion.filter(|a| a.work > 0.0);
        let mut st = SurfaceTension {
            gamma,
            adhesion,
            faces: faces.to_vec(),
            outward: Vec::new(),
            rule: Rule::new(mesh.family),
        };
        if st.adhesion.is_some() {
            st.outward = faces.iter().map(|&f| orientation(&st.rule, mesh, f)).collect();
        }
        st
    }

    /// The adhesion with the plates' planes, if both (without plates nothing adheres).
    fn adhering(&self, planes: Option<PlatePlanes>) -> Option<(Adhesion, PlatePlanes)> {
        self.adhesion.zip(planes)
    }

    /// Adds the energy's gradient to the residual `f` (local layout) at the displacement `u`:
    /// γ ∂A/∂x, or with adhesion ∂E/∂x with the plates at `planes` (the residual's time).
    pub(crate) fn add_residual(
        &self,
        mesh: &LocalMesh,
        dofs: &DofMap,
        u: &[f64],
        planes: Option<PlatePlanes>,
        f: &mut [f64],
    ) {
        let adhering = self.adhering(planes);
        for (i, &face) in self.faces.iter().enumerate() {
            let (idx, x, n) = face_state(&self.rule, mesh, dofs, face, u);
            match adhering {
                None => {
                    let g = area_gradient(&self.rule, &x[..n]);
                    for (k, &l) in idx[..n].iter().enumerate() {
                        f[l] += self.gamma * g[k];
                    }
                }
                Some((ad, pl)) => {
                    let g = energy_gradient(&self.rule, &x[..n], self.gamma, self.outward[i], ad, pl);
                    for (k, &l) in idx[..n].iter().enumerate() {
                        f[l] += g[k];
                    }
                }
            }
        }
    }

    /// The adhesion's pull on each plate, [lower, upper] (nN, this rank's faces; 0 without
    /// adhesion or plates): the plate's position enters the energy only through the gaps, so the
    /// force on a plate is −∂E/∂z_plate, of size Σ_q P_q w S'(g_q/g_a)/g_a over the points nearer
    /// it, towards the aggregate. The contact reactions miss it: it acts on faces within the
    /// range but off the plate.
    pub(crate) fn plate_pull(
        &self,
        mesh: &LocalMesh,
        dofs: &DofMap,
        u: &[f64],
        planes: Option<PlatePlanes>,
    ) -> [f64; 2] {
        let mut pull = [0.0; 2];
        let Some((ad, pl)) = self.adhering(planes) else { return pull };
        for (i, &face) in self.faces.iter().enumerate() {
            let (_, x, n) = face_state(&self.rule, mesh, dofs, face, u);
            for q in 0..self.rule.w.len() {
                let (gap, _, sigma) = point_gap(&self.rule, q, &x[..n], pl);
                let (p, _) = point_projection::<f64>(&self.rule, q, &x[..n], sigma, self.outward[i]);
                pull[usize::from(sigma < 0.0)] += p * weight(ad, gap).1;
            }
        }
        pull
    }

    /// Calls `add` with each face's local dofs and its block γ ∂²A/∂x² (with adhesion ∂²E/∂x²,
    /// the plates at `planes`), row-major.
    pub(crate) fn for_each_block(
        &self,
        mesh: &LocalMesh,
        dofs: &DofMap,
        u: &[f64],
        planes: Option<PlatePlanes>,
        mut add: impl FnMut(&[usize], &[f64]) -> crate::error::Result<()>,
    ) -> crate::error::Result<()> {
        let adhering = self.adhering(planes);
        for (i, &face) in self.faces.iter().enumerate() {
            let (idx, x, n) = face_state(&self.rule, mesh, dofs, face, u);
            let block: Vec<f64> = match adhering {
                None => {
                    let h = area_hessian(&self.rule, &x[..n]);
                    (0..n * n).map(|k| self.gamma * h[k / n][k % n]).collect()
                }
                Some((ad, pl)) => {
                    let h = energy_hessian(&self.rule, &x[..n], self.gamma, self.outward[i], ad, pl);
                    (0..n * n).map(|k| h[k / n][k % n]).collect()
                }
            };
            add(&idx[..n], &block)?;
        }
        Ok(())
    }
}

#[cfg(test)]
#[path = "surface_tension_tests.rs"]
pub(super) mod tests;
