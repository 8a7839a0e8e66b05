//! The medium's face load against independent truths: its block against central differences
//! of the load, the load of a closed surface against ∫_V ∇p_m dv (the divergence theorem,
//! volumes by hand), and the symmetry of the tangent assembled over a closed surface (`super`).

use super::*;
use crate::reference_cell::Family;

/// A medium with pressure gradient `weight` on no mesh (the face functions take coordinates).
fn medium(family: Family, weight: [f64; 3]) -> Medium {
    Medium {
        weight,
        factor: 1.0,
        faces: vec![],
        outward: vec![],
        rule: Rule::exact_for_linear_fields(family),
        meridian: family == Family::Tri6,
        suctions: vec![],
        drag: None,
    }
}

/// A pipette (Rp = 1, wall 0.4, rim 0.3) on the z axis, its mouth at z = 1.2 looking down
/// (a = −e_z), at Δp = 2.5 kPa: its ramp 0 ≤ ζ ≤ 0.3 spans z ∈ [0.9, 1.2].
fn sucking(family: Family) -> Medium {
    use crate::physics::suction::Suction;
    use crate::physics::tools::{Profile, Tool};
    let tool = Tool::new("p", Profile::Pipette { inner: 1.0, wall: 0.4, rim: 0.3 }, [0.0, 0.0, 1.2], [0.0, 0.0, -1.0]);
    let mut s = Suction::new(tool, 0, vec![(0.0, 0.0), (1.0, 2.5)]);
    s.move_to(1.0, 0.0);
    medium(family, [0.3, -0.7, 1.1]).with_suctions(vec![s])
}

/// A curved 6-node triangle and a curved meridian edge (the surface tension's test faces).
fn curved(family: Family) -> Vec<f64> {
    match family {
        Family::Tet10 => crate::physics::surface_tension::tests::octant(),
        Family::Tri6 => vec![1.0, 0.0, 0.72, 0.71, 0.93, 0.37],
    }
}

/// The block against central differences of the load, with a gradient along every axis and a
/// level shift (p_m ≠ 0 at the origin would be a constant term: here the shift moves the
/// face), both orientations.
#[test]
fn block_matches_central_differences() {
    for family in [Family::Tet10, Family::Tri6] {
        let m = medium(family, [0.3, -0.7, 1.1]);
        block_against_differences(&m, family, &curved(family).iter().map(|v| v + 0.4).collect::<Vec<_>>());
    }
}

/// The curved test face halved, its last coordinate (z) shifted by 0.8 and the others by
/// `radial`: z from 0.8 to ~1.3 across the suction's ramp (0.9–1.2), inside the bore's radius.
fn on_the_ramp(family: Family, radial: f64) -> Vec<f64> {
    let d = if family == Family::Tri6 { 2 } else { 3 };
    curved(family).iter().enumerate().map(|(i, v)| 0.5 * v + if i % d == d - 1 { 0.8 } else { radial }).collect()
}

/// With a pipette's suction whose ramp the face straddles: the suction's pressure gradient
/// differentiated exactly, and the face does feel the suction (its load differs from the
/// hydrostatic one's).
#[test]
fn block_with_suction_on_the_ramp_matches_central_differences() {
    for family in [Family::Tet10, Family::Tri6] {
        let m = sucking(family);
        let x = on_the_ramp(family, if family == Family::Tri6 { 0.5 } else { 0.2 });
        block_against_differences(&m, family, &x);
        let (with, without) = (m.face_load(&x, 1.0), medium(family, [0.3, -0.7, 1.1]).face_load(&x, 1.0));
        assert!((0..x.len()).any(|i| (with[i] - without[i]).abs() > 1e-3), "{family:?}: the suction does not act");
    }
}

/// `m`'s block at the face `x` against central differences of its load, both orientations.
fn block_against_differences(m: &Medium, family: Family, x: &[f64]) {
    {
        for outward in [1.0, -1.0] {
            let x = x.to_vec();
            let n = x.len();
            let block = m.face_block(&x, outward);
            let h = 1e-6;
            for j in 0..n {
                let (mut xp, mut xm) = (x.clone(), x.clone());
                xp[j] += h;
                xm[j] -= h;
                let (rp, rm) = (m.face_load(&xp, outward), m.face_load(&xm, outward));
                for i in 0..n {
                    let fd = (rp[i] - rm[i]) / (2.0 * h);
                    assert!(
                        (block[i][j] - fd).abs() < 1e-8,
                        "{family:?} {outward} ({i}, {j}): {} vs {fd}",
                        block[i][j]
                    );
                }
            }
        }
    }
}

