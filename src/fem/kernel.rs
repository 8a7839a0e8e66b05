//! Element residual and Jacobian of the u–p weak form on one Taylor–Hood P2–P1 cell of either
//! family (`fem::cell`: the 10-node tetrahedron, the 6-node meridian triangle):
//!
//! ```text
//!   r_u[a,i] = ∫ (P : Grad(N_a e_i) − b_i N_a) dV     (a: P2 nodes, i: displacement component)
//!   r_p[m]   = ∫ (ṡ L_m + W · ∇L_m) dV                 (m: P1 vertices)
//! ```
//!
//! with Grad(N_a e_i) = e_i ⊗ ∇N_a, plus on the meridian the hoop entry N_a / R in θθ for the
//! radial component (so P_θθ enters the u_r rows), and dV = 2πR dR dZ there.
//!
//! plus the pressure stabilisation c_s ∫ (ṗ − Πṗ)(q − Πq) dV (Π: element mean; see
//! [`ElementKernel::stab`]) and the element block of the fixed-stress Schur approximation
//! Ŝ = ∫ ∇L_m · (∂W/∂Grad p) ∇L_n + (shift/K_dr) L_m L_n dV, which stays spectrally close to
//! the true Schur complement as Δt → 0 and as the conductivity → 0.
//! Element dofs in the layout of `fem::element` (u of node a, component c at NC a + c, then p of
//! vertex m at NU + m), arrays sized for the largest family (`MAX_DOF`).

use super::cell::{p1_gradients, CellShape};
use super::element::{ElementMatrix, Tabulation, MAX_DOF};
use super::equal_order;
use super::point::{PointFlux, PointModel, PointState, QpId, QpState};
use crate::error::Result;
use crate::material::idx;
use crate::reference_cell::shape::{MAX_NODES, MAX_VERTICES};
use nalgebra::{Matrix3, Vector3};
use std::marker::PhantomData;

/// θθ in the flattened index of a second-order tensor: where the hoop entries live.
const THETA: usize = idx(1, 1);

/// What the kernel needs of one element: its number in the mesh file (for messages), node
/// coordinates, nodal values, the step size and the committed qp state of its points.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ElementInput<'a> {
    pub(crate) elem: usize,
    pub(crate) coords: [[f64; 3]; MAX_NODES],
    pub(crate) values: ElementValues,
    pub(crate) dt: f64,
    pub(crate) qp_state: QpState<'a>,
}

/// Nodal values of one element: `u[a][c]` is component c of node a (its family's components).
#[derive(Debug, Clone, Copy)]
pub(crate) struct ElementValues {
    pub(crate) u: [[f64; 3]; MAX_NODES],
    pub(crate) udot: [[f64; 3]; MAX_NODES],
    pub(crate) p: [f64; MAX_VERTICES],
    pub(crate) pdot: [f64; MAX_VERTICES],
}

/// Kinematics at one quadrature point.
struct Point {
    w: f64,
    /// The point's share of the cell's own measure (no 2πR), for the stabilisation's h.
    w_cell: f64,
    n2: [f64; MAX_NODES],
    dn: [[f64; 3]; MAX_NODES],
    /// 1/R on the meridian, 0 in 3-D.
    inv_r: f64,
    n1: [f64; MAX_VERTICES],
    g1: [[f64; 3]; MAX_VERTICES],
    state: PointState,
}

impl Point {
    /// Σ_j T[(i, j)] ∂N_a/∂X_j (+ T_θθ N_a / R for the radial component on the meridian): a row
    /// of a tensor T (flattened with `idx`, `t(idx(i, j))`) tested with the virtual gradient of N_a e_i.
    #[inline]
    fn test<C: CellShape>(&self, a: usize, i: usize, t: impl Fn(usize) -> f64) -> f64 {
        let mut s = 0.0;
        for j in 0..3 {
            s += t(idx(i, j)) * self.dn[a][j];
        }
        if C::AXI && i == 0 {
            s += t(THETA) * self.n2[a] * self.inv_r;
        }
        s
    }
}

