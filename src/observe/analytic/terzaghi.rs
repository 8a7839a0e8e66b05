//! Terzaghi's consolidation of a laterally confined column.
//!
//! Column 0 ≤ z ≤ H, impermeable and fixed bottom z = 0, drained (p = 0) loaded top z = H,
//! laterally confined. With depth d = 1 − z/H and M_m = (2m + 1)π/2:
//! p/P = Σ_m (2/M_m) sin(M_m d) e^{−M_m² τ},
//! settlement w(t) = P H/(λ + 2µ) · [1 − Σ_m (2/M_m²) e^{−M_m² τ}].
//! Short times use the method-of-images form
//! p/P = 1 − Σ_n (−1)^n [erfc((2n + d)/(2√τ)) + erfc((2n + 2 − d)/(2√τ))],
//! w = P H/(λ + 2µ) · 2√τ [1/√π + 2 Σ_{n≥1} (−1)^n ierfc(n/√τ)].
//!

use super::drained::Drained;
use super::special::{erfc, ierfc, FRAC_1_SQRT_PI};

/// Below this dimensionless time the Terzaghi functions use the erfc (images) form.
const TERZAGHI_SHORT_TIME: f64 = 0.1;

/// Terzaghi pore pressure p(z, t) [same unit as `load`] in a column of height `height` loaded at
/// t = 0⁺ by a compressive traction `load` on its drained top z = H (bottom z = 0 impermeable and
/// fixed). p(z, 0⁺) = P for z < H; p(H, t) = 0. z is clamped to [0, H] within 1e-12 H; beyond
/// that, and for invalid parameters, the result is NaN.
pub(crate) fn terzaghi_pressure(z: f64, t: f64, height: f64, load: f64, mat: &Drained) -> f64 {
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
pub(crate) fn terzaghi_settlement(t: f64, height: f64, load: f64, mat: &Drained) -> f64 {
    if !(mat.is_valid() && height > 0.0 && height.is_finite() && load.is_finite() && t.is_finite()) {
        return f64::NAN;
    }
    let tau = mat.consolidation_coefficient() * t / (height * height);
    load * height / mat.oedometric_modulus() * terzaghi_consolidation_degree(tau)
}

/// Dimensionless Terzaghi pressure p/P at ζ = z/H ∈ [0, 1], τ = c t/H² (form chosen by τ).
fn terzaghi_pressure_dimensionless(zeta: f64, tau: f64) -> f64 {
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
fn terzaghi_consolidation_degree(tau: f64) -> f64 {
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
fn terzaghi_pressure_fourier(zeta: f64, tau: f64) -> f64 {
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
fn terzaghi_pressure_images(zeta: f64, tau: f64) -> f64 {
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
fn terzaghi_consolidation_fourier(tau: f64) -> f64 {
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
fn terzaghi_consolidation_images(tau: f64) -> f64 {
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

#[cfg(test)]
mod tests {
    use super::super::reference::{nanmax, terzaghi_fd};
    use super::*;

    fn soil() -> Drained {
        Drained::new(3.0, 0.25, 2e-3).unwrap()
    }

    #[test]
    fn terzaghi_initial_and_final_states() {
        let m = soil();
        let (h, p) = (2.0, 5.0);
        let c = m.consolidation_coefficient();
        // t = 0⁺: P in the interior, 0 at the drained top
        for z in [0.0, 0.5, 1.0, 1.9, 1.999] {
            assert!((terzaghi_pressure(z, 0.0, h, p, &m) - p).abs() < 1e-14);
            assert!((terzaghi_pressure(z, 1e-9 * h * h / c, h, p, &m) - p).abs() < 1e-10);
        }
        assert_eq!(terzaghi_pressure(h, 0.0, h, p, &m), 0.0);
        assert!(terzaghi_pressure(h, 0.3 * h * h / c, h, p, &m).abs() < 1e-14);
        // settlement: 0 at 0⁺, P H/(λ+2µ) at ∞, monotone
        let w_inf = p * h / m.oedometric_modulus();
        assert_eq!(terzaghi_settlement(0.0, h, p, &m), 0.0);
        assert!(terzaghi_settlement(1e-12, h, p, &m) < 1e-6 * w_inf);
        assert!((terzaghi_settlement(50.0 * h * h / c, h, p, &m) - w_inf).abs() < 1e-12 * w_inf);
        let mut last = 0.0;
        for i in 1..200 {
            let t = 1e-5 * 1.1f64.powi(i) * h * h / c;
            let w = terzaghi_settlement(t, h, p, &m);
            assert!(w >= last && w <= w_inf * (1.0 + 1e-14));
            last = w;
        }
        // classic values: U(τ) ≈ 2√(τ/π) for small τ; U(0.2) = 0.504 (tables: 0.5041)
        assert!((terzaghi_consolidation_degree(1e-4) - 2.0 * (1e-4 / std::f64::consts::PI).sqrt()).abs() < 1e-14);
        assert!((terzaghi_consolidation_degree(0.2) - 0.5041).abs() < 1e-4);
        // invalid input
        assert!(terzaghi_pressure(3.0, 1.0, h, p, &m).is_nan());
        assert!(terzaghi_pressure(1.0, 1.0, -1.0, p, &m).is_nan());
        let bad = Drained { mu: 1.0, nu: 0.5, k: 1.0 };
        assert!(terzaghi_settlement(1.0, h, p, &bad).is_nan());
        assert!(Drained::new(1.0, 0.5, 1.0).is_err());
    }

    #[test]
    fn terzaghi_fourier_and_images_forms_agree() {
        let mut worst: f64 = 0.0;
        for tau in [1e-3, 0.01, 0.05, 0.1, 0.3, 1.0] {
            for i in 0..=40 {
                let z = i as f64 / 40.0;
                worst = nanmax(worst, (terzaghi_pressure_fourier(z, tau) - terzaghi_pressure_images(z, tau)).abs());
            }
            worst = nanmax(worst, (terzaghi_consolidation_fourier(tau) - terzaghi_consolidation_images(tau)).abs());
        }
        assert!(worst < 1e-13, "forms differ by {worst:e}");
    }

    #[test]
    fn terzaghi_matches_crank_nicolson() {
        let times = [0.01, 0.05, 0.2, 0.5];
        let n = 400;
        let fd = terzaghi_fd(n, 2e-5, &times);
        let mut worst: f64 = 0.0;
        for (k, &tau) in times.iter().enumerate() {
            for node in [0, 100, 200, 300, 360, 399] {
                let zeta = node as f64 / n as f64;
                let exact = terzaghi_pressure_dimensionless(zeta, tau);
                worst = nanmax(worst, (fd[k][node] - exact).abs());
            }
        }
        println!("Terzaghi: max |CN - series| = {worst:e}");
        assert!(worst < 1e-4, "{worst:e}");
    }
}