/// The Tri6 faces of the tetrahedron (0, 0, 0), (a, 0, 0), (0, b, 0), (0, 0, c) with straight
/// edges, each with its outward node order, as (the 10 nodes' coordinates, per face its node
/// numbers in the Tet10 numbering: vertices 0–3, edge midpoints 4–9).
fn tetrahedron(a: f64, b: f64, c: f64) -> (Vec<[f64; 3]>, Vec<[usize; 6]>) {
    let v = [[0.0, 0.0, 0.0], [a, 0.0, 0.0], [0.0, b, 0.0], [0.0, 0.0, c]];
    let edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)];
    let mut nodes: Vec<[f64; 3]> = v.to_vec();
    for &(i, j) in &edges {
        nodes.push(std::array::from_fn(|k| 0.5 * (v[i][k] + v[j][k])));
    }
    let mid = |i: usize, j: usize| 4 + edges.iter().position(|&e| e == (i, j) || e == (j, i)).unwrap();
    let faces =
        [[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]].map(|[p, q, r]| [p, q, r, mid(p, q), mid(q, r), mid(r, p)]);
    (nodes, faces.to_vec())
}

/// A closed surface's load is ∫_V ∇p_m dv = ∇p_m V (the buoyancy), and a uniform pressure
/// loads it with nothing: the tetrahedron (V = abc/6) in 3-D, the cylinder r ≤ a, 0 ≤ z ≤ h
/// (V = π a² h, its axis carrying no load) on the meridian, each with a level shift.
#[test]
fn closed_surface_load_is_the_buoyancy() {
    let grad = [0.3, -0.7, 1.1];
    let (a, b, c) = (1.3, 0.8, 2.1);
    let m = medium(Family::Tet10, grad);
    let (nodes, faces) = tetrahedron(a, b, c);
    let shifted = |s: f64| {
        let mut total = [0.0; 3];
        for f in &faces {
            let x: Vec<f64> = f.iter().flat_map(|&k| nodes[k].map(|v| v + s)).collect();
            let r = m.face_load(&x, 1.0);
            for (k, t) in total.iter_mut().enumerate() {
                *t += (0..6).map(|node| r[3 * node + k]).sum::<f64>();
            }
        }
        total
    };
    let volume = a * b * c / 6.0;
    for s in [0.0, 5.0] {
        let total = shifted(s);
        for k in 0..3 {
            assert!((total[k] - grad[k] * volume).abs() < 1e-13, "3-D axis {k}: {} vs {}", total[k], grad[k] * volume);
        }
    }
    // The meridian: bottom (axis → rim), side (up), top (rim → axis), straight edges in (r, z),
    // traversed so that (t_z, −t_r) points out.
    let (ra, h) = (0.9, 1.7);
    let m = medium(Family::Tri6, [0.0, 2.3, 0.0]);
    for s in [0.0, 4.0] {
        let edges = [[(0.0, 0.0), (ra, 0.0)], [(ra, 0.0), (ra, h)], [(ra, h), (0.0, h)]];
        let mut fz = 0.0;
        for [p, q] in edges {
            let x = [p.0, p.1 + s, q.0, q.1 + s, 0.5 * (p.0 + q.0), 0.5 * (p.1 + q.1) + s];
            // Line3 node order: the two ends, then the midpoint.
            let r = m.face_load(&x, 1.0);
            fz += r[1] + r[3] + r[5];
        }
        let expected = 2.3 * std::f64::consts::PI * ra * ra * h;
        assert!((fz - expected).abs() < 1e-12 * expected, "meridian: {fz} vs {expected}");
    }
}

/// The tangent assembled over the closed tetrahedron is symmetric (δ²∫_V p_m dv), though one
/// face's block is not.
#[test]
fn closed_surface_tangent_is_symmetric() {
    let m = medium(Family::Tet10, [0.3, -0.7, 1.1]);
    let (nodes, faces) = tetrahedron(1.3, 0.8, 2.1);
    // Curve the faces: move the midpoints (shared by two faces each) off their edges.
    let nodes: Vec<[f64; 3]> = nodes
        .iter()
        .enumerate()
        .map(|(k, p)| if k >= 4 { p.map(|v| v * 1.07 + 0.02 * k as f64) } else { *p })
        .collect();
    let mut k = vec![[0.0; 30]; 30];
    let mut one_face_asymmetry: f64 = 0.0;
    for f in &faces {
        let x: Vec<f64> = f.iter().flat_map(|&n| nodes[n]).collect();
        let block = m.face_block(&x, 1.0);
        for a in 0..18 {
            for b in 0..18 {
                k[3 * f[a / 3] + a % 3][3 * f[b / 3] + b % 3] += block[a][b];
                one_face_asymmetry = one_face_asymmetry.max((block[a][b] - block[b][a]).abs());
            }
        }
    }
    assert!(one_face_asymmetry > 1e-3, "one face's block is not symmetric: {one_face_asymmetry}");
    for i in 0..30 {
        for j in 0..30 {
            assert!((k[i][j] - k[j][i]).abs() < 1e-13, "({i}, {j}): {} vs {}", k[i][j], k[j][i]);
        }
    }
}

