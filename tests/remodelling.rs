//! 0-D verification of the visco-plastic remodelling (model.md §4) on the shipped `relaxation`
//! scene: a block held at the isochoric stretch F = diag(l^-½, l^-½, l), l = 0.8, from t = 0 with
//! B_p(0) = I, with its Holmes–Mow solid and made neo-Hookean. The reference is computed here, independently of the library: by symmetry
//! B_p = diag(b^-½, b^-½, b), and b(t) solves the scalar ODE ḃ = −2 γp b (dev Σ)_zz, integrated
//! with classical RK4 at a step small enough that halving it changes nothing to 1e-10.

use crate::common::*;
use std::path::Path;

/// Table 1 with (56): α0 = (1 − ν) µ / (2 (1 − 2ν)), α1 = (1 − 3ν)/(1 − ν), α2 = ν/(1 − ν), α3 = 1.
const MU: f64 = 20.0;
const NU: f64 = 0.2;
const PHI_S: f64 = 0.6;
const LAMBDA_P: f64 = 0.001;
const SIGMA_Y: f64 = 2.0;
const L: f64 = 0.8;

/// The exact 0-D problem: stresses of the solid at (F, B_p(b)) and the flow rule.
struct Ode {
    /// Holmes–Mow's α's, or None: the neo-Hookean solid of the same µ.
    a: Option<[f64; 4]>,
}

impl Ode {
    fn new() -> Ode {
        let a0 = (1.0 - NU) * MU / (2.0 * (1.0 - 2.0 * NU));
        Ode { a: Some([a0, (1.0 - 3.0 * NU) / (1.0 - NU), NU / (1.0 - NU), 1.0]) }
    }
    fn neo_hookean() -> Ode {
        Ode { a: None }
    }
    /// (σ_xx, σ_zz, (dev Σ)_zz, ‖dev σ‖) at b. With M = C B_p = diag(m1, m1, m3), J = 1, σ = Σ
    /// (diagonal, J = 1; the compaction penalty is off at J = 1 > J_cr, p = 0), and
    /// Holmes–Mow: Σ = e [(α1 + α2 tr M) M − α2 M² − α3 I], e = 2 Φs α0 exp[α1 (tr M − 3) + α2 (I2 − 3)];
    /// neo-Hookean: Σ = Φs µ (M − I) (ln J = 0).
    fn state(&self, b: f64) -> (f64, f64, f64, f64) {
        let (m1, m3) = (1.0 / (L * b.sqrt()), L * L * b);
        let tr = 2.0 * m1 + m3;
        let (e, s1, s3, iso) = match self.a {
            Some([a0, a1, a2, a3]) => {
                let i2 = 0.5 * (tr * tr - (2.0 * m1 * m1 + m3 * m3));
                let e = 2.0 * PHI_S * a0 * (a1 * (tr - 3.0) + a2 * (i2 - 3.0)).exp();
                (e, (a1 + a2 * tr) * m1 - a2 * m1 * m1, (a1 + a2 * tr) * m3 - a2 * m3 * m3, a3)
            }
            None => (PHI_S * MU, m1, m3, 1.0),
        };
        let mean = (2.0 * s1 + s3) / 3.0;
        let (d1, d3) = (e * (s1 - mean), e * (s3 - mean));
        (e * (s1 - iso), e * (s3 - iso), d3, (2.0 * d1 * d1 + d3 * d3).sqrt())
    }
    fn rate(&self, b: f64) -> f64 {
        let (_, _, d3, s) = self.state(b);
        let k = (2.0f64 / 3.0).sqrt() * SIGMA_Y;
        let gamma = LAMBDA_P * (s - k).max(0.0) / s;
        -2.0 * gamma * b * d3
    }
    /// b at the times `at` (increasing), RK4 with step h.
    fn solve(&self, at: &[f64], h: f64) -> Vec<f64> {
        let (mut t, mut b) = (0.0, 1.0);
        at.iter()
            .map(|&target| {
                while t < target - 1e-12 {
                    let dt = h.min(target - t);
                    let k1 = self.rate(b);
                    let k2 = self.rate(b + 0.5 * dt * k1);
                    let k3 = self.rate(b + 0.5 * dt * k2);
                    let k4 = self.rate(b + dt * k3);
                    b += dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
                    t += dt;
                }
                b
            })
            .collect()
    }
    /// Reference σ_zz at the times `at`, checked against a run at half the step.
    fn stress_zz(&self, at: &[f64]) -> Vec<f64> {
        let (fine, finer) = (self.solve(at, 0.01), self.solve(at, 0.005));
        for (x, y) in fine.iter().zip(&finer) {
            assert!((x - y).abs() < 1e-10, "reference ODE not converged: {x} vs {y}");
        }
        finer.iter().map(|&b| self.state(b).1).collect()
    }
}

