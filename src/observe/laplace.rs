//! The lab's Laplace analysis of a compressed aggregate (tissue surface tensiometry), on the
//! model: from the current boundary's profile in the (r, z) half-plane (the meridian's nodes,
//! or every surface node of a 3-D mesh at r = √(x² + y²): a profile fitted to the cloud),
//!
//! * R2, the equatorial radius, and R1, the radius of curvature of the profile there (signed:
//!   positive for a bulge, negative for a neck), from a least-squares sextic r(z) over the
//!   middle half of the gap and its stationary point nearest the mid-plane;
//! * R3, the radius of the contact with the upper plate, between nodes: the circle through the
//!   three free nodes nearest the contact edge, cut with the plate (or its point nearest the
//!   plate, for a tangent contact);
//! * σ_app = F / (π R3² (1/R1 + 1/R2)), the apparent surface tension: the surface tension
//!   that balances the plate force F by the Laplace pressure at the equator, acting on the
//!   contact area. It equals γ for a liquid at rest on non-adhesive plates (the surface meets
//!   them tangentially, so the plate carries the pressure alone); residual elasticity, yield,
//!   incomplete relaxation and adhesion bias it.
//!
//! Units: µm, nN; σ_app in nN/µm = mN/m.

use crate::io::recorder::Declared;
use crate::physics::contact::Touch;
use nalgebra::{DMatrix, DVector};

/// The `history.csv` columns of a [`Reading`] (the experiment's last; `history.csv` and the run
/// summary say NaN where a reading does not apply).
pub(crate) const COLUMNS: [Declared<Reading>; 4] = [
    Declared::real(
        "R1",
        "µm",
        "the Laplace analysis of the profile ([model](model.md), \"The lab's Laplace analysis\"): the radius of \
         curvature of the profile at the equator (negative for a neck); NaN without enough free nodes between the \
         plates to fit the profile",
        |r| r.r1,
    ),
    Declared::real("R2", "µm", "the equatorial radius of the profile; NaN where R1 is", |r| r.r2),
    Declared::real(
        "R3",
        "µm",
        "the radius of the contact with the upper plate, between nodes; NaN without upper contact",
        |r| r.r3,
    ),
    Declared::real(
        "sigma_app",
        "mN/m",
        "the apparent surface tension F / (π R3² (1/R1 + 1/R2)) the lab would read; NaN where R1, R2 or R3 is",
        |r| r.sigma_app,
    ),
];

/// One surface node in the (r, z) half-plane.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Point {
    pub(crate) r: f64,
    pub(crate) z: f64,
    pub(crate) side: Touch,
}

/// The Laplace analysis of one state; NaN where it does not apply (no contact, too few nodes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Reading {
    pub(crate) r1: f64,
    pub(crate) r2: f64,
    pub(crate) r3: f64,
    pub(crate) sigma_app: f64,
}

/// Free nodes a sextic needs at least (else a quartic from 7, a parabola from 3).
const SEXTIC_POINTS: usize = 11;
const QUARTIC_POINTS: usize = 7;
/// Free nodes nearest the contact edge the circle passes through.
const EDGE_POINTS: usize = 3;

/// The reading of `points` between the plates at `z_lower` < `z_upper` under the upper
/// plate's force `force` (nN, full sphere).
pub(crate) fn read(points: &[Point], z_lower: f64, z_upper: f64, force: f64) -> Reading {
    let (r1, r2) = equator(points, z_lower, z_upper).unwrap_or((f64::NAN, f64::NAN));
    let r3 = contact_radius(points, z_lower, z_upper).unwrap_or(f64::NAN);
    let pressure_per_tension = 1.0 / r1 + 1.0 / r2;
    let sigma_app = force / (std::f64::consts::PI * r3 * r3 * pressure_per_tension);
    Reading { r1, r2, r3, sigma_app: if r3 > 0.0 { sigma_app } else { f64::NAN } }
}

