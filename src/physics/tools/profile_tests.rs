//! The profiles' signed distances against a brute-force distance to their boundary, their
//! closest points (on the boundary to round-off), their derivatives against central
//! differences, and the mirror about the axis.

use super::brute_force::{inside, minimise, Boundary};
use super::profile::Profile;
use super::sdf::Sdf2;
use crate::material::test_util::Rng;

/// The profiles tested, with their length scale: the sizes of the issue's pipette (R_p = 35,
/// wall 20, rim 5 µm), an indenter and a punch.
pub(super) fn profiles() -> Vec<(Profile, f64)> {
    vec![
        (Profile::Plane, 50.0),
        (Profile::Sphere { radius: 50.0 }, 50.0),
        (Profile::Punch { radius: 40.0, edge: 6.0 }, 40.0),
        (Profile::Pipette { inner: 35.0, wall: 20.0, rim: 5.0 }, 55.0),
    ]
}

/// The smallest radius of curvature of the profile's boundary (none: the scale).
pub(super) fn rounding(p: &Profile, scale: f64) -> f64 {
    match *p {
        Profile::Plane => scale,
        Profile::Sphere { radius } => radius,
        Profile::Punch { edge, .. } => edge,
        Profile::Pipette { rim, .. } => rim,
    }
}

/// Points (ρ ≥ 0, ζ): half uniform in [0, 2 scale] × [−2 scale, 2 scale], half within the
/// rounding radius of a random point of the boundary down to depth 2 scale (so every zone, the
/// rounded corners inside and out among them, is hit). Their nearest points lie within 3 scale
/// of the axis and of the mouth.
pub(super) fn points(p: &Profile, scale: f64, n: usize, rng: &mut Rng) -> Vec<[f64; 2]> {
    let b = Boundary::of(p, 2.0 * scale);
    let r = rounding(p, scale);
    (0..n)
        .map(|i| {
            if i % 2 == 0 {
                [rng.uniform(0.0, 2.0 * scale), rng.uniform(-2.0 * scale, 2.0 * scale)]
            } else {
                let y = b.at(rng.uniform(0.0, b.length));
                [(y[0] + rng.uniform(-r, r)).abs(), y[1] + rng.uniform(-r, r)]
            }
        })
        .collect()
}

