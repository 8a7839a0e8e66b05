//! Finite-strain biphasic mixture (incompressible solid and fluid), total-Lagrangian u–p form
//! (model.md §2–§3). Per unit reference volume, with F = I + Grad u, J = det F, cof F = J F⁻ᵀ:
//!
//! ```text
//!   P = P_sc(F, B_p) − p cof F                      total first Piola stress
//!   b = [ϱs Φs + ϱf (J − Φs)] a_g                   body force (mixture weight)
//!   ṡ = (J(F) − J(F_n)) / dt,   F_n = F − dt Grad u̇  fluid-content rate (backward Euler J̇)
//!   W = −Q = K(F, B_p) (Grad p − ϱf Fᵀ a_g)         negative referential Darcy flux
//! ```
//!
//! P_sc is the skeleton law L (any [`SkeletonLaw`], one per file in [`crate::material::laws`])
//! plus the optional compaction penalty ([`crate::material::Solid`]), K the referential
//! conductivity ([`crate::material::Permeability`]). With D = dt Grad u̇ the rate is evaluated without
//! cancellation from the exact expansion det(F − D) = J − cof F : D + F : cof D − det D:
//!
//! ```text
//!   ṡ = cof F : Grad u̇ − dt F : cof Grad u̇ + dt² det Grad u̇
//! ```
//!
//! so ∫ ṡ dt is exactly the change of ∫ J over a backward-Euler step (discrete fluid mass is
//! conserved to round-off), and dt → 0 gives J̇ = cof F : Grad u̇. Tangent blocks (index map
//! (i, j) → 3 i + j, derivatives with respect to Grad u = F − I):
//!
//! ```text
//!   ∂P_ij/∂F_kl  = A_sc,ijkl − p ∂(cof F)_ij/∂F_kl,  ∂(cof F)_ij/∂F_kl = J (F⁻ᵀ_ij F⁻ᵀ_kl − F⁻ᵀ_il F⁻ᵀ_kj)
//!   ∂P/∂p        = −cof F
//!   ∂b_i/∂F_kl   = ϱf a_g,i (cof F)_kl
//!   dṡ/dF        = (cof F − cof F_n)/dt + shift cof F_n
//!   ∂W_i/∂F_kl   = (∂K/∂F_kl g)_i − K_il ϱf a_g,k,   g = Grad p − ϱf Fᵀ a_g
//!   ∂W/∂Grad p   = K
//! ```
//!
//! With remodelling, B_p = B_p^{n+1}(B_p^n, C, Δt) is the end-of-step value of the local update
//! ([`crate::material::remodelling`]) from the committed B_p^n of the point's [`QpState`], and
//! the blocks above gain the chain terms through it (`add_remodelling_tangent`):
//! ∂P/∂F += F ∂S/∂B_p[dB_p/dF], ∂W/∂F += ∂K/∂B_p[dB_p/dF] g. Without it B_p = I.
//!
//! Post-processing ([`Biphasic::point_fields`]): porosity 1 − Φs/J, σ_sc = J⁻¹ P_sc Fᵀ,
//! σ_VM = √(3/2) ‖dev σ_sc‖, spatial Darcy flux q = J⁻¹ F Q.

use crate::error::{Error, Result};
use crate::fem::point::{PointFields, PointFlux, PointModel, PointState, PointTangent, QpId, QpState};
use crate::material::tensor::{cof_cross, dcof, from_sym6, to_sym6};
use crate::material::{
    cof, domain_error, idx, locate, AtPoint, CompactionPenalty, Kinematics, Permeability, Remodelling, SkeletonLaw,
    Solid, SolidLaw, Tangent,
};
use nalgebra::{Matrix3, SMatrix, Vector3};

/// (kg/m³)·(m/s²) → kPa/µm: 1 N/m³ = 1 Pa/m = 1e-3 kPa / 1e6 µm.
pub(crate) const KG_M3_M_S2_TO_KPA_PER_UM: f64 = 1e-9;

