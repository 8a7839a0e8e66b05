//! The independent reference for a liquid drop squeezed between two parallel plates: the
//! axisymmetric Young–Laplace (Delaunay) equilibrium of a drop of volume V between plates at the
//! gap H, with the surface tension γ and the contact angle θ on both plates (inside the liquid;
//! θ = 180° non-adhesive, Young–Dupré cos θ = w/γ − 1 with the work of adhesion w), no gravity.
//! It shares no code with poroplast: the profile's ODE integrated by RK4 and shot on its one
//! shape parameter.
//!
//! The profile, symmetric about the mid-plane, is followed in arc length s from the equator
//! (r = R2, z = 0, the surface vertical) towards the upper plate z = H/2:
//!
//!     r' = cos φ,   z' = sin φ,   φ' = ΔP/γ − sin φ / r,
//!
//! φ the tangent's angle to the plate (π/2 at the equator; the contact angle is φ where the
//! profile meets the plate). Lengths scaled by R2 leave one parameter, c = ΔP R2/γ = 1 + R2/R1
//! (R1 the meridional curvature radius at the equator): each c gives a profile that reaches
//! φ = θ at the height h(c) R2 with the half-volume v(c) R2³, so the drop's V/H³ = v/(4h³) fixes
//! c (bisection), and H = 2 h R2 then R2. The force that pushes the upper plate off, the pressure
//! on the wetted disc less the tension's pull at the contact line,
//!
//!     F = π R3² ΔP − 2π R3 γ sin θ,
//!
//! is the same through every horizontal section (the first integral
//! π r² ΔP − 2π r γ sin φ = F), through the mid-plane F = π R2² ΔP − 2π R2 γ: both are returned,
//! their agreement a check of the integration.

use std::f64::consts::{FRAC_PI_2, PI};

/// The equilibrium of a drop between plates (µm, kPa = mN/m / µm, nN).
#[derive(Clone, Debug)]
pub struct Bridge {
    /// Laplace pressure ΔP = γ (1/R1 + 1/R2), kPa.
    pub dp: f64,
    /// Meridional curvature radius at the equator (positive for a bulge, infinite for the cylinder).
    pub r1: f64,
    /// Equatorial radius (half the width), µm.
    pub r2: f64,
    /// Contact radius on each plate, µm.
    pub r3: f64,
    /// Force on a plate from the contact (F = π R3² ΔP − 2π R3 γ sin θ), nN; compressive > 0.
    pub force: f64,
    /// The same force through the mid-plane, π R2² ΔP − 2π R2 γ, nN.
    pub force_mid: f64,
    /// The upper half's profile from the equator to the plate: (r, z, φ), µm and radians.
    pub profile: Vec<[f64; 3]>,
}

/// The contact angle of Young–Dupré for the work of adhesion `w` (mN/m) and tension `gamma`.
pub fn young_dupre(gamma: f64, w: f64) -> f64 {
    (w / gamma - 1.0).acos()
}

/// nN → mg (the history's unit: 1 mg = 9.81 µN).
pub fn mg(nn: f64) -> f64 {
    nn * 1e-3 / 9.81
}

