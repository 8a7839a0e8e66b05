//! Tests of the biphasic point model: its tangents against central differences, its limits and
//! its conservation identities.

use super::super::linear::LinearPoroelastic;
use super::*;
use crate::material::laws::{HolmesMow, NeoHookean};
use crate::material::test_util::Rng;
use crate::material::{Integrator, PermeabilityModel};

/// Table 1: µ = 20 kPa, ν = 0.2, Φs = 0.6; penalty J_cr = 0.7, U0 = 1000 kPa, q = 2, r = 0.5;
/// k0 = 3.7729 µm⁴/(nN s), κ = 4.638, m0 = 0.0848.
fn table1(model: PermeabilityModel, rho: [f64; 2], g: [f64; 3]) -> Biphasic<HolmesMow> {
    let solid = HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap();
    let pen = CompactionPenalty::new(0.6, 1000.0, 0.7, 2.0, 0.5).unwrap();
    let perm = Permeability::new(3.7729, 0.6, 4.638, 0.0848, model).unwrap();
    Biphasic::new(solid, Some(pen), perm, rho[0], rho[1], g).unwrap()
}

/// Both permeability laws (the remodelling-dependent one with c = 2, as in Fig 11).
const MODELS: [PermeabilityModel; 2] =
    [PermeabilityModel::Isotropic, PermeabilityModel::RemodellingDependent { c: 2.0 }];
/// An arbitrary point: domain errors must come back naming it.
const AT: QpId = QpId { elem: 7, point: 3 };

/// ‖x − y‖ / ‖y‖ (Frobenius over the whole block).
fn rel<const R: usize, const C: usize>(x: &SMatrix<f64, R, C>, y: &SMatrix<f64, R, C>) -> f64 {
    (x - y).norm() / y.norm()
}

/// State with F given (Grad u = F − I).
fn state(f: Matrix3<f64>, l: Matrix3<f64>, p: f64, gp: Vector3<f64>, dt: f64) -> PointState {
    PointState { grad_u: f - Matrix3::identity(), grad_udot: l, p, grad_p: gp, dt }
}

/// Central differences of every block of `eval`, the Grad u columns perturbing Grad u̇ by
/// shift times the same amount (what the assembler's U̇ = shift U + … does).
fn fd_tangent(m: &Biphasic<HolmesMow>, s: &PointState, h: QpState, shift: f64) -> PointTangent {
    let ev = |s: &PointState| m.eval(AT, s, h).unwrap();
    let mut t = PointTangent {
        dstress_du: SMatrix::zeros(),
        dstress_dp: Matrix3::zeros(),
        dbody_du: SMatrix::zeros(),
        drate_du: Matrix3::zeros(),
        dflux_du: SMatrix::zeros(),
        dflux_dgradp: Matrix3::zeros(),
    };
    let h = 1e-6 * (Matrix3::identity() + s.grad_u).norm();
    for k in 0..3 {
        for l in 0..3 {
            let (mut sp, mut sm) = (*s, *s);
            sp.grad_u[(k, l)] += h;
            sm.grad_u[(k, l)] -= h;
            sp.grad_udot[(k, l)] += shift * h;
            sm.grad_udot[(k, l)] -= shift * h;
            let (fp, fm) = (ev(&sp), ev(&sm));
            let c = idx(k, l);
            let ds = (fp.stress - fm.stress) / (2.0 * h);
            for i in 0..3 {
                for j in 0..3 {
                    t.dstress_du[(idx(i, j), c)] = ds[(i, j)];
                }
                t.dbody_du[(i, c)] = (fp.body[i] - fm.body[i]) / (2.0 * h);
                t.dflux_du[(i, c)] = (fp.flux[i] - fm.flux[i]) / (2.0 * h);
            }
            t.drate_du[(k, l)] = (fp.rate - fm.rate) / (2.0 * h);
        }
    }
    let hp = 1e-6 * s.p.abs().max(1.0);
    let (mut sp, mut sm) = (*s, *s);
    sp.p += hp;
    sm.p -= hp;
    t.dstress_dp = (ev(&sp).stress - ev(&sm).stress) / (2.0 * hp);
    let hg = 1e-6 * s.grad_p.norm().max(1.0);
    for j in 0..3 {
        let (mut sp, mut sm) = (*s, *s);
        sp.grad_p[j] += hg;
        sm.grad_p[j] -= hg;
        let d = (ev(&sp).flux - ev(&sm).flux) / (2.0 * hg);
        for i in 0..3 {
            t.dflux_dgradp[(i, j)] = d[i];
        }
    }
    t
}

