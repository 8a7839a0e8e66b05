//! Holmes–Mow's closed-form loss of strong ellipticity (the law's module docs) against the
//! sampled acoustic tensor, along compression and tension paths and with a remodelling metric.

use super::{critical_stretch_squared, isochoric_compression_limit, uniaxial_stress_tension_limit, HolmesMow};

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::law::{SolidLaw, SolidResponse};
    use crate::material::penalty::CompactionPenalty;
    use crate::material::solid::Solid;
    use crate::material::tensor::{idx, Tangent};
    use crate::material::test_util::{kin, Rng};
    use nalgebra::{Matrix3, Vector3};

    /// Directions on the unit sphere (a Fibonacci lattice; N and −N give the same Q, so the upper
    /// half suffices).
    fn directions(n: usize) -> impl Iterator<Item = Vector3<f64>> {
        let golden = std::f64::consts::PI * (1.0 + 5f64.sqrt());
        (0..n).map(move |i| {
            let z = 1.0 - (i as f64 + 0.5) / n as f64; // (0, 1]
            let r = (1.0 - z * z).sqrt();
            let th = golden * i as f64;
            Vector3::new(r * th.cos(), r * th.sin(), z)
        })
    }

    /// Q_ik(N) = A_iJkL N_J N_L.
    fn acoustic_tensor(a: &Tangent, n: &Vector3<f64>) -> Matrix3<f64> {
        Matrix3::from_fn(|i, k| {
            let mut q = 0.0;
            for j in 0..3 {
                for l in 0..3 {
                    q += a[(idx(i, j), idx(k, l))] * n[j] * n[l];
                }
            }
            q
        })
    }

    /// The smallest eigenvalue of Q(N) over 1000 directions N: negative where the law has lost
    /// strong ellipticity. Any law; it can miss a loss by a thin margin (the minimising N is a
    /// principal axis, generally not on the lattice).
    pub(crate) fn min_acoustic_eigenvalue(a: &Tangent) -> f64 {
        directions(1000).map(|n| acoustic_tensor(a, &n).symmetric_eigenvalues().min()).fold(f64::INFINITY, f64::min)
    }

    /// Whether the Holmes–Mow solid is strongly elliptic at the elastic right Cauchy–Green tensor
    /// C_e = B_p^½ C B_p^½ (symmetric; its eigenvalues are those of C B_p), from the module's
    /// closed form. Exact for α2 ≥ 0. For α2 < 0 the bounds leave α1 + α2 c_max > 0 ≥
    /// α1 + α2 (c_mid + c_max) undecided: None there, since a longitudinal mode can go before the
    /// shear (test `negative_alpha2_gap_is_real`; with α3 = 1, as (56) gives, none was seen to).
    /// None also when C_e is not finite or not positive definite.
    pub(crate) fn is_strongly_elliptic(law: &HolmesMow, c_e: &Matrix3<f64>) -> Option<bool> {
        // The eigen-solver iterates without bound on NaN: check first.
        if !c_e.iter().all(|x| x.is_finite()) {
            return None;
        }
        let mut c: [f64; 3] = c_e.symmetric_eigenvalues().into();
        c.sort_by(f64::total_cmp);
        if c[0] <= 0.0 {
            return None;
        }
        let (a1, a2) = (law.alpha1, law.alpha2);
        // Lower and upper bounds of min m·Q(N)m / e over unit m, N; equal for α2 ≥ 0.
        let (lower, upper) =
            if a2 >= 0.0 { (a1 + a2 * c[0], a1 + a2 * c[0]) } else { (a1 + a2 * (c[1] + c[2]), a1 + a2 * c[2]) };
        if lower > 0.0 {
            Some(true)
        } else if upper <= 0.0 {
            Some(false)
        } else {
            None
        }
    }

    const NUS: [f64; 5] = [0.2, 0.35, 0.4, 0.45, 0.49];
    const ID: Matrix3<f64> = Matrix3::new(1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);

    fn law(mu: f64, nu: f64) -> HolmesMow {
        HolmesMow::from_mu_nu(mu, nu, 0.6).unwrap()
    }

    /// The independent reference: the sampled acoustic tensor of the law's tangent.
    fn sampled(law: &HolmesMow, f: &Matrix3<f64>, bp: &Matrix3<f64>) -> f64 {
        min_acoustic_eigenvalue(&law.response(&kin(f), bp).unwrap().a)
    }

    /// e = 2 Φs α0 e^f from the energy Ψ = Φs α0 (e^f − 1).
    fn prefactor(law: &HolmesMow, f: &Matrix3<f64>) -> f64 {
        2.0 * (law.energy(&kin(f), &ID).unwrap() + law.phi_s * law.alpha0)
    }

    /// Smallest eigenvalue of C = FᵀF.
    fn c_min(f: &Matrix3<f64>) -> f64 {
        (f.transpose() * f).symmetric_eigenvalues().min()
    }

    /// F = R1 diag(s) R2 with log-stretches uniform in [lo, hi].
    fn random_f(rng: &mut Rng, lo: f64, hi: f64) -> Matrix3<f64> {
        let s = Vector3::from_fn(|_, _| rng.uniform(lo, hi).exp());
        rng.rotation() * Matrix3::from_diagonal(&s) * rng.rotation()
    }

    /// Like [`random_f`], with the smallest eigenvalue of C within ±0.1% of `c_crit`.
    fn random_f_near(rng: &mut Rng, c_crit: f64) -> Matrix3<f64> {
        let lo = (1.001 * c_crit).sqrt().ln();
        let s = Vector3::new(
            (c_crit * rng.uniform(0.999, 1.001)).sqrt(),
            rng.uniform(lo, 0.5).exp(),
            rng.uniform(lo, 0.5).exp(),
        );
        rng.rotation() * Matrix3::from_diagonal(&s) * rng.rotation()
    }

    /// Lateral stretch of uniaxial stress F = diag(l, l, axial), from the law's stress alone:
    /// Newton on P_xx(l) = 0 with dP_xx/dl = A[xx, xx] + A[xx, yy].
    fn lateral_stretch(law: &HolmesMow, axial: f64) -> f64 {
        let mut l: f64 = 1.0;
        for _ in 0..50 {
            let SolidResponse { p, a, .. } =
                law.response(&kin(&Matrix3::from_diagonal(&Vector3::new(l, l, axial))), &ID).unwrap();
            let step = p[(0, 0)] / (a[(idx(0, 0), idx(0, 0))] + a[(idx(0, 0), idx(1, 1))]);
            l -= step;
            if step.abs() < 1e-15 {
                break;
            }
        }
        l
    }

    /// Bisection of `elliptic` on [a, b] (elliptic at b, not at a) to 1e-8.
    fn bisect(mut a: f64, mut b: f64, elliptic: impl Fn(f64) -> bool) -> f64 {
        assert!(elliptic(b) && !elliptic(a), "no sign change on [{a}, {b}]");
        while (b - a).abs() > 1e-8 {
            let mid = 0.5 * (a + b);
            if elliptic(mid) {
                b = mid;
            } else {
                a = mid;
            }
        }
        b
    }

    #[test]
    fn principal_shears_have_the_closed_form_acoustic_value() {
        // N = v_a and m = F v_b/|F v_b| for principal axes a ≠ b of C: m·Q(N)m = e (α1 + α2 c_c),
        // c the third axis, with or without the compaction penalty (its rank-one term is normal
        // to m). J = 0.65 is inside the penalty's range (J_cr = 0.7).
        let pen = CompactionPenalty::new(0.6, 1000.0, 0.7, 2.0, 0.5).unwrap();
        let mut rng = Rng::new(32);
        let mut worst: f64 = 0.0;
        for nu in NUS {
            let law = law(3.0, nu);
            for _ in 0..20 {
                let f = random_f(&mut rng, -0.5, 0.4);
                let f = f * (0.65 / f.determinant()).cbrt();
                let eig = (f.transpose() * f).symmetric_eigen();
                let e = prefactor(&law, &f);
                let alone = law.response(&kin(&f), &ID).unwrap().a;
                let with_penalty = Solid { law: &law, penalty: Some(&pen) }.response(&kin(&f), &ID).unwrap().a;
                assert!((with_penalty - alone).norm() > 1.0, "penalty inactive");
                for tangent in [alone, with_penalty] {
                    for (a, b, c) in [(0, 1, 2), (1, 0, 2), (0, 2, 1), (2, 0, 1), (1, 2, 0), (2, 1, 0)] {
                        let n = eig.eigenvectors.column(a).into_owned();
                        let m = (f * eig.eigenvectors.column(b)).normalize();
                        let got = m.dot(&(acoustic_tensor(&tangent, &n) * m));
                        let expect = e * (law.alpha1 + law.alpha2 * eig.eigenvalues[c]);
                        let err = (got - expect).abs() / tangent.norm();
                        assert!(err < 1e-13, "nu = {nu}: {got} vs {expect}");
                        worst = worst.max(err);
                    }
                }
            }
        }
        println!("principal shears: worst |m.Q m - e (a1 + a2 c)| / |A| = {worst:.1e}");
    }

    #[test]
    fn closed_form_is_the_minimum_of_the_sampled_acoustic_tensor() {
        // Random F with det > 0, B_p = I: 300 with stretches in [0.33, 1.65], and for ν > 1/3
        // 300 more with c_min within 0.1% of the critical −α1/α2. The exact minimum
        // e (α1 + α2 c_min) bounds the sampled one from below and is reached up to the lattice's
        // miss of the principal axes, measured as a band in c, (sampled − exact)/(e α2): the
        // sampled sign can differ only for c_min in (critical − band, critical).
        let mut rng = Rng::new(31);
        for nu in NUS {
            let law = law(3.0, nu);
            let crit = critical_stretch_squared(&law);
            let n = if crit.is_some() { 600 } else { 300 };
            let (mut band, mut near_band, mut worst_miss) = (0.0f64, 0.0f64, 0.0f64);
            let (mut losses, mut misses) = (0, 0);
            for k in 0..n {
                let f = match crit {
                    Some(c) if k % 2 == 1 => random_f_near(&mut rng, c),
                    _ => random_f(&mut rng, -1.1, 0.5),
                };
                let (e, cm) = (prefactor(&law, &f), c_min(&f));
                let exact = e * (law.alpha1 + law.alpha2 * cm);
                let a = law.response(&kin(&f), &ID).unwrap().a;
                let s = min_acoustic_eigenvalue(&a);
                assert!(s >= exact - 1e-12 * a.norm(), "nu = {nu}: sampled {s} below the exact {exact}");
                let gap = (s - exact) / (e * law.alpha2);
                band = band.max(gap);
                if k % 2 == 1 && crit.is_some() {
                    near_band = near_band.max(gap);
                }
                let elliptic = is_strongly_elliptic(&law, &(f.transpose() * f)).unwrap();
                assert_eq!(elliptic, exact > 0.0);
                losses += usize::from(!elliptic);
                if elliptic != (s > 0.0) {
                    misses += 1;
                    worst_miss = worst_miss.max(crit.unwrap() - cm);
                }
            }
            println!(
                "nu = {nu}: {losses}/{n} not elliptic, {misses} missed by sampling (c_min at most \
                 {worst_miss:.2e} below critical); band in c: {band:.2e} overall, {near_band:.2e} near critical"
            );
            // Measured: near critical ≤ 2.8e-5, overall ≤ 3.7e-3.
            assert!(worst_miss <= near_band && near_band < 1e-4 && band < 5e-3, "nu = {nu}: {band}, {near_band}");
        }
    }

    #[test]
    fn closed_form_sign_holds_with_a_remodelling_metric() {
        // Ψ(F, B_p) = Ψ(F B_p^½, I): the criterion on the eigenvalues of C_e = B_p^½ C B_p^½.
        // F = F_e B_p^−½ with F_e random, half of them with c_min(C_e) within 0.1% of critical.
        let mut rng = Rng::new(34);
        for nu in [0.4, 0.45, 0.49] {
            let law = law(3.0, nu);
            let crit = critical_stretch_squared(&law).unwrap();
            let (mut losses, mut misses, mut worst_miss): (usize, usize, f64) = (0, 0, 0.0);
            for k in 0..400 {
                let bp = rng.remodelling_metric();
                let f_e = if k % 2 == 0 { random_f(&mut rng, -0.6, 0.4) } else { random_f_near(&mut rng, crit) };
                let eig = bp.symmetric_eigen();
                let inv_root = eig.eigenvectors
                    * Matrix3::from_diagonal(&eig.eigenvalues.map(|x| 1.0 / x.sqrt()))
                    * eig.eigenvectors.transpose();
                let f = f_e * inv_root;
                let c_e = f_e.transpose() * f_e;
                let elliptic = is_strongly_elliptic(&law, &c_e).unwrap();
                losses += usize::from(!elliptic);
                if elliptic != (sampled(&law, &f, &bp) > 0.0) {
                    misses += 1;
                    worst_miss = worst_miss.max((c_min(&f_e) - crit).abs());
                }
            }
            println!("nu = {nu}, random B_p: {losses}/400 not elliptic, {misses} sign disagreements");
            assert_eq!(misses, 0, "nu = {nu}: within {worst_miss:.2e} of c_crit");
        }
    }

    #[test]
    fn holmes_mow_loses_ellipticity_only_for_nu_above_one_third() {
        // References: finite differences of the energy, 2000 directions (measured before the
        // closed form: λ² = 7/9, 1/2, 1/7 to the 2e-3 of that bisection).
        for (nu, lam_c) in [(0.45, (7.0f64 / 9.0).sqrt()), (0.4, 0.5f64.sqrt()), (0.35, (1.0f64 / 7.0).sqrt())] {
            let got = isochoric_compression_limit(&law(3.0, nu), 0.2).unwrap().expect("loses ellipticity");
            assert!((got - lam_c).abs() < 1e-15, "nu = {nu}: limit {got}, reference {lam_c}");
        }
        for nu in [-0.9, -0.3, 0.0, 0.2, 0.3] {
            assert_eq!(isochoric_compression_limit(&law(3.0, nu), 0.5).unwrap(), None, "nu = {nu}");
        }
        // α2 < 0: the bounds prove ellipticity only down to λ = 2|α2|/α1 (0.32 for ν = −0.3).
        assert!(isochoric_compression_limit(&law(3.0, -0.3), 0.2).is_err());
        assert_eq!(isochoric_compression_limit(&law(3.0, -0.3), 0.35).unwrap(), None);
    }

    #[test]
    fn compression_thresholds_do_not_depend_on_mu() {
        // λ² = −α1/α2 = (3ν − 1)/ν: 11.8% for ν = 0.45, 29.3% for 0.4, 2.1% for 0.49.
        for (nu, lam2, pct) in [(0.45, 7.0 / 9.0, "11.8"), (0.4, 0.5, "29.3"), (0.49, 47.0 / 49.0, "2.1")] {
            for mu in [3.0, 20.0] {
                let c = critical_stretch_squared(&law(mu, nu)).unwrap();
                assert!((c - lam2).abs() < 1e-15, "nu = {nu}, mu = {mu}: {c}");
                assert_eq!(format!("{:.1}", 100.0 * (1.0 - c.sqrt())), pct);
            }
        }
        for nu in [-0.5, 0.0, 0.2, 0.3] {
            assert_eq!(critical_stretch_squared(&law(3.0, nu)), None, "nu = {nu}");
        }
    }

    #[test]
    fn compression_paths_lose_ellipticity_at_the_closed_form_stretch() {
        // Uniaxial strain, uniaxial stress (lateral stretch from the law's stress) and
        // isochoric compression: bisection on the axial stretch with the sampled acoustic tensor
        // finds the loss at √(−α1/α2), the axial stretch being the smallest on all three.
        type Path = fn(&HolmesMow, f64) -> Vector3<f64>;
        let paths: [(&str, Path); 3] = [
            ("uniaxial strain", |_, lam| Vector3::new(1.0, 1.0, lam)),
            ("uniaxial stress", |law, lam| {
                let l = lateral_stretch(law, lam);
                Vector3::new(l, l, lam)
            }),
            ("isochoric", |_, lam| Vector3::new(lam.powf(-0.5), lam.powf(-0.5), lam)),
        ];
        let mut worst: f64 = 0.0;
        for nu in [0.4, 0.45, 0.49] {
            for mu in [3.0, 20.0] {
                let law = law(mu, nu);
                let lam_c = critical_stretch_squared(&law).unwrap().sqrt();
                for (name, path) in paths {
                    let elliptic = |lam: f64| sampled(&law, &Matrix3::from_diagonal(&path(&law, lam)), &ID) > 0.0;
                    let got = bisect(0.9 * lam_c, 1.0, elliptic);
                    println!("nu = {nu}, mu = {mu}, {name}: sampled loss at {got:.7}, closed form {lam_c:.7}");
                    assert!(got <= lam_c + 1e-8 && lam_c - got < 1e-6, "{name}: {got} vs {lam_c}");
                    worst = worst.max(lam_c - got);
                }
            }
        }
        println!("compression paths: sampled loss at most {worst:.1e} below the closed-form stretch");
    }

    #[test]
    fn uniaxial_stress_tension_limit_is_sqrt_of_minus_alpha3_over_alpha1() {
        // ν = 0.45: √(11/7) = 1.2536. At that axial stretch the lateral stretch from the law's
        // stress has l² = −α1/α2, and the sampled acoustic tensor turns indefinite there.
        let t = uniaxial_stress_tension_limit(&law(3.0, 0.45)).unwrap();
        assert!((t - (11.0f64 / 7.0).sqrt()).abs() < 1e-15 && (t - 1.254).abs() < 5e-4);
        for nu in [0.4, 0.45, 0.49] {
            for mu in [3.0, 20.0] {
                let law = law(mu, nu);
                let t = uniaxial_stress_tension_limit(&law).unwrap();
                let l = lateral_stretch(&law, t);
                assert!((l * l - critical_stretch_squared(&law).unwrap()).abs() < 1e-12, "nu = {nu}: l = {l}");
                let elliptic = |lam: f64| {
                    let l = lateral_stretch(&law, lam);
                    sampled(&law, &Matrix3::from_diagonal(&Vector3::new(l, l, lam)), &ID) > 0.0
                };
                let got = bisect(1.1 * t, 1.0, elliptic);
                println!("nu = {nu}, mu = {mu}: sampled tension loss at {got:.7}, closed form {t:.7}");
                assert!(got >= t - 1e-8 && got - t < 1e-6, "nu = {nu}: {got} vs {t}");
            }
        }
        for nu in [-0.3, 0.2, 0.3] {
            assert_eq!(uniaxial_stress_tension_limit(&law(3.0, nu)), None);
        }
    }

    #[test]
    fn acoustic_eigenvalue_at_the_reference_is_the_shear_modulus() {
        // Linear elasticity: Q(N) = µ I + (λ + µ) N ⊗ N, smallest eigenvalue µ = Φs µ_solid, and
        // the closed form e (α1 + α2) = 2 Φs α0 (α1 + α2) = Φs µ.
        let law = law(3.0, 0.45);
        let a = law.response(&kin(&ID), &ID).unwrap().a;
        assert!((min_acoustic_eigenvalue(&a) - 0.6 * 3.0).abs() < 1e-9);
        assert!((2.0 * 0.6 * law.alpha0 * (law.alpha1 + law.alpha2) - 0.6 * 3.0).abs() < 1e-12);
    }

    #[test]
    fn negative_alpha2_bounds_agree_with_the_sampled_tensor() {
        // ν < 0 (α2 < 0): where the bounds decide, Some(true) has a positive sampled minimum and
        // Some(false) a non-positive principal shear. In the undecided gap, with α3 = 1 as (56)
        // gives, the sampled sign here follows the shear bound α1 + α2 c_max (observed only).
        let mut rng = Rng::new(33);
        for nu in [-0.3, -0.9] {
            let law = law(3.0, nu);
            let (mut counts, mut gap_follows_shear) = ([0usize; 3], 0);
            for _ in 0..300 {
                let f = random_f(&mut rng, -0.6, 1.0);
                let c = f.transpose() * f;
                let a = law.response(&kin(&f), &ID).unwrap().a;
                let s = min_acoustic_eigenvalue(&a);
                match is_strongly_elliptic(&law, &c) {
                    Some(true) => {
                        counts[0] += 1;
                        assert!(s > 0.0, "nu = {nu}: decided elliptic, sampled {s}");
                    }
                    Some(false) => {
                        counts[1] += 1;
                        let eig = c.symmetric_eigen();
                        let at_axes = (0..3)
                            .map(|k| {
                                acoustic_tensor(&a, &eig.eigenvectors.column(k).into_owned())
                                    .symmetric_eigenvalues()
                                    .min()
                            })
                            .fold(f64::INFINITY, f64::min);
                        assert!(at_axes <= 1e-12 * a.norm(), "nu = {nu}: decided not elliptic, principal {at_axes}");
                    }
                    None => {
                        counts[2] += 1;
                        let shear = law.alpha1 + law.alpha2 * c.symmetric_eigenvalues().max();
                        gap_follows_shear += usize::from((s > 0.0) == (shear > 0.0));
                    }
                }
            }
            println!(
                "nu = {nu}: elliptic {}, not {}, undecided {} (sampled sign = shear bound's in {gap_follows_shear})",
                counts[0], counts[1], counts[2]
            );
        }
    }

    #[test]
    fn negative_alpha2_gap_is_real() {
        // With α2 < 0 the shear bound α1 + α2 c_max > 0 is not sufficient in general: for small
        // α's (α3 = 0.01, α2/α3 of ν = −0.99) a longitudinal mode along the least-stretched
        // axis goes first. Here α1 + α2 c_max = +0.001 while the sampled minimum is negative.
        let (a3, nu) = (0.01, -0.99);
        let law = HolmesMow::new(0.6, 1.0, a3 * (1.0 - 3.0 * nu) / (1.0 - nu), a3 * nu / (1.0 - nu), a3).unwrap();
        let f = Matrix3::from_diagonal(&Vector3::new(1.95, 1.95, 1.85));
        let c = f.transpose() * f;
        assert!(law.alpha1 + law.alpha2 * c.symmetric_eigenvalues().max() > 0.0);
        assert_eq!(is_strongly_elliptic(&law, &c), None);
        let s = sampled(&law, &f, &ID);
        println!("alpha3 = 0.01, nu = -0.99, F = diag(1.95, 1.95, 1.85): sampled minimum {s:.3e}");
        assert!(s < 0.0);
    }

    #[test]
    fn undecidable_inputs_give_none() {
        let law = law(3.0, 0.45);
        assert_eq!(is_strongly_elliptic(&law, &Matrix3::from_element(f64::NAN)), None);
        assert_eq!(is_strongly_elliptic(&law, &Matrix3::from_diagonal(&Vector3::new(1.0, 1.0, -0.5))), None);
        assert_eq!(is_strongly_elliptic(&law, &ID), Some(true));
        assert_eq!(is_strongly_elliptic(&law, &Matrix3::from_diagonal(&Vector3::new(2.0, 1.0, 0.7))), Some(false));
    }
}
