//! The tools' 3-D signed distance against a brute-force distance to the surface of revolution
//! (on and off the aggregate's axis), the sphere's closed form, central differences of the lift
//! (its hoop curvature included), the meridian against the 3-D lift, and the tool a scene's
//! entry builds.

use super::brute_force::{inside, minimise, Boundary};
use super::profile::Profile;
use super::profile_tests::{profiles, rounding};
use super::tool::{Gap, Tool};
use crate::error::Error;
use crate::material::test_util::Rng;
use std::f64::consts::PI;

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    std::array::from_fn(|i| a[i] - b[i])
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// (origin, axis (not unit), position d): on the aggregate's axis, and tilted off it.
const PLACEMENTS: [([f64; 3], [f64; 3], f64); 2] =
    [([0.0, 0.0, 10.0], [0.0, 0.0, 1.0], 2.5), ([12.0, -7.0, 30.0], [0.3, -0.5, 0.8], -3.5)];

/// Two unit vectors completing the unit `a` to an orthonormal frame (Gram–Schmidt on e_x or e_y).
fn frame(a: [f64; 3]) -> ([f64; 3], [f64; 3]) {
    let e = if a[0].abs() < 0.9 { [1.0, 0.0, 0.0] } else { [0.0, 1.0, 0.0] };
    let k = dot(e, a);
    let u = sub(e, a.map(|c| k * c));
    let u = u.map(|c| c / norm(u));
    let v = [a[1] * u[2] - a[2] * u[1], a[2] * u[0] - a[0] * u[2], a[0] * u[1] - a[1] * u[0]];
    (u, v)
}

/// The point of the surface of revolution at arc length s of the section and angle θ.
fn surface(b: &Boundary, c: [f64; 3], a: [f64; 3], uv: ([f64; 3], [f64; 3]), s: f64, theta: f64) -> [f64; 3] {
    let [rho, zeta] = b.at(s);
    let (cos, sin) = (theta.cos(), theta.sin());
    std::array::from_fn(|i| c[i] + rho * (cos * uv.0[i] + sin * uv.1[i]) + zeta * a[i])
}

#[test]
fn the_lift_is_the_distance_to_the_surface_of_revolution() {
    // The surface swept by the section, sampled every ~0.5 µm along it and 1.5° around, refined
    // around the best local minima; the sign from the solid's definition. The distance to its
    // round-off (measured ≤ 2 ε scale); the closest point, which checks that the nearest point
    // lies in the point's meridian, to the brute force's resolution of a flat minimum, √ε scale.
    let mut rng = Rng::new(531);
    for (p, scale) in profiles() {
        // Points near the boundary down to depth 1.5 scale (their nearest points above 2.5
        // scale), the reference down to 3 scale.
        let b = Boundary::of(&p, 3.0 * scale);
        let sampled = Boundary::of(&p, 1.5 * scale);
        let r = rounding(&p, scale);
        for (origin, axis, d) in PLACEMENTS {
            let tool = Tool::new("t", p, origin, axis);
            let (a, c) = (tool.axis, tool.centre(d));
            let uv = frame(a);
            let (mut e_phi, mut e_closest): (f64, f64) = (0.0, 0.0);
            for i in 0..12 {
                let x: [f64; 3] = if i % 2 == 0 {
                    std::array::from_fn(|k| c[k] + rng.uniform(-1.5 * scale, 1.5 * scale))
                } else {
                    let y = surface(&sampled, c, a, uv, rng.uniform(0.0, sampled.length), rng.uniform(-PI, PI));
                    y.map(|yk| yk + rng.uniform(-r, r))
                };
                let (d2, [s, theta]) = minimise(
                    |[s, t]| {
                        let y = surface(&b, c, a, uv, s, t);
                        dot(sub(x, y), sub(x, y))
                    },
                    [0.0, -1.5 * PI],
                    [b.length, 1.5 * PI],
                    [(b.length / 0.5) as usize, 360],
                    4,
                );
                let v = sub(x, c);
                let zeta = dot(v, a);
                let rho = norm(sub(v, a.map(|ak| zeta * ak)));
                let sign = if inside(&p, rho, zeta) { -1.0 } else { 1.0 };
                let g = tool.gap(x, d);
                let near = surface(&b, c, a, uv, s, theta);
                e_phi = e_phi.max((g.phi - sign * d2.sqrt()).abs() / scale);
                e_closest = e_closest.max(norm(sub(g.closest, near)) / scale);
                assert!(
                    (g.phi - sign * d2.sqrt()).abs() <= 1e-14 * scale && norm(sub(g.closest, near)) <= 1e-7 * scale,
                    "{p:?} placed at {origin:?} along {axis:?}, x = {x:?}: φ = {}, closest {:?}; brute force {}, {near:?}",
                    g.phi,
                    g.closest,
                    sign * d2.sqrt()
                );
            }
            eprintln!("{p:?} along {axis:?}: |φ − brute force| ≤ {e_phi:.1e} scale, closest points within {e_closest:.1e} scale");
        }
    }
}