/// Test 1: every tangent block against central differences of `eval`.
#[test]
fn tangent_matches_central_differences() {
    let mut rng = Rng::new(31);
    let mut worst = [0.0f64; 6];
    // Realistic gravity (ϱ g ≈ 1e-5 kPa/µm) and an exaggerated one (ϱf g = 0.2 kPa/µm) that
    // makes the gravity parts of the body and flux blocks visible next to Grad p.
    for g in [[0.0, 0.0, -9.81], [3e4, -1e5, -2e5]] {
        for model in MODELS {
            let m = table1(model, [1100.0, 1000.0], g);
            // det F in [0.75, 1.3], plus two states where the compaction penalty is active.
            for j in [0.75, 0.9, 1.0, 1.15, 1.3, 0.68, 0.65] {
                let f = rng.deformation(j);
                let (l, dt) = (rng.matrix(0.3), rng.uniform(0.1, 1.0));
                let (p, gp) = (rng.uniform(-5.0, 5.0), rng.vector(0.5));
                let s = state(f, l, p, gp, dt);
                assert!((f - l * dt).determinant() > 0.0);
                for shift in [1.0 / dt, 1.5 / dt, 0.0] {
                    let (flux, t) = m.eval_tangent(AT, &s, QpState::NONE, shift).unwrap();
                    let e = m.eval(AT, &s, QpState::NONE).unwrap();
                    assert!(flux.stress == e.stress && flux.body == e.body);
                    assert!(flux.rate == e.rate && flux.flux == e.flux);
                    let fd = fd_tangent(&m, &s, QpState::NONE, shift);
                    let errs = [
                        rel(&t.dstress_du, &fd.dstress_du),
                        rel(&t.dstress_dp, &fd.dstress_dp),
                        rel(&t.dbody_du, &fd.dbody_du),
                        rel(&t.drate_du, &fd.drate_du),
                        rel(&t.dflux_du, &fd.dflux_du),
                        rel(&t.dflux_dgradp, &fd.dflux_dgradp),
                    ];
                    for (w, e) in worst.iter_mut().zip(errs) {
                        assert!(e < 1e-6, "{model:?}, g = {g:?}, J = {j}, shift = {shift}: errors {errs:?}");
                        *w = w.max(e);
                    }
                }
            }
        }
    }
    println!(
        "worst rel. errors: dstress_du {:.2e}, dstress_dp {:.2e}, dbody_du {:.2e}, drate_du {:.2e}, \
         dflux_du {:.2e}, dflux_dgradp {:.2e}",
        worst[0], worst[1], worst[2], worst[3], worst[4], worst[5]
    );
}

/// The tangent with remodelling active (the consistent tangent of the local update chained
/// through stress and permeability) against central differences, both permeability models;
/// with the qp state held (evolve = false) the committed B_p^n is used as is.
#[test]
fn remodelling_tangent_matches_central_differences() {
    let mut rng = Rng::new(38);
    let mut worst: f64 = 0.0;
    // The trapezoidal rule's start (C^n from F − Δt Grad u̇) is fixed by the step's start: with
    // U̇'s shift 1/Δt it adds nothing to the tangent.
    let integrators = [Integrator::Implicit, Integrator::Trapezoidal];
    for (model, integrator) in MODELS.into_iter().flat_map(|m| integrators.map(|i| (m, i))) {
        let m = table1(model, [1000.0, 1000.0], [0.0, 0.0, -9.81])
            .with_remodelling(Remodelling::new(0.001, 2.0).unwrap().with_integrator(integrator));
        assert_eq!(m.qp_state_len(), 6);
        for (j, dt) in [(0.75, 0.5f64), (0.9, 4.0), (1.0, 40.0), (1.15, 1e3), (0.68, 2.0)] {
            let committed = to_sym6(&rng.remodelling_metric());
            let h = QpState { committed: &committed, evolve: true };
            let s =
                state(rng.deformation(j), rng.matrix(0.1) / dt.max(1.0), rng.uniform(-5.0, 5.0), rng.vector(0.5), dt);
            let shift = 1.0 / dt;
            let (flux, t) = m.eval_tangent(AT, &s, h, shift).unwrap();
            assert_eq!(flux.stress, m.eval(AT, &s, h).unwrap().stress);
            let fd = fd_tangent(&m, &s, h, shift);
            let (es, ef) = (rel(&t.dstress_du, &fd.dstress_du), rel(&t.dflux_du, &fd.dflux_du));
            // The same state without the chain terms is visibly wrong: the check can fail.
            let frozen = fd_tangent(&m, &s, QpState { committed: &committed, evolve: false }, shift);
            let held = rel(&frozen.dstress_du, &fd.dstress_du);
            println!("{model:?} {integrator:?} J = {j} dt = {dt}: dP/dF {es:.2e}, dW/dF {ef:.2e} (frozen-B_p tangent off by {held:.2e})");
            assert!(es < 1e-6 && ef < 1e-6);
            assert!(held > 1e-4);
            worst = worst.max(es).max(ef);
            // The committed update is the one the residual used.
            let mut out = [0.0; 6];
            m.advance_qp_state(AT, &s, h, &mut out).unwrap();
            let later = QpState { committed: &out, evolve: false };
            assert_eq!(m.eval(AT, &s, later).unwrap().stress, flux.stress);
            let pf = m.point_fields(AT, &s, later).unwrap();
            assert!(pf.det_bp_dev < 1e-13 && pf.norm_ep > 0.0);
        }
    }
    println!("worst rel. error with remodelling {worst:.2e}");
}