/// (R1, R2): a least-squares polynomial r(s), s = (z − z_c)/(H/2), over the free nodes of the
/// middle half of the gap (|s| < ½, tapered; the nearest in z if fewer than
/// [`QUARTIC_POINTS`]), and its stationary point nearest the mid-plane z_c.
fn equator(points: &[Point], z_lower: f64, z_upper: f64) -> Option<(f64, f64)> {
    let (zc, half) = (0.5 * (z_lower + z_upper), 0.5 * (z_upper - z_lower));
    let mut free: Vec<(f64, f64)> =
        points.iter().filter(|p| p.side == Touch::Free).map(|p| ((p.z - zc) / half, p.r)).collect();
    free.sort_by(|a, b| a.0.abs().total_cmp(&b.0.abs()));
    let inside = free.iter().filter(|p| p.0.abs() < 0.5).count();
    let window = &free[..inside.max(QUARTIC_POINTS).min(free.len())];
    // Weights that vanish smoothly at the window's edge, so that a node entering it does not
    // make the reading jump (all 1 when the window is the nearest nodes).
    let weight = |s: f64| if inside >= QUARTIC_POINTS { taper(s / 0.5) } else { 1.0 };
    let degree = match window.len() {
        n if n >= SEXTIC_POINTS => 6,
        n if n >= QUARTIC_POINTS => 4,
        _ => 2,
    };
    if window.len() < 3 {
        return None;
    }
    let c = least_squares(
        window.len(),
        degree + 1,
        |i, j| weight(window[i].0).sqrt() * window[i].0.powi(j as i32),
        |i| weight(window[i].0).sqrt() * window[i].1,
    )?;
    let d = |s: f64, k: usize| -> f64 {
        // k-th derivative of the polynomial at s.
        (k..c.len()).map(|j| c[j] * falling(j, k) * s.powi((j - k) as i32)).sum()
    };
    // Newton on r'(s) = 0 from the mid-plane, kept in the window.
    let mut s = 0.0;
    for _ in 0..30 {
        let step = d(s, 1) / d(s, 2);
        if !step.is_finite() {
            break;
        }
        s = (s - step).clamp(-0.5, 0.5);
        if step.abs() < 1e-13 {
            break;
        }
    }
    let r2 = d(s, 0);
    // Curvature of the profile where r' = 0: −r''(z) (positive for a bulge).
    let r1 = -half * half / d(s, 2);
    (r2.is_finite() && r1.is_finite() && r2 > 0.0).then_some((r1, r2))
}

/// The biweight (1 − x²)² on |x| < 1: a window's weights, falling smoothly to 0 at its edge.
fn taper(x: f64) -> f64 {
    (1.0 - x * x).max(0.0).powi(2)
}

/// j (j − 1) … (j − k + 1).
fn falling(j: usize, k: usize) -> f64 {
    (0..k).map(|i| (j - i) as f64).product()
}

/// R3 of the upper plate: the outermost node on it, refined between nodes by the circle through
/// the [`EDGE_POINTS`] free nodes of the upper half nearest that node, cut with the plate at the
/// root nearest the node, or, if it does not reach the plate, its point nearest the plate (a
/// tangent contact). Local, because the profile's meridional curvature changes fast near the
/// contact line (on a liquid drop at 180° it is ΔP/γ at the edge and 1/R1 at the equator, the
/// relative change about s/R3 over an arc s): a circle over a wider band extrapolates the
/// flatter profile and overshoots the edge. Kept between the node on the plate and the nearest
/// free node. None without upper contact.
fn contact_radius(points: &[Point], z_lower: f64, z_upper: f64) -> Option<f64> {
    let edge = points.iter().filter(|p| p.side == Touch::Upper).map(|p| p.r).fold(f64::NAN, f64::max);
    if edge.is_nan() {
        return None;
    }
    let zc = 0.5 * (z_lower + z_upper);
    // Local coordinates: the edge node at the origin, z downwards from the plate.
    let mut near: Vec<(f64, f64)> =
        points.iter().filter(|p| p.side == Touch::Free && p.z > zc).map(|p| (p.r - edge, z_upper - p.z)).collect();
    near.sort_by(|a, b| a.0.hypot(a.1).total_cmp(&b.0.hypot(b.1)));
    let fit = &near[..EDGE_POINTS.min(near.len())];
    if fit.len() < 3 {
        return Some(edge);
    }
    // Kåsa's circle: x² + y² + D x + E y + F = 0 (through the points, or the least-squares fit).
    let c = least_squares(
        fit.len(),
        3,
        |i, j| match j {
            0 => fit[i].0,
            1 => fit[i].1,
            _ => 1.0,
        },
        |i| -(fit[i].0 * fit[i].0 + fit[i].1 * fit[i].1),
    );
    let Some(c) = c else { return Some(edge) };
    let (a, b) = (-0.5 * c[0], -0.5 * c[1]);
    let rho2 = a * a + b * b - c[2];
    if rho2.is_nan() || rho2 <= 0.0 {
        return Some(edge);
    }
    // The circle meets y = 0 at x = a ± √(ρ² − b²).
    let disc = rho2 - b * b;
    let x = if disc > 0.0 {
        let root = disc.sqrt();
        if (a - root).abs() < (a + root).abs() {
            a - root
        } else {
            a + root
        }
    } else {
        a
    };
    // The edge lies between the node on the plate and the nearest free node: the discrete
    // surface leaves the plate at its last contact node, so a circle whose cut falls inside
    // it (a kink there, common on a liquid's tangent contact) reads that node.
    Some(edge + x.clamp(0.0, fit[0].0.max(0.0)))
}