fn point<C: CellShape>(
    coords: &[[f64; 3]; MAX_NODES],
    tab: &Tabulation<MAX_NODES>,
    xi: &[f64; 3],
    q: usize,
    v: &ElementValues,
    dt: f64,
) -> Result<Point> {
    let geo = C::point(coords, tab, q)?;
    let dn = geo.dn;
    let g1 = p1_gradients::<C>(&dn);
    let n1 = C::p1_values(xi);
    let n2 = tab.n[q];
    let mut grad_u = Matrix3::zeros();
    let mut grad_udot = Matrix3::zeros();
    for a in 0..C::NN {
        for c in 0..C::NC {
            let i = C::AXES[c];
            for j in 0..3 {
                grad_u[(i, j)] += v.u[a][c] * dn[a][j];
                grad_udot[(i, j)] += v.udot[a][c] * dn[a][j];
            }
            if C::AXI && i == 0 {
                grad_u[(1, 1)] += v.u[a][c] * n2[a] * geo.inv_r;
                grad_udot[(1, 1)] += v.udot[a][c] * n2[a] * geo.inv_r;
            }
        }
    }
    let mut p = 0.0;
    let mut grad_p = Vector3::zeros();
    for m in 0..C::NV {
        p += n1[m] * v.p[m];
        for j in 0..3 {
            grad_p[j] += g1[m][j] * v.p[m];
        }
    }
    Ok(Point {
        w: geo.w,
        w_cell: geo.w_cell,
        n2,
        dn,
        inv_r: geo.inv_r,
        n1,
        g1,
        state: PointState { grad_u, grad_udot, p, grad_p, dt },
    })
}

/// What the element loops need besides the element itself, for cells of family `C`.
pub(crate) struct ElementKernel<'a, C: CellShape> {
    pub(crate) model: &'a dyn PointModel,
    pub(crate) tab: &'a Tabulation<MAX_NODES>,
    /// Reference coordinates of the quadrature points of `tab`.
    pub(crate) xi: &'a [[f64; 3]],
    /// c_s of the pressure stabilisation c_s ∫ (ṗ − Πṗ)(q − Πq) dV, Π the element mean.
    ///
    /// Why: in the undrained limit (Δt → 0) next to a drained boundary, Taylor–Hood is stable
    /// but not monotone. Tested with interior P1 functions, the mass balance then reduces to a
    /// P1 mass-matrix projection of a step, (1/E) M p = (P/E) M 1 with p = 0 on drained nodes
    /// (E = λ + 2µ), and the inverse mass matrix alternates in sign: the pressure overshoots
    /// next to the boundary (≈ 27% in 1-D, 69% measured on the 3-D column). With the term the
    /// matrix becomes (1 + c) M − c M_Π, and c = 4 makes it exactly the lumped (diagonal) P1
    /// mass on every tetrahedron: the undrained response is then monotone (p = 1 to 1e-13 at all
    /// interior vertices). The term is O(h²) since ṗ − Πṗ = O(h ∇ṗ), vanishes on constants
    /// (so it conserves fluid mass exactly element by element), and needs no mesh size. This is
    /// the local pressure projection of Dohrmann & Bochev (2004) used by White & Borja (2008)
    /// for poroelasticity, applied here to Taylor–Hood for monotonicity.
    pub(crate) stab: Stabilisation,
    /// Equal-order P1–P1: the displacement's mid-edge nodes tied to their edges' vertices
    /// (`fem::equal_order`; tetrahedra only).
    pub(crate) equal_order: bool,
    pub(crate) family: PhantomData<C>,
}

/// The pressure stabilisation of a run: c_s and how it fades.
///
/// Why fade: the term is needed for the undrained jump a step makes where its drainage layer,
/// of width √(c_v Δt), is thinner than an element; it costs accuracy everywhere else (an
/// artificial storage of the sub-element pressure modes: Cryer's centre-pressure peak 2.2% low on
/// its default mesh with the constant term, 0.4% without it). Where the whole loading is
/// undrained at the element's scale (c_v t_load / h² ≪ 1: a soft or a large aggregate), that
/// storage is a fixed compliance of the elements at drained boundaries, and the plate force is
/// low by it in proportion to the part of the load taken while the term acts (3.2% of the peak
/// of a soft aggregate that kept it through its ramp). So the weight is c_s (1 − r²)₊ with r
/// the larger of τ/τ₀, τ = c_v Δt / h² (the step resolves the drainage), and
/// (Δt/Δt₀ − 1)/(s − 1) (the steps have grown since the kink, where the schedule restarts them
/// at Δt₀): full weight at the first step after each kink, gone once the steps are s times
/// longer, whatever c_v. Quadratic, so that at Δt → 0 it stays the exact lumping
/// (a linear fade let the undrained first step overshoot by 5e-6).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Stabilisation {
    /// c_s = c / (λ + 2µ) as Δt → 0 (0: off).
    pub(crate) c_s: f64,
    /// How the weight fades (None: constant weight).
    pub(crate) fade: Option<Fade>,
    /// The consolidation coefficient c_v = k (λ + 2µ) of the reference state (µm²/s).
    pub(crate) c_v: f64,
}