fn diff(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

#[test]
fn the_signed_distance_is_the_distance_to_the_boundary() {
    // Against the boundary sampled every ~0.2 µm and refined around its best local minima (to
    // ~1e-11 µm along it), the sign from the solid's definition; equal to the round-off of the
    // sums (measured ≤ 2 ε scale).
    let mut rng = Rng::new(53);
    for (p, scale) in profiles() {
        let b = Boundary::of(&p, 4.0 * scale);
        let mut worst: f64 = 0.0;
        for x in points(&p, scale, 400, &mut rng) {
            let (d2, _) = minimise(
                |[s]| {
                    let y = b.at(s);
                    (x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2)
                },
                [0.0],
                [b.length],
                [(b.length / 0.2) as usize],
                4,
            );
            let sign = if inside(&p, x[0], x[1]) { -1.0 } else { 1.0 };
            let phi = p.sdf(x[0], x[1]).phi;
            let err = (phi - sign * d2.sqrt()).abs();
            assert!(err <= 1e-14 * scale, "{p:?} at {x:?}: φ = {phi}, brute force {}", sign * d2.sqrt());
            worst = worst.max(err / scale);
        }
        eprintln!("{p:?}: |φ − brute force| ≤ {worst:.1e} scale");
    }
}

#[test]
fn the_closest_point_is_on_the_boundary_along_the_gradient() {
    // φ(closest) = 0 to a few ulp of the scale; x − closest = φ ∇φ (the projection x − φ∇φ).
    let mut rng = Rng::new(7);
    for (p, scale) in profiles() {
        let (mut on, mut along) = (0.0f64, 0.0f64);
        for x in points(&p, scale, 20_000, &mut rng) {
            let s = p.sdf(x[0], x[1]);
            let ulp = f64::EPSILON * scale.max(x[0].abs()).max(x[1].abs());
            on = on.max(p.sdf(s.closest[0], s.closest[1]).phi.abs() / ulp);
            let projected = [x[0] - s.phi * s.grad[0], x[1] - s.phi * s.grad[1]];
            along = along.max(diff(projected, s.closest) / ulp);
            assert!((s.grad[0].hypot(s.grad[1]) - 1.0).abs() <= 4.0 * f64::EPSILON, "{p:?} at {x:?}: |∇φ| ≠ 1");
        }
        eprintln!("{p:?}: |φ(closest)| ≤ {on:.1} ulp, |x − φ∇φ − closest| ≤ {along:.1} ulp (of the scale)");
        assert!(on <= 4.0 && along <= 4.0, "{p:?}: {on} ulp, {along} ulp");
    }
}

/// Central differences of φ (for ∇φ) and of ∇φ (for the Hessian) at `x`, with step `h`; None
/// where the stencil straddles a line at which the curvature jumps (flat on one side, curved on
/// the other).
pub(super) fn differences(p: &Profile, x: [f64; 2], h: f64) -> Option<([f64; 2], [[f64; 2]; 2])> {
    let at = |k: usize, sign: f64| {
        let mut y = x;
        y[k] += sign * h;
        p.sdf(y[0], y[1])
    };
    let curved = |s: &Sdf2| s.hess != [[0.0; 2]; 2];
    let here = curved(&p.sdf(x[0], x[1]));
    let stencil: Vec<[Sdf2; 2]> = (0..2).map(|k| [at(k, 1.0), at(k, -1.0)]).collect();
    if stencil.iter().flatten().any(|s| curved(s) != here) {
        return None;
    }
    let grad = std::array::from_fn(|k| (stencil[k][0].phi - stencil[k][1].phi) / (2.0 * h));
    let hess =
        std::array::from_fn(|i| std::array::from_fn(|k| (stencil[k][0].grad[i] - stencil[k][1].grad[i]) / (2.0 * h)));
    Some((grad, hess))
}

#[test]
fn gradient_and_hessian_match_central_differences() {
    // Off the medial axis (deeper than half the rounding inside; the pipette's bore axis), with
    // h = 1e-6 scale: truncation h²/(6 r²) ~ 1e-10 on ∇φ, round-off ε |φ| / h ~ 1e-9.
    let mut rng = Rng::new(11);
    for (p, scale) in profiles() {
        let r = rounding(&p, scale);
        let h = 1e-6 * scale;
        let (mut eg, mut eh, mut tested, mut total) = (0.0f64, 0.0f64, 0, 0);
        for x in points(&p, scale, 4000, &mut rng) {
            let s = p.sdf(x[0], x[1]);
            if s.phi < -0.5 * r || (matches!(p, Profile::Pipette { .. }) && x[0] < 1e-3 * scale) {
                continue;
            }
            total += 1;
            let Some((g, hs)) = differences(&p, x, h) else { continue };
            tested += 1;
            eg = eg.max(diff(g, s.grad));
            for i in 0..2 {
                eh = eh.max(diff(hs[i], s.hess[i]) * r);
            }
        }
        eprintln!("{p:?}: {tested}/{total} points; |∇φ − differences| ≤ {eg:.1e}, |H − differences| ≤ {eh:.1e} / r");
        assert!(tested as f64 >= 0.95 * total as f64, "{p:?}: only {tested} of {total} points away from the seams");
        assert!(eg <= 1e-8 && eh <= 1e-8, "{p:?}: ∇φ {eg:.1e}, H {eh:.1e} / r");
    }
}

#[test]
fn sections_are_mirrored_about_the_axis() {
    // φ(−ρ, ζ) = φ(ρ, ζ) with φ_ρ odd, bit for bit; the sphere and the punch are smooth through
    // the axis (φ_ρ = 0 on it, the curvature across it that of the point next to it); in the
    // pipette's bore φ = R_p − |ρ| (the mirrored wall never nearer).
    let mut rng = Rng::new(3);
    for (p, scale) in profiles() {
        for x in points(&p, scale, 2000, &mut rng) {
            let (a, b) = (p.sdf(x[0], x[1]), p.sdf(-x[0], x[1]));
            assert_eq!(a.phi, b.phi, "{p:?} at {x:?}");
            assert_eq!((a.grad[0], a.grad[1]), (-b.grad[0], b.grad[1]), "{p:?} at {x:?}");
            assert_eq!((a.hess[0][0], a.hess[0][1], a.hess[1][1]), (b.hess[0][0], -b.hess[0][1], b.hess[1][1]));
            assert_eq!((a.closest[0], a.closest[1]), (-b.closest[0], b.closest[1]), "{p:?} at {x:?}");
        }
    }
    let h = 1e-6;
    for p in [Profile::Sphere { radius: 50.0 }, Profile::Punch { radius: 40.0, edge: 6.0 }] {
        // Above the face, and (punch) inside under it, nearer the face than the edge.
        for zeta in [80.0, 20.0, 1.0, -2.0] {
            let s = p.sdf(0.0, zeta);
            if matches!(p, Profile::Sphere { .. }) && zeta < 0.0 {
                continue;
            }
            assert_eq!(s.grad, [0.0, 1.0], "{p:?} at ζ = {zeta}");
            let across = (p.sdf(h, zeta).grad[0] - p.sdf(-h, zeta).grad[0]) / (2.0 * h);
            assert!((across - s.hess[0][0]).abs() <= 1e-9, "{p:?} at ζ = {zeta}: {across} vs {}", s.hess[0][0]);
        }
    }
    let p = Profile::Pipette { inner: 35.0, wall: 20.0, rim: 5.0 };
    for (rho, zeta) in [(0.0, -10.0), (1e-9, -10.0), (-20.0, -300.0), (30.0, -5.5)] {
        let s = p.sdf(rho, zeta);
        assert_eq!(s.phi, 35.0 - f64::abs(rho), "bore at ({rho}, {zeta})");
        assert_eq!(s.grad, [-f64::signum(rho), 0.0], "bore at ({rho}, {zeta})");
    }
}

#[test]
fn closed_forms_of_the_sections() {
    // The sphere's √(ρ² + ζ²) − R with (I − ν⊗ν)/|x|; the plane's ζ; the punch's face and side;
    // the pipette's rim as the circle of centre (R_p + r, −r).
    let s = Profile::Sphere { radius: 2.0 }.sdf(3.0, 4.0);
    assert_eq!((s.phi, s.grad, s.closest), (3.0, [0.6, 0.8], [1.2, 1.6]));
    let want = [[(1.0 - 0.36) / 5.0, -0.48 / 5.0], [-0.48 / 5.0, (1.0 - 0.64) / 5.0]];
    for i in 0..2 {
        assert!(diff(s.hess[i], want[i]) <= 1e-16, "{:?} vs {want:?}", s.hess);
    }
    assert_eq!(
        Profile::Plane.sdf(-7.0, 3.0),
        Sdf2 { phi: 3.0, grad: [0.0, 1.0], hess: [[0.0; 2]; 2], closest: [-7.0, 0.0] }
    );
    let punch = Profile::Punch { radius: 40.0, edge: 6.0 };
    assert_eq!(punch.sdf(10.0, 3.0).phi, 3.0);
    assert_eq!(punch.sdf(45.0, -20.0).phi, 5.0);
    assert_eq!(punch.sdf(39.0, -20.0).phi, -1.0);
    // Along the rim's bisector: the inner corner at (35 + 5 − 5/√2, −5 + 5/√2).
    let pip = Profile::Pipette { inner: 35.0, wall: 20.0, rim: 5.0 };
    let t = 3.0 / f64::sqrt(2.0);
    let s = pip.sdf(40.0 - 5.0 / f64::sqrt(2.0) - t, -5.0 + 5.0 / f64::sqrt(2.0) + t);
    assert!((s.phi - 3.0).abs() <= 1e-14 && diff(s.grad, [-f64::sqrt(0.5), f64::sqrt(0.5)]) <= 1e-15, "{s:?}");
    assert!((s.hess[0][0] - 0.5 / 8.0).abs() <= 1e-16, "curvature 1/(r + φ): {s:?}");
}
