//! Element residual and Jacobian of the u–p weak form on one Taylor–Hood P2–P1 tetrahedron:
//!
//! ```text
//!   r_u[a,i] = ∫ (P_ij ∂N_a/∂X_j − b_i N_a) dV        (a: 10 P2 nodes, i: component)
//!   r_p[m]   = ∫ (ṡ L_m + W · ∇L_m) dV                 (m: 4 P1 vertices)
//! ```
//!
//! plus the pressure stabilisation c_s ∫ (ṗ − Πṗ)(q − Πq) dV (Π: element mean; see
//! [`ElementKernel::stab`]) and the element block of the fixed-stress Schur approximation
//! Ŝ = ∫ ∇L_m · (∂W/∂Grad p) ∇L_n + (shift/K_dr) L_m L_n dV, which stays spectrally close to
//! the true Schur complement as Δt → 0 and as the conductivity → 0.
//! Element dof order: u of node a, component i at 3a + i (0..30), then p of vertex m at 30 + m.

use super::element::{tet10_geometry, Tabulation, TET10_EDGES};
use super::equal_order;
use super::point::{ij, History, PointFlux, PointModel, PointState, QpId};
use crate::error::Result;
use nalgebra::{Matrix3, Vector3};

pub const NU: usize = 30;
pub const NDOF: usize = 34;

/// What the kernel needs of one element: its number (for messages), node coordinates, nodal
/// values, the step size and the committed history of its points.
#[derive(Debug, Clone, Copy)]
pub struct ElementInput<'a> {
    pub elem: usize,
    pub coords: [[f64; 3]; 10],
    pub values: ElementValues,
    pub dt: f64,
    pub history: History<'a>,
}

/// Nodal values of one element.
#[derive(Debug, Clone, Copy)]
pub struct ElementValues {
    pub u: [[f64; 3]; 10],
    pub udot: [[f64; 3]; 10],
    pub p: [f64; 4],
    pub pdot: [f64; 4],
}

/// Physical gradients of the P1 (vertex) functions, exact on curved elements: the vertex
/// function L_m equals N_m + ½ Σ N_mid over the mid-edge nodes of edges touching m, in
/// reference coordinates, so its gradient follows from the P2 gradients.
#[inline]
pub fn p1_gradients(dn: &[[f64; 3]; 10]) -> [[f64; 3]; 4] {
    let mut g = [[0.0; 3]; 4];
    for (m, gm) in g.iter_mut().enumerate() {
        *gm = dn[m];
    }
    for (e, &(a, b)) in TET10_EDGES.iter().enumerate() {
        for d in 0..3 {
            g[a][d] += 0.5 * dn[4 + e][d];
            g[b][d] += 0.5 * dn[4 + e][d];
        }
    }
    g
}

/// P1 values at a reference point: barycentric coordinates.
#[inline]
pub fn p1_values(xi: &[f64; 3]) -> [f64; 4] {
    [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]]
}

/// Kinematics at one quadrature point.
struct Point {
    w: f64,
    n2: [f64; 10],
    dn: [[f64; 3]; 10],
    n1: [f64; 4],
    g1: [[f64; 3]; 4],
    state: PointState,
}

fn point(
    coords: &[[f64; 3]; 10],
    tab: &Tabulation<10>,
    xi: &[f64; 3],
    q: usize,
    v: &ElementValues,
    dt: f64,
) -> Result<Point> {
    let geo = tet10_geometry(coords, tab, q)?;
    let dn = geo.dn_dx;
    let g1 = p1_gradients(&dn);
    let n1 = p1_values(xi);
    let mut grad_u = Matrix3::zeros();
    let mut grad_udot = Matrix3::zeros();
    for a in 0..10 {
        for i in 0..3 {
            for j in 0..3 {
                grad_u[(i, j)] += v.u[a][i] * dn[a][j];
                grad_udot[(i, j)] += v.udot[a][i] * dn[a][j];
            }
        }
    }
    let mut p = 0.0;
    let mut grad_p = Vector3::zeros();
    for m in 0..4 {
        p += n1[m] * v.p[m];
        for j in 0..3 {
            grad_p[j] += g1[m][j] * v.p[m];
        }
    }
    Ok(Point {
        w: tab.weights[q] * geo.jac_det,
        n2: tab.n[q],
        dn,
        n1,
        g1,
        state: PointState { grad_u, grad_udot, p, grad_p, dt },
    })
}