/// The fade of the stabilisation: by the step's drainage (τ₀) and by the steps' growth since a
/// kink (Δt₀, the first step after one; gone at Δt = `steps` Δt₀).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Fade {
    /// τ₀: gone from c_v Δt / h² = τ₀ on.
    pub(crate) tau0: f64,
    /// Δt₀: the schedule's first step after a kink (`time.dt`).
    pub(crate) dt0: f64,
    /// The growth Δt/Δt₀ at which it is gone (`fem.stabilisation_steps`, default `STEP_FADE`).
    pub(crate) steps: f64,
}

/// The default growth of the steps since a kink, Δt/Δt₀, at which the faded weight is gone:
/// 8 keeps it through the first eight to ten steps of the shipped growth (1.25–1.3). A soft
/// aggregate's peak then costs it 0.02% (the fade by drainage alone: 2.8%); with 4 PETSc's
/// reduced-space VI Newton had to cut a step early in a hold that it takes whole with 8
/// (docs/decisions/0012-stabilisation-fade-by-steps.md).
pub(crate) const STEP_FADE: f64 = 8.0;

impl Stabilisation {
    /// c (the weight as Δt → 0, relative to the model's P-wave modulus) and the fade (None:
    /// constant), with the model's reference consolidation coefficient.
    pub(crate) fn new(c: f64, fade: Option<Fade>, model: &dyn PointModel) -> Stabilisation {
        let m = model.p_wave_modulus();
        Stabilisation { c_s: c / m, fade, c_v: model.conductivity() * m }
    }

    /// The weight for a cell of (reference) measure `m` in a step of `dt`; h is the edge of the
    /// regular cell of that volume (or area, on the meridian).
    pub(crate) fn weight<C: CellShape>(&self, m: f64, dt: f64) -> f64 {
        match self.fade {
            Some(Fade { tau0, dt0, steps }) if dt > 0.0 => {
                let drained = self.c_v * dt / (C::h2(m) * tau0);
                let grown = (dt / dt0 - 1.0) / (steps - 1.0);
                let r = drained.max(grown);
                self.c_s * (1.0 - r * r).max(0.0)
            }
            _ => self.c_s,
        }
    }
}

/// Element integrals of the projection stabilisation: volume, ∫ L_m, ∫ L_m L_n, ∫ ṗ, ∫ ṗ L_m,
/// and the cell's own measure (volume, or area on the meridian) for its size.
#[derive(Default)]
struct Projection {
    vol: f64,
    measure: f64,
    m: [f64; MAX_VERTICES],
    mm: [[f64; MAX_VERTICES]; MAX_VERTICES],
    ip: f64,
    ipl: [f64; MAX_VERTICES],
}

impl Projection {
    fn add<C: CellShape>(&mut self, pt: &Point, pdot: &[f64; MAX_VERTICES]) {
        let pd: f64 = (0..C::NV).map(|i| pt.n1[i] * pdot[i]).sum();
        self.vol += pt.w;
        self.measure += pt.w_cell;
        self.ip += pt.w * pd;
        for i in 0..C::NV {
            self.m[i] += pt.w * pt.n1[i];
            self.ipl[i] += pt.w * pd * pt.n1[i];
            for j in 0..C::NV {
                self.mm[i][j] += pt.w * pt.n1[i] * pt.n1[j];
            }
        }
    }
    /// c ∫ (ṗ − Πṗ) L_m = c (∫ ṗ L_m − ∫ ṗ ∫ L_m / V)
    fn residual<C: CellShape>(&self, c: f64, r: &mut [f64; MAX_DOF]) {
        for i in 0..C::NV {
            r[C::NU + i] += c * (self.ipl[i] - self.ip * self.m[i] / self.vol);
        }
    }
    /// c shift (∫ L_m L_n − ∫ L_m ∫ L_n / V), into the Jacobian and the Schur block.
    fn jacobian<C: CellShape>(
        &self,
        c: f64,
        shift: f64,
        k: &mut ElementMatrix,
        schur: &mut [[f64; MAX_VERTICES]; MAX_VERTICES],
    ) {
        for i in 0..C::NV {
            for j in 0..C::NV {
                let s = c * shift * (self.mm[i][j] - self.m[i] * self.m[j] / self.vol);
                k[C::NU + i][C::NU + j] += s;
                schur[i][j] += s;
            }
        }
    }
}