/// At Grad u = O(1e-7) the mixture `m` is linear poroelasticity `lin` (the linear model of the
/// scene, whose µ is the aggregate's drained Φs µ): stress, rate and flux to 1e-5 relative, no
/// body force; its drained moduli are the linear model's to round-off.
fn check_small_strain_limit<L: SkeletonLaw>(name: &str, m: &Biphasic<L>, lin: &LinearPoroelastic) {
    let eps = 1e-7;
    let mut rng = Rng::new(32);
    let mut worst = [0.0f64; 4];
    for _ in 0..5 {
        let gu = rng.matrix(1.0) * eps;
        let gud = rng.matrix(1.0) * eps;
        for p in [0.0, rng.uniform(-1.0, 1.0) * 10.0 * eps] {
            let s = PointState { grad_u: gu, grad_udot: gud, p, grad_p: rng.vector(1.0), dt: 0.5 };
            let (a, b) = (m.eval(AT, &s, QpState::NONE).unwrap(), lin.eval(AT, &s, QpState::NONE).unwrap());
            let errs = [
                rel(&a.stress, &b.stress),
                (a.rate - b.rate).abs() / b.rate.abs(),
                rel(&a.flux, &b.flux),
                a.body.norm(),
            ];
            for (w, e) in worst.iter_mut().zip(errs) {
                *w = w.max(e);
            }
        }
    }
    println!(
        "{name}, small strain (eps = {eps:e}): stress {:.2e}, rate {:.2e}, flux {:.2e}, |body| {:.1e}",
        worst[0], worst[1], worst[2], worst[3]
    );
    assert!(worst[0] < 1e-5 && worst[1] < 1e-5 && worst[2] < 1e-5 && worst[3] == 0.0, "{name}");
    let (kl, ml) = (lin.lambda + 2.0 * lin.mu / 3.0, lin.lambda + 2.0 * lin.mu);
    println!("{name}: K_dr = {} (linear {kl}), M = {} (linear {ml})", m.drained_bulk_modulus(), m.p_wave_modulus());
    assert!((m.drained_bulk_modulus() - kl).abs() < 1e-14 * kl, "{name}");
    assert!((m.p_wave_modulus() - ml).abs() < 1e-14 * ml, "{name}");
    assert_eq!(m.conductivity(), lin.k);
    assert!(!m.is_linear());
}

