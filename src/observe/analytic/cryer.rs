//! Cryer's consolidation of a sphere under a uniform compressive traction.
//!
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

#[cfg(test)]
use super::drained::Drained;
use super::special::gamma_half;
use crate::error::{Error, Result};

/// Below this dimensionless time the Cryer centre and mean pressures use the short-time expansion
/// (its truncation error there is below 1e-9; the root series is used above).
const CRYER_SHORT_TIME: f64 = 1e-3;

/// Smallest τ for which [`CryerSeries`] computes enough roots (≈ 21 000 roots).
const CRYER_MIN_TAU: f64 = 1e-8;

/// Order (in powers of √τ) of the short-time expansion.
const SHORT_ORDER: usize = 10;

/// Roots of Cryer's characteristic equation and the series coefficients, for one ν.
#[derive(Debug, Clone)]
pub(crate) struct CryerSeries {
    /// β = 4µ/(3K) = 2(1 − 2ν)/(1 + ν).
    beta: f64,
    roots: Vec<f64>,
    /// A_n
    coef: Vec<f64>,
    /// sin ξ_n (computed stably from the root relation)
    sin_root: Vec<f64>,
}

impl CryerSeries {
    /// Series for drained Poisson ratio `nu` (−1 < ν < 1/2), with enough roots that the truncation
    /// error is below ~1e-16 for every τ ≥ `tau_min` (clamped to ≥ 1e-8).
    pub(crate) fn new(nu: f64, tau_min: f64) -> Result<Self> {
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
        Ok(CryerSeries { beta, roots, coef, sin_root })
    }