/// The biphasic point model: the skeleton law L, optional compaction penalty, permeability, and
/// the weights ϱs a_g, ϱf a_g in solver units (kPa/µm).
#[derive(Debug, Clone)]
pub(crate) struct Biphasic<L> {
    /// The skeleton law (energy per reference volume of mixture).
    solid: L,
    /// Compaction penalty U(J), if any.
    penalty: Option<CompactionPenalty>,
    /// Referential conductivity law.
    perm: Permeability,
    /// Referential solid fraction Φs (common to the three laws).
    phi_s: f64,
    /// ϱs a_g in kPa/µm.
    rho_s_g: Vector3<f64>,
    /// ϱf a_g in kPa/µm.
    rho_f_g: Vector3<f64>,
    /// (ϱs a_g, ϱf a_g) of the scene: the two above are these times the gravity factor.
    weights: (Vector3<f64>, Vector3<f64>),
    /// Drained bulk modulus of the mixture at the reference state (kPa).
    k_drained: f64,
    /// Drained P-wave modulus of the mixture at the reference state (kPa).
    m_drained: f64,
    /// Visco-plastic remodelling of B_p (none: B_p = I, no qp state is stored).
    remodel: Option<Remodelling>,
}

/// What eval and eval_tangent share at one point, after the domain checks.
struct Kin {
    /// The kinematics of F = I + Grad u (J cancellation-free near F = I, C, C⁻¹, F⁻¹, cof F,
    /// ln J), computed once per point for every law.
    kin: Kinematics,
    /// B_p at the end of the step at this point.
    bp: Matrix3<f64>,
    /// ∂x_s/∂c_r of the remodelling update (x, c: the symmetric components of B_p and C), when
    /// asked for and plastic.
    dbp_dc: Option<[[f64; 6]; 6]>,
}

impl<L: SkeletonLaw> Biphasic<L> {
    /// Builds the model from the three laws, the densities (kg/m³) and the gravity acceleration
    /// (m/s², e.g. [0, 0, −9.81]); ϱ a_g is converted to kPa/µm with
    /// [`KG_M3_M_S2_TO_KPA_PER_UM`]. The laws must agree on Φs (relative 1e-12); densities must be
    /// finite and >= 0, gravity finite. The drained moduli are computed here, once, from the
    /// exact tangent at F = B_p = I (see [`PointModel::drained_bulk_modulus`]).
    pub(crate) fn new(
        solid: L,
        penalty: Option<CompactionPenalty>,
        perm: Permeability,
        rho_s_kg_m3: f64,
        rho_f_kg_m3: f64,
        g_vec_m_s2: [f64; 3],
    ) -> Result<Self> {
        let phi_s = solid.phi_s();
        let same = |x: f64| (x - phi_s).abs() <= 1e-12 * phi_s;
        if !same(perm.phi_s) || !penalty.as_ref().is_none_or(|u| same(u.phi_s)) {
            return Err(Error::Material(format!(
                "biphasic: the laws disagree on the solid fraction (solid {phi_s}, permeability {}, penalty {})",
                perm.phi_s,
                penalty.map_or("none".to_string(), |u| u.phi_s.to_string())
            )));
        }
        for (name, rho) in [("solid", rho_s_kg_m3), ("fluid", rho_f_kg_m3)] {
            if !(rho >= 0.0 && rho.is_finite()) {
                return Err(Error::Material(format!("biphasic: {name} density = {rho} must be finite and >= 0")));
            }
        }
        if !g_vec_m_s2.iter().all(|g| g.is_finite()) {
            return Err(Error::Material(format!("biphasic: gravity {g_vec_m_s2:?} must be finite")));
        }
        let a_g = Vector3::from(g_vec_m_s2) * KG_M3_M_S2_TO_KPA_PER_UM;
        let id = Matrix3::identity();
        let a0 = Solid { law: &solid, penalty: penalty.as_ref() }.response(&Kinematics::new(&id)?, &id)?.a;
        // K_dr = (1/9) δ_ij A_ijkl δ_kl = Φs (λ + 2µ/3) and M = A_zzzz = Φs (λ + 2µ) for the
        // isotropic linearisation A = Φs [λ δ_ij δ_kl + µ (δ_ik δ_jl + δ_il δ_jk)].
        let k_drained = (0..3).map(|i| (0..3).map(|k| a0[(idx(i, i), idx(k, k))]).sum::<f64>()).sum::<f64>() / 9.0;
        let m_drained = a0[(idx(2, 2), idx(2, 2))];
        if !(k_drained > 0.0 && m_drained > 0.0 && k_drained.is_finite() && m_drained.is_finite()) {
            return Err(Error::Material(format!(
                "biphasic: drained moduli at the reference state not positive (K = {k_drained}, M = {m_drained})"
            )));
        }
        Ok(Biphasic {
            solid,
            penalty,
            perm,
            phi_s,
            rho_s_g: a_g * rho_s_kg_m3,
            rho_f_g: a_g * rho_f_kg_m3,
            weights: (a_g * rho_s_kg_m3, a_g * rho_f_kg_m3),
            k_drained,
            m_drained,
            remodel: None,
        })
    }

