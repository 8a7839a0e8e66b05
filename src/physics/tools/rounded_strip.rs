//! The rounded semi-infinite strip, the section of the flat punch and of the pipette's wall:
//! ρ_c − h ≤ ρ ≤ ρ_c + h, ζ ≤ 0, its two front corners rounded with radius r ≤ h. Its signed
//! distance is exact (Euclidean) inside and outside:
//!
//!   q_ρ = |ρ − ρ_c| − (h − r),  q_ζ = ζ + r,
//!   φ = |(max(q_ρ, 0), max(q_ζ, 0))| + min(max(q_ρ, q_ζ), 0) − r,
//!
//! and C¹ across the lines where the rounding meets the flat faces (the curvature jumps there).
//! Why exact: the closest-point projection x − φ∇φ, which makes the contact exact, holds only
//! for a true distance.

use super::sdf::Sdf2;

/// The strip centred at `rc` (its ρ_c), of half-width `h`, corners rounded with radius `r`
/// (0 < r ≤ h; the profile's checks ensure it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct RoundedStrip {
    pub(crate) rc: f64,
    pub(crate) h: f64,
    pub(crate) r: f64,
}

impl RoundedStrip {
    /// φ, ∇φ, its Hessian and the closest point at (ρ, ζ), by zone (off the medial axis, where
    /// the closest point is unique).
    pub(crate) fn sdf(&self, rho: f64, zeta: f64) -> Sdf2 {
        let RoundedStrip { rc, h, r } = *self;
        let d = (rho - rc).abs();
        // The side of the strip's mid-line the point is on (on it: the outer side).
        let s = if rho >= rc { 1.0 } else { -1.0 };
        let q_rho = d - (h - r);
        let q_zeta = zeta + r;
        let side = || Sdf2::flat(d - h, [s, 0.0], [rc + s * h, zeta]);
        let front = || Sdf2::flat(zeta, [0.0, 1.0], [rho, 0.0]);
        if q_rho > 0.0 && q_zeta > 0.0 {
            // The rounded corner: the circle of centre (ρ_c ± (h − r), −r) and radius r.
            let n = q_rho.hypot(q_zeta);
            let g = [s * q_rho / n, q_zeta / n];
            let centre = [rc + s * (h - r), -r];
            Sdf2::curved(n - r, g, 1.0 / n, [centre[0] + r * g[0], centre[1] + r * g[1]])
        } else if q_rho > 0.0 || (q_zeta <= 0.0 && q_rho > q_zeta) {
            // Beside the wall below the rounding, or inside nearer the side than the front.
            side()
        } else {
            front()
        }
    }
}
