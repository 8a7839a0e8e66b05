//! The tests of the remodelling update (`super::remodelling`): the local solve, its tangent, the
//! flow forms and the integrators.
use super::dual::{Scalar, M3};
use super::law::{SkeletonLaw, SolidLaw};
use super::laws::HolmesMow;
use super::remodelling::*;
use super::tensor::{from_sym6, to_sym6};
use super::test_util::{kin, Rng};
use crate::material::tensor::sym_basis;
use nalgebra::Matrix3;

fn table1() -> (HolmesMow, Remodelling) {
    (HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap(), Remodelling::new(0.001, 2.0).unwrap())
}

#[test]
fn sym_components_round_trip() {
    let m = Matrix3::new(1.0, 2.0, 3.0, 2.0, 4.0, 5.0, 3.0, 5.0, 6.0);
    assert_eq!(to_sym6(&m), [1.0, 4.0, 6.0, 2.0, 3.0, 5.0]);
    assert_eq!(from_sym6(&to_sym6(&m)), m);
    let sum: Matrix3<f64> = (0..6).map(|s| sym_basis()[s] * to_sym6(&m)[s]).sum();
    assert_eq!(sum, m);
}

/// dev Σ of the generic Holmes–Mow code equals dev(C S) from the stress code, and
/// ‖dev σ‖ = ‖dev (J⁻¹ F S Fᵀ)‖.
#[test]
fn mandel_stress_matches_second_piola() {
    let (hm, _) = table1();
    let mut rng = Rng::new(71);
    for j in [0.7, 1.0, 1.2] {
        let f = rng.deformation(j);
        let bp = rng.remodelling_metric();
        let c = f.transpose() * f;
        let s = hm.stresses(&kin(&f), &bp).unwrap().1;
        let sigma_m = c * s;
        let dev = sigma_m - Matrix3::identity() * (sigma_m.trace() / 3.0);
        let d = re3(&hm.mandel_dev(&to_m3(&(c * bp)), f.determinant().ln()));
        assert!((d - dev).norm() < 1e-12 * dev.norm(), "{d} vs {dev}");
        let tau = f * s * f.transpose() / f.determinant();
        let dtau = tau - Matrix3::identity() * (tau.trace() / 3.0);
        let n = Remodelling::dev_stress_norm(&hm, &c, &bp);
        assert!((n - dtau.norm()).abs() < 1e-12 * n);
    }
}

/// Plastic updates: symmetric, det 1 to round-off, and the residual of the implicit update
/// holds with the returned B_p; elastic updates keep B_p^n.
#[test]
fn update_is_symmetric_isochoric_and_implicit() {
    let (hm, rm) = table1();
    let mut rng = Rng::new(72);
    for (j, dt) in [(0.8, 0.1), (1.0, 5.0), (0.9, 200.0), (1.1, 1e6)] {
        let f = rng.deformation(j) * 1.0;
        let c = f.transpose() * f;
        let bp_n = rng.remodelling_metric();
        let up = rm.update(&hm, &c, &bp_n, dt).unwrap();
        let b = up.bp;
        println!(
            "J = {j}, dt = {dt}: dgamma = {:.3e}, {} its, det - 1 = {:e}",
            up.dgamma,
            up.iterations,
            b.determinant() - 1.0
        );
        assert!(up.iterations > 0 && up.dgamma > 0.0);
        assert!((b - b.transpose()).norm() == 0.0);
        assert!((b.determinant() - bp_n.determinant()).abs() < 1e-14);
        assert!(b.cholesky().is_some());
        // The implicit consistency condition.
        let s = Remodelling::dev_stress_norm(&hm, &c, &b);
        let want = rm.lambda_p * dt * (s - rm.yield_radius());
        assert!((up.dgamma * s - want).abs() < 1e-10 * (1.0 + want.abs()), "{} vs {want}", up.dgamma * s);
        assert!(s > rm.yield_radius());
    }
    // Elastic branch: a small strain stays below yield.
    let f = Matrix3::identity() + rng.matrix(1e-3);
    let up = rm.update(&hm, &(f.transpose() * f), &Matrix3::identity(), 1.0).unwrap();
    assert_eq!(up.iterations, 0);
    assert_eq!(up.bp, Matrix3::identity());
}

/// The spatial form (40a): the consistency condition with λp/J, and its tangent.
#[test]
fn spatial_form_scales_the_rate_by_one_over_j() {
    let (hm, rm) = table1();
    let rs = rm.with_form(FlowForm::Spatial);
    let mut rng = Rng::new(74);
    let f = rng.deformation(0.8);
    let c = f.transpose() * f;
    let bp_n = rng.remodelling_metric();
    let (a, b) = (rm.update(&hm, &c, &bp_n, 2.0).unwrap(), rs.update(&hm, &c, &bp_n, 2.0).unwrap());
    let s = Remodelling::dev_stress_norm(&hm, &c, &b.bp);
    let want = rm.lambda_p / 0.8 * 2.0 * (s - rm.yield_radius());
    assert!((b.dgamma * s - want).abs() < 1e-10 * want);
    assert!(b.dgamma > a.dgamma);
    let t = rs.update_and_tangent(&hm, &c, &bp_n, 2.0).unwrap().1.unwrap();
    let h = 1e-6;
    for r in 0..6 {
        let dc = sym_basis()[r] * h;
        let fd = to_sym6(
            &((rs.update(&hm, &(c + dc), &bp_n, 2.0).unwrap().bp - rs.update(&hm, &(c - dc), &bp_n, 2.0).unwrap().bp)
                / (2.0 * h)),
        );
        for s in 0..6 {
            assert!((t[s][r] - fd[s]).abs() < 1e-7, "{} vs {}", t[s][r], fd[s]);
        }
    }
}