    /// Centre pressure p_c/P at dimensionless time τ = c t/a² (τ ≤ 0 gives the 0⁺ value 1).
    pub(crate) fn center_pressure(&self, tau: f64) -> f64 {
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

    /// Root-series value of p_c/P (accurate for τ at or above the `tau_min` it was built for).
    fn center_pressure_series(&self, tau: f64) -> f64 {
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
    fn center_pressure_short_time(&self, tau: f64) -> f64 {
        let s = self.short_series();
        eval_short(&s, tau)
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

/// The test oracles: the root table, the mean pressure, the pressure profile, the peak.
#[cfg(test)]
impl CryerSeries {
    /// The positive roots ξ_n of tan ξ = ξ/(1 − γξ²), increasing.
    fn roots(&self) -> &[f64] {
        &self.roots
    }

    /// Volume-averaged pressure p̄/P at τ (τ ≤ 0 gives 1).
    fn mean_pressure(&self, tau: f64) -> f64 {
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
    fn mean_pressure_series(&self, tau: f64) -> f64 {
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
    fn mean_pressure_short_time(&self, tau: f64) -> f64 {
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
    /// τ at or above the `tau_min` it was built for; at smaller τ the truncated series is returned). τ ≤ 0 gives
    /// the 0⁺ value (1 inside, 0 on the surface); ρ outside [0, 1] gives NaN.
    fn pressure(&self, rho: f64, tau: f64) -> f64 {
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
    fn peak(&self) -> (f64, f64) {
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

// The series in physical units, for the tests.

/// Cryer centre pressure normalised by the load, p_c(t)/P, for a sphere of radius `radius`
/// (starts at 1 at t = 0⁺, rises above 1, then decays to 0). NaN for invalid parameters.
/// Builds the root table on every call (~0.1 ms); for many evaluations build one [`CryerSeries`].
#[cfg(test)]
fn cryer_center_pressure(t: f64, radius: f64, mat: &Drained) -> f64 {
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
#[cfg(test)]
fn cryer_pressure(r: f64, t: f64, radius: f64, mat: &Drained) -> f64 {
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
#[cfg(test)]
fn cryer_surface_displacement(t: f64, radius: f64, load: f64, mat: &Drained) -> f64 {
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

#[cfg(test)]
fn cryer_tau(t: f64, radius: f64, mat: &Drained) -> Option<f64> {
    if mat.is_valid() && radius > 0.0 && radius.is_finite() && t.is_finite() {
        Some(mat.consolidation_coefficient() * t / (radius * radius))
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::super::reference::{cryer_fd, nanmax};
    use super::*;

    #[test]
    fn cryer_initial_value_peak_and_decay() {
        let mut peaks = Vec::new();
        for nu in [0.0, 0.2, 0.3] {
            let s = CryerSeries::new(nu, 1e-4).unwrap();
            assert_eq!(s.center_pressure(0.0), 1.0);
            assert!((s.center_pressure(1e-12) - 1.0).abs() < 1e-5);
            assert!((s.mean_pressure(1e-12) - 1.0).abs() < 1e-5);
            let (tp, vp) = s.peak();
            println!("Cryer nu = {nu}: peak p_c/P = {vp:.6} at c t/a^2 = {tp:.5}");
            assert!(vp > 1.0);
            // decays to ~0 for τ ≥ 1
            assert!(s.center_pressure(1.0) < 0.04 && s.center_pressure(2.0) < 1e-3);
            assert!(s.center_pressure(1.0) > 0.0);
            peaks.push((nu, tp, vp));
        }
        // ν = 0.2 reference values (this implementation; confirmed by the FD test below)
        let (_, tp, vp) = peaks[1];
        assert!((vp - 1.3643).abs() < 2e-4 && (tp - 0.0522).abs() < 5e-4, "{vp} {tp}");
        // smaller ν → larger peak
        assert!(peaks[0].2 > peaks[1].2 && peaks[1].2 > peaks[2].2);
    }

    #[test]
    fn cryer_series_matches_short_time_expansion_and_literature_form() {
        for nu in [-0.3, 0.0, 0.2, 0.3, 0.45] {
            let s = CryerSeries::new(nu, 1e-5).unwrap();
            for tau in [1e-5, 1e-4, 1e-3, 3e-3] {
                let d1 = s.center_pressure_series(tau) - s.center_pressure_short_time(tau);
                let d2 = s.mean_pressure_series(tau) - s.mean_pressure_short_time(tau);
                assert!(d1.abs() < 1e-12 && d2.abs() < 1e-12, "nu {nu} tau {tau}: {d1:e} {d2:e}");
            }
            // Detournay & Cheng (1993) form in the incompressible limit, η = (1−ν)/(1−2ν):
            // p_c/P = Σ η (sin ξ − ξ) e^{−ξ²τ} / (η ξ cos ξ / 2 + (η − 1) sin ξ),
            // with (1 − η ξ²/2) tan ξ = ξ.
            let eta = (1.0 - nu) / (1.0 - 2.0 * nu);
            for &xi in &s.roots()[..50] {
                let res = (1.0 - eta * xi * xi / 2.0) * xi.tan() - xi;
                assert!(res.abs() < 1e-9 * (1.0 + eta * xi * xi), "root {xi}: {res:e}");
            }
            for tau in [0.01, 0.05, 0.2] {
                let lit: f64 = s
                    .roots()
                    .iter()
                    .map(|&xi| {
                        eta * (xi.sin() - xi) * (-xi * xi * tau).exp()
                            / (eta * xi * xi.cos() / 2.0 + (eta - 1.0) * xi.sin())
                    })
                    .sum();
                assert!((lit - s.center_pressure(tau)).abs() < 1e-9, "nu {nu} tau {tau}");
            }
            // roots: one per interval, increasing, spacing → π
            let r = s.roots();
            for w in r.windows(2) {
                assert!(w[1] > w[0] + 2.0);
            }
            // pressure profile: centre value at ρ = 0, zero on the surface
            for tau in [1e-3, 0.05, 0.3] {
                assert!((s.pressure(0.0, tau) - s.center_pressure(tau)).abs() < 1e-8);
                assert!((s.pressure(1e-6, tau) - s.center_pressure(tau)).abs() < 1e-8);
                assert!(s.pressure(1.0, tau).abs() < 1e-8);
            }
        }
        assert!(CryerSeries::new(0.5, 1e-3).is_err());
    }

    #[test]
    fn cryer_matches_coupled_finite_differences() {
        let times = [1e-3, 0.01, 0.03, 0.05, 0.1, 0.2, 0.5];
        let n = 400;
        for nu in [0.0, 0.2, 0.3] {
            let fd = cryer_fd(nu, n, &times);
            assert_eq!(fd.len(), times.len());
            let s = CryerSeries::new(nu, 1e-4).unwrap();
            let mat = Drained::new(1.0, nu, 1.0 / (2.0 * (1.0 - nu) / (1.0 - 2.0 * nu))).unwrap();
            assert!((mat.consolidation_coefficient() - 1.0).abs() < 1e-14);
            let (mut wc, mut wr, mut wu) = (0.0f64, 0.0f64, 0.0f64);
            for (k, &tau) in times.iter().enumerate() {
                // centre: first cell centre is at h/2 (p is even in r: O(h²) offset)
                wc = nanmax(wc, fd[k].p[0] - s.center_pressure(tau));
                // profile at cell centres near r = a/2 and r = 0.9 a
                for j in [n / 2, 9 * n / 10] {
                    let rho = (j as f64 + 0.5) / n as f64;
                    wr = nanmax(wr, fd[k].p[j] - s.pressure(rho, tau));
                }
                // surface displacement (P = 1, a = 1), relative to its final value
                let ua = cryer_surface_displacement(tau, 1.0, 1.0, &mat);
                wu = nanmax(wu, (fd[k].u[n] - ua) * 3.0 * mat.bulk_modulus());
            }
            println!(
                "Cryer nu = {nu}: max |FV - series| centre {wc:.2e}, profile {wr:.2e}, \
                 surface displacement (rel. to final) {wu:.2e}"
            );
            // observed ≤ 5.3e-5 with n = 400 (O(h²) + O(dt²) convergence checked up to n = 800)
            assert!(wc < 1e-4 && wr < 1e-4 && wu < 1e-4, "{wc:e} {wr:e} {wu:e}");
        }
    }

    #[test]
    fn cryer_free_functions_and_units() {
        let m = Drained::new(2.0, 0.2, 0.1).unwrap();
        let a = 3.0;
        let c = m.consolidation_coefficient();
        let s = CryerSeries::new(0.2, 1e-4).unwrap();
        for tau in [0.0, 1e-4, 0.02, 0.3] {
            let t = tau * a * a / c;
            assert!((cryer_center_pressure(t, a, &m) - s.center_pressure(tau)).abs() < 1e-12);
            assert!((cryer_pressure(0.5 * a, t, a, &m) - s.pressure(0.5, tau)).abs() < 1e-10);
        }
        // surface displacement: 0 at 0⁺, −aP/(3K) at ∞, negative in between
        let load = 4.0;
        assert_eq!(cryer_surface_displacement(0.0, a, load, &m), 0.0);
        let u_inf = -a * load / (3.0 * m.bulk_modulus());
        let u_late = cryer_surface_displacement(10.0 * a * a / c, a, load, &m);
        assert!((u_late - u_inf).abs() < 1e-12 * u_inf.abs());
        let u_mid = cryer_surface_displacement(0.05 * a * a / c, a, load, &m);
        assert!(u_mid < 0.0 && u_mid > u_inf);
        assert!(cryer_center_pressure(1.0, -1.0, &m).is_nan());
        assert!(cryer_pressure(2.0 * a, 1.0, a, &m).is_nan());
    }
}
