//! Exact series solutions of Terzaghi's (1-D column) and Cryer's (sphere) consolidation problems for linear poroelasticity with incompressible constituents (Biot α = 1, 1/M = 0), used to verify the finite-element solver.
//!
//! # Model and sign conventions
//! * Drained isotropic skeleton: shear modulus µ, Poisson ratio ν, λ = 2µν/(1 − 2ν),
//!   bulk modulus K = λ + 2µ/3, oedometric (P-wave) modulus λ + 2µ.
//! * Total stress σ = λ tr(ε) I + 2µ ε − p I (tension positive); pore pressure p is positive in
//!   compression. Darcy: q = −k ∇p; incompressible constituents: ∂(div u)/∂t = div(k ∇p).
//! * Consolidation coefficient c = k (λ + 2µ).
//! * Loads P are the magnitude of a COMPRESSIVE normal traction applied as a step at t = 0⁺
//!   (σ·n = −P n on the loaded boundary); compressive loads are positive.
//! * With incompressible constituents the undrained response is rigid in volume (undrained
//!   Poisson ratio 1/2): at t = 0⁺ there is no volume change and the pressure carries the load.
//!
//! Times are also used in dimensionless form τ = c t / L² with L = H (Terzaghi) or a (Cryer).
//! For t ≤ 0 the functions return the t = 0⁺ state (just after loading). Invalid parameters
//! (µ ≤ 0, ν outside (−1, 1/2), k ≤ 0, non-positive lengths, non-finite numbers) give NaN, never
//! a panic; [`Drained::new`] reports them as [`Error::Material`].
//!
//! # Terzaghi
//! Column 0 ≤ z ≤ H, impermeable and fixed bottom z = 0, drained (p = 0) loaded top z = H,
//! laterally confined. With depth d = 1 − z/H and M_m = (2m + 1)π/2:
//! p/P = Σ_m (2/M_m) sin(M_m d) e^{−M_m² τ},
//! settlement w(t) = P H/(λ + 2µ) · [1 − Σ_m (2/M_m²) e^{−M_m² τ}].
//! Short times use the method-of-images form
//! p/P = 1 − Σ_n (−1)^n [erfc((2n + d)/(2√τ)) + erfc((2n + 2 − d)/(2√τ))],
//! w = P H/(λ + 2µ) · 2√τ [1/√π + 2 Σ_{n≥1} (−1)^n ierfc(n/√τ)].
//!
//! # Cryer
//! Sphere of radius a, drained surface, uniform compressive traction P from t = 0⁺. Equilibrium
//! gives (λ + 2µ) div u − p = f(t) uniform in space; the boundary condition and the volume
//! balance then reduce the problem to p_t − c ∇²p = −β dp̄/dt with p̄ the volume average of p,
//! p(a) = 0, p(r, 0⁺) = P and β = 4µ/(3K) = 2(1 − 2ν)/(1 + ν). Laplace transform and residues give,
//! with ξ_n > 0 the roots of the characteristic equation
//!   tan ξ = ξ / (1 − γ ξ²),  γ = (1 + β)/(3β) = (1 − ν)/(2(1 − 2ν)),
//! and A_n = 2(1 + β)/(3 (1 − β γ² ξ_n²)):
//! * p(r, t)/P = Σ_n A_n [1 − a sin(ξ_n r/a)/(r sin ξ_n)] e^{−ξ_n² τ}, τ = c t/a²,
//! * p_c(t)/P = Σ_n A_n (1 − ξ_n / sin ξ_n) e^{−ξ_n² τ} (centre),
//! * p̄(t)/P = −(1/β) Σ_n A_n e^{−ξ_n² τ} (volume average),
//! * surface radial displacement u_r(a, t) = −(a P/(3K)) (1 − p̄/P) (outward positive, so ≤ 0).
//!
//! For small τ the centre and mean pressures use the exact large-s expansion of the Laplace
//! transform: with y = s^{−1/2}, b = β/(1 + β), F = 3y − 3y² (exact up to exponentially small
//! terms), p̃_c = 1/(s (1 − bF)), each y^k/s inverting to τ^{k/2}/Γ(1 + k/2).
//! This reproduces the Mandel–Cryer effect: p_c rises above P before it decays.

use crate::error::{Error, Result};

const FRAC_1_SQRT_PI: f64 = 0.564_189_583_547_756_3;

