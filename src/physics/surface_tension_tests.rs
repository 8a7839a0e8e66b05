//! The face energy's gradient and Hessian against central differences, with and without the
//! work of adhesion (`super`).

use super::*;

/// A curved 6-node triangle: nodes of the unit sphere's octant face, perturbed (the medium's tests
/// take it too).
pub(crate) fn octant() -> Vec<f64> {
    let v = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    let mid = |a: [f64; 3], b: [f64; 3]| {
        let m = [a[0] + b[0], a[1] + b[1], a[2] + b[2]];
        let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
        [m[0] / l, m[1] / l, m[2] / l]
    };
    let nodes = [v[0], v[1], v[2], mid(v[0], v[1]), mid(v[1], v[2]), mid(v[2], v[0])];
    nodes.iter().enumerate().flat_map(|(k, p)| p.map(|c| c * (1.0 + 0.03 * k as f64))).collect()
}

fn edge() -> Vec<f64> {
    // r, z of a meridian arc from the equator up, perturbed
    vec![1.0, 0.0, 0.72, 0.71, 0.93, 0.37]
}

/// The gradient against central differences of the area, the Hessian against central
/// differences of the gradient: both families.
#[test]
fn gradient_and_hessian_match_central_differences() {
    for (family, x) in [(Family::Tet10, octant()), (Family::Tri6, edge())] {
        let rule = Rule::new(family);
        let n = x.len();
        let g = area_gradient(&rule, &x);
        let hess = area_hessian(&rule, &x);
        let h = 1e-6;
        for i in 0..n {
            let (mut xp, mut xm) = (x.clone(), x.clone());
            xp[i] += h;
            xm[i] -= h;
            let fd = (area(&rule, &xp) - area(&rule, &xm)) / (2.0 * h);
            assert!((g[i] - fd).abs() < 1e-8, "{family:?} gradient {i}: {} vs {fd}", g[i]);
            let (gp, gm) = (area_gradient(&rule, &xp), area_gradient(&rule, &xm));
            for j in 0..n {
                let fd = (gp[j] - gm[j]) / (2.0 * h);
                assert!((hess[j][i] - fd).abs() < 1e-7, "{family:?} hessian {j} {i}: {} vs {fd}", hess[j][i]);
                assert!((hess[i][j] - hess[j][i]).abs() < 1e-12);
            }
        }
    }
}

/// A rigid translation leaves the area unchanged: the gradient sums to zero along each axis
/// in 3-D (and along z on the meridian, where r is not translation-invariant).
#[test]
fn translation_does_no_work() {
    let rule = Rule::new(Family::Tet10);
    let g = area_gradient(&rule, &octant());
    for i in 0..3 {
        let s: f64 = (0..6).map(|k| g[3 * k + i]).sum();
        assert!(s.abs() < 1e-13, "{s}");
    }
    let rule = Rule::new(Family::Tri6);
    let g = area_gradient(&rule, &edge());
    assert!((g[1] + g[3] + g[5]).abs() < 1e-13);
}

/// Scaling the face by λ scales its area by λ², so x · ∂A/∂x = 2A (Euler's theorem), on both
/// families: the gradient carries the whole Laplace pressure of a sphere.
#[test]
fn the_gradient_is_homogeneous_of_degree_one() {
    for (family, x) in [(Family::Tet10, octant()), (Family::Tri6, edge())] {
        let rule = Rule::new(family);
        let g = area_gradient(&rule, &x);
        let dot: f64 = x.iter().zip(g.iter()).map(|(a, b)| a * b).sum();
        let a = area(&rule, &x);
        assert!((dot - 2.0 * a).abs() < 1e-12 * a, "{family:?}: {dot} vs {}", 2.0 * a);
    }
}

/// The face's energy with adhesion, Σ_q γ a_q − w (1 − S(g_q/g_a)) P_q: what
/// [`energy_gradient`] differentiates.
fn energy(rule: &Rule, x: &[f64], gamma: f64, outward: f64, ad: Adhesion, planes: PlatePlanes) -> f64 {
    (0..rule.w.len())
        .map(|q| {
            let (gap, _, sigma) = point_gap(rule, q, x, planes);
            gamma * point_area(rule, q, x).0 + weight(ad, gap).0 * point_projection(rule, q, x, sigma, outward).0
        })
        .sum()
}

/// The gaps of the face's points over the range (to see which part of the step a case
/// exercises).
fn gaps(rule: &Rule, x: &[f64], ad: Adhesion, planes: PlatePlanes) -> Vec<f64> {
    (0..rule.w.len()).map(|q| point_gap(rule, q, x, planes).0 / ad.range).collect()
}

