//! Visco-plastic remodelling (54c), (41): dB_p/dt = −2 γp B_p dev Σ with the Mandel stress
//! Σ = C S_sc and the Perzyna rate γp = λp [‖dev σ_sc‖ − √(2/3) σy]₊ / ‖dev σ_sc‖, integrated
//! over a step by the implicit, symmetric exponential map
//!
//! ```text
//!   B_p^{n+1} = exp(−Δγ dev Σᵀ) B_p^n exp(−Δγ dev Σ),   Σ = Σ(C^{n+1}, B_p^{n+1}),
//!   Δγ ‖dev σ‖ = Δt λp (‖dev σ‖ − √(2/3) σy)              (plastic step; Δγ = Δt γp)
//! ```
//!
//! Why this form: B_p dev Σ is symmetric (B_p Σ = B_p C S), so B_p exp(−2Δγ dev Σ) is the exact
//! flow for a frozen rate; splitting the exponential symmetrically keeps the update symmetric
//! positive definite for any iterate, and det B_p^{n+1} = det B_p^n exp(−2Δγ tr dev Σ) = det B_p^n
//! to round-off (tr dev Σ = 0 by construction). Being backward Euler in Δγ it is unconditionally
//! stable: as Δt λp µ → ∞ the consistency condition becomes ‖dev σ‖ = √(2/3) σy (rate-independent
//! return). ‖dev σ‖ = J⁻¹ √(tr (dev Σ)²), since dev τ = F⁻ᵀ dev Σ Fᵀ is similar to dev Σ.
//!
//! The local problem (B_p^{n+1}: six symmetric components, and Δγ) is solved by Newton with a
//! backtracking line search; its Jacobian comes from forward-mode duals ([`super::dual`]). The
//! consistent tangent ∂B_p^{n+1}/∂C follows from the implicit-function theorem on the converged
//! residual, R(x, C) = 0 ⇒ dx/dC = −(∂R/∂x)⁻¹ ∂R/∂C. The elastic branch (trial ‖dev σ‖ ≤
//! √(2/3) σy at B_p^n) keeps B_p^n and has a zero tangent.

use super::domain::domain_error;
use super::dual::{m_det, m_exp, m_mul, m_scale, m_trace_mul, m_transpose, Dual, Scalar, M3};
use super::law::SkeletonLaw;
use super::tensor::{from_sym6, to_sym6, SYM_PAIRS};
use crate::error::{Error, Result};
use crate::range::Range;
use nalgebra::{Matrix3, SMatrix, SVector};
use serde::{Deserialize, Serialize};

fn sym_generic<T: Scalar>(x: &[T]) -> M3<T> {
    [[x[0], x[3], x[4]], [x[3], x[1], x[5]], [x[4], x[5], x[2]]]
}

/// Which of the paper's two "equivalent" flow rules (40): they differ by the factor J
/// (model.md §6). (40b) is what the paper says it solved and our default. In a scene:
/// `form = "40b"`, `"40a"`, or `"40b_tau"`, a third place a J can enter: γp of the Kirchhoff
/// stress τ = J σ (the reproduction weighs it against (40a)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
pub(crate) enum FlowForm {
    /// (40b)/(54c): dB_p/dt = −2 γp B_p dev Σ (pushed forward: L b_e = −2 γp b_e dev τ).
    #[default]
    #[serde(rename = "40b")]
    Referential,
    /// (40a): L b_e = −2 γp b_e dev σ, i.e. dB_p/dt = −2 (γp/J) B_p dev Σ.
    #[serde(rename = "40a")]
    Spatial,
    /// (40b) with the overstress ratio of τ = J σ in (41): γp = λp [‖dev τ‖ − √(2/3) σy]₊ / ‖dev τ‖.
    /// Slower than (40b) where J < 1 (a compressed aggregate yields later).
    #[serde(rename = "40b_tau")]
    Kirchhoff,
}

/// How a step integrates the flow rule (in a scene: `integrator = "implicit"` or `"explicit"`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum Integrator {
    /// The implicit, symmetric exponential map (module docs): unconditionally stable, det B_p
    /// kept. The default.
    #[default]
    Implicit,
    /// The trapezoidal rule in split form: half a step of the exponential map with the rate
    /// frozen at the start-of-step state (C^n, B_p^n) ([`Remodelling::start`]), then the implicit
    /// map over the other half. Second order in Δt where backward Euler over-integrates a rate
    /// that rises through the step by about Δt/t (the overstress through a loading ramp); det B_p
    /// kept. Where a step is stiff (the frozen-rate half step would relax more than half the
    /// overstress: Δt λp µ ≳ 1) it is backward Euler's instead, which returns to the yield
    /// surface where the trapezoidal rule would ring about it.
    Trapezoidal,
    /// Forward Euler in B_p with the rate at the trial state (C^{n+1}, B_p^n):
    /// B_p^{n+1} = B_p^n − 2 Δt γp B_p^n dev Σ. For stability studies only: it is stable only
    /// while 2 Δt λp times the stiffness of the overstress stays below about 2, and it does not
    /// keep det B_p = 1 (an O(Δt²) drift per step).
    Explicit,
}