/// Test 2: at Grad u = O(1e-7) the mixture is linear poroelasticity with drained Lamé constants
/// Φs (λ, µ), whichever the skeleton law (Holmes–Mow with the penalty, neo-Hookean with constant
/// permeability: κ = m0 = 0); the drained moduli match the α closed form too.
#[test]
fn small_strain_limit_is_linear_poroelasticity() {
    let lin = LinearPoroelastic::new(0.6 * 20.0, 0.2, 3.7729).unwrap();
    let m = table1(PermeabilityModel::Isotropic, [1000.0, 1000.0], [0.0; 3]);
    check_small_strain_limit("Holmes–Mow", &m, &lin);
    let nh = NeoHookean::from_mu_nu(20.0, 0.2, 0.6).unwrap();
    let perm = Permeability::new(3.7729, 0.6, 0.0, 0.0, PermeabilityModel::Isotropic).unwrap();
    check_small_strain_limit("neo-Hookean", &Biphasic::new(nh, None, perm, 1000.0, 1000.0, [0.0; 3]).unwrap(), &lin);
    // The closed form of the α's: µ/Φs = 2 α0 (α3 − α2), K/Φs = 4 α0 (α3 + 2 α2)/3.
    let hm = HolmesMow::new(0.6, 0.125, 0.78, 0.11, 1.0).unwrap();
    let perm = Permeability::new(1.0, 0.6, 4.638, 0.0848, PermeabilityModel::Isotropic).unwrap();
    let m = Biphasic::new(hm, None, perm, 0.0, 0.0, [0.0; 3]).unwrap();
    let mu = 0.6 * 2.0 * 0.125 * (1.0 - 0.11);
    let kb = 0.6 * 4.0 * 0.125 * (1.0 + 2.0 * 0.11) / 3.0;
    assert!((m.drained_bulk_modulus() - kb).abs() < 1e-14 * kb);
    assert!((m.p_wave_modulus() - (kb + 4.0 * mu / 3.0)).abs() < 1e-14 * kb);
}

/// Test 3: ṡ dt is exactly det F − det F_n; ṡ → cof F : Grad u̇ as dt → 0.
#[test]
fn rate_is_exact_change_of_j() {
    // Entries on a 2^-14 grid and dt a power of 2: det F, det F_n and F − dt L = F_n are then
    // exact in f64 (triple products on a 2^-42 grid, below 2^5), so the reference is exact.
    let m = table1(PermeabilityModel::Isotropic, [1000.0, 1000.0], [0.0, 0.0, -9.81]);
    let mut rng = Rng::new(33);
    let grid = |a: Matrix3<f64>| a.map(|x| (x * 16384.0).round() / 16384.0);
    let mut worst: f64 = 0.0;
    for (j, j_n, near) in [(1.0, 0.8, false), (0.75, 1.3, false), (1.3, 0.7, false), (0.9, 0.0, true), (1.2, 0.0, true)]
    {
        let f = grid(rng.deformation(j));
        let f_n = if near { grid(f + rng.matrix(0.01)) } else { grid(rng.deformation(j_n)) };
        let exact = f.determinant() - f_n.determinant();
        assert_eq!(f.determinant(), f.transpose().determinant());
        assert_eq!(f_n.determinant(), f_n.transpose().determinant());
        for dt in [0.25, 2.0, 1.0 / 64.0] {
            let l = (f - f_n) / dt;
            assert_eq!(f - l * dt, f_n);
            let s = state(f, l, 1.0, Vector3::zeros(), dt);
            let rate = m.eval(AT, &s, QpState::NONE).unwrap().rate;
            let err = (rate * dt - exact).abs() / exact.abs();
            assert!(err < 1e-14, "J = {j}, near = {near}, dt = {dt}: rel. error {err:e}");
            worst = worst.max(err);
        }
    }
    // dt → 0: the cancellation-free form tends to J̇ = cof F : L (exactly at dt = 0; the
    // difference is −dt F : cof L + dt² det L).
    let f = rng.deformation(0.8);
    let l = rng.matrix(1.0);
    let cof_f = f.try_inverse().unwrap().transpose() * f.determinant();
    let jdot = cof_f.dot(&l);
    let mut errs = [0.0; 2];
    for (e, dt) in errs.iter_mut().zip([0.0, 1e-12]) {
        let rate = m.eval(AT, &state(f, l, 0.0, Vector3::zeros(), dt), QpState::NONE).unwrap().rate;
        *e = (rate - jdot).abs() / (cof_f.norm() * l.norm());
    }
    println!("mass rate: worst rel. error {worst:e}; vs cof F : L at dt = 0: {:e}, dt = 1e-12: {:e}", errs[0], errs[1]);
    assert!(errs[0] < 1e-15 && errs[1] < 1e-11);
}