fn value_at(h: &History, col: &str, t: f64) -> f64 {
    let (time, v) = (h.col("time"), h.col(col));
    let i = time.iter().position(|&x| (x - t).abs() < 1e-9).unwrap_or_else(|| panic!("no row at t = {t}"));
    v[i]
}

fn run_relaxation(np: usize, dir: &Path, edits: &[(&str, &str)]) -> History {
    let sc = scene_variant("relaxation", dir, edits);
    run_ok(np, &["run", &sc, "--out", dir.join("run").to_str().unwrap(), "-q"]);
    History::read(&dir.join("run"))
}

/// The relaxation scene with constant steps dt (2 ranks) and one more edit.
fn run_constant_steps(dir: &Path, dt: &str, extra: (&str, &str)) -> History {
    let (first, max) = (format!("dt = {dt}"), format!("dt_max = {dt}"));
    run_relaxation(2, dir, &[("dt = 0.05", &first), ("dt_max = 0.5", &max), ("growth = 1.1", "growth = 1.0"), extra])
}

/// √(2/3) σy: the relaxed ‖dev σ‖; for the diagonal state ‖dev σ‖ = √(2/3) |σ_zz − σ_xx|.
fn relaxed_error(h: &History) -> f64 {
    let (zz, xx) = (h.col("stress_zz"), h.col("stress_xx"));
    let n = zz.len() - 1;
    let dev = (2.0f64 / 3.0).sqrt() * (zz[n] - xx[n]).abs();
    let k = (2.0f64 / 3.0).sqrt() * SIGMA_Y;
    (dev - k).abs() / k
}

/// A relaxation run `h` (`label` in the messages) against `ode`: the elastic state at t = 0 to
/// 1e-10 (the FE model's homogeneous state is exact), σ_zz and σ_xx at 10, 50, 100 s within
/// 0.5%, det B_p = 1 to 1e-10.
fn check_against_the_ode(ode: &Ode, h: &History, label: &str) {
    let times = [10.0, 50.0, 100.0];
    let want = ode.stress_zz(&times);
    let (sxx0, szz0, _, _) = ode.state(1.0);
    let (xx0, zz0) = (value_at(h, "stress_xx", 0.0), value_at(h, "stress_zz", 0.0));
    println!("{label}, t = 0: stress_zz {zz0:.12} vs {szz0:.12}, stress_xx {xx0:.12} vs {sxx0:.12}");
    assert!((zz0 - szz0).abs() < 1e-10 * szz0.abs() && (xx0 - sxx0).abs() < 1e-10 * sxx0.abs(), "{label}");
    for (&t, &w) in times.iter().zip(&want) {
        let wxx = ode.state(ode.solve(&[t], 0.005)[0]).0;
        let (got, gxx) = (value_at(h, "stress_zz", t), value_at(h, "stress_xx", t));
        let (ez, ex) = ((got - w) / w, (gxx - wxx) / wxx);
        println!("{label}, t = {t}: stress_zz {got:.6} vs exact {w:.6} ({ez:+.2e}); stress_xx {gxx:.6} vs {wxx:.6} ({ex:+.2e})");
        assert!(ez.abs() < 5e-3 && ex.abs() < 5e-3, "{label}");
    }
    let det = h.col("det_bp_max_dev").iter().cloned().fold(0.0, f64::max);
    assert!(det < 1e-10, "{label}: max |det B_p - 1| {det:.2e}");
}

