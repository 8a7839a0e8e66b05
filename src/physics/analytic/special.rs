//! The complementary error function and its first integral, for the short-time forms of the
//! series.

use super::FRAC_1_SQRT_PI;

/// Complementary error function, absolute error below 1e-15 (series for |x| < 2, continued
/// fraction beyond, relative error ~1e-15 there).
pub fn erfc(x: f64) -> f64 {
    if x.is_nan() {
        return f64::NAN;
    }
    if x < 0.0 {
        return 2.0 - erfc(-x);
    }
    if x < 2.0 {
        // erf x = (2/√π) e^{-x²} Σ_n (2x²)^n x / (1·3···(2n+1)), all terms positive.
        let x2 = x * x;
        let mut term = x;
        let mut sum = x;
        let mut n = 0.0;
        while term > 1e-17 * sum {
            n += 1.0;
            term *= 2.0 * x2 / (2.0 * n + 1.0);
            sum += term;
            if n > 500.0 {
                break;
            }
        }
        1.0 - 2.0 * FRAC_1_SQRT_PI * (-x2).exp() * sum
    } else if x > 27.3 {
        0.0
    } else {
        // erfc x = e^{-x²}/√π / (x + (1/2)/(x + 1/(x + (3/2)/(x + ...)))), modified Lentz.
        let tiny = 1e-300;
        let mut f = x;
        let mut c = x;
        let mut d = 0.0;
        for i in 1..2000 {
            let a = 0.5 * i as f64;
            d = x + a * d;
            if d.abs() < tiny {
                d = tiny;
            }
            d = 1.0 / d;
            c = x + a / c;
            if c.abs() < tiny {
                c = tiny;
            }
            let delta = c * d;
            f *= delta;
            if (delta - 1.0).abs() < 1e-16 {
                break;
            }
        }
        FRAC_1_SQRT_PI * (-x * x).exp() / f
    }
}

/// First integral of erfc: ierfc(x) = ∫_x^∞ erfc(s) ds = e^{−x²}/√π − x erfc(x).
pub fn ierfc(x: f64) -> f64 {
    FRAC_1_SQRT_PI * (-x * x).exp() - x * erfc(x)
}