/// What the element loops need besides the element itself.
pub struct ElementKernel<'a> {
    pub model: &'a dyn PointModel,
    pub tab: &'a Tabulation<10>,
    /// Reference coordinates of the quadrature points of `tab`.
    pub xi: &'a [[f64; 3]],
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
    pub stab: Stabilisation,
    /// Equal-order P1–P1: the displacement's mid-edge nodes tied to their edges' vertices
    /// (`fem::equal_order`).
    pub equal_order: bool,
}

/// The pressure stabilisation of a run: c_s and how it fades once a step resolves the drainage.
///
/// Why fade: the term is needed where a step's drainage layer, of width √(c_v Δt), is thinner
/// than an element; it costs accuracy everywhere else (an artificial storage of the sub-element
/// pressure modes: Cryer's centre-pressure peak 2.2% low on its default mesh with the constant
/// term, 0.4% without it). The weight is c_s (1 − (τ/τ₀)²)₊, τ = c_v Δt / h²: quadratic, so that
/// at Δt → 0 it stays the exact lumping (a linear fade let the undrained first step overshoot
/// by 5e-6).
#[derive(Clone, Copy, Debug)]
pub struct Stabilisation {
    /// c_s = c / (λ + 2µ) as Δt → 0 (0: off).
    pub c_s: f64,
    /// τ₀ of the fade (None: constant weight).
    pub fade: Option<f64>,
    /// The consolidation coefficient c_v = k (λ + 2µ) of the reference state (µm²/s).
    pub c_v: f64,
}

impl Stabilisation {
    /// c (the weight as Δt → 0, relative to the model's P-wave modulus) and the fade τ₀ (None:
    /// constant), with the model's reference consolidation coefficient.
    pub fn new(c: f64, fade: Option<f64>, model: &dyn PointModel) -> Stabilisation {
        let m = model.p_wave_modulus();
        Stabilisation { c_s: c / m, fade, c_v: model.conductivity() * m }
    }

    /// The weight for an element of (reference) volume `vol` in a step of `dt`; h is the edge of
    /// the regular tetrahedron of that volume.
    pub fn weight(&self, vol: f64, dt: f64) -> f64 {
        match self.fade {
            Some(tau0) if dt > 0.0 => {
                let h2 = (6.0 * std::f64::consts::SQRT_2 * vol).powf(2.0 / 3.0);
                let r = self.c_v * dt / (h2 * tau0);
                self.c_s * (1.0 - r * r).max(0.0)
            }
            _ => self.c_s,
        }
    }
}

/// Element integrals of the projection stabilisation: volume, ∫ L_m, ∫ L_m L_n, ∫ ṗ, ∫ ṗ L_m.
#[derive(Default)]
struct Projection {
    vol: f64,
    m: [f64; 4],
    mm: [[f64; 4]; 4],
    ip: f64,
    ipl: [f64; 4],
}

impl Projection {
    fn add(&mut self, pt: &Point, pdot: &[f64; 4]) {
        let pd: f64 = (0..4).map(|i| pt.n1[i] * pdot[i]).sum();
        self.vol += pt.w;
        self.ip += pt.w * pd;
        for i in 0..4 {
            self.m[i] += pt.w * pt.n1[i];
            self.ipl[i] += pt.w * pd * pt.n1[i];
            for j in 0..4 {
                self.mm[i][j] += pt.w * pt.n1[i] * pt.n1[j];
            }
        }
    }
    /// c ∫ (ṗ − Πṗ) L_m = c (∫ ṗ L_m − ∫ ṗ ∫ L_m / V)
    fn residual(&self, c: f64, r: &mut [f64; NDOF]) {
        for i in 0..4 {
            r[NU + i] += c * (self.ipl[i] - self.ip * self.m[i] / self.vol);
        }
    }
    /// c shift (∫ L_m L_n − ∫ L_m ∫ L_n / V), into the Jacobian and the Schur block.
    fn jacobian(&self, c: f64, shift: f64, k: &mut [[f64; NDOF]; NDOF], schur: &mut [[f64; 4]; 4]) {
        for i in 0..4 {
            for j in 0..4 {
                let s = c * shift * (self.mm[i][j] - self.m[i] * self.m[j] / self.vol);
                k[NU + i][NU + j] += s;
                schur[i][j] += s;
            }
        }
    }
}