/// Test 4: F = Q gives P = −p0 Q, zero solid Cauchy stress and consistently rotated fluxes;
/// superposed rotations on a general state are objective.
#[test]
fn rigid_rotation() {
    let mut rng = Rng::new(34);
    let p0 = 2.5;
    for model in MODELS {
        for g in [[0.0; 3], [0.0, 0.0, -9.81e5]] {
            let m = table1(model, [1000.0, 1000.0], g);
            let q = rng.rotation();
            let gp = rng.vector(1.0);
            let s = state(q, Matrix3::zeros(), p0, gp, 0.5);
            let r = m.eval(AT, &s, QpState::NONE).unwrap();
            let e = rel(&r.stress, &(-q * p0));
            let fields = m.point_fields(AT, &s, QpState::NONE).unwrap();
            println!("{model:?}: P vs -p0 Q rel. err {e:e}, |sigma_sc| = {:e}", fields.cauchy_sc.norm());
            assert!(e < 1e-14);
            assert!(fields.cauchy_sc.norm() < 1e-13 && fields.von_mises < 1e-13);
            assert!((fields.j - 1.0).abs() < 1e-15 && (fields.porosity - 0.4).abs() < 1e-15);
            // K(Q) = K(I); W = K(I) (Grad p − ϱf Qᵀ a_g), q = Q Q_ref = −Q W.
            let k_ref = Permeability::new(3.7729, 0.6, 4.638, 0.0848, model)
                .unwrap()
                .tensor(&Kinematics::new(&Matrix3::identity()).unwrap(), &Matrix3::identity())
                .unwrap();
            let w = k_ref * (gp - q.transpose() * m.fluid_weight());
            assert!(rel(&r.flux, &w) < 1e-14);
            assert!(rel(&fields.darcy, &(-q * w)) < 1e-14);
            // Superposed rotation on a general state: P(QF) = Q P(F); without gravity the
            // referential flux is unchanged and the spatial flux rotates.
            let f = rng.deformation(0.85);
            let (sf, sq) = (state(f, Matrix3::zeros(), p0, gp, 0.5), state(q * f, Matrix3::zeros(), p0, gp, 0.5));
            let (rf, rq) = (m.eval(AT, &sf, QpState::NONE).unwrap(), m.eval(AT, &sq, QpState::NONE).unwrap());
            assert!(rel(&rq.stress, &(q * rf.stress)) < 1e-13);
            if g == [0.0; 3] {
                assert!(rel(&rq.flux, &rf.flux) < 1e-13);
                let (ff, fq) =
                    (m.point_fields(AT, &sf, QpState::NONE).unwrap(), m.point_fields(AT, &sq, QpState::NONE).unwrap());
                assert!(rel(&fq.darcy, &(q * ff.darcy)) < 1e-13);
                assert!(rel(&fq.cauchy_sc, &(q * ff.cauchy_sc * q.transpose())) < 1e-13);
                assert!((fq.von_mises - ff.von_mises).abs() < 1e-13 * ff.von_mises);
            }
        }
    }
}