/// With adhesion (γ = 1, w = 1.5) the face energy's gradient against central differences of
/// the energy and its Hessian against central differences of the gradient, on both families,
/// with the plates placed so that the face lies partly within the adhesion range (points on
/// both sides of g_a), wholly within it, and near the upper plate; both orientations.
#[test]
fn adhesion_gradient_and_hessian_match_central_differences() {
    let (gamma, work) = (1.0, 1.5);
    for (family, x) in [(Family::Tet10, octant()), (Family::Tri6, edge())] {
        let rule = Rule::new(family);
        let n = x.len();
        let a: f64 = (0..rule.w.len()).map(|q| point_area(&rule, q, &x).0).sum();
        assert!((a - area(&rule, &x)).abs() < 1e-14 * a);
        // (lower, upper, range), the face's heights in [0, top]
        let (d, _) = rule.layout();
        let top = x.iter().skip(d - 1).step_by(d).cloned().fold(0.0, f64::max);
        let placements = [(-0.05, 5.0, 0.4), (-0.3, 5.0, 2.0), (-10.0, top + 0.05, 0.6 * top)];
        for (k, &(lower, upper, range)) in placements.iter().enumerate() {
            let (ad, planes) = (Adhesion { work, range }, PlatePlanes { lower, upper });
            let s = gaps(&rule, &x, ad, planes);
            let within = s.iter().filter(|&&v| v > 0.0 && v < 1.0).count();
            match k {
                0 => assert!(within > 0 && within < s.len(), "{family:?} partly: {s:?}"),
                _ => assert!(within > 1, "{family:?} case {k}: {s:?}"),
            }
            for outward in [1.0, -1.0] {
                let e = |x: &[f64]| energy(&rule, x, gamma, outward, ad, planes);
                let grad = |x: &[f64]| energy_gradient(&rule, x, gamma, outward, ad, planes);
                let (g, hess) = (grad(&x), energy_hessian(&rule, &x, gamma, outward, ad, planes));
                let h = 1e-6;
                for i in 0..n {
                    let (mut xp, mut xm) = (x.clone(), x.clone());
                    xp[i] += h;
                    xm[i] -= h;
                    let fd = (e(&xp) - e(&xm)) / (2.0 * h);
                    assert!((g[i] - fd).abs() < 1e-8, "{family:?} case {k} gradient {i}: {} vs {fd}", g[i]);
                    let (gp, gm) = (grad(&xp), grad(&xm));
                    for j in 0..n {
                        let fd = (gp[j] - gm[j]) / (2.0 * h);
                        let hj = hess[j][i];
                        assert!((hj - fd).abs() < 1e-6, "{family:?} case {k} hessian {j} {i}: {hj} vs {fd}");
                        assert!((hess[i][j] - hj).abs() < 1e-11);
                    }
                }
            }
        }
    }
}

/// A face lying on a plate (facing it) carries γ − w, one beyond the range γ; the top of a
/// wedge within the range (facing away from the plate) more than γ, a vertical face γ
/// (the projected area: no film of the aggregate over a wetted patch can gain adhesion);
/// beyond the range, or with w = 0, the gradient is the tension's γ ∂A/∂x.
#[test]
fn adhesion_lowers_the_tension_on_the_plates_only() {
    let (gamma, work) = (2.0, 1.5);
    let flat = |z: f64| vec![1.0, z, 2.0, z, 1.5, z];
    let rule = Rule::new(Family::Tri6);
    let planes = PlatePlanes { lower: 0.0, upper: 10.0 };
    let ad = Adhesion { work, range: 0.1 };
    let a = area(&rule, &flat(0.0));
    let e = |x: &[f64], outward: f64| energy(&rule, x, gamma, outward, ad, planes);
    assert!((e(&flat(0.0), 1.0) - (gamma - work) * a).abs() < 1e-13);
    assert!((e(&flat(10.0), -1.0) - (gamma - work) * a).abs() < 1e-13);
    assert!((e(&flat(0.2), 1.0) - gamma * a).abs() < 1e-13);
    assert!((e(&flat(0.0), -1.0) - (gamma + work) * a).abs() < 1e-13);
    let vertical = [1.0, 0.0, 1.0, 0.05, 1.0, 0.025];
    assert!((e(&vertical, 1.0) - gamma * area(&rule, &vertical)).abs() < 1e-13);
    for (family, x) in [(Family::Tet10, octant()), (Family::Tri6, edge())] {
        let rule = Rule::new(family);
        let far = energy_gradient(&rule, &x, gamma, 1.0, ad, PlatePlanes { lower: -5.0, upper: 10.0 });
        let none = energy_gradient(&rule, &x, gamma, 1.0, Adhesion { work: 0.0, range: 0.4 }, planes);
        let tension = area_gradient(&rule, &x);
        for k in 0..x.len() {
            assert!((far[k] - gamma * tension[k]).abs() < 1e-13);
            assert!((none[k] - gamma * tension[k]).abs() < 1e-13);
        }
    }
}