/// Drained skeleton and permeability of a linear poroelastic medium with incompressible constituents.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Drained {
    /// Drained shear modulus µ (> 0).
    pub mu: f64,
    /// Drained Poisson ratio ν, −1 < ν < 1/2.
    pub nu: f64,
    /// Permeability / hydraulic conductivity k in Darcy's law q = −k ∇p (> 0).
    pub k: f64,
}

impl Drained {
    /// Validated parameters: µ > 0, −1 < ν < 1/2, k > 0, all finite.
    pub fn new(mu: f64, nu: f64, k: f64) -> Result<Self> {
        let m = Drained { mu, nu, k };
        if m.is_valid() {
            Ok(m)
        } else {
            Err(Error::Material(format!(
                "poroelastic reference solution needs mu > 0, -1 < nu < 0.5, k > 0 \
                 (got mu = {mu}, nu = {nu}, k = {k})"
            )))
        }
    }

    /// True when the parameters are admissible (see [`Drained::new`]).
    pub fn is_valid(&self) -> bool {
        self.mu.is_finite()
            && self.mu > 0.0
            && self.nu.is_finite()
            && self.nu > -1.0
            && self.nu < 0.5
            && self.k.is_finite()
            && self.k > 0.0
    }

    /// Lamé λ = 2µν/(1 − 2ν).
    pub fn lambda(&self) -> f64 {
        2.0 * self.mu * self.nu / (1.0 - 2.0 * self.nu)
    }

    /// Oedometric modulus λ + 2µ.
    pub fn oedometric_modulus(&self) -> f64 {
        self.lambda() + 2.0 * self.mu
    }

    /// Drained bulk modulus K = λ + 2µ/3.
    pub fn bulk_modulus(&self) -> f64 {
        self.lambda() + 2.0 * self.mu / 3.0
    }

    /// Consolidation coefficient c = k (λ + 2µ).
    pub fn consolidation_coefficient(&self) -> f64 {
        self.k * self.oedometric_modulus()
    }
}

// ---------------------------------------------------------------------------------------------
// Terzaghi
// ---------------------------------------------------------------------------------------------

/// Below this dimensionless time the Terzaghi functions use the erfc (images) form.
pub const TERZAGHI_SHORT_TIME: f64 = 0.1;

/// Terzaghi pore pressure p(z, t) [same unit as `load`] in a column of height `height` loaded at
/// t = 0⁺ by a compressive traction `load` on its drained top z = H (bottom z = 0 impermeable and
/// fixed). p(z, 0⁺) = P for z < H; p(H, t) = 0. z is clamped to [0, H] within 1e-12 H; beyond
/// that, and for invalid parameters, the result is NaN.
pub fn terzaghi_pressure(z: f64, t: f64, height: f64, load: f64, mat: &Drained) -> f64 {
    if !(mat.is_valid() && height > 0.0 && height.is_finite() && load.is_finite()) {
        return f64::NAN;
    }
    let tol = 1e-12 * height;
    if !(z >= -tol && z <= height + tol && t.is_finite()) {
        return f64::NAN;
    }
    let zeta = (z / height).clamp(0.0, 1.0);
    let tau = mat.consolidation_coefficient() * t / (height * height);
    load * terzaghi_pressure_dimensionless(zeta, tau)
}

/// Settlement (downward displacement of the loaded top, ≥ 0) of the Terzaghi column at time t:
/// 0 at t = 0⁺, P H/(λ + 2µ) as t → ∞. NaN for invalid parameters.
pub fn terzaghi_settlement(t: f64, height: f64, load: f64, mat: &Drained) -> f64 {
    if !(mat.is_valid() && height > 0.0 && height.is_finite() && load.is_finite() && t.is_finite()) {
        return f64::NAN;
    }
    let tau = mat.consolidation_coefficient() * t / (height * height);
    load * height / mat.oedometric_modulus() * terzaghi_consolidation_degree(tau)
}

/// Dimensionless Terzaghi pressure p/P at ζ = z/H ∈ [0, 1], τ = c t/H² (form chosen by τ).
pub fn terzaghi_pressure_dimensionless(zeta: f64, tau: f64) -> f64 {
    if !(zeta.is_finite() && tau.is_finite()) {
        return f64::NAN;
    }
    let zeta = zeta.clamp(0.0, 1.0);
    if tau <= 0.0 {
        return if zeta < 1.0 { 1.0 } else { 0.0 };
    }
    if tau < TERZAGHI_SHORT_TIME {
        terzaghi_pressure_images(zeta, tau)
    } else {
        terzaghi_pressure_fourier(zeta, tau)
    }
}