/// The shipped scene on 1 rank (and on 2 ranks to 100 s) against the ODE: the elastic state at
/// t = 0, σ_zz and σ_xx at 10, 50, 100 s within 0.5%, the relaxed state at 1000 s to 1e-6,
/// det B_p = 1 to 1e-10; the two rank counts' common rows agree to round-off.
#[test]
fn relaxation_matches_the_ode() {
    let ode = Ode::new();
    let mut runs = vec![];
    for np in [1, 2] {
        let dir = scratch(&format!("relaxation-np{np}"));
        // The relaxed state is checked once: the second rank count stops at 100 s.
        let h = run_relaxation(np, &dir, if np == 2 { &[("t_end = 1000.0", "t_end = 100.0")] } else { &[] });
        check_against_the_ode(&ode, &h, &format!("np {np}"));
        if np == 1 {
            let rel = relaxed_error(&h);
            let vm = *h.col("max_von_mises").last().unwrap();
            println!("np {np}: relaxed |dev sigma| rel. error {rel:.2e}, von Mises {vm:.10} (sigma_y = {SIGMA_Y})");
            assert!(rel < 1e-6 && (vm - SIGMA_Y).abs() < 1e-6 * SIGMA_Y);
        }
        // The remodelling strain grows monotonically and is homogeneous.
        let (mx, mean) = (h.col("max_norm_ep"), h.col("mean_norm_ep"));
        assert!(mx.windows(2).all(|w| w[1] >= w[0] - 1e-15));
        assert!(mx.iter().zip(&mean).all(|(a, b)| (a - b).abs() <= 1e-12 * a.max(1e-300)));
        runs.push(h);
    }
    let n = runs[1].rows.len();
    assert_eq!(runs[0].col("time")[..n], runs[1].col("time")[..]);
    let d = runs[0].col("stress_zz")[..n]
        .iter()
        .zip(runs[1].col("stress_zz"))
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max);
    println!("1 vs 2 ranks: max |stress_zz difference| {d:.2e} kPa");
    assert!(d < 1e-12);
}

/// The relaxation scene made neo-Hookean (`model = "neo_hookean"`, the same µ, ν, remodelling),
/// to 100 s on 1 rank, against its ODE as the Holmes–Mow run is.
#[test]
fn neo_hookean_relaxation_matches_the_ode() {
    let dir = scratch("relaxation-neo-hookean");
    let edits = [("model = \"holmes_mow\"", "model = \"neo_hookean\""), ("t_end = 1000.0", "t_end = 100.0")];
    check_against_the_ode(&Ode::neo_hookean(), &run_relaxation(1, &dir, &edits), "neo-Hookean");
}

/// Constant steps Δt = 2, 1, 0.5 s to t = 100 s: the error at 10, 50, 100 s halves with Δt
/// (backward Euler in the flow rule: first order).
#[test]
fn relaxation_converges_first_order_in_dt() {
    let ode = Ode::new();
    let times = [10.0, 50.0, 100.0];
    let want = ode.stress_zz(&times);
    let mut errs = vec![];
    for dt in ["2.0", "1.0", "0.5"] {
        let dir = scratch(&format!("relaxation-dt{dt}"));
        let h = run_constant_steps(&dir, dt, ("t_end = 1000.0", "t_end = 100.0"));
        let e =
            times.iter().zip(&want).map(|(&t, w)| ((value_at(&h, "stress_zz", t) - w) / w).abs()).fold(0.0, f64::max);
        println!("dt = {dt} s: max rel. error of stress_zz at t = 10, 50, 100 s: {e:.3e}");
        errs.push(e);
    }
    for w in errs.windows(2) {
        let order = (w[0] / w[1]).log2();
        println!("observed order {order:.3}");
        assert!(order > 0.9 && order < 1.5, "order {order}");
    }
}