/// The Kirchhoff variant: at a fixed C (so a fixed J) it is (40b) with the yield stress σy/J,
/// exactly; it flows less than (40b) where J < 1; its tangent (σy/J depends on C) matches
/// central differences.
#[test]
fn kirchhoff_variant_is_40b_with_the_yield_stress_over_j() {
    let (hm, rm) = table1();
    let rk = rm.with_form(FlowForm::Kirchhoff);
    let mut rng = Rng::new(75);
    let f = rng.deformation(0.8);
    let c = f.transpose() * f;
    let j = c.determinant().sqrt();
    assert!((j - 0.8).abs() < 1e-12);
    let bp_n = rng.remodelling_metric();
    let equivalent = Remodelling::new(rm.lambda_p, rm.sigma_y / j).unwrap();
    let (a, k, e) = (
        rm.update(&hm, &c, &bp_n, 2.0).unwrap(),
        rk.update(&hm, &c, &bp_n, 2.0).unwrap(),
        equivalent.update(&hm, &c, &bp_n, 2.0).unwrap(),
    );
    assert!((k.bp - e.bp).norm() < 1e-12, "{} vs {}", k.bp, e.bp);
    // Δγ ‖dev τ‖ = Δt λp (‖dev τ‖ − k) at the end of the step.
    let tau = j * Remodelling::dev_stress_norm(&hm, &c, &k.bp);
    let want = rm.lambda_p * 2.0 * (tau - rm.yield_radius());
    assert!((k.dgamma * tau - want).abs() < 1e-10 * want);
    assert!(k.dgamma < a.dgamma && k.dgamma > 0.0);
    tangent_check(&rk, &[(0.8, 0.5), (1.05, 20.0), (0.9, 1e4)]);
    tangent_check(&rk.with_integrator(Integrator::Explicit), &[(0.8, 0.5)]);
}

/// Under an isochoric compression ramp (the overstress rising through it), B_p at its end
/// converges at first order with the backward-Euler map and at second order with the
/// trapezoidal rule (against the trapezoidal rule at 256 times the steps); both keep det B_p.
#[test]
fn trapezoidal_rule_is_second_order_through_a_ramp() {
    let (hm, _) = table1();
    let stretch = |t: f64| {
        // From l = 0.85, above yield at t = 0: a smooth flow (a yield kink inside the ramp
        // would cost the trapezoidal rule its order at that step).
        let l = 0.85 - 0.15 * t / 5.0;
        let f = Matrix3::from_diagonal(&nalgebra::Vector3::new(l.powf(-0.5), l.powf(-0.5), l));
        f.transpose() * f
    };
    let ramp = |rm: &Remodelling, n: usize| {
        let dt = 5.0 / n as f64;
        let mut bp = Matrix3::identity();
        for k in 0..n {
            let (b0, h) = rm.start(&hm, &stretch(k as f64 * dt), &bp, dt).unwrap();
            bp = rm.update(&hm, &stretch((k + 1) as f64 * dt), &b0, h).unwrap().bp;
        }
        bp
    };
    // λp ten times Table 1's: the flow changes B_p by O(10%) over the ramp.
    let be = Remodelling::new(0.01, 2.0).unwrap();
    let tr = be.with_integrator(Integrator::Trapezoidal);
    let exact = ramp(&tr, 5120);
    assert!((exact - Matrix3::identity()).norm() > 0.05, "{exact}");
    let err = |rm: &Remodelling, n: usize| (ramp(rm, n) - exact).norm();
    let (b1, b2, b3) = (err(&be, 20), err(&be, 40), err(&be, 80));
    let (t1, t2, t3) = (err(&tr, 20), err(&tr, 40), err(&tr, 80));
    println!("backward Euler {b1:.3e} {b2:.3e} {b3:.3e}; trapezoidal {t1:.3e} {t2:.3e} {t3:.3e}");
    for (a, b) in [(b1, b2), (b2, b3)] {
        assert!((1.7..2.3).contains(&(a / b)), "backward Euler's ratio {}", a / b);
    }
    for (a, b) in [(t1, t2), (t2, t3)] {
        assert!((3.4..4.6).contains(&(a / b)), "trapezoidal ratio {}", a / b);
    }
    assert!(t1 < 0.1 * b1);
    assert!((ramp(&tr, 20).determinant() - 1.0).abs() < 1e-13);
}