/// Test 5: inadmissible states (J <= Φs, J <= 0, J(F_n) <= 0, NaN/inf input) are domain
/// errors at the evaluated point, with and without the penalty.
#[test]
fn domain_errors_carry_the_point() {
    let mut rng = Rng::new(35);
    let solid = HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap();
    let perm = Permeability::new(3.7729, 0.6, 4.638, 0.0848, PermeabilityModel::Isotropic).unwrap();
    let pen = CompactionPenalty::new(0.6, 1000.0, 0.7, 2.0, 0.5).unwrap();
    let nan = f64::NAN;
    for penalty in [Some(pen), None] {
        let m = Biphasic::new(solid, penalty, perm, 1000.0, 1000.0, [0.0, 0.0, -9.81]).unwrap();
        let ok = state(rng.deformation(0.9), rng.matrix(0.1), 1.0, rng.vector(1.0), 0.5);
        let f = ok.grad_u + Matrix3::identity();
        let cases = [
            ("J = 0.55", state(rng.deformation(0.55), Matrix3::zeros(), 1.0, Vector3::zeros(), 0.5), 0.55),
            (
                "J = phi_s",
                state(
                    Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, 0.6)),
                    Matrix3::zeros(),
                    0.0,
                    Vector3::zeros(),
                    0.5,
                ),
                0.6,
            ),
            ("J < 0", state(-rng.deformation(0.9), Matrix3::zeros(), 0.0, Vector3::zeros(), 0.5), -0.9),
            ("J(F_n) < 0", state(f, f * 3.0, 0.0, Vector3::zeros(), 0.5), 0.9),
            ("NaN F", PointState { grad_u: Matrix3::from_element(nan), ..ok }, nan),
            ("NaN p", PointState { p: nan, ..ok }, nan),
            ("inf Grad p", PointState { grad_p: Vector3::new(0.0, f64::INFINITY, 0.0), ..ok }, nan),
            ("NaN Grad u_dot", PointState { grad_udot: Matrix3::from_element(nan), ..ok }, nan),
        ];
        for (name, s, j_want) in cases {
            let check = |r: Result<()>, what: &str| match r {
                Err(Error::Domain { cell: 7, point: 3, j, msg }) => {
                    assert!((j_want.is_nan() && j.is_nan()) || (j - j_want).abs() < 1e-12, "{name} ({what}): J = {j}");
                    msg
                }
                other => panic!("{name} ({what}): expected a domain error at (7, 3), got {other:?}"),
            };
            let msg = check(m.eval(AT, &s, QpState::NONE).map(|_| ()), "eval");
            check(m.eval_tangent(AT, &s, QpState::NONE, 2.0).map(|_| ()), "eval_tangent");
            if name != "J(F_n) < 0" {
                check(m.point_fields(AT, &s, QpState::NONE).map(|_| ()), "point_fields");
            } else {
                assert!(msg.contains("F_n"), "{msg}");
            }
        }
        assert!(m.eval(AT, &ok, QpState::NONE).is_ok());
    }
}

/// Test 6: at F = I, p = 0 the body force is the mixture weight and W = −ϱf k0 a_g.
#[test]
fn gravity_at_reference() {
    let (rho_s, rho_f) = (1100.0, 1000.0);
    let m = table1(PermeabilityModel::Isotropic, [rho_s, rho_f], [0.0, 0.0, -9.81]);
    let a_g = Vector3::new(0.0, 0.0, -9.81e-9);
    let s = state(Matrix3::identity(), Matrix3::zeros(), 0.0, Vector3::zeros(), 0.5);
    let r = m.eval(AT, &s, QpState::NONE).unwrap();
    let body = a_g * (rho_s * 0.6 + rho_f * 0.4);
    let w = -a_g * (rho_f * 3.7729);
    println!("body {:e} (expect {:e}), W {:e} (expect {:e})", r.body[2], body[2], r.flux[2], w[2]);
    assert!(rel(&r.body, &body) < 1e-15);
    assert!(rel(&r.flux, &w) < 1e-15);
    assert!((m.fluid_weight()[2] + 9.81e-6).abs() < 1e-15 * 9.81e-6);
    assert!(r.stress.norm() < 1e-15 && r.rate == 0.0);
    // Hydrostatic fluid (Grad p = ϱf a_g at F = I) does not flow.
    let s = PointState { grad_p: m.fluid_weight(), ..s };
    assert_eq!(m.eval(AT, &s, QpState::NONE).unwrap().flux, Vector3::zeros());
}