#[test]
fn the_sphere_is_its_closed_form() {
    // |x − c| − R, ∇φ = ν = (x − c)/|x − c|, ∇²φ = (I − ν⊗ν)/|x − c|, closest c + R ν; on the axis
    // too (where the lift takes the hoop curvature's limit).
    let mut rng = Rng::new(5);
    let radius = 50.0;
    for (origin, axis, d) in PLACEMENTS {
        let tool = Tool::new("bead", Profile::Sphere { radius }, origin, axis);
        let c = tool.centre(d);
        let mut worst: f64 = 0.0;
        for i in 0..2000 {
            let x: [f64; 3] = if i % 10 == 0 {
                tool.axis.map(|ak| rng.uniform(0.1, 3.0) * radius * ak)
            } else {
                std::array::from_fn(|_| rng.uniform(-3.0 * radius, 3.0 * radius))
            };
            let x = std::array::from_fn(|k| c[k] + x[k]);
            let v = sub(x, c);
            let n = norm(v);
            let nu = v.map(|vk| vk / n);
            let g = tool.gap(x, d);
            let mut err = (g.phi - (n - radius)).abs() / radius;
            for i in 0..3 {
                err = err.max((g.normal[i] - nu[i]).abs());
                err = err.max((g.closest[i] - (c[i] + radius * nu[i])).abs() / radius);
                for j in 0..3 {
                    let want = (if i == j { 1.0 } else { 0.0 } - nu[i] * nu[j]) / n;
                    err = err.max((g.hess[i][j] - want).abs() * n);
                }
            }
            worst = worst.max(err);
        }
        eprintln!("sphere along {axis:?}: relative error ≤ {worst:.1e}");
        assert!(worst <= 1e-14, "sphere along {axis:?}: {worst:.1e}");
    }
}

#[test]
fn the_lift_matches_central_differences() {
    // ∇φ from differences of φ, ∇²φ (hoop curvature included) from differences of ∇φ, h = 1e-6
    // scale, off the medial axis (as in the section's test), stencils across a seam of the
    // section's curvature left out; points down to 1e-2 scale from the axis, where the hoop
    // curvature is 1/ρ and the differences' truncation (h/ρ)² = 1e-8.
    let mut rng = Rng::new(17);
    for (p, scale) in profiles() {
        let r = rounding(&p, scale);
        let h = 1e-6 * scale;
        for (origin, axis, d) in PLACEMENTS {
            let tool = Tool::new("t", p, origin, axis);
            let (a, c) = (tool.axis, tool.centre(d));
            let uv = frame(a);
            let section = |x: [f64; 3]| {
                let v = sub(x, c);
                let zeta = dot(v, a);
                (norm(sub(v, a.map(|ak| zeta * ak))), zeta)
            };
            let curved = |x: [f64; 3]| {
                let (rho, zeta) = section(x);
                p.sdf(rho, zeta).hess != [[0.0; 2]; 2]
            };
            let (mut eg, mut eh, mut tested) = (0.0f64, 0.0f64, 0);
            while tested < 300 {
                let rho = scale * 10f64.powf(rng.uniform(-2.0, 0.4));
                let (zeta, theta) = (rng.uniform(-1.5 * scale, 1.5 * scale), rng.uniform(-PI, PI));
                let x: [f64; 3] =
                    std::array::from_fn(|k| c[k] + rho * (theta.cos() * uv.0[k] + theta.sin() * uv.1[k]) + zeta * a[k]);
                let g = tool.gap(x, d);
                let shifted = |k: usize, s: f64| {
                    let mut y = x;
                    y[k] += s * h;
                    y
                };
                let stencil: Vec<[f64; 3]> = (0..3).flat_map(|k| [shifted(k, 1.0), shifted(k, -1.0)]).collect();
                let medial = g.phi < -0.5 * r || (matches!(p, Profile::Pipette { .. }) && rho < 1e-3 * scale);
                if medial || stencil.iter().any(|&y| curved(y) != curved(x)) {
                    continue;
                }
                tested += 1;
                let at: Vec<Gap> = stencil.iter().map(|&y| tool.gap(y, d)).collect();
                for k in 0..3 {
                    eg = eg.max(((at[2 * k].phi - at[2 * k + 1].phi) / (2.0 * h) - g.normal[k]).abs());
                    for i in 0..3 {
                        let fd = (at[2 * k].normal[i] - at[2 * k + 1].normal[i]) / (2.0 * h);
                        eh = eh.max((fd - g.hess[i][k]).abs() * r.min(rho));
                    }
                }
            }
            eprintln!(
                "{p:?} along {axis:?}: |∇φ − differences| ≤ {eg:.1e}, |∇²φ − differences| ≤ {eh:.1e} / min(r, ρ)"
            );
            assert!(eg <= 1e-8 && eh <= 1e-8, "{p:?} along {axis:?}: ∇φ {eg:.1e}, ∇²φ {eh:.1e}");
        }
    }
}