/// Perzyna flow-rule parameters.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Remodelling {
    /// λp ((kPa s)⁻¹; Table 1: 0.001 = 1 (MPa s)⁻¹).
    pub(crate) lambda_p: f64,
    /// Yield stress σy (kPa).
    pub(crate) sigma_y: f64,
    pub(crate) form: FlowForm,
    pub(crate) integrator: Integrator,
}

/// The end-of-step remodelling metric at one point.
#[derive(Clone, Copy, Debug)]
pub(crate) struct Update {
    pub(crate) bp: Matrix3<f64>,
    /// Δγ = Δt γp (0 on the elastic branch). Read by the tests of the local solve, as are the
    /// iterations.
    #[cfg_attr(not(test), allow(dead_code))]
    pub(crate) dgamma: f64,
    /// Local Newton iterations (0 on the elastic branch).
    #[cfg_attr(not(test), allow(dead_code))]
    pub(crate) iterations: usize,
}

impl Update {
    /// The elastic branch: B_p stays B_p^n.
    fn elastic(bp_n: &Matrix3<f64>) -> Update {
        Update { bp: *bp_n, dgamma: 0.0, iterations: 0 }
    }
}

/// Unknowns of the local problem: six components of B_p^{n+1}, then Δγ.
const NX: usize = 7;
/// Local Newton: iteration limit and tolerance on the scaled residual (all entries are O(1)).
/// The residual's round-off floor grows with Δγ σ_ref (the map's sensitivity to B_p), so the
/// tolerance is `TOLERANCE (1 + Δγ σ_ref)`: a step of λp Δt ≳ 1 (kPa)⁻¹ (σy = 0, fast relaxation)
/// otherwise stalls at ~1e-14 and fails. It grows with B_p's largest entry too (a liquid
/// aggregate squeezed between adhesive plates reaches ‖E_p‖ ≈ 2, and stalled at 2.5e-14).
const MAX_ITERATIONS: usize = 50;
const TOLERANCE: f64 = 1e-14;

/// The valid λp ((kPa s)⁻¹) and σy (kPa), which a scene's keys check too.
pub(crate) const LAMBDA_P: Range = Range::NON_NEGATIVE;
pub(crate) const SIGMA_Y: Range = Range::NON_NEGATIVE;

impl Remodelling {
    /// Requires λp in [`LAMBDA_P`] and σy in [`SIGMA_Y`].
    pub(crate) fn new(lambda_p: f64, sigma_y: f64) -> Result<Self> {
        LAMBDA_P.check("remodelling: lambda_p", lambda_p).map_err(Error::Material)?;
        SIGMA_Y.check("remodelling: sigma_y", sigma_y).map_err(Error::Material)?;
        Ok(Remodelling { lambda_p, sigma_y, form: FlowForm::Referential, integrator: Integrator::Implicit })
    }

    /// The same law in the other form of (40).
    pub(crate) fn with_form(self, form: FlowForm) -> Self {
        Remodelling { form, ..self }
    }

    /// The same law with another step integrator.
    pub(crate) fn with_integrator(self, integrator: Integrator) -> Self {
        Remodelling { integrator, ..self }
    }

    /// γp's factor of the overstress ratio: λp, or λp/J in the spatial form (40a).
    fn rate_factor<T: Scalar>(&self, j: T) -> T {
        match self.form {
            FlowForm::Referential | FlowForm::Kirchhoff => T::cst(self.lambda_p),
            FlowForm::Spatial => T::cst(self.lambda_p) / j,
        }
    }

    /// The stress norm γp compares with the yield radius, from s = ‖dev σ‖: s, or ‖dev τ‖ = J s
    /// in the Kirchhoff variant.
    fn measured<T: Scalar>(&self, s: T, j: T) -> T {
        match self.form {
            FlowForm::Referential | FlowForm::Spatial => s,
            FlowForm::Kirchhoff => s * j,
        }
    }

    /// The measured norm ([`Self::measured`]) at (C, B_p).
    fn overstress_norm<L: SkeletonLaw>(&self, law: &L, c: &Matrix3<f64>, bp: &Matrix3<f64>) -> f64 {
        self.measured(Self::dev_stress_norm(law, c, bp), c.determinant().sqrt())
    }