/// Output fields against closed forms (isotropic Darcy flux, confined compression).
#[test]
fn point_fields_closed_form() {
    // Isotropic K = J k C⁻¹ gives q = −k(J) (F⁻ᵀ Grad p − ϱf a_g) for any F.
    let m = table1(PermeabilityModel::Isotropic, [1000.0, 1000.0], [1e4, 0.0, -9.81e4]);
    let perm = Permeability::new(3.7729, 0.6, 4.638, 0.0848, PermeabilityModel::Isotropic).unwrap();
    let mut rng = Rng::new(36);
    for j in [0.66, 0.8, 1.2] {
        let f = rng.deformation(j);
        let s = state(f, Matrix3::zeros(), 1.0, rng.vector(1.0), 0.5);
        let pf = m.point_fields(AT, &s, QpState::NONE).unwrap();
        let k = perm.k(j).unwrap().0;
        let q = -(f.try_inverse().unwrap().transpose() * s.grad_p - m.fluid_weight()) * k;
        assert!((pf.j - j).abs() < 1e-14 && (pf.porosity - (1.0 - 0.6 / j)).abs() < 1e-14);
        assert!(rel(&pf.darcy, &q) < 1e-13, "{:e}", rel(&pf.darcy, &q));
        assert!(rel(&pf.cauchy_sc, &pf.cauchy_sc.transpose()) < 1e-15);
    }
    // Confined compression F = diag(1, 1, λ), no penalty above J_cr: S_zz = e (α1 + 2α2 − α3/λ²),
    // S_xx = e (α1 + α2 (1 + λ²) − α3), e = 2 Φs α0 exp[(α1 + 2α2)(λ² − 1) − 2 α3 ln λ];
    // σ_zz = λ S_zz, σ_xx = S_xx/λ, σ_VM = |σ_zz − σ_xx|.
    let HolmesMow { phi_s, alpha0: a0, alpha1: a1, alpha2: a2, alpha3: a3 } = m.solid;
    for lam in [0.75, 0.9, 1.2] {
        let e = 2.0 * phi_s * a0 * ((a1 + 2.0 * a2) * (lam * lam - 1.0) - 2.0 * a3 * f64::ln(lam)).exp();
        let (szz, sxx) = (lam * e * (a1 + 2.0 * a2 - a3 / (lam * lam)), e * (a1 + a2 * (1.0 + lam * lam) - a3) / lam);
        let f = Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, lam));
        let pf = m.point_fields(AT, &state(f, Matrix3::zeros(), 0.0, Vector3::zeros(), 0.5), QpState::NONE).unwrap();
        let want = Matrix3::from_diagonal(&Vector3::new(sxx, sxx, szz));
        println!("lambda = {lam}: sigma_zz = {szz:.10e}, sigma_VM = {:.10e}", pf.von_mises);
        assert!(rel(&pf.cauchy_sc, &want) < 1e-13);
        assert!((pf.von_mises - (szz - sxx).abs()).abs() < 1e-13 * (szz - sxx).abs());
    }
}

/// Inconsistent Φs, negative or non-finite densities and non-finite gravity are rejected.
#[test]
fn rejects_bad_construction() {
    let solid = HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap();
    let perm = Permeability::new(3.7729, 0.6, 4.638, 0.0848, PermeabilityModel::Isotropic).unwrap();
    let perm_other = Permeability::new(3.7729, 0.5, 4.638, 0.0848, PermeabilityModel::Isotropic).unwrap();
    let pen_other = CompactionPenalty::new(0.65, 1000.0, 0.7, 2.0, 0.5).unwrap();
    let g = [0.0, 0.0, -9.81];
    let msg = |r: Result<Biphasic<HolmesMow>>| match r {
        Err(Error::Material(m)) => m,
        other => panic!("expected a material error, got {other:?}"),
    };
    assert!(msg(Biphasic::new(solid, None, perm_other, 1000.0, 1000.0, g)).contains("permeability 0.5"));
    assert!(msg(Biphasic::new(solid, Some(pen_other), perm, 1000.0, 1000.0, g)).contains("penalty 0.65"));
    assert!(msg(Biphasic::new(solid, None, perm, -1.0, 1000.0, g)).contains("solid density = -1"));
    assert!(msg(Biphasic::new(solid, None, perm, 1000.0, f64::NAN, g)).contains("fluid density = NaN"));
    assert!(msg(Biphasic::new(solid, None, perm, 1000.0, 1000.0, [0.0, f64::INFINITY, 0.0])).contains("gravity"));
    assert!(Biphasic::new(solid, None, perm, 0.0, 0.0, [0.0; 3]).is_ok());
}

/// cof, its bilinear part and its derivative against the inverse-based formulas.
#[test]
fn cofactor_helpers() {
    let mut rng = Rng::new(37);
    let (a, b) = (rng.matrix(1.0), rng.matrix(1.0));
    let inv_t = a.try_inverse().unwrap().transpose();
    assert!(rel(&cof(&a), &(inv_t * a.determinant())) < 1e-14);
    assert!(rel(&(cof(&a) + cof_cross(&a, &b) + cof(&b)), &cof(&(a + b))) < 1e-14);
    let j = a.determinant();
    let want = Tangent::from_fn(|r, c| {
        let (i, jj, k, l) = (r / 3, r % 3, c / 3, c % 3);
        j * (inv_t[(i, jj)] * inv_t[(k, l)] - inv_t[(i, l)] * inv_t[(k, jj)])
    });
    assert!(rel(&dcof(&a), &want) < 1e-13);
}