/// Degree of consolidation U(τ) = settlement / final settlement (0 at τ = 0, → 1).
pub fn terzaghi_consolidation_degree(tau: f64) -> f64 {
    if !tau.is_finite() {
        return f64::NAN;
    }
    if tau <= 0.0 {
        0.0
    } else if tau < TERZAGHI_SHORT_TIME {
        terzaghi_consolidation_images(tau)
    } else {
        terzaghi_consolidation_fourier(tau)
    }
}

/// Fourier-series form of the dimensionless Terzaghi pressure (any τ > 0; slow for tiny τ).
pub fn terzaghi_pressure_fourier(zeta: f64, tau: f64) -> f64 {
    let d = 1.0 - zeta;
    let mut sum = 0.0;
    for m in 0..2_000_000u32 {
        let big_m = (2 * m + 1) as f64 * std::f64::consts::FRAC_PI_2;
        let decay = (-big_m * big_m * tau).exp();
        let amp = 2.0 / big_m * decay;
        sum += amp * (big_m * d).sin();
        if amp < 1e-18 {
            break;
        }
    }
    sum
}

/// Method-of-images (erfc) form of the dimensionless Terzaghi pressure (any τ > 0; slow for large τ).
pub fn terzaghi_pressure_images(zeta: f64, tau: f64) -> f64 {
    let d = 1.0 - zeta;
    let s = 2.0 * tau.sqrt();
    let mut sum = 0.0;
    let mut sign = 1.0;
    for n in 0..1_000_000u32 {
        let two_n = 2.0 * n as f64;
        let term = erfc((two_n + d) / s) + erfc((two_n + 2.0 - d) / s);
        sum += sign * term;
        sign = -sign;
        if erfc((two_n + 2.0) / s) < 1e-18 && term < 1e-18 {
            break;
        }
    }
    1.0 - sum
}

/// Fourier-series form of the degree of consolidation U(τ).
pub fn terzaghi_consolidation_fourier(tau: f64) -> f64 {
    let mut sum = 0.0;
    for m in 0..2_000_000u32 {
        let big_m = (2 * m + 1) as f64 * std::f64::consts::FRAC_PI_2;
        let amp = 2.0 / (big_m * big_m) * (-big_m * big_m * tau).exp();
        sum += amp;
        if amp < 1e-18 {
            break;
        }
    }
    1.0 - sum
}

/// Method-of-images (ierfc) form of the degree of consolidation U(τ).
pub fn terzaghi_consolidation_images(tau: f64) -> f64 {
    let r = tau.sqrt();
    let mut sum = FRAC_1_SQRT_PI;
    let mut sign = -1.0;
    for n in 1..1_000_000u32 {
        let term = ierfc(n as f64 / r);
        sum += 2.0 * sign * term;
        sign = -sign;
        if term < 1e-18 {
            break;
        }
    }
    2.0 * r * sum
}

// ---------------------------------------------------------------------------------------------
// Cryer
// ---------------------------------------------------------------------------------------------

/// Below this dimensionless time the Cryer centre and mean pressures use the short-time expansion
/// (its truncation error there is below 1e-9; the root series is used above).
pub const CRYER_SHORT_TIME: f64 = 1e-3;

/// Smallest τ for which [`CryerSeries`] computes enough roots (≈ 21 000 roots).
pub const CRYER_MIN_TAU: f64 = 1e-8;

/// Order (in powers of √τ) of the short-time expansion.
const SHORT_ORDER: usize = 10;

/// Roots of Cryer's characteristic equation and the series coefficients, for one ν.
#[derive(Debug, Clone)]
pub struct CryerSeries {
    beta: f64,
    tau_min: f64,
    roots: Vec<f64>,
    /// A_n
    coef: Vec<f64>,
    /// sin ξ_n (computed stably from the root relation)
    sin_root: Vec<f64>,
}