    /// The same mixture with visco-plastic remodelling of B_p (model.md §4).
    pub(crate) fn with_remodelling(self, remodel: Remodelling) -> Self {
        Biphasic { remodel: Some(remodel), ..self }
    }

    /// ϱf a_g in kPa/µm.
    #[cfg(test)]
    pub(crate) fn fluid_weight(&self) -> Vector3<f64> {
        self.rho_f_g
    }

    /// The solid law: the skeleton law plus the penalty, if any.
    fn solid_law(&self) -> Solid<'_, L> {
        Solid { law: &self.solid, penalty: self.penalty.as_ref() }
    }

    /// Output fields at a point (uses Grad u, p, Grad p). Domain error as in `eval`.
    pub(crate) fn point_fields(&self, at: QpId, s: &PointState, h: QpState) -> Result<PointFields> {
        let k = self.kinematics(at, s, h, false)?;
        let (_, s_sc) = self.solid_law().stresses(&k.kin, &k.bp).at_point(at.elem, at.point)?;
        let cauchy = k.kin.f * s_sc * k.kin.f.transpose() / k.kin.j;
        let cauchy_sc = 0.5 * (cauchy + cauchy.transpose());
        let dev = cauchy_sc - Matrix3::identity() * (cauchy_sc.trace() / 3.0);
        let kt = self.perm.tensor(&k.kin, &k.bp).at_point(at.elem, at.point)?;
        let w = kt * self.driving_gradient(&k, s);
        Ok(PointFields {
            j: k.kin.j,
            porosity: 1.0 - self.phi_s / k.kin.j,
            cauchy_sc,
            von_mises: (1.5f64).sqrt() * dev.norm(),
            darcy: -(k.kin.f * w) / k.kin.j,
            pressure_stress: -k.kin.cof_f * s.p,
            norm_ep: match self.remodel {
                // E_p = ½(B_p⁻¹ − I); B_p is symmetric positive definite.
                Some(_) => {
                    (k.bp.try_inverse().unwrap_or(Matrix3::from_element(f64::NAN)) - Matrix3::identity()).norm() * 0.5
                }
                None => 0.0,
            },
            det_bp_dev: (k.bp.determinant() - 1.0).abs(),
        })
    }

    /// F, J, cof F and the end-of-step B_p (with its tangent if `tangent`), with every domain
    /// check: non-finite input, J <= 0, J <= Φs, a failed remodelling update.
    fn kinematics(&self, at: QpId, s: &PointState, h: QpState, tangent: bool) -> Result<Kin> {
        let finite = s.p.is_finite()
            && s.dt.is_finite()
            && s.grad_p.iter().all(|x| x.is_finite())
            && s.grad_udot.iter().all(|x| x.is_finite());
        if !finite {
            let msg = "non-finite pressure, pressure gradient, velocity gradient or time step";
            return Err(locate(domain_error(f64::NAN, msg), at.elem, at.point));
        }
        let f = Matrix3::identity() + s.grad_u;
        let kin = Kinematics::new(&f).at_point(at.elem, at.point)?;
        let j = kin.j;
        if j <= self.phi_s {
            let msg = format!("J <= phi_s = {} (mixture compacted to its solid fraction)", self.phi_s);
            return Err(locate(domain_error(j, msg), at.elem, at.point));
        }
        let bp_n = if h.committed.is_empty() { Matrix3::identity() } else { from_sym6(h.committed) };
        let (bp, dbp_dc) = match (&self.remodel, h.evolve) {
            (Some(rm), true) => {
                let c = &kin.c;
                // F_n = F − Δt Grad u̇: the step's start, for an integrator that uses it.
                let f_n = f - s.grad_udot * s.dt;
                let (b0, dt) =
                    rm.start(&self.solid, &(f_n.transpose() * f_n), &bp_n, s.dt).at_point(at.elem, at.point)?;
                if tangent {
                    let (up, t) = rm.update_and_tangent(&self.solid, c, &b0, dt).at_point(at.elem, at.point)?;
                    (up.bp, t)
                } else {
                    (rm.update(&self.solid, c, &b0, dt).at_point(at.elem, at.point)?.bp, None)
                }
            }
            _ => (bp_n, None),
        };
        Ok(Kin { kin, bp, dbp_dc })
    }

    /// Adds the remodelling chain terms to the tangent: with y_s = dx_s/dF_kl = Σ_r T_sr
    /// ∂c_r/∂F_kl (∂C_ab/∂F_kl = F_kb δ_la + F_ka δ_lb), ∂P/∂F_kl += Σ_s y_s F ∂S/∂B_p[H_s] and
    /// ∂W/∂F_kl += Σ_s y_s ∂K/∂B_p[H_s] g.
    fn add_remodelling_tangent(
        &self,
        k: &Kin,
        t6: &[[f64; 6]; 6],
        g: &Vector3<f64>,
        dstress: &mut Tangent,
        dflux: &mut SMatrix<f64, 3, 9>,
    ) -> Result<()> {
        let ds = self.solid.stress_derivative_bp(&k.kin, &k.bp)?;
        let dk = self.perm.derivative_bp(&k.kin, &k.bp)?;
        let dp: [Matrix3<f64>; 6] = ds.map(|d| k.kin.f * d);
        let dw: [Vector3<f64>; 6] = dk.map(|d| d * g);
        let pairs = crate::material::tensor::SYM_PAIRS;
        for kk in 0..3 {
            for l in 0..3 {
                // ∂c_r/∂F_kl for the six components of C.
                let dc: [f64; 6] = pairs.map(|(a, b)| {
                    (if l == a { k.kin.f[(kk, b)] } else { 0.0 }) + (if l == b { k.kin.f[(kk, a)] } else { 0.0 })
                });
                let y: [f64; 6] = std::array::from_fn(|s| (0..6).map(|r| t6[s][r] * dc[r]).sum());
                let col = idx(kk, l);
                for s in 0..6 {
                    if y[s] == 0.0 {
                        continue;
                    }
                    for i in 0..3 {
                        for j in 0..3 {
                            dstress[(idx(i, j), col)] += dp[s][(i, j)] * y[s];
                        }
                        dflux[(i, col)] += dw[s][i] * y[s];
                    }
                }
            }
        }
        Ok(())
    }

    /// ṡ = cof F : L − dt F : cof L + dt² det L (L = Grad u̇), cof L, and J(F_n) checked > 0.
    fn rate(&self, at: QpId, k: &Kin, s: &PointState) -> Result<(f64, Matrix3<f64>)> {
        let (l, dt) = (&s.grad_udot, s.dt);
        let cof_l = cof(l);
        let rate = k.kin.cof_f.dot(l) - dt * k.kin.f.dot(&cof_l) + dt * dt * l.determinant();
        let j_n = (k.kin.f - l * dt).determinant();
        if !(j_n > 0.0 && rate.is_finite()) {
            let msg = format!("J(F_n) = {j_n} <= 0 for F_n = F - dt Grad u_dot (dt = {dt})");
            return Err(locate(domain_error(k.kin.j, msg), at.elem, at.point));
        }
        Ok((rate, cof_l))
    }

    /// b = Φs ϱs a_g + (J − Φs) ϱf a_g.
    fn body(&self, k: &Kin) -> Vector3<f64> {
        self.rho_s_g * self.phi_s + self.rho_f_g * (k.kin.j - self.phi_s)
    }

    /// g = Grad p − ϱf Fᵀ a_g.
    fn driving_gradient(&self, k: &Kin, s: &PointState) -> Vector3<f64> {
        s.grad_p - k.kin.f.transpose() * self.rho_f_g
    }
}