/// Post-processing of one element: nodal forces of the total stress and of its pressure part,
/// the raw mass residual, and element averages of the output fields.
pub(crate) struct ElementPost {
    /// The element residual (u rows: internal minus body force; p rows: mass balance).
    pub(crate) r: [f64; MAX_DOF],
    /// u rows of the pressure part alone, ∫ P_p : Grad w (P_p = −p J F⁻ᵀ).
    pub(crate) r_pressure: [f64; MAX_DOF],
    /// ∫ dV and ∫ J dV over the element (reference volume, current volume).
    pub(crate) volume: f64,
    pub(crate) volume_j: f64,
    /// Element averages: J, porosity, von Mises, spatial Darcy flux, ‖E_p‖.
    pub(crate) j: f64,
    pub(crate) porosity: f64,
    pub(crate) von_mises: f64,
    pub(crate) darcy: [f64; 3],
    pub(crate) norm_ep: f64,
    /// ∫ σ_sc dV over the element (solid Cauchy stress, reference volume).
    pub(crate) int_cauchy: [[f64; 3]; 3],
    /// Largest von Mises stress, ‖E_p‖ and |det B_p − 1| at the element's points.
    pub(crate) max_von_mises: f64,
    pub(crate) max_norm_ep: f64,
    pub(crate) max_det_bp_dev: f64,
}

impl<C: CellShape> ElementKernel<'_, C> {
    /// The qp state of point q out of the element's slice.
    #[inline]
    fn at_point<'h>(&self, h: QpState<'h>, q: usize) -> QpState<'h> {
        let n = self.model.qp_state_len();
        QpState { committed: &h.committed[q * n..(q + 1) * n], evolve: h.evolve }
    }

    /// Runs `body` at every quadrature point of the element with its kinematics and qp state.
    #[inline]
    fn for_points<'h>(
        &self,
        e: &ElementInput<'h>,
        mut body: impl FnMut(QpId, &Point, QpState<'h>) -> Result<()>,
    ) -> Result<()> {
        for q in 0..self.tab.weights.len() {
            let pt = point::<C>(&e.coords, self.tab, &self.xi[q], q, &e.values, e.dt)?;
            body(QpId { elem: e.elem, point: q }, &pt, self.at_point(e.qp_state, q))?;
        }
        Ok(())
    }

    /// The residual terms of one point into `r`, and its share of the projection integrals.
    #[inline]
    fn add_point_residual(
        &self,
        at: QpId,
        pt: &Point,
        h: QpState,
        pdot: &[f64; MAX_VERTICES],
        r: &mut [f64; MAX_DOF],
        proj: &mut Projection,
    ) -> Result<()> {
        let f = self.model.eval(at, &pt.state, h)?;
        add_residual::<C>(pt, &f, r);
        proj.add::<C>(pt, pdot);
        Ok(())
    }

    /// The tie rows' scale for an element of volume `vol`: P-wave modulus × size.
    fn tie_stiffness(&self, vol: f64) -> f64 {
        self.model.p_wave_modulus() * vol.cbrt()
    }
}

/// The element operations of a kernel, whatever its cell family: what the one element loop
/// (`fem::assembly`) calls.
pub(crate) trait CellKernel {
    fn residual(&self, e: &ElementInput, r: &mut [f64; MAX_DOF]) -> Result<()>;
    fn jacobian(
        &self,
        e: &ElementInput,
        shift: f64,
        k: &mut ElementMatrix,
        schur: &mut [[f64; MAX_VERTICES]; MAX_VERTICES],
    ) -> Result<()>;
    fn post(&self, e: &ElementInput) -> Result<ElementPost>;
    fn advance_qp_state(&self, e: &ElementInput, out: &mut [f64]) -> Result<()>;
    fn min_j(&self, e: &ElementInput) -> Result<f64>;
}