impl CryerSeries {
    /// Series for drained Poisson ratio `nu` (−1 < ν < 1/2), with enough roots that the truncation
    /// error is below ~1e-16 for every τ ≥ `tau_min` (clamped to ≥ [`CRYER_MIN_TAU`]).
    pub fn new(nu: f64, tau_min: f64) -> Result<Self> {
        if !(nu.is_finite() && nu > -1.0 && nu < 0.5) {
            return Err(Error::Material(format!("Cryer solution needs -1 < nu < 0.5 (got {nu})")));
        }
        let tau_min = if tau_min.is_finite() { tau_min.max(CRYER_MIN_TAU) } else { CRYER_MIN_TAU };
        let beta = 2.0 * (1.0 - 2.0 * nu) / (1.0 + nu);
        let gamma = (1.0 + beta) / (3.0 * beta);
        // e^{-ξ² τ} < 1e-20 for ξ > ξ_max; roots are ~π apart.
        let xi_max = (46.0 / tau_min).sqrt();
        let n_roots = (xi_max / std::f64::consts::PI).ceil() as usize + 2;
        let roots = cryer_roots(gamma, n_roots);
        let mut coef = Vec::with_capacity(roots.len());
        let mut sin_root = Vec::with_capacity(roots.len());
        for &xi in &roots {
            coef.push(2.0 * (1.0 + beta) / (3.0 * (1.0 - beta * gamma * gamma * xi * xi)));
            let (s, c) = xi.sin_cos();
            let g = 1.0 - gamma * xi * xi;
            // At a root (1 − γξ²) sin ξ = ξ cos ξ; use it where it is well conditioned.
            sin_root.push(if c.abs() > 0.5 { xi * c / g } else { s });
        }
        Ok(CryerSeries { beta, tau_min, roots, coef, sin_root })
    }

    /// β = 4µ/(3K) = 2(1 − 2ν)/(1 + ν).
    pub fn beta(&self) -> f64 {
        self.beta
    }

    /// The positive roots ξ_n of tan ξ = ξ/(1 − γξ²), increasing.
    pub fn roots(&self) -> &[f64] {
        &self.roots
    }

    /// Smallest τ for which the root series is fully converged.
    pub fn tau_min(&self) -> f64 {
        self.tau_min
    }

    /// Centre pressure p_c/P at dimensionless time τ = c t/a² (τ ≤ 0 gives the 0⁺ value 1).
    pub fn center_pressure(&self, tau: f64) -> f64 {
        if tau.is_nan() {
            return f64::NAN;
        }
        if tau <= 0.0 {
            1.0
        } else if tau < CRYER_SHORT_TIME {
            self.center_pressure_short_time(tau)
        } else {
            self.center_pressure_series(tau)
        }
    }

    /// Root-series value of p_c/P (accurate for τ ≥ [`CryerSeries::tau_min`]).
    pub fn center_pressure_series(&self, tau: f64) -> f64 {
        let mut sum = 0.0;
        for ((&xi, &a), &s) in self.roots.iter().zip(&self.coef).zip(&self.sin_root) {
            let e = (-xi * xi * tau).exp();
            sum += a * (1.0 - xi / s) * e;
            if e < 1e-22 {
                break;
            }
        }
        sum
    }

    /// Short-time expansion of p_c/P (accurate to ~1e-9 for τ ≤ 1e-3, exact as τ → 0).
    pub fn center_pressure_short_time(&self, tau: f64) -> f64 {
        let s = self.short_series();
        eval_short(&s, tau)
    }

    /// Volume-averaged pressure p̄/P at τ (τ ≤ 0 gives 1).
    pub fn mean_pressure(&self, tau: f64) -> f64 {
        if tau.is_nan() {
            return f64::NAN;
        }
        if tau <= 0.0 {
            1.0
        } else if tau < CRYER_SHORT_TIME {
            self.mean_pressure_short_time(tau)
        } else {
            self.mean_pressure_series(tau)
        }
    }

    /// Root-series value of p̄/P.
    pub fn mean_pressure_series(&self, tau: f64) -> f64 {
        let mut sum = 0.0;
        for (&xi, &a) in self.roots.iter().zip(&self.coef) {
            let e = (-xi * xi * tau).exp();
            sum += a * e;
            if e < 1e-22 {
                break;
            }
        }
        -sum / self.beta
    }

    /// Short-time expansion of p̄/P.
    pub fn mean_pressure_short_time(&self, tau: f64) -> f64 {
        // p̄̃ = (1 − F) S / s
        let s = self.short_series();
        let f = short_f();
        let mut m = [0.0; SHORT_ORDER + 1];
        for i in 0..=SHORT_ORDER {
            m[i] = s[i];
            for j in 0..=i {
                m[i] -= f[j] * s[i - j];
            }
        }
        eval_short(&m, tau)
    }

