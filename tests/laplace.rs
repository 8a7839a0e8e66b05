//! The lab's Laplace analysis on runs (docs/model.md, "The lab's Laplace analysis"): the
//! `R1, R2, R3, sigma_app` columns and the summary's `[laplace]` on a liquid drop between
//! non-adhesive plates, where σ_app should read the surface tension γ.

use crate::common::{cores, run_ok, scratch, History, Summary};
use std::path::Path;

/// `tst_hold` made a fast liquid: λp = 1 (kPa s)⁻¹ (the deviatoric stress relaxes in 1/(λp µ) =
/// 0.05 s), 100× the permeability, no gravity, γ = 20 mN/m; squeezed by 15% in 0.5 s and held to
/// `t_end` (`table`: the plates' table instead); surface nodes every `h_surf` R / 2 (P2).
fn drop(np: usize, dir: &Path, h_surf: f64, h: f64, t_end: f64, table: Option<&str>) -> History {
    let sizes =
        format!("mesh.relative_sizes={{ h = {h}, h_pole = {h}, r_pole = 0.5, h_surf = {h_surf}, w_surf = 0.15 }}");
    let table = format!("plates.table={}", table.unwrap_or(&format!("[[0, 0], [0.5, 0.15], [{t_end}, 0.15]]")));
    let end = format!("time.t_end={t_end}");
    let mut args = vec!["run", "tst_hold", "--out", dir.to_str().unwrap(), "-q", "--force"];
    let sets = [
        sizes.as_str(),
        "material.remodelling.lambda_p=1",
        "material.k0=377.29",
        "material.gravity=[0, 0, 0]",
        "surface.tension=20",
        &table,
        &end,
        "time.dt=0.01",
        "time.dt_max=0.5",
        "output.fields=false",
        "output.fields_at=[]",
    ];
    for s in sets.iter() {
        args.extend(["--set", s]);
    }
    run_ok(np, &args);
    History::read(dir)
}

/// Two holds, 15% from 0.5 to 0.7 s and 20% from 0.75 s to the end (1 s).
const TWO_HOLDS: &str = "[[0, 0], [0.5, 0.15], [0.7, 0.15], [0.75, 0.2], [1, 0.2]]";

/// The reading on 1 and 2 ranks is the same to round-off (the profile is gathered from both;
/// measured 1e-13), mid-relaxation (t = 1 s, two holds) on a coarse surface (10 µm faces); R2
/// agrees with the half-width (the largest node radius) to 0.1%, R3 lies within a surface node
/// spacing (5 µm) of the outermost node on the plate; the summary's `[laplace]` repeats the last
/// row, its `[[hold]]` entries the rows at the holds' ends, its `[liquid_test]` their ratio. (σ_app
/// against γ at rest: `laplace_drop::liquid_drop_matches_young_laplace`, and below.) 2 × 3 s.
#[test]
fn the_reading_is_the_same_on_one_and_two_ranks() {
    let _cores = cores(2);
    let dir = scratch("laplace-drop");
    let one = drop(1, &dir.join("one"), 0.1, 0.3, 1.0, Some(TWO_HOLDS));
    let two = drop(2, &dir.join("two"), 0.1, 0.3, 1.0, Some(TWO_HOLDS));
    let last = |h: &History, c: &str| *h.col(c).last().unwrap();
    for c in ["R1", "R2", "R3", "sigma_app", "force_total_mg"] {
        let (a, b) = (last(&one, c), last(&two, c));
        println!("{c}: 1 rank {a}, 2 ranks {b}");
        assert!((a - b).abs() <= 1e-7 * a.abs(), "{c}: {a} on 1 rank, {b} on 2");
    }
    let (r2, half) = (last(&one, "R2"), 0.5 * last(&one, "width"));
    assert!((r2 / half - 1.0).abs() < 1e-3, "R2 {r2} against the half-width {half}");
    let (r3, edge) = (last(&one, "R3"), last(&one, "contact_radius_upper"));
    assert!((r3 - edge).abs() < 5.0, "R3 {r3} against the outermost node on the plate at {edge}");
    let s = Summary::read(&dir.join("one"));
    assert_eq!(s.num("laplace.final_sigma_app_mN_m"), Some(last(&one, "sigma_app")));
    assert_eq!(s.num("laplace.hold_end_R3_um"), Some(r3));
    // The holds, each against the history's row at its end (the steps land on the table's rows
    // and on t_end).
    let t = one.col("time");
    let row = |when: f64| t.iter().position(|&x| (x - when).abs() < 1e-9).unwrap_or_else(|| panic!("no row at {when}"));
    let holds = s.array("hold");
    assert_eq!(holds.len(), 2, "{holds:?}");
    let mut sigma = Vec::new();
    for (hold, (start, end, compression)) in holds.iter().zip([(0.5, 0.7, 0.15), (0.75, 1.0, 0.2)]) {
        let num = |k: &str| hold.get(k).and_then(|v| v.as_float()).unwrap_or_else(|| panic!("no {k} in {hold:?}"));
        assert_eq!((num("start_s"), num("end_s"), num("compression")), (start, end, compression));
        let i = row(end);
        for (key, col) in [("sigma_app_mN_m", "sigma_app"), ("R3_um", "R3"), ("force_mg", "force_total_mg")] {
            assert_eq!(num(key), one.col(col)[i], "{key} of the hold ending at {end} s");
        }
        assert_eq!(num("force_uN"), one.col("force_total_uN")[i]);
        sigma.push(num("sigma_app_mN_m"));
    }
    // The liquid test on them: σ_app at 20% over σ_app at 15%, within 10% or not; each hold
    // lasts 4 and 5 relaxation times of 0.05 s, which it names.
    let ratio = sigma[1] / sigma[0];
    assert!((s.num("liquid_test.ratio").unwrap() / ratio - 1.0).abs() < 1e-15, "{ratio}");
    let liquid = ratio.max(1.0 / ratio) - 1.0 <= 0.1;
    let test = s.table("liquid_test");
    assert_eq!(test["liquid"].as_bool(), Some(liquid), "ratio {ratio}");
    let caveats: Vec<&str> = test["caveats"].as_array().unwrap().iter().map(|c| c.as_str().unwrap()).collect();
    assert!(caveats[0].starts_with("holds 1, 2 last 4, 5 relaxation times 1/(λp µ) = 0.05 s"), "{caveats:?}");
    assert!(!caveats.iter().any(|c| c.contains("gravity")), "{caveats:?}");
    // Every force in µN is its mg twin × 9.81.
    for (mg, un) in one.col("force_lower_mg").iter().zip(one.col("force_lower_uN")) {
        assert_eq!(mg * 9.81, un);
    }
}