/// The contrast to `relaxation_large_steps_stay_bounded`: the explicit (forward Euler) update
/// at the same Δt = 50 s and 200 s overshoots the yield surface into the elastic region in its
/// first step, where the flow stops: the relaxed state is missed (measured 84% and 70%) and det B_p
/// drifts from 1 (measured 0.13 and 0.99) — where the implicit map is relaxed to 1e-6 and 1e-3,
/// isochoric to 1e-10.
#[test]
fn explicit_remodelling_update_fails_at_large_steps() {
    for dt in ["50.0", "200.0"] {
        let dir = scratch(&format!("relaxation-explicit-dt{dt}"));
        let (first, max) = (format!("dt = {dt}"), format!("dt_max = {dt}"));
        let h = run_relaxation(
            1,
            &dir,
            &[
                ("dt = 0.05", &first),
                ("dt_max = 0.5", &max),
                ("growth = 1.1", "growth = 1.0"),
                ("land_on = [10.0, 50.0, 100.0]", "land_on = []"),
                ("sigma_y = 2.0 }", "sigma_y = 2.0, integrator = \"explicit\" }"),
            ],
        );
        let det = h.col("det_bp_max_dev").iter().cloned().fold(0.0, f64::max);
        let rel = relaxed_error(&h);
        println!("explicit, dt = {dt} s: relaxed rel. error {rel:.3}, max |det B_p - 1| {det:.3}");
        assert!(rel > 0.5 && det > 0.1, "dt = {dt}: explicit update error {rel}, det drift {det}");
    }
}

/// Δt = 50 s and 200 s (Δt λp µ = 1 and 4): the update stays bounded — σ_zz moves monotonically
/// from the elastic value towards the relaxed one without overshoot, and every step shrinks the
/// distance ‖dev σ‖ − √(2/3) σy to the yield surface (a contraction, as for backward Euler on
/// a decaying mode) — and isochoric to 1e-10. After 1000 s: relaxed to 1e-6 at Δt = 50 s; at
/// Δt = 200 s (5 steps) still on its way, within 1e-3.
#[test]
fn relaxation_large_steps_stay_bounded() {
    let ode = Ode::new();
    let (_, szz0, _, _) = ode.state(1.0);
    for (dt, end_tol) in [("50.0", 1e-6), ("200.0", 1e-3)] {
        let dir = scratch(&format!("relaxation-big-dt{dt}"));
        let h = run_constant_steps(&dir, dt, ("land_on = [10.0, 50.0, 100.0]", "land_on = []"));
        let (zz, xx) = (h.col("stress_zz"), h.col("stress_xx"));
        let n = zz.len() - 1;
        let det = h.col("det_bp_max_dev").iter().cloned().fold(0.0, f64::max);
        let rel = relaxed_error(&h);
        println!("dt = {dt} s: {n} steps, stress_zz {:.6} -> {:.6}, relaxed rel. error {rel:.2e}, max |det B_p - 1| {det:.2e}", zz[0], zz[n]);
        assert!((zz[0] - szz0).abs() < 1e-10 * szz0.abs());
        // Compressive and relaxing: |σ_zz| decreases step by step (so, from σ_zz(0) above, it stays
        // between the initial and the final value).
        assert!(zz.windows(2).all(|w| w[1] >= w[0] - 1e-12), "stress_zz not monotone: {zz:?}");
        let k = (2.0f64 / 3.0).sqrt() * SIGMA_Y;
        let dist: Vec<f64> = zz.iter().zip(&xx).map(|(z, x)| (2.0f64 / 3.0).sqrt() * (z - x).abs() - k).collect();
        let ratios: Vec<f64> = dist.windows(2).map(|w| w[1] / w[0]).collect();
        println!(
            "  distance to the yield surface shrinks by {:?} per step",
            ratios.iter().take(5).map(|r| format!("{r:.3}")).collect::<Vec<_>>()
        );
        assert!(ratios.iter().all(|&r| r > 0.0 && r < 1.0));
        assert!(det < 1e-10 && rel < end_tol);
    }
}