    /// Pressure p/P at radius r = ρ a (0 ≤ ρ ≤ 1) and time τ, from the root series (accurate for
    /// τ ≥ [`CryerSeries::tau_min`]; at smaller τ the truncated series is returned). τ ≤ 0 gives
    /// the 0⁺ value (1 inside, 0 on the surface); ρ outside [0, 1] gives NaN.
    pub fn pressure(&self, rho: f64, tau: f64) -> f64 {
        if !(rho.is_finite() && (0.0..=1.0).contains(&rho)) || tau.is_nan() {
            return f64::NAN;
        }
        if tau <= 0.0 {
            return if rho < 1.0 { 1.0 } else { 0.0 };
        }
        if rho < 1e-9 {
            return self.center_pressure(tau);
        }
        let mut sum = 0.0;
        for ((&xi, &a), &s) in self.roots.iter().zip(&self.coef).zip(&self.sin_root) {
            let e = (-xi * xi * tau).exp();
            sum += a * (1.0 - (xi * rho).sin() / (rho * s)) * e;
            if e < 1e-22 {
                break;
            }
        }
        sum
    }

    /// Time τ and value of the maximum of p_c/P (Mandel–Cryer peak), searched on τ ∈ [1e-6, 2].
    pub fn peak(&self) -> (f64, f64) {
        // coarse log scan, then golden section on ln τ
        let n = 240;
        let (lo, hi) = (1e-6f64.ln(), 2f64.ln());
        let mut best = (lo, f64::MIN);
        for i in 0..=n {
            let lt = lo + (hi - lo) * i as f64 / n as f64;
            let v = self.center_pressure(lt.exp());
            if v > best.1 {
                best = (lt, v);
            }
        }
        let step = (hi - lo) / n as f64;
        let (mut a, mut b) = (best.0 - step, best.0 + step);
        let g = 0.5 * (5f64.sqrt() - 1.0);
        let mut c = b - g * (b - a);
        let mut d = a + g * (b - a);
        let mut fc = self.center_pressure(c.exp());
        let mut fd = self.center_pressure(d.exp());
        for _ in 0..80 {
            if fc > fd {
                b = d;
                d = c;
                fd = fc;
                c = b - g * (b - a);
                fc = self.center_pressure(c.exp());
            } else {
                a = c;
                c = d;
                fc = fd;
                d = a + g * (b - a);
                fd = self.center_pressure(d.exp());
            }
        }
        let t = (0.5 * (a + b)).exp();
        (t, self.center_pressure(t))
    }

    /// Coefficients S_k of S(y) = 1/(1 − bF(y)) = Σ S_k y^k, b = β/(1 + β), F = 3y − 3y².
    fn short_series(&self) -> [f64; SHORT_ORDER + 1] {
        let b = self.beta / (1.0 + self.beta);
        let f = short_f();
        let mut bf = [0.0; SHORT_ORDER + 1];
        for i in 0..=SHORT_ORDER {
            bf[i] = b * f[i];
        }
        // S = 1 + bF S  →  S_k = δ_k0 + Σ_{j≥1} bF_j S_{k−j}
        let mut s = [0.0; SHORT_ORDER + 1];
        s[0] = 1.0;
        for k in 1..=SHORT_ORDER {
            let mut acc = 0.0;
            for j in 1..=k {
                acc += bf[j] * s[k - j];
            }
            s[k] = acc;
        }
        s
    }
}

fn short_f() -> [f64; SHORT_ORDER + 1] {
    let mut f = [0.0; SHORT_ORDER + 1];
    f[1] = 3.0;
    f[2] = -3.0;
    f
}

/// Σ_k c_k τ^{k/2} / Γ(1 + k/2).
fn eval_short(c: &[f64; SHORT_ORDER + 1], tau: f64) -> f64 {
    let r = tau.sqrt();
    let mut sum = 0.0;
    let mut pow = 1.0;
    for (k, &ck) in c.iter().enumerate() {
        sum += ck * pow / gamma_half(k);
        pow *= r;
    }
    sum
}

/// Γ(1 + k/2) for small k.
fn gamma_half(k: usize) -> f64 {
    // Γ(1) = 1, Γ(3/2) = √π/2, Γ(x + 1) = x Γ(x)
    let mut g = if k.is_multiple_of(2) { 1.0 } else { 0.5 / FRAC_1_SQRT_PI };
    let mut x = if k.is_multiple_of(2) { 1.0 } else { 1.5 };
    while x < 1.0 + k as f64 / 2.0 - 1e-9 {
        g *= x;
        x += 1.0;
    }
    g
}