/// σ_app converges to γ with the surface mesh: halving the surface spacing shrinks the error (R3,
/// within a node spacing of the contact edge, dominates it: the plate force is right to 0.1%),
/// and the extrapolation h → 0 reads γ within 1%. Measured at t = 10 s: 20.383 and 20.153
/// mN/m (+1.9%, +0.77%), extrapolated 19.92 (−0.4%).
#[test]
#[ignore = "slow tier: the finer drop takes 40 s"]
fn the_liquid_drop_reading_converges_to_the_surface_tension() {
    let _cores = cores(1);
    let dir = scratch("laplace-drop-convergence");
    let coarse = *drop(1, &dir.join("coarse"), 0.05, 0.2, 10.0, None).col("sigma_app").last().unwrap();
    let fine = *drop(1, &dir.join("fine"), 0.025, 0.1, 10.0, None).col("sigma_app").last().unwrap();
    let extrapolated = 2.0 * fine - coarse;
    println!("sigma_app {coarse}, {fine}; extrapolated {extrapolated}");
    assert!(fine < coarse && (fine - 20.0) < 0.6 * (coarse - 20.0), "{coarse} -> {fine}");
    assert!((extrapolated / 20.0 - 1.0).abs() < 0.01, "extrapolated {extrapolated}");
}

/// In 3-D the profile is fitted to every surface node at r = √(x² + y²): the default quarter
/// and the meridian of the same aggregate read the same shape at t = 8 s of the reference
/// protocol (mid-ramp). Measured: R1 85.62 against 85.77 µm (−0.2%), R2 107.45 against 107.48,
/// R3 63.21 against 62.11 (+1.8%; the outermost nodes on the plate at 61.7 and 56.3: different
/// meshes), σ_app 586 against 614 mN/m (the forces 15.74 and 15.89 mg). 19 s + 2 s on 1 rank.
#[test]
#[ignore = "slow tier: the 3-D quarter takes 20 s"]
fn the_quarter_and_the_meridian_read_the_same_profile() {
    let _cores = cores(1);
    let dir = scratch("laplace-3d");
    let read = |scene: &str| {
        let out = dir.join(scene);
        let args = ["run", scene, "--out", out.to_str().unwrap(), "-q", "--force", "--set", "time.t_end=8"];
        run_ok(1, &[&args[..], &["--set", "output.fields=false"]].concat());
        let h = History::read(&out);
        ["R1", "R2", "R3"].map(|c| *h.col(c).last().unwrap())
    };
    let (quarter, meridian) = (read("reference"), read("reference_axi"));
    println!("quarter {quarter:?}, meridian {meridian:?}");
    for (k, tol) in [0.005, 0.005, 0.03].iter().enumerate() {
        assert!((quarter[k] / meridian[k] - 1.0).abs() < *tol, "R{}: {} against {}", k + 1, quarter[k], meridian[k]);
    }
}