#[test]
fn the_meridian_is_the_lift_in_the_r_z_plane() {
    // Tools on the z axis, facing up and down: φ, ∇φ = (φ_r, φ_z), the (r, z) block of the
    // Hessian and the closest point equal the 3-D lift's at (r, 0, z), to round-off; on the axis
    // the normal is ±e_z exactly (an identity frame) for the plane, the sphere and the punch.
    let mut rng = Rng::new(23);
    for (p, scale) in profiles() {
        for (sigma, d) in [(1.0, 4.0), (-1.0, -6.0)] {
            let tool = Tool::new("t", p, [0.0, 0.0, 20.0], [0.0, 0.0, sigma]);
            let cz = tool.centre(d)[2];
            let mut worst: f64 = 0.0;
            for _ in 0..2000 {
                let (r, z) = (rng.uniform(0.0, 2.0 * scale), cz + rng.uniform(-2.0 * scale, 2.0 * scale));
                let m = tool.meridian([r, z], d);
                let g = tool.gap([r, 0.0, z], d);
                let pairs = [
                    (m.phi / scale, g.phi / scale),
                    (m.grad[0], g.normal[0]),
                    (m.grad[1], g.normal[2]),
                    (m.closest[0] / scale, g.closest[0] / scale),
                    (m.closest[1] / scale, g.closest[2] / scale),
                ];
                for (u, v) in pairs {
                    worst = worst.max((u - v).abs() / f64::EPSILON);
                }
                let curvature = 1.0 / rounding(&p, scale);
                for (u, v) in [(m.hess[0][0], g.hess[0][0]), (m.hess[0][1], g.hess[0][2]), (m.hess[1][1], g.hess[2][2])]
                {
                    worst = worst.max((u - v).abs() / curvature / f64::EPSILON);
                }
                assert_eq!(g.normal[1], 0.0);
            }
            eprintln!("{p:?} facing {sigma:+}: meridian vs lift within {worst:.1} ulp");
            assert!(worst <= 2.0, "{p:?} facing {sigma}: {worst} ulp");
            if !matches!(p, Profile::Pipette { .. }) {
                for zeta in [0.5, 3.0, 70.0] {
                    let m = tool.meridian([0.0, cz + sigma * zeta], d);
                    assert_eq!((m.grad[0], m.grad[1], m.hess[0][1]), (0.0, sigma, 0.0), "{p:?} at ζ = {zeta}");
                }
            }
        }
    }
}

#[test]
fn a_scene_entry_builds_its_tool_and_a_malformed_one_names_the_key() {
    let spec = |text: &str| toml::from_str::<crate::scene::tools::ToolSpec>(text).unwrap();
    let pipette = spec(
        "name = \"pipette\"\nkind = \"pipette\"\ninner_radius = 35.0\nwall = 20.0\nrim_radius = 5.0\n\
         origin = [0.0, 0.0, 350.0]\naxis = [0.0, 0.0, -2.0]",
    );
    let tool = Tool::from_spec(&pipette, "aspiration.toml").unwrap();
    assert_eq!(tool.profile, Profile::Pipette { inner: 35.0, wall: 20.0, rim: 5.0 });
    assert_eq!((tool.origin, tool.axis, tool.name.as_str()), ([0.0, 0.0, 350.0], [0.0, 0.0, -1.0], "pipette"));
    // The mouth is 350 µm up, facing down. 10 µm in front of it on the axis the nearest points
    // are the ring of the inner rounding (centre ρ = R_p + r, 5 µm behind the mouth); 10 µm
    // into the bore, the inner wall at R_p.
    assert_eq!(tool.gap([0.0, 0.0, 340.0], 0.0).phi, (35.0f64 + 5.0).hypot(10.0 + 5.0) - 5.0);
    assert_eq!(tool.gap([0.0, 0.0, 360.0], 0.0).phi, 35.0);
    let mut bad = pipette.clone();
    bad.rim_radius = Some(12.0);
    match Tool::from_spec(&bad, "aspiration.toml") {
        Err(Error::Scene { path, msg }) => {
            assert_eq!(path, "aspiration.toml");
            assert!(msg.contains("tools.rim_radius = 12") && msg.contains("wall / 2 = 10"), "{msg}");
        }
        other => panic!("expected a scene error, got {other:?}"),
    }
}