impl<L: SkeletonLaw> PointModel for Biphasic<L> {
    fn set_gravity_factor(&mut self, factor: f64) {
        self.rho_s_g = self.weights.0 * factor;
        self.rho_f_g = self.weights.1 * factor;
    }
    fn fields(&self, at: QpId, s: &PointState, h: QpState) -> Result<PointFields> {
        self.point_fields(at, s, h)
    }
    /// B_p (six symmetric components) with remodelling; nothing without.
    fn qp_state_len(&self) -> usize {
        if self.remodel.is_some() {
            6
        } else {
            0
        }
    }
    fn initial_qp_state(&self, out: &mut [f64]) {
        out.copy_from_slice(&to_sym6(&Matrix3::identity()));
    }
    fn advance_qp_state(&self, at: QpId, s: &PointState, h: QpState, out: &mut [f64]) -> Result<()> {
        out.copy_from_slice(&to_sym6(&self.kinematics(at, s, h, false)?.bp));
        Ok(())
    }
    fn solid_fraction(&self) -> Option<f64> {
        Some(self.phi_s)
    }
    /// (P, b, ṡ, W) at the point; domain error outside J > Φs, J(F_n) > 0, finite input.
    fn eval(&self, at: QpId, s: &PointState, h: QpState) -> Result<PointFlux> {
        let k = self.kinematics(at, s, h, false)?;
        let (rate, _) = self.rate(at, &k, s)?;
        let (p_sc, _) = self.solid_law().stresses(&k.kin, &k.bp).at_point(at.elem, at.point)?;
        let kt = self.perm.tensor(&k.kin, &k.bp).at_point(at.elem, at.point)?;
        Ok(PointFlux {
            stress: p_sc - k.kin.cof_f * s.p,
            body: self.body(&k),
            rate,
            flux: kt * self.driving_gradient(&k, s),
        })
    }