    /// √(2/3) σy: the yield radius of ‖dev σ‖.
    pub(crate) fn yield_radius(&self) -> f64 {
        (2.0f64 / 3.0).sqrt() * self.sigma_y
    }

    /// ‖dev σ_sc‖ at (C, B_p).
    pub(crate) fn dev_stress_norm<L: SkeletonLaw>(law: &L, c: &Matrix3<f64>, bp: &Matrix3<f64>) -> f64 {
        let cm = to_m3(c);
        let ln_j = 0.5 * m_det(&cm).ln();
        let d = law.mandel_dev(&m_mul(&cm, &to_m3(bp)), ln_j);
        m_trace_mul(&d, &d).max(0.0).sqrt() / ln_j.exp()
    }

    /// Where the end-of-step update starts from, and over which part of the step: (B_p^n, Δt),
    /// or for the trapezoidal rule (B_p after half a step with the rate frozen at (C^n, B_p^n),
    /// Δt/2) — (B_p^n, Δt) again where that step is stiff (see [`Integrator::Trapezoidal`]).
    /// C^n depends on the step's start only, so it adds nothing to the tangent of the
    /// backward-Euler system (U̇ = (U − U^n)/Δt).
    pub(crate) fn start<L: SkeletonLaw>(
        &self,
        law: &L,
        c_n: &Matrix3<f64>,
        bp_n: &Matrix3<f64>,
        dt: f64,
    ) -> Result<(Matrix3<f64>, f64)> {
        if self.integrator != Integrator::Trapezoidal {
            return Ok((*bp_n, dt));
        }
        let half = 0.5 * dt;
        let Some(s) = self.trial_overstress(law, c_n, bp_n, half)? else { return Ok((*bp_n, half)) };
        let rate = self.rate_factor(c_n.determinant().sqrt());
        // In a stiff step (Δt λp µ ≳ 1) a frozen rate overshoots the yield surface, and the
        // trapezoidal rule rings: where the half step would relax more than half the overstress,
        // the step is backward Euler's (L-stable) instead. The choice depends on the step's start
        // only, so the residual stays smooth in the unknowns.
        let c6 = to_sym6(c_n);
        let mut x = [0.0; NX];
        x[..6].copy_from_slice(&to_sym6(bp_n));
        x[6] = half * rate * (s - self.yield_radius()) / s;
        let (_, b) = self.map(law, &c6, bp_n, &x);
        let b = Matrix3::from_fn(|i, k| 0.5 * (b[i][k] + b[k][i]));
        let s_half = self.overstress_norm(law, c_n, &b);
        if s_half.is_finite() && s_half - self.yield_radius() >= 0.5 * (s - self.yield_radius()) {
            Ok((b, half))
        } else {
            Ok((*bp_n, dt))
        }
    }

    /// B_p^{n+1} from B_p^n over a step dt at the end-of-step C (domain error if the local
    /// Newton fails, so the caller can cut the step). For the trapezoidal rule, B_p^n and dt are
    /// what [`Remodelling::start`] returns.
    pub(crate) fn update<L: SkeletonLaw>(
        &self,
        law: &L,
        c: &Matrix3<f64>,
        bp_n: &Matrix3<f64>,
        dt: f64,
    ) -> Result<Update> {
        if self.integrator == Integrator::Explicit {
            return Ok(self.explicit(law, c, bp_n, dt)?.0);
        }
        Ok(self.solve(law, c, bp_n, dt)?.0)
    }

    /// The update and ∂x_s/∂c_r (x: the six components of B_p^{n+1}, c: those of C; None on the
    /// elastic branch, where it is zero).
    #[allow(clippy::type_complexity)]
    pub(crate) fn update_and_tangent<L: SkeletonLaw>(
        &self,
        law: &L,
        c: &Matrix3<f64>,
        bp_n: &Matrix3<f64>,
        dt: f64,
    ) -> Result<(Update, Option<[[f64; 6]; 6]>)> {
        if self.integrator == Integrator::Explicit {
            return self.explicit(law, c, bp_n, dt);
        }
        let (up, x) = self.solve(law, c, bp_n, dt)?;
        let Some(x) = x else { return Ok((up, None)) };
        // R(x, c) with both seeded: 7 + 6 directions.
        let xd: [Dual<13>; NX] = std::array::from_fn(|i| Dual::var(x[i], i));
        let c6 = to_sym6(c);
        let cd: [Dual<13>; 6] = std::array::from_fn(|r| Dual::var(c6[r], NX + r));
        let (r, _) = self.residual(law, &cd, bp_n, &xd, dt);
        let jx = SMatrix::<f64, NX, NX>::from_fn(|i, j| r[i].d[j]);
        let jc = SMatrix::<f64, NX, 6>::from_fn(|i, j| r[i].d[NX + j]);
        let lu = jx.lu();
        let dx = lu.solve(&(-jc)).ok_or_else(|| domain_error(f64::NAN, "remodelling: singular local tangent"))?;
        Ok((up, Some(std::array::from_fn(|s| std::array::from_fn(|r| dx[(s, r)])))))
    }