/// The coefficients minimising Σᵢ (Σⱼ aᵢⱼ cⱼ − bᵢ)² (SVD), or None if the columns are dependent.
fn least_squares(n: usize, m: usize, a: impl Fn(usize, usize) -> f64, b: impl Fn(usize) -> f64) -> Option<Vec<f64>> {
    let a = DMatrix::from_fn(n, m, a);
    let b = DVector::from_fn(n, |i, _| b(i));
    let svd = a.svd(true, true);
    let smax = svd.singular_values.max();
    if svd.rank(1e-12 * smax) < m {
        return None;
    }
    svd.solve(&b, 1e-12 * smax).ok().map(|c| c.iter().copied().collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f64::consts::PI;

    /// Nodes along r = c + √(ρ² − (z − zc)²) between the plates at zc ± H/2 (spacing h in
    /// arc length, from `offset`), and nodes on each plate at r ≤ R3 (spacing h).
    fn arc(c: f64, rho: f64, zc: f64, height: f64, h: f64, offset: f64) -> (Vec<Point>, f64) {
        let half = 0.5 * height;
        let r3 = c + (rho * rho - half * half).max(0.0).sqrt();
        let phi_max = (half / rho).asin();
        let mut pts = Vec::new();
        let mut s = -phi_max * rho + offset;
        while s < phi_max * rho {
            let phi = s / rho;
            pts.push(Point { r: c + rho * phi.cos(), z: zc + rho * phi.sin(), side: Touch::Free });
            s += h;
        }
        let mut r = r3 - offset;
        while r >= 0.0 {
            pts.push(Point { r, z: zc + half, side: Touch::Upper });
            pts.push(Point { r, z: zc - half, side: Touch::Lower });
            r -= h;
        }
        (pts, r3)
    }

    /// A circular arc cutting the plates (a drop on adhesive plates): R3 = c + √(ρ² − H²/4) to
    /// 1e-6 whatever the nodes' offset from the contact edge, R2 = c + ρ to 1e-5, R1 = ρ to
    /// 5e-4 (the sextic's truncation over |z − z_c| ≤ H/4 = 0.42 ρ: measured 1.0e-4); σ_app is
    /// the γ whose Laplace pressure, on that area, makes the force (to 3e-4).
    #[test]
    fn a_circular_profile_cut_by_the_plates_reads_exactly() {
        let (c, rho, zc, height, gamma) = (40.0, 60.0, 95.0, 100.0, 3.0);
        for offset in [0.1, 0.7, 1.6] {
            let (pts, r3) = arc(c, rho, zc, height, 2.0, offset);
            let force = gamma * PI * r3 * r3 * (1.0 / rho + 1.0 / (c + rho));
            let got = read(&pts, zc - 0.5 * height, zc + 0.5 * height, force);
            assert!((got.r1 / rho - 1.0).abs() < 5e-4, "{got:?}");
            assert!((got.r2 / (c + rho) - 1.0).abs() < 1e-5, "{got:?}");
            assert!((got.r3 / r3 - 1.0).abs() < 1e-6, "{got:?} against R3 = {r3}");
            assert!((got.sigma_app / gamma - 1.0).abs() < 3e-4, "{got:?}");
        }
    }

    /// A semicircular profile meeting the plates tangentially (θ = 180°, a liquid on
    /// non-adhesive plates): R3 = c found between nodes to 0.1% of the node spacing (R1 to 1e-3:
    /// the window reaches 0.5 ρ, measured 3.4e-4).
    #[test]
    fn a_tangent_contact_edge_is_found_between_nodes() {
        let (c, zc, height, h) = (50.0, 0.0, 120.0, 2.5);
        let rho = 0.5 * height;
        for offset in [0.3, 1.2, 2.2] {
            let (pts, r3) = arc(c, rho, zc, height, h, offset);
            let got = read(&pts, zc - rho, zc + rho, 1.0);
            assert!((got.r3 - r3).abs() < 1e-3 * h, "{got:?} against R3 = {r3} (offset {offset})");
            assert!((got.r1 / rho - 1.0).abs() < 1e-3 && (got.r2 / (c + rho) - 1.0).abs() < 1e-5, "{got:?}");
        }
    }

    /// A neck (a concave profile, strongly adhesive plates): R1 negative, |R1| = ρ (to 1e-4).
    #[test]
    fn a_neck_has_a_negative_meridional_radius() {
        let (c, rho, height) = (120.0, 80.0, 100.0);
        let mut pts: Vec<Point> = (0..80)
            .map(|i| {
                let z = -50.0 + 100.0 * (i as f64 + 0.5) / 80.0;
                Point { r: c - (rho * rho - z * z).sqrt(), z, side: Touch::Free }
            })
            .collect();
        pts.push(Point { r: c - (rho * rho - 2500.0f64).sqrt(), z: 50.0, side: Touch::Upper });
        let got = read(&pts, -0.5 * height, 0.5 * height, 10.0);
        assert!((got.r1 / -rho - 1.0).abs() < 1e-4 && (got.r2 / (c - rho) - 1.0).abs() < 1e-6, "{got:?}");
    }

    /// No node on the upper plate: no R3, no σ_app; too few free nodes: no R1, R2.
    #[test]
    fn without_contact_there_is_no_reading() {
        let (pts, _) = arc(40.0, 60.0, 0.0, 100.0, 2.0, 0.5);
        let free: Vec<Point> = pts.into_iter().filter(|p| p.side == Touch::Free).collect();
        let got = read(&free, -50.0, 50.0, 1.0);
        assert!(got.r3.is_nan() && got.sigma_app.is_nan() && got.r1.is_finite(), "{got:?}");
        let got = read(&free[..2], -50.0, 50.0, 1.0);
        assert!(got.r1.is_nan() && got.r2.is_nan(), "{got:?}");
    }
}