impl<C: CellShape> CellKernel for ElementKernel<'_, C> {
    /// Residual, its pressure part and averaged fields of one element.
    fn post(&self, e: &ElementInput) -> Result<ElementPost> {
        let mut out = ElementPost {
            r: [0.0; MAX_DOF],
            r_pressure: [0.0; MAX_DOF],
            volume: 0.0,
            volume_j: 0.0,
            j: 0.0,
            porosity: 0.0,
            von_mises: 0.0,
            darcy: [0.0; 3],
            norm_ep: 0.0,
            int_cauchy: [[0.0; 3]; 3],
            max_von_mises: 0.0,
            max_norm_ep: 0.0,
            max_det_bp_dev: 0.0,
        };
        let mut proj = Projection::default();
        self.for_points(e, |at, pt, hq| {
            self.add_point_residual(at, pt, hq, &e.values.pdot, &mut out.r, &mut proj)?;
            let pf = self.model.fields(at, &pt.state, hq)?;
            let ps = |k: usize| pf.pressure_stress[(k / 3, k % 3)];
            for a in 0..C::NN {
                for c in 0..C::NC {
                    out.r_pressure[C::NC * a + c] += pt.w * pt.test::<C>(a, C::AXES[c], ps);
                }
            }
            out.volume += pt.w;
            out.volume_j += pt.w * pf.j;
            out.j += pt.w * pf.j;
            out.porosity += pt.w * pf.porosity;
            out.von_mises += pt.w * pf.von_mises;
            out.norm_ep += pt.w * pf.norm_ep;
            for d in 0..3 {
                out.darcy[d] += pt.w * pf.darcy[d];
                for e in 0..3 {
                    out.int_cauchy[d][e] += pt.w * pf.cauchy_sc[(d, e)];
                }
            }
            out.max_von_mises = out.max_von_mises.max(pf.von_mises);
            out.max_norm_ep = out.max_norm_ep.max(pf.norm_ep);
            out.max_det_bp_dev = out.max_det_bp_dev.max(pf.det_bp_dev);
            Ok(())
        })?;
        if self.stab.c_s > 0.0 {
            proj.residual::<C>(self.stab.weight::<C>(proj.measure, e.dt), &mut out.r);
        }
        // Equal order: the nodal forces of the P1 rows, as the residual has them (the reaction
        // of a contact vertex includes what its edges' tie rows move to it).
        if self.equal_order {
            equal_order::tie_residual(&mut out.r, &e.values.u, self.tie_stiffness(proj.measure));
            equal_order::fold_forces(&mut out.r_pressure);
        }
        let v = out.volume;
        out.j /= v;
        out.porosity /= v;
        out.von_mises /= v;
        out.norm_ep /= v;
        out.darcy.iter_mut().for_each(|x| *x /= v);
        Ok(out)
    }

    /// The end-of-step qp state of every point of the element (the model's update at the
    /// converged state), into `out` (the element's slice of the store).
    fn advance_qp_state(&self, e: &ElementInput, out: &mut [f64]) -> Result<()> {
        let n = self.model.qp_state_len();
        self.for_points(e, |at, pt, hq| {
            self.model.advance_qp_state(at, &pt.state, hq, &mut out[at.point * n..(at.point + 1) * n])
        })
    }

    /// The smallest J = det F over the element's points (kinematics only, no material law).
    fn min_j(&self, e: &ElementInput) -> Result<f64> {
        let mut m = f64::INFINITY;
        self.for_points(e, |_, pt, _| {
            m = m.min((Matrix3::identity() + pt.state.grad_u).determinant());
            Ok(())
        })?;
        Ok(m)
    }

    /// The element residual into `r` (zero on entry).
    fn residual(&self, e: &ElementInput, r: &mut [f64; MAX_DOF]) -> Result<()> {
        let mut proj = Projection::default();
        self.for_points(e, |at, pt, hq| self.add_point_residual(at, pt, hq, &e.values.pdot, r, &mut proj))?;
        if self.stab.c_s > 0.0 {
            proj.residual::<C>(self.stab.weight::<C>(proj.measure, e.dt), r);
        }
        if self.equal_order {
            equal_order::tie_residual(r, &e.values.u, self.tie_stiffness(proj.measure));
        }
        Ok(())
    }

    /// The element Jacobian (row-major NDOF × NDOF) and Schur block into `k` and `schur` (zero
    /// on entry).
    fn jacobian(
        &self,
        e: &ElementInput,
        shift: f64,
        k: &mut ElementMatrix,
        schur: &mut [[f64; MAX_VERTICES]; MAX_VERTICES],
    ) -> Result<()> {
        let mut proj = Projection::default();
        let inv_kdr = 1.0 / self.model.drained_bulk_modulus();
        self.for_points(e, |at, pt, hq| {
            let (_, t) = self.model.eval_tangent(at, &pt.state, hq, shift)?;
            proj.add::<C>(pt, &e.values.pdot);
            let w = pt.w;
            let dn = &pt.dn;
            // Column (b, kk) is the trial gradient e_k ⊗ ∇N_b (+ N_b / R in θθ for k = r):
            // T_b[(ij), kk] = Σ_l A[(ij),(kl)] ∂N_b/∂X_l (+ A[(ij),θθ] N_b / R), then
            // K_ab[i][kk] = Σ_j ∂N_a/∂X_j T_b[(ij), kk] (+ N_a / R T_b[θθ, kk] for i = r).
            for b in 0..C::NN {
                let hoop_b = pt.n2[b] * pt.inv_r;
                let mut tb = [[0.0; 3]; 9];
                let mut bb = [[0.0; 3]; 3]; // ∂b_i/∂F : trial gradient
                let mut rb = [0.0; 3]; // ∂ṡ/∂F : trial gradient
                let mut wb = [[0.0; 3]; 3]; // ∂W_j/∂F : trial gradient
                for kk in 0..C::NC {
                    let k_ax = C::AXES[kk];
                    for l in 0..3 {
                        let d = dn[b][l];
                        for row in 0..9 {
                            tb[row][kk] += t.dstress_du[(row, idx(k_ax, l))] * d;
                        }
                        for i in 0..3 {
                            bb[i][kk] += t.dbody_du[(i, idx(k_ax, l))] * d;
                            wb[i][kk] += t.dflux_du[(i, idx(k_ax, l))] * d;
                        }
                        rb[kk] += t.drate_du[(k_ax, l)] * d;
                    }
                    if C::AXI && k_ax == 0 {
                        for row in 0..9 {
                            tb[row][kk] += t.dstress_du[(row, THETA)] * hoop_b;
                        }
                        for i in 0..3 {
                            bb[i][kk] += t.dbody_du[(i, THETA)] * hoop_b;
                            wb[i][kk] += t.dflux_du[(i, THETA)] * hoop_b;
                        }
                        rb[kk] += t.drate_du[(1, 1)] * hoop_b;
                    }
                }
                for a in 0..C::NN {
                    for c in 0..C::NC {
                        let i = C::AXES[c];
                        let row = &mut k[C::NC * a + c];
                        for kk in 0..C::NC {
                            let s = pt.test::<C>(a, i, |x| tb[x][kk]) - pt.n2[a] * bb[i][kk];
                            row[C::NC * b + kk] += w * s;
                        }
                    }
                }
                for m in 0..C::NV {
                    for kk in 0..C::NC {
                        let mut s = pt.n1[m] * rb[kk];
                        for j in 0..3 {
                            s += pt.g1[m][j] * wb[j][kk];
                        }
                        k[C::NU + m][C::NC * b + kk] += w * s;
                    }
                }
            }
            for a in 0..C::NN {
                for c in 0..C::NC {
                    let cp = pt.test::<C>(a, C::AXES[c], |x| t.dstress_dp[(x / 3, x % 3)]);
                    for m in 0..C::NV {
                        k[C::NC * a + c][C::NU + m] += w * cp * pt.n1[m];
                    }
                }
            }
            for m in 0..C::NV {
                let km = t.dflux_dgradp.transpose() * Vector3::from(pt.g1[m]);
                for n in 0..C::NV {
                    let mut s = 0.0;
                    for j in 0..3 {
                        s += km[j] * pt.g1[n][j];
                    }
                    k[C::NU + m][C::NU + n] += w * s;
                    schur[m][n] += w * (s + shift * inv_kdr * pt.n1[m] * pt.n1[n]);
                }
            }
            Ok(())
        })?;
        if self.stab.c_s > 0.0 {
            proj.jacobian::<C>(self.stab.weight::<C>(proj.measure, e.dt), shift, k, schur);
        }
        if self.equal_order {
            equal_order::tie_jacobian(k, self.tie_stiffness(proj.measure));
        }
        Ok(())
    }
}

/// Adds the pointwise terms of one quadrature point to the element residual.
fn add_residual<C: CellShape>(pt: &Point, f: &PointFlux, r: &mut [f64; MAX_DOF]) {
    let w = pt.w;
    for a in 0..C::NN {
        for c in 0..C::NC {
            let i = C::AXES[c];
            let s = pt.test::<C>(a, i, |k| f.stress[(k / 3, k % 3)]) - f.body[i] * pt.n2[a];
            r[C::NC * a + c] += w * s;
        }
    }
    for m in 0..C::NV {
        let mut s = f.rate * pt.n1[m];
        for j in 0..3 {
            s += f.flux[j] * pt.g1[m][j];
        }
        r[C::NU + m] += w * s;
    }
}