    /// The measured norm ([`Self::measured`]) at the trial state (C^{n+1}, B_p^n) if it lies
    /// outside the yield surface and the step can flow (λp > 0, Δt > 0); None on the elastic branch.
    fn trial_overstress<L: SkeletonLaw>(
        &self,
        law: &L,
        c: &Matrix3<f64>,
        bp_n: &Matrix3<f64>,
        dt: f64,
    ) -> Result<Option<f64>> {
        if !(self.lambda_p > 0.0 && dt > 0.0) {
            return Ok(None);
        }
        let s_trial = self.overstress_norm(law, c, bp_n);
        if !(s_trial.is_finite()) {
            return Err(domain_error(f64::NAN, format!("remodelling: non-finite trial stress ({s_trial})")));
        }
        Ok((s_trial > self.yield_radius()).then_some(s_trial))
    }

    /// The explicit (forward Euler) update and its tangent ∂x_s/∂c_r (None on the elastic branch).
    #[allow(clippy::type_complexity)]
    fn explicit<L: SkeletonLaw>(
        &self,
        law: &L,
        c: &Matrix3<f64>,
        bp_n: &Matrix3<f64>,
        dt: f64,
    ) -> Result<(Update, Option<[[f64; 6]; 6]>)> {
        if self.trial_overstress(law, c, bp_n, dt)?.is_none() {
            return Ok((Update::elastic(bp_n), None));
        }
        let c6 = to_sym6(c);
        let cd: [Dual<6>; 6] = std::array::from_fn(|r| Dual::var(c6[r], r));
        let cm = sym_generic(&cd);
        let ln_j = m_det(&cm).ln().scale(0.5);
        let bn: M3<Dual<6>> = std::array::from_fn(|i| std::array::from_fn(|j| Dual::cst(bp_n[(i, j)])));
        let d = law.mandel_dev(&m_mul(&cm, &bn), ln_j);
        let j = ln_j.exp();
        let s = self.measured(m_trace_mul(&d, &d).sqrt() / j, j);
        // Δγ = Δt γp = Δt λp (s − k)/s (spatial form: λp/J).
        let dgamma = (s - Dual::cst(self.yield_radius())) / s * self.rate_factor(j).scale(dt);
        let bd = m_mul(&bn, &d);
        let x: [Dual<6>; 6] = std::array::from_fn(|k| {
            let (a, b) = SYM_PAIRS[k];
            bn[a][b] - dgamma * (bd[a][b] + bd[b][a])
        });
        let bp = from_sym6(&x.map(|v| v.re));
        if !(bp.iter().all(|v| v.is_finite()) && bp.determinant() > 0.0) {
            return Err(domain_error(f64::NAN, format!("remodelling: explicit update lost det B_p > 0 (dt = {dt})")));
        }
        let tangent = std::array::from_fn(|s| std::array::from_fn(|r| x[s].d[r]));
        Ok((Update { bp, dgamma: dgamma.re, iterations: 0 }, Some(tangent)))
    }