/// First `n` positive roots of G(ξ) = (1 − γξ²) sin ξ − ξ cos ξ (equivalently
/// tan ξ = ξ/(1 − γξ²)), by scanning in steps of π/40 for sign changes and bisecting each bracket
/// to machine precision. G has no poles, and sin ξ = 0 is never a root, so the sign changes are
/// exactly the roots of the characteristic equation (ξ = 0 excluded).
fn cryer_roots(gamma: f64, n: usize) -> Vec<f64> {
    let g = |x: f64| (1.0 - gamma * x * x) * x.sin() - x * x.cos();
    let step = std::f64::consts::PI / 40.0;
    let mut roots = Vec::with_capacity(n);
    let mut a = 0.5 * step;
    let mut ga = g(a);
    let mut i = 0usize;
    while roots.len() < n && i < 200 * (n + 10) {
        i += 1;
        let b = a + step;
        let gb = g(b);
        if gb == 0.0 {
            roots.push(b);
        } else if ga * gb < 0.0 {
            let (mut lo, mut hi, mut glo) = (a, b, ga);
            for _ in 0..200 {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                let gm = g(mid);
                if gm == 0.0 {
                    lo = mid;
                    hi = mid;
                    break;
                }
                if (gm < 0.0) == (glo < 0.0) {
                    lo = mid;
                    glo = gm;
                } else {
                    hi = mid;
                }
            }
            roots.push(0.5 * (lo + hi));
        }
        a = b;
        ga = gb;
    }
    roots
}

/// Cryer centre pressure normalised by the load, p_c(t)/P, for a sphere of radius `radius`
/// (starts at 1 at t = 0⁺, rises above 1, then decays to 0). NaN for invalid parameters.
/// Builds the root table on every call (~0.1 ms); for many evaluations build one [`CryerSeries`].
pub fn cryer_center_pressure(t: f64, radius: f64, mat: &Drained) -> f64 {
    let Some(tau) = cryer_tau(t, radius, mat) else {
        return f64::NAN;
    };
    match CryerSeries::new(mat.nu, tau.max(CRYER_SHORT_TIME)) {
        Ok(s) => s.center_pressure(tau),
        Err(_) => f64::NAN,
    }
}

/// Cryer pressure normalised by the load, p(r, t)/P, 0 ≤ r ≤ a (accurate for c t/a² ≥ 1e-8).
/// Builds a root table sized for this t on every call (thousands of roots for very small t);
/// for many evaluations build one [`CryerSeries`] with the smallest τ needed.
pub fn cryer_pressure(r: f64, t: f64, radius: f64, mat: &Drained) -> f64 {
    let Some(tau) = cryer_tau(t, radius, mat) else {
        return f64::NAN;
    };
    let rho = r / radius;
    let rho = if rho > 1.0 && rho < 1.0 + 1e-12 { 1.0 } else { rho };
    match CryerSeries::new(mat.nu, tau) {
        Ok(s) => s.pressure(rho, tau),
        Err(_) => f64::NAN,
    }
}

/// Radial displacement of the Cryer sphere's surface, u_r(a, t) = −(a P/(3K)) (1 − p̄/P), outward
/// positive (so ≤ 0 under a compressive load `load` > 0): 0 at t = 0⁺, −a P/(3K) as t → ∞.
pub fn cryer_surface_displacement(t: f64, radius: f64, load: f64, mat: &Drained) -> f64 {
    let Some(tau) = cryer_tau(t, radius, mat) else {
        return f64::NAN;
    };
    if !load.is_finite() {
        return f64::NAN;
    }
    match CryerSeries::new(mat.nu, tau.max(CRYER_SHORT_TIME)) {
        Ok(s) => -radius * load / (3.0 * mat.bulk_modulus()) * (1.0 - s.mean_pressure(tau)),
        Err(_) => f64::NAN,
    }
}

fn cryer_tau(t: f64, radius: f64, mat: &Drained) -> Option<f64> {
    if mat.is_valid() && radius > 0.0 && radius.is_finite() && t.is_finite() {
        Some(mat.consolidation_coefficient() * t / (radius * radius))
    } else {
        None
    }
}

mod special;
#[cfg(test)]
mod tests;

pub use special::{erfc, ierfc};