/// The same on the meridian: the cylinder's three edges (7 nodes), midpoints off their edges.
#[test]
fn closed_meridian_tangent_is_symmetric() {
    let m = medium(Family::Tri6, [0.0, 2.3, 0.0]);
    // Nodes: 0 (0, 0), 1 (a, 0), 2 (a, h), 3 (0, h); midpoints 4, 5, 6 of the edges 0–1, 1–2, 2–3.
    let (a, h) = (0.9, 1.7);
    let nodes = [(0.0, 0.0), (a, 0.0), (a, h), (0.0, h), (0.5 * a, -0.1), (a + 0.15, 0.5 * h), (0.4 * a, h + 0.2)];
    let edges = [[0, 1, 4], [1, 2, 5], [2, 3, 6]];
    let mut k = [[0.0; 14]; 14];
    for e in edges {
        let x: Vec<f64> = e.iter().flat_map(|&n| [nodes[n].0, nodes[n].1]).collect();
        let block = m.face_block(&x, 1.0);
        for i in 0..6 {
            for j in 0..6 {
                k[2 * e[i / 2] + i % 2][2 * e[j / 2] + j % 2] += block[i][j];
            }
        }
    }
    for i in 0..14 {
        for j in 0..14 {
            assert!((k[i][j] - k[j][i]).abs() < 1e-12, "({i}, {j}): {} vs {}", k[i][j], k[j][i]);
        }
    }
}

/// The level of p_m is irrelevant: a uniform shift c of the medium's pressure with the pore
/// pressure shifted by c leaves every residual row unchanged (so u is the same and p moves by
/// c). Shown by translating a small mesh with its whole boundary wetted by d along gravity,
/// which shifts p_m by c = ρ_m a_g·d (the bulk does not see the position), at a random state:
/// the element loop plus the medium's load, both families.
#[test]
fn a_uniform_shift_of_the_medium_shifts_p_and_leaves_u() {
    use crate::fem::kernel::Stabilisation;
    use crate::fem::{quadrature, test_util::discretization_of};
    use crate::material::test_util::Rng;
    use crate::mesh::test_util::{structured, with_boundary};
    use crate::physics::kernel_tests::table1;
    for family in [Family::Tet10, Family::Tri6] {
        let q = match family {
            Family::Tet10 => quadrature::tet(3),
            Family::Tri6 => quadrature::tri(4),
        };
        let model = table1(true);
        let stab = Stabilisation::new(0.5, None, &model);
        let mut disc = discretization_of(with_boundary(structured(family, 2)), Box::new(model), stab, &q);
        // 10 µm, off the axis on the meridian but touching it (the axis' faces carry nothing).
        disc.mesh.coords.iter_mut().for_each(|x| x.iter_mut().for_each(|c| *c *= 10.0));
        let faces: Vec<u32> = (0..disc.mesh.faces.len() as u32).collect();
        let medium = Medium::new(1000.0, [0.0, 0.0, -9.81], &disc.mesh, &faces);
        let (nd, nu) = (disc.dofs.n_local(), disc.dofs.n_u_local());
        let mut rng = Rng::new(7);
        let u: Vec<f64> = (0..nd).map(|i| rng.uniform(-1.0, 1.0) * if i < nu { 0.05 } else { 2.0 }).collect();
        let udot: Vec<f64> = (0..nd).map(|_| rng.uniform(-0.1, 0.1)).collect();
        let residual = |disc: &crate::fem::assembly::Discretization, u: &[f64]| {
            let mut f = vec![0.0; nd];
            disc.add_residual(u, &udot, 0.5, &mut f).unwrap();
            medium.add_residual(&disc.mesh, &disc.dofs, u, &udot, &mut f);
            f
        };
        let f0 = residual(&disc, &u);
        let d = 40.0;
        disc.mesh.coords.iter_mut().for_each(|x| x[2] += d);
        let c = -1000.0 * 9.81 * crate::physics::biphasic::KG_M3_M_S2_TO_KPA_PER_UM * d;
        let shifted: Vec<f64> = u.iter().enumerate().map(|(i, &v)| if i < nu { v } else { v + c }).collect();
        let f1 = residual(&disc, &shifted);
        let scale = f0.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let worst = f0.iter().zip(&f1).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        // Without the medium the same shift changes the u rows by the uniform pressure's load.
        let mut bare = vec![0.0; nd];
        disc.add_residual(&shifted, &udot, 0.5, &mut bare).unwrap();
        let mut bare0 = vec![0.0; nd];
        disc.mesh.coords.iter_mut().for_each(|x| x[2] -= d);
        disc.add_residual(&u, &udot, 0.5, &mut bare0).unwrap();
        let moved = bare.iter().zip(&bare0).fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        println!("{family:?}: shift {c:.3e} kPa, largest row change {worst:.2e} of {scale:.2e}; without the medium {moved:.2e}");
        assert!(worst <= 1e-12 * scale, "{family:?}: {worst} of {scale}");
        assert!(moved > 1e-6 * scale, "{family:?}: the shift is seen without the medium: {moved}");
    }
}