    /// Local Newton. Returns the update and, on the plastic branch, the converged unknowns.
    fn solve<L: SkeletonLaw>(
        &self,
        law: &L,
        c: &Matrix3<f64>,
        bp_n: &Matrix3<f64>,
        dt: f64,
    ) -> Result<(Update, Option<[f64; NX]>)> {
        let Some(s_trial) = self.trial_overstress(law, c, bp_n, dt)? else { return Ok((Update::elastic(bp_n), None)) };
        let c6 = to_sym6(c).map(f64::cst);
        let norm = |r: &[f64; NX]| r.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let mut x = [0.0; NX];
        x[..6].copy_from_slice(&to_sym6(bp_n));
        // Residuals in f64 (the convergence test and the line search); the dual Jacobian only
        // where a Newton step is taken. At the start (x = B_p^n, Δγ = 0) the map is the identity,
        // so R_B = 0 and R_γ is the trial overstress.
        let mut r0 = [0.0; NX];
        r0[6] = (s_trial - self.yield_radius()) / law.shear_modulus();
        let mut it = 0;
        let sref = law.shear_modulus();
        loop {
            let n0 = norm(&r0);
            // The floor also grows with B_p's entries (O(1) only while the remodelling is small).
            let bscale = x[..6].iter().fold(1.0f64, |m, v| m.max(v.abs()));
            if n0 <= TOLERANCE * (1.0 + x[6] * sref) * bscale {
                break;
            }
            if it == MAX_ITERATIONS || !n0.is_finite() {
                return Err(domain_error(
                    f64::NAN,
                    format!("remodelling: local Newton failed (residual {n0:e} after {it} iterations, dt = {dt})"),
                ));
            }
            it += 1;
            let xd: [Dual<NX>; NX] = std::array::from_fn(|i| Dual::var(x[i], i));
            let (r, _) = self.residual(law, &c6.map(Dual::cst), bp_n, &xd, dt);
            let jx = SMatrix::<f64, NX, NX>::from_fn(|i, j| r[i].d[j]);
            let step = jx
                .lu()
                .solve(&-SVector::<f64, NX>::from(r0))
                .ok_or_else(|| domain_error(f64::NAN, "remodelling: singular local Jacobian"))?;
            // Backtracking on the residual norm, keeping Δγ >= 0.
            let mut alpha = 1.0;
            loop {
                let mut trial: [f64; NX] = std::array::from_fn(|i| x[i] + alpha * step[i]);
                trial[6] = trial[6].max(0.0);
                let (rt, _) = self.residual(law, &c6, bp_n, &trial, dt);
                let nt = norm(&rt);
                if (nt.is_finite() && nt < (1.0 - 1e-4 * alpha) * n0) || alpha < 1e-6 {
                    x = trial;
                    r0 = rt;
                    break;
                }
                alpha *= 0.5;
            }
        }
        // B_p^{n+1} from the converged Δγ and dev Σ through the map itself: symmetric, and det
        // preserved to round-off (x[..6] agrees with it to the tolerance).
        let (_, bp) = self.map(law, &c6, bp_n, &x);
        let bp = Matrix3::from_fn(|i, j| 0.5 * (bp[i][j] + bp[j][i]));
        Ok((Update { bp, dgamma: x[6], iterations: it }, Some(x)))
    }

    /// dev Σ at (C, B) and the mapped exp(−Δγ dev Σᵀ) B_p^n exp(−Δγ dev Σ).
    fn map<T: Scalar, L: SkeletonLaw>(&self, law: &L, c6: &[T; 6], bp_n: &Matrix3<f64>, x: &[T; NX]) -> (M3<T>, M3<T>) {
        let cm = sym_generic(c6);
        let ln_j = m_det(&cm).ln().scale(0.5);
        let d = law.mandel_dev(&m_mul(&cm, &sym_generic(&x[..6])), ln_j);
        let g = m_exp(&m_scale(&m_transpose(&d), -x[6]));
        let bn: M3<T> = std::array::from_fn(|i| std::array::from_fn(|j| T::cst(bp_n[(i, j)])));
        (d, m_mul(&m_mul(&g, &bn), &m_transpose(&g)))
    }

    /// R_B = x_B − sym6(map), R_γ = [(s − k) − Δγ s/(λp Δt)] / σ_ref with s = ‖dev σ‖ (‖dev τ‖
    /// in the Kirchhoff variant), k = √(2/3) σy and σ_ref the mixture shear modulus (R is O(1) and
    /// finite as Δt → ∞); the spatial form (40a) has λp/J in place of λp.
    fn residual<T: Scalar, L: SkeletonLaw>(
        &self,
        law: &L,
        c6: &[T; 6],
        bp_n: &Matrix3<f64>,
        x: &[T; NX],
        dt: f64,
    ) -> ([T; NX], T) {
        let (d, mapped) = self.map(law, c6, bp_n, x);
        let cm = sym_generic(c6);
        let j = m_det(&cm).sqrt();
        let s = self.measured(m_trace_mul(&d, &d).sqrt() / j, j);
        let sref = law.shear_modulus();
        let mut r = [T::cst(0.0); NX];
        for (k, &(a, b)) in SYM_PAIRS.iter().enumerate() {
            r[k] = x[k] - mapped[a][b];
        }
        let flow = s / self.rate_factor(j).scale(dt);
        r[6] = ((s - T::cst(self.yield_radius())) - x[6] * flow).scale(1.0 / sref);
        (r, s)
    }
}

pub(super) fn to_m3(m: &Matrix3<f64>) -> [[f64; 3]; 3] {
    std::array::from_fn(|i| std::array::from_fn(|j| m[(i, j)]))
}