    /// (P, b, ṡ, W) and the exact tangent blocks listed in the module documentation.
    fn eval_tangent(&self, at: QpId, s: &PointState, h: QpState, shift: f64) -> Result<(PointFlux, PointTangent)> {
        let k = self.kinematics(at, s, h, true)?;
        let (rate, cof_l) = self.rate(at, &k, s)?;
        let sc = self.solid_law().response(&k.kin, &k.bp).at_point(at.elem, at.point)?;
        let (kt, dk) = self.perm.tensor_and_derivative(&k.kin, &k.bp).at_point(at.elem, at.point)?;
        let g = self.driving_gradient(&k, s);
        let flux = PointFlux { stress: sc.p - k.kin.cof_f * s.p, body: self.body(&k), rate, flux: kt * g };

        // (cof F − cof F_n)/dt = X(F, L) − dt cof L and cof F_n = cof F − dt X(F, L) + dt² cof L,
        // both free of cancellation (X: the bilinear part of cof, cof(A + B) = cof A + X + cof B).
        let (l, dt) = (&s.grad_udot, s.dt);
        let x = cof_cross(&k.kin.f, l);
        let cof_fn = k.kin.cof_f - x * dt + cof_l * (dt * dt);
        let drate_du = x - cof_l * dt + cof_fn * shift;

        let mut dbody_du = SMatrix::<f64, 3, 9>::zeros();
        let mut dflux_du = SMatrix::<f64, 3, 9>::zeros();
        for kk in 0..3 {
            for l in 0..3 {
                let c = idx(kk, l);
                let dkg = dk[c] * g;
                for i in 0..3 {
                    dbody_du[(i, c)] = self.rho_f_g[i] * k.kin.cof_f[(kk, l)];
                    dflux_du[(i, c)] = dkg[i] - kt[(i, l)] * self.rho_f_g[kk];
                }
            }
        }
        let mut dstress_du = sc.a - dcof(&k.kin.f) * s.p;
        if let Some(t6) = &k.dbp_dc {
            self.add_remodelling_tangent(&k, t6, &g, &mut dstress_du, &mut dflux_du).at_point(at.elem, at.point)?;
        }
        let t = PointTangent { dstress_du, dstress_dp: -k.kin.cof_f, dbody_du, drate_du, dflux_du, dflux_dgradp: kt };
        Ok((flux, t))
    }

    /// Φs (λ + 2µ/3) = (1/9) δ_ij A_ijkl δ_kl with A = ∂P_sc/∂F at F = B_p = I, computed at
    /// construction from the material's own tangent (penalty included if active at J = 1).
    fn drained_bulk_modulus(&self) -> f64 {
        self.k_drained
    }

    /// Φs (λ + 2µ) = A_zzzz at F = B_p = I, computed at construction.
    fn p_wave_modulus(&self) -> f64 {
        self.m_drained
    }

    /// k0 of the permeability law.
    fn conductivity(&self) -> f64 {
        self.perm.k0
    }

    /// Nonlinear: the Jacobian changes with the state.
    fn is_linear(&self) -> bool {
        false
    }
}

/// The model's defining properties, tests 1–6: a consistent tangent, the linear small-strain
/// limit, the exact rate of J, objectivity, domain errors at inadmissible states, and gravity at
/// the reference state; plus closed forms for the output fields and the cofactor helpers.
#[cfg(test)]
mod tests;