/// Post-processing of one element: nodal forces of the total stress and of its pressure part,
/// the raw mass residual, and element averages of the output fields.
pub struct ElementPost {
    /// The element residual (u rows: internal minus body force; p rows: mass balance).
    pub r: [f64; NDOF],
    /// u rows of the pressure part alone, ∫ P_p : Grad w (P_p = −p J F⁻ᵀ).
    pub r_pressure: [f64; NU],
    /// ∫ dV and ∫ J dV over the element (reference volume, current volume).
    pub volume: f64,
    pub volume_j: f64,
    /// Element averages: J, porosity, von Mises, spatial Darcy flux, ‖E_p‖.
    pub j: f64,
    pub porosity: f64,
    pub von_mises: f64,
    pub darcy: [f64; 3],
    pub norm_ep: f64,
    /// ∫ σ_sc dV over the element (solid Cauchy stress, reference volume).
    pub int_cauchy: [[f64; 3]; 3],
    /// Largest von Mises stress, ‖E_p‖ and |det B_p − 1| at the element's points.
    pub max_von_mises: f64,
    pub max_norm_ep: f64,
    pub max_det_bp_dev: f64,
}

impl ElementKernel<'_> {
    /// The history of point q out of the element's slice.
    #[inline]
    fn at_point<'h>(&self, h: History<'h>, q: usize) -> History<'h> {
        let n = self.model.history_len();
        History { committed: &h.committed[q * n..(q + 1) * n], evolve: h.evolve }
    }

    /// Runs `body` at every quadrature point of the element with its kinematics and history.
    #[inline]
    fn for_points<'h>(
        &self,
        e: &ElementInput<'h>,
        mut body: impl FnMut(QpId, &Point, History<'h>) -> Result<()>,
    ) -> Result<()> {
        for q in 0..self.tab.weights.len() {
            let pt = point(&e.coords, self.tab, &self.xi[q], q, &e.values, e.dt)?;
            body(QpId { elem: e.elem, point: q }, &pt, self.at_point(e.history, q))?;
        }
        Ok(())
    }

    /// The residual terms of one point into `r`, and its share of the projection integrals.
    #[inline]
    fn add_point_residual(
        &self,
        at: QpId,
        pt: &Point,
        h: History,
        pdot: &[f64; 4],
        r: &mut [f64; NDOF],
        proj: &mut Projection,
    ) -> Result<()> {
        let f = self.model.eval(at, &pt.state, h)?;
        add_residual(pt, &f, r);
        proj.add(pt, pdot);
        Ok(())
    }

    /// Residual, its pressure part and averaged fields of one element.
    pub fn post(&self, e: &ElementInput) -> Result<ElementPost> {
        let mut out = ElementPost {
            r: [0.0; NDOF],
            r_pressure: [0.0; NU],
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
            for a in 0..10 {
                for i in 0..3 {
                    out.r_pressure[3 * a + i] +=
                        pt.w * (0..3).map(|j| pf.pressure_stress[(i, j)] * pt.dn[a][j]).sum::<f64>();
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
            proj.residual(self.stab.weight(proj.vol, e.dt), &mut out.r);
        }
        let v = out.volume;
        out.j /= v;
        out.porosity /= v;
        out.von_mises /= v;
        out.norm_ep /= v;
        out.darcy.iter_mut().for_each(|x| *x /= v);
        Ok(out)
    }

    /// The end-of-step history of every point of the element (the model's update at the
    /// converged state), into `out` (the element's slice of the store).
    pub fn advance_history(&self, e: &ElementInput, out: &mut [f64]) -> Result<()> {
        let n = self.model.history_len();
        self.for_points(e, |at, pt, hq| {
            self.model.advance_history(at, &pt.state, hq, &mut out[at.point * n..(at.point + 1) * n])
        })
    }

    /// The smallest J = det F over the element's points (kinematics only, no material law).
    pub fn min_j(&self, e: &ElementInput) -> Result<f64> {
        let mut m = f64::INFINITY;
        self.for_points(e, |_, pt, _| {
            m = m.min((Matrix3::identity() + pt.state.grad_u).determinant());
            Ok(())
        })?;
        Ok(m)
    }

    /// The element residual into `r` (zero on entry).
    pub fn residual(&self, e: &ElementInput, r: &mut [f64; NDOF]) -> Result<()> {
        let mut proj = Projection::default();
        self.for_points(e, |at, pt, hq| self.add_point_residual(at, pt, hq, &e.values.pdot, r, &mut proj))?;
        if self.stab.c_s > 0.0 {
            proj.residual(self.stab.weight(proj.vol, e.dt), r);
        }
        if self.equal_order {
            equal_order::tie_residual(r, &e.values.u, self.tie_stiffness(proj.vol));
        }
        Ok(())
    }

    /// The tie rows' scale for an element of volume `vol`: P-wave modulus × size.
    fn tie_stiffness(&self, vol: f64) -> f64 {
        self.model.p_wave_modulus() * vol.cbrt()
    }

    /// The element residual, Jacobian (row-major NDOF × NDOF) and Schur block into `r`, `k` and
    /// `schur` (zero on entry).
    pub fn jacobian(
        &self,
        e: &ElementInput,
        shift: f64,
        r: &mut [f64; NDOF],
        k: &mut [[f64; NDOF]; NDOF],
        schur: &mut [[f64; 4]; 4],
    ) -> Result<()> {
        let mut proj = Projection::default();
        let inv_kdr = 1.0 / self.model.drained_bulk_modulus();
        self.for_points(e, |at, pt, hq| {
            let (f, t) = self.model.eval_tangent(at, &pt.state, hq, shift)?;
            add_residual(pt, &f, r);
            proj.add(pt, &e.values.pdot);
            let w = pt.w;
            let dn = &pt.dn;
            // T_b[(ij), k] = Σ_l A[(ij),(kl)] ∂N_b/∂X_l, then K_ab[i][k] = Σ_j ∂N_a/∂X_j T_b[(ij), k].
            for b in 0..10 {
                let mut tb = [[0.0; 3]; 9];
                let mut bb = [[0.0; 3]; 3]; // Σ_l ∂b_i/∂F_kl ∂N_b/∂X_l
                let mut rb = [0.0; 3]; // Σ_l ∂ṡ/∂F_kl ∂N_b/∂X_l
                let mut wb = [[0.0; 3]; 3]; // Σ_l ∂W_j/∂F_kl ∂N_b/∂X_l
                for kk in 0..3 {
                    for l in 0..3 {
                        let d = dn[b][l];
                        for row in 0..9 {
                            tb[row][kk] += t.dstress_du[(row, ij(kk, l))] * d;
                        }
                        for i in 0..3 {
                            bb[i][kk] += t.dbody_du[(i, ij(kk, l))] * d;
                            wb[i][kk] += t.dflux_du[(i, ij(kk, l))] * d;
                        }
                        rb[kk] += t.drate_du[(kk, l)] * d;
                    }
                }
                for a in 0..10 {
                    for i in 0..3 {
                        let row = &mut k[3 * a + i];
                        for kk in 0..3 {
                            let mut s = -pt.n2[a] * bb[i][kk];
                            for j in 0..3 {
                                s += dn[a][j] * tb[ij(i, j)][kk];
                            }
                            row[3 * b + kk] += w * s;
                        }
                    }
                }
                for m in 0..4 {
                    for kk in 0..3 {
                        let mut s = pt.n1[m] * rb[kk];
                        for j in 0..3 {
                            s += pt.g1[m][j] * wb[j][kk];
                        }
                        k[NU + m][3 * b + kk] += w * s;
                    }
                }
            }
            for a in 0..10 {
                for i in 0..3 {
                    let mut c = 0.0;
                    for j in 0..3 {
                        c += dn[a][j] * t.dstress_dp[(i, j)];
                    }
                    for m in 0..4 {
                        k[3 * a + i][NU + m] += w * c * pt.n1[m];
                    }
                }
            }
            for m in 0..4 {
                let km = t.dflux_dgradp.transpose() * Vector3::from(pt.g1[m]);
                for n in 0..4 {
                    let mut s = 0.0;
                    for j in 0..3 {
                        s += km[j] * pt.g1[n][j];
                    }
                    k[NU + m][NU + n] += w * s;
                    schur[m][n] += w * (s + shift * inv_kdr * pt.n1[m] * pt.n1[n]);
                }
            }
            Ok(())
        })?;
        if self.stab.c_s > 0.0 {
            proj.jacobian(self.stab.weight(proj.vol, e.dt), shift, k, schur);
        }
        if self.equal_order {
            let s = self.tie_stiffness(proj.vol);
            equal_order::tie_residual(r, &e.values.u, s);
            equal_order::tie_jacobian(k, s);
        }
        Ok(())
    }
}

/// Adds the pointwise terms of one quadrature point to the element residual.
fn add_residual(pt: &Point, f: &PointFlux, r: &mut [f64; NDOF]) {
    let w = pt.w;
    for a in 0..10 {
        for i in 0..3 {
            let mut s = -f.body[i] * pt.n2[a];
            for j in 0..3 {
                s += f.stress[(i, j)] * pt.dn[a][j];
            }
            r[3 * a + i] += w * s;
        }
    }
    for m in 0..4 {
        let mut s = f.rate * pt.n1[m];
        for j in 0..3 {
            s += f.flux[j] * pt.g1[m][j];
        }
        r[NU + m] += w * s;
    }
}