/// Large Δt: the rate-independent limit ‖dev σ‖ → √(2/3) σy.
#[test]
fn large_steps_return_to_the_yield_surface() {
    let (hm, rm) = table1();
    let f = Matrix3::from_diagonal(&nalgebra::Vector3::new(0.8f64.powf(-0.5), 0.8f64.powf(-0.5), 0.8));
    let c = f.transpose() * f;
    let tr = rm.with_integrator(Integrator::Trapezoidal);
    for (rm, dt) in [1e3, 1e6, 1e12].into_iter().flat_map(|dt| [(rm, dt), (tr, dt)]) {
        // The trapezoidal rule from the same C (a held strain).
        let (b0, dt) = rm.start(&hm, &c, &Matrix3::identity(), dt).unwrap();
        let up = rm.update(&hm, &c, &b0, dt).unwrap();
        let s = Remodelling::dev_stress_norm(&hm, &c, &up.bp);
        let rel = (s - rm.yield_radius()) / rm.yield_radius();
        println!("dt = {dt:e}: (s - k)/k = {rel:e}, {} iterations", up.iterations);
        assert!(rel >= 0.0 && rel < 50.0 / (rm.lambda_p * dt * 24.0));
    }
}

/// σy = 0, the liquid limit: a held strain relaxes its deviatoric stress towards zero as
/// exp(−2 λp G t) would (G the mixture's shear modulus); over long steps it vanishes, while
/// det B_p stays 1 and the isotropic part remains.
#[test]
fn without_a_yield_stress_the_deviator_relaxes_fully() {
    let hm = HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap();
    let rm = Remodelling::new(0.001, 0.0).unwrap();
    assert_eq!(rm.yield_radius(), 0.0);
    let f = Matrix3::from_diagonal(&nalgebra::Vector3::new(0.8f64.powf(-0.5), 0.8f64.powf(-0.5), 0.8));
    let c = f.transpose() * f;
    let s0 = Remodelling::dev_stress_norm(&hm, &c, &Matrix3::identity());
    let mut bp = Matrix3::identity();
    let mut last = s0;
    for _ in 0..20 {
        bp = rm.update(&hm, &c, &bp, 50.0).unwrap().bp;
        let s = Remodelling::dev_stress_norm(&hm, &c, &bp);
        assert!(s < last, "{s} after {last}");
        last = s;
    }
    println!("‖dev σ‖: {s0:.4} kPa → {last:.3e} kPa after 1000 s");
    assert!(last < 1e-6 * s0, "{last} of {s0}");
    assert!((bp.determinant() - 1.0).abs() < 1e-12);
}

/// The consistent tangent against central differences of the update in C.
#[test]
fn tangent_matches_finite_differences() {
    let (_, rm) = table1();
    tangent_check(&rm, &[(0.8, 0.5), (1.05, 20.0), (0.9, 1e4)]);
}

/// The explicit update's tangent too (steps small enough to stay in det B_p > 0); and it
/// is not isochoric: det B_p drifts at O(Δt²) per step, unlike the map's.
#[test]
fn explicit_update_tangent_and_drift() {
    let (hm, rm) = table1();
    let re = rm.with_integrator(Integrator::Explicit);
    tangent_check(&re, &[(0.8, 0.5), (1.05, 5.0)]);
    let f = Matrix3::from_diagonal(&nalgebra::Vector3::new(0.8f64.powf(-0.5), 0.8f64.powf(-0.5), 0.8));
    let c = f.transpose() * f;
    let (ex, im) = (
        re.update(&hm, &c, &Matrix3::identity(), 5.0).unwrap(),
        rm.update(&hm, &c, &Matrix3::identity(), 5.0).unwrap(),
    );
    assert!((ex.bp.determinant() - 1.0).abs() > 1e-4, "explicit det {}", ex.bp.determinant());
    assert!((im.bp.determinant() - 1.0).abs() < 1e-13, "implicit det {}", im.bp.determinant());
}

fn tangent_check(rm: &Remodelling, cases: &[(f64, f64)]) {
    let (hm, _) = table1();
    let mut rng = Rng::new(73);
    for &(j, dt) in cases {
        let f = rng.deformation(j);
        let c = f.transpose() * f;
        let bp_n = rng.remodelling_metric();
        let t = rm.update_and_tangent(&hm, &c, &bp_n, dt).unwrap().1.unwrap();
        let mut worst: f64 = 0.0;
        let scale = t.iter().flatten().fold(0.0f64, |m, x| m.max(x.abs()));
        for r in 0..6 {
            let h = 1e-6;
            let dc = sym_basis()[r] * h;
            let bp = rm.update(&hm, &(c + dc), &bp_n, dt).unwrap().bp;
            let bm = rm.update(&hm, &(c - dc), &bp_n, dt).unwrap().bp;
            let fd = to_sym6(&((bp - bm) / (2.0 * h)));
            for s in 0..6 {
                worst = worst.max((t[s][r] - fd[s]).abs());
            }
        }
        println!("J = {j}, dt = {dt}: tangent max error {worst:e} (scale {scale:e})");
        assert!(scale > 1e-4 && worst < 1e-7 * scale);
    }
}

fn re3<T: Scalar>(m: &M3<T>) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| m[i][j].re())
}