/// Where the scaled profile (R2 = 1, ΔP/γ = c) first reaches φ = θ: (h, v, r3, profile), or None
/// if it turns back to vertical, reaches the axis or runs past 40 R2 before.
fn shoot(c: f64, theta: f64, keep: bool) -> Option<(f64, f64, f64, Vec<[f64; 3]>)> {
    // y = (r, z, φ, half-volume)
    let rhs = |y: &[f64; 4]| -> [f64; 4] {
        let (r, phi) = (y[0], y[2]);
        [phi.cos(), phi.sin(), c - phi.sin() / r, PI * r * r * phi.sin()]
    };
    let rk4 = |y: &[f64; 4], h: f64| -> [f64; 4] {
        let add = |a: &[f64; 4], k: &[f64; 4], f: f64| std::array::from_fn(|i| a[i] + f * k[i]);
        let k1 = rhs(y);
        let k2 = rhs(&add(y, &k1, h / 2.0));
        let k3 = rhs(&add(y, &k2, h / 2.0));
        let k4 = rhs(&add(y, &k3, h));
        std::array::from_fn(|i| y[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]))
    };
    let up = theta > FRAC_PI_2; // φ grows from π/2 to θ (a bulge) or falls (a neck)
    let past = |phi: f64| if up { phi >= theta } else { phi <= theta };
    let base = 1e-3 / (c - 1.0).abs().max(1.0);
    let mut y = [1.0, 0.0, FRAC_PI_2, 0.0];
    let mut s = 0.0;
    let mut profile = Vec::new();
    loop {
        if keep {
            profile.push([y[0], y[1], y[2]]);
        }
        let h = base.min(0.02 * y[0]);
        let next = rk4(&y, h);
        if !next.iter().all(|v| v.is_finite()) || next[0] <= 0.0 {
            return None;
        }
        if past(next[2]) {
            // The fraction of the step that lands on φ = θ (bisection on the step's length).
            let (mut lo, mut hi) = (0.0, h);
            for _ in 0..80 {
                let mid = 0.5 * (lo + hi);
                if past(rk4(&y, mid)[2]) {
                    hi = mid;
                } else {
                    lo = mid;
                }
            }
            let end = rk4(&y, 0.5 * (lo + hi));
            if keep {
                profile.push([end[0], end[1], end[2]]);
            }
            return Some((end[1], end[3], end[0], profile));
        }
        // Turned back to vertical without reaching θ (an unduloid's half period), or too long.
        let back = if up { next[2] < FRAC_PI_2 } else { next[2] > FRAC_PI_2 };
        s += h;
        if (s > 1e-6 && back) || s > 40.0 {
            return None;
        }
        y = next;
    }
}

/// The Young–Laplace equilibrium of the drop of volume `volume` (µm³) between plates at the gap
/// `gap` (µm), tension `gamma` (mN/m), contact angle `theta` (radians, in (0, π]).
pub fn young_laplace(gap: f64, volume: f64, gamma: f64, theta: f64) -> Bridge {
    assert!(theta > 0.0 && theta <= PI, "contact angle {theta}");
    let target = volume / gap.powi(3);
    if (theta - FRAC_PI_2).abs() < 1e-12 {
        // The cylinder (c = 1: the profile never leaves the vertical).
        let r = (volume / (PI * gap)).sqrt();
        let dp = gamma / r;
        let profile = vec![[r, 0.0, FRAC_PI_2], [r, gap / 2.0, FRAC_PI_2]];
        let force = PI * r * r * dp - 2.0 * PI * r * gamma;
        return Bridge { dp, r1: f64::INFINITY, r2: r, r3: r, force, force_mid: force, profile };
    }
    // c = 1 ± e^x: the scaled volume v/(4h³) grows with x, from 0 (no crossing, or a tall
    // bridge) to the pancake's ∞; the first x past the target brackets it.
    let sign = if theta > FRAC_PI_2 { 1.0 } else { -1.0 };
    let cof = |x: f64| 1.0 + sign * x.exp();
    let excess = |x: f64| match shoot(cof(x), theta, false) {
        Some((h, v, _, _)) => v / (4.0 * h.powi(3)) - target,
        None => -target,
    };
    let mut x = -14.0;
    let mut prev = excess(x);
    assert!(prev < 0.0, "V/H³ = {target} is below the family's start");
    let hi = loop {
        let next = x + 0.05;
        let e = excess(next);
        if e >= 0.0 {
            break next;
        }
        assert!(next < 8.0, "no Young–Laplace bridge for V/H³ = {target}, θ = {theta}");
        (x, prev) = (next, e);
    };
    let (mut lo, mut hi) = (x, hi);
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if excess(mid) < 0.0 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let _ = prev;
    let c = cof(0.5 * (lo + hi));
    let (h, _, r3, profile) = shoot(c, theta, true).expect("the bracketed profile");
    let r2 = gap / (2.0 * h);
    let dp = gamma * c / r2;
    let r3 = r3 * r2;
    Bridge {
        dp,
        r1: r2 / (c - 1.0),
        r2,
        r3,
        force: PI * r3 * r3 * dp - 2.0 * PI * r3 * gamma * theta.sin(),
        force_mid: PI * r2 * r2 * dp - 2.0 * PI * r2 * gamma,
        profile: profile.into_iter().map(|[r, z, phi]| [r * r2, z * r2, phi]).collect(),
    }
}
