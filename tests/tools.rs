//! Rigid tools (issue 53): exact frictionless contact with a sphere on the meridian, against
//! Hertz's closed form, F = (4/3) E* √R δ^{3/2} with E* = 4G undrained (ν = ½) and
//! 2G / (1 − ν) drained; the largest penetration at round-off; one rank ≡ two; bad input.

use crate::common::{assert_jacobian_checks, poroplast, run_ok, run_with_sets, scratch, History};
use std::path::Path;

/// The run of tests/data/hertz_block.toml (a sphere of radius 100 µm indenting a linear block,
/// G = 1 kPa, ν = 0.2, H = 500 µm, ramped to δ over 1 s in steps of 0.25 s) in `out`: `drained`
/// with a huge permeability and the top drained (drained within each step), else sealed
/// (undrained: ν = ½); the mesh size h_c at the contact.
fn run_hertz(np: usize, out: &Path, drained: bool, delta: f64, h_c: f64) -> History {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/hertz_block.toml");
    let mut sets = vec![
        format!("material.permeability={}", if drained { 1e6 } else { 1e-6 }),
        format!("mesh.params.h_c={h_c}"),
        format!("mesh.params.d_c={}", 40.0 * h_c),
        format!("tools.0.protocol=[{{t=0.0,displacement=0.0}},{{t=1.0,displacement={delta}}}]"),
    ];
    if drained {
        sets.push(r#"bc=[{group="bottom",displacement={z=0.0}},{group="top",pressure=0.0}]"#.into());
    }
    run_with_sets(np, &scene, out, &sets)
}

/// (δ, a/R, F / F_Hertz − 1, penetration) of every step after the first row, `e_star` in kPa.
fn against_hertz(h: &History, e_star: f64) -> Vec<(f64, f64, f64, f64)> {
    let (d, f, pen) = (h.col("bead_position"), h.col("bead_force_uN"), h.col("bead_penetration"));
    (1..d.len())
        .map(|i| {
            let a = (100.0 * d[i]).sqrt();
            let hertz = 4.0 / 3.0 * e_star * 100f64.sqrt() * d[i].powf(1.5);
            (d[i], a / 100.0, 1e3 * f[i] / hertz - 1.0, pen[i])
        })
        .collect()
}

/// Undrained (ν = ½, E* = 4G): within 1% of Hertz at every step (measured at this mesh: at most
/// 0.5%; a finite block of H = 50a and Sneddon's sphere, −0.1% at a/R = 0.1, bound the rest), the
/// contact radius within one cell of √(Rδ), and every node on the sphere at round-off.
#[test]
fn a_sphere_indents_a_block_undrained_as_hertz_says() {
    let dir = scratch("tools_hertz_undrained");
    let h = run_hertz(1, &dir.join("run"), false, 1.0, 1.0);
    let rows = against_hertz(&h, 4.0);
    assert_eq!(rows.len(), 4, "{rows:?}");
    for &(d, _, err, pen) in &rows {
        assert!(err.abs() <= 0.01, "δ = {d}: F / F_Hertz − 1 = {err:.4}");
        assert!(pen.abs() <= 1e-12 * 100.0, "δ = {d}: penetration {pen} µm");
    }
    let (d, r) = (h.col("bead_position"), h.col("bead_contact_radius"));
    let last = d.len() - 1;
    assert!((r[last] - (100.0 * d[last]).sqrt()).abs() <= 1.0, "contact radius {} vs √(Rδ) = 10", r[last]);
    assert!(h.col("bead_contact_nodes")[last] >= 10.0);
}

/// Drained (E* = 2G / (1 − ν)): the contact is on the current surface, which the compressible
/// skeleton also moves sideways, so the force departs from Hertz's linear theory at first order
/// in a/R (measured: about 0.36 a/R). Two indentations, the mesh scaled with the contact (h_c =
/// a/10), extrapolate linearly to a/R → 0 at Hertz's within 0.3%.
#[test]
fn a_drained_block_tends_to_hertz_as_the_contact_shrinks() {
    let dir = scratch("tools_hertz_drained");
    let mut last = Vec::new();
    for delta in [0.1, 0.025] {
        let h = run_hertz(1, &dir.join(format!("run{delta}")), true, delta, (100.0 * delta).sqrt() / 10.0);
        let rows = against_hertz(&h, 2.0 / 0.8);
        for &(d, _, err, pen) in &rows {
            assert!(err.abs() <= 0.015, "δ = {d}: F / F_Hertz − 1 = {err:.4}");
            assert!(pen.abs() <= 1e-12 * 100.0, "δ = {d}: penetration {pen} µm");
        }
        last.push(rows[rows.len() - 1]);
    }
    // a/R halves from the first run to the second.
    let limit = 2.0 * last[1].2 - last[0].2;
    assert!(limit.abs() <= 0.003, "extrapolated F / F_Hertz − 1 at a → 0: {limit:.5} ({last:?})");
}

/// Two ranks give the one-rank history (the ghost nodes' frames are computed from the same bits).
#[test]
fn tool_contact_on_two_ranks_is_the_one_rank_run() {
    let dir = scratch("tools_ranks");
    let h: Vec<History> =
        [1, 2].iter().map(|&np| run_hertz(np, &dir.join(format!("np{np}")), false, 1.0, 2.0)).collect();
    for col in ["bead_force_uN", "bead_contact_radius", "bead_contact_nodes"] {
        for (a, b) in h[0].col(col).iter().zip(h[1].col(col)) {
            assert!((a - b).abs() <= 1e-9 * a.abs().max(1e-6), "{col}: {a} on 1 rank, {b} on 2");
        }
    }
}

/// A tool inside the body at t = 0, a pulling force row and rows out of order are refused by
/// name before anything runs.
#[test]
fn a_tool_overlapping_the_body_or_with_bad_rows_is_refused() {
    let dir = scratch("tools_bad");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/hertz_block.toml").display().to_string();
    let cases = [
        ("tools.0.origin=[0,0,599.5]", "overlaps the body by 0.5000 µm at t = 0"),
        ("tools.0.protocol=[{t=0.0,force=-1.0}]", "row 1: force = -1 µN: a tool cannot pull"),
        (
            "tools.0.protocol=[{t=1.0,displacement=1.0},{t=0.5,displacement=0.0}]",
            "row 2: time 0.5 s comes before row 1's 1 s",
        ),
        ("tools.0.radius=-1.0", "tools.radius"),
    ];
    for (set, want) in cases {
        let out = dir.join("bad");
        let o = poroplast(1, &["run", &scene, "-q", "--out", &out.display().to_string(), "--set", set]);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(!o.status.success() && err.contains(want), "--set {set}: {err}");
        assert!(!out.exists(), "--set {set}: the refused run wrote {}", out.display());
    }
}

/// A sealed linear sphere (R = 100 µm) between a dish and a bead (R = 50 µm) pressed 4 µm on the
/// axis, on the meridian and on the 3-D quarter (two ranks; frames in space): the dish carries the
/// bead's force (equilibrium, to the Newton tolerance: 1e-7), no node enters a tool, and the two discretisations
/// agree to within their meshes' difference (measured +1.95% at these sizes, 4.2% while the
/// quarter's symmetry-plane nodes were left out of the contact; the meridian's own refinement
/// moves it by 4%, and it approaches Hertz's two contacts in series, 4.03 µm at its finest force).
/// The bound, 3%, fails with those nodes left out.
#[test]
fn a_bead_on_a_dish_in_space_balances_and_matches_the_meridian() {
    let dir = scratch("tools_bead_dish");
    let text = r#"name = "bead_dish"
[mesh]
geo = "sphere_quarter.geo"
meridian = "sphere_meridian.geo"
params = { R = 100.0, h = 25.0, h_pole = 4.0, r_pole = 40.0 }
[material]
model = "linear"
mu = 1.0
nu = 0.2
permeability = 1e-6
[[bc]]
group = "symmetry_x"
roller = true
geometry = "solid"
[[bc]]
group = "symmetry_y"
roller = true
geometry = "solid"
[[tools]]
name = "dish"
kind = "plane"
origin = [0.0, 0.0, 0.0]
axis = [0.0, 0.0, 1.0]
[[tools]]
name = "bead"
kind = "sphere"
radius = 50.0
origin = [0.0, 0.0, 250.0]
axis = [0.0, 0.0, -1.0]
protocol = [ { t = 0.0, displacement = 0.0 }, { t = 1.0, displacement = 4.0 } ]
[time]
t_end = 1.0
dt = 0.25
"#;
    let scene = dir.join("bead_dish.toml");
    std::fs::write(&scene, text).unwrap();
    let scene = scene.display().to_string();
    let (q, m) = (dir.join("quarter"), dir.join("meridian"));
    run_ok(2, &["run", &scene, "-q", "--out", &q.display().to_string()]);
    run_ok(1, &["run", &scene, "-q", "--out", &m.display().to_string(), "--set", "mesh.geometry=axisymmetric"]);
    let (hq, hm) = (History::read(&q), History::read(&m));
    for h in [&hq, &hm] {
        for (b, d) in h.col("bead_force_uN").iter().zip(h.col("dish_force_uN")) {
            assert!((b - d).abs() <= 1e-7 * b.abs().max(1e-9), "bead {b} against dish {d} µN");
        }
        for col in ["bead_penetration", "dish_penetration"] {
            assert!(h.col(col).iter().all(|p| p.abs() <= 1e-12 * 100.0), "{col}: {:?}", h.col(col));
        }
    }
    // The quarter's force is a quarter of the body's.
    let (fq, fm) = (4.0 * hq.col("bead_force_uN")[4], hm.col("bead_force_uN")[4]);
    println!("quarter × 4: {fq} µN, meridian {fm} µN ({:+.2}%)", 100.0 * (fq / fm - 1.0));
    assert!((fq / fm - 1.0).abs() <= 0.03, "quarter × 4: {fq} µN, meridian {fm} µN");
}

/// A sphere pressed by a pipette's rim onto a dish, 10 µm (tests/data/pipette_press.toml): the rim
/// ring carries the dish's force, no node enters the wall, and the contact lies on the rim
/// (between the bore, 20 µm, and the wall's outside, 30 µm). With a surface coarser than the rim
/// the run says so.
#[test]
fn a_pipette_presses_on_its_rim_and_says_when_the_surface_is_too_coarse_for_it() {
    let dir = scratch("tools_pipette");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/pipette_press.toml").display().to_string();
    let out = dir.join("run");
    run_ok(1, &["run", &scene, "-q", "--out", &out.display().to_string(), "--set", "time.t_end=0.5"]);
    let h = History::read(&out);
    let last = h.rows.len() - 1;
    let (pipette, dish) = (h.col("pipette_force_uN")[last], h.col("dish_force_uN")[last]);
    assert!(pipette > 0.1 && (pipette - dish).abs() <= 1e-7 * pipette, "pipette {pipette}, dish {dish} µN");
    for col in ["pipette_penetration", "dish_penetration"] {
        assert!(h.col(col).iter().all(|p| p.abs() <= 1e-12 * 100.0), "{col}: {:?}", h.col(col));
    }
    let r = h.col("pipette_contact_radius")[last];
    assert!((20.0..=30.0).contains(&r) && h.col("pipette_contact_nodes")[last] >= 3.0, "contact at r = {r}");
    let coarse = run_ok(
        1,
        &[
            "run",
            &scene,
            "--out",
            &dir.join("coarse").display().to_string(),
            "--set",
            "time.t_end=0.1",
            "--set",
            "mesh.params.h_pole=2",
        ],
    );
    assert!(coarse.contains("\"pipette\" has a rim of radius 2 µm, below the surface cells"), "{coarse}");
}

/// tests/data/hertz_block.toml with its top drained by `[drainage]` (k = 1 µm⁴/(nN s), h_c = 2 µm,
/// the penalty raised as the contact's cells are far below the mean size, two steps to δ = 0.5 µm; `drain` false: without it, sealed as before), probes of p under the
/// sphere's pole and at r = 30 µm (3a) on the top, `sets` added; with `extra` PETSc options.
/// Returns the history and stdout.
fn run_drained_top(dir: &Path, drain: bool, sets: &[&str], extra: &[&str]) -> (History, String) {
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/hertz_block.toml");
    let out = dir.join("run");
    let mut args: Vec<String> = vec!["run".into(), scene.display().to_string(), "-q".into(), "--out".into()];
    args.push(out.display().to_string());
    let base = [
        "material.permeability=1.0",
        "mesh.params.h_c=2",
        "mesh.params.d_c=60",
        "time.t_end=0.5",
        r#"probe=[{name="p_pole",field="p",point=[0.0,0.0,500.0]},{name="p_out",field="p",point=[30.0,0.0,500.0]}]"#,
    ];
    let drainage: &[&str] =
        if drain { &["drainage.group=top", "drainage.seal_gap=0.05", "drainage.penalty=1e4"] } else { &[] };
    for s in base.iter().chain(drainage).chain(sets) {
        args.extend(["--set".to_string(), s.to_string()]);
    }
    if !extra.is_empty() {
        args.push("--".into());
        args.extend(extra.iter().map(|s| s.to_string()));
    }
    let stdout = run_ok(1, &args.iter().map(String::as_str).collect::<Vec<_>>());
    (History::read(&out), stdout)
}

/// The drainage off a sealing tool (fully implicit: the iterate's gap) is differentiated exactly:
/// the seal distance (0.05 µm) puts the nodes at the contact's edge on the smoothstep's ramp (four
/// steps to δ = 1 µm, each checked).
#[test]
fn drainage_off_a_sealing_tool_matches_central_differences() {
    let dir = scratch("tools_drainage_jacobian");
    let (_, stdout) = run_drained_top(&dir, true, &["time.t_end=1.0"], &["-poroplast_check_jacobian", "1e-7"]);
    assert_jacobian_checks(&stdout);
}

/// `[drainage]` drains the top where the sphere is not: the pore pressure 3a from the axis is the
/// bath's (0, within 1% of the pole's), while under the sealing sphere it rises as undrained; a
/// `free` sphere lets the pole drain too; without `[drainage]` the surface stays sealed as before
/// (pole pressure and force higher).
#[test]
fn a_sealing_tool_keeps_the_surface_under_it_undrained_and_a_free_one_does_not() {
    let dir = scratch("tools_drainage_seal");
    let last = |h: &History, c: &str| *h.col(c).last().unwrap();
    let (sealed, _) = run_drained_top(&dir.join("sealed"), true, &[], &[]);
    let (free, _) = run_drained_top(&dir.join("free"), true, &[r#"tools.0.drainage="free""#], &[]);
    let (p_pole, p_out) = (last(&sealed, "p_pole"), last(&sealed, "p_out"));
    assert!(p_pole > 0.05, "sealed pole: p = {p_pole} kPa");
    assert!(p_out.abs() <= 0.01 * p_pole, "drained at 3a: p = {p_out} kPa against {p_pole} at the pole");
    let free_pole = last(&free, "p_pole");
    assert!(free_pole.abs() <= 0.01 * p_pole, "free sphere: p = {free_pole} kPa at the pole");
    // Drained under the sphere too, the skeleton takes more of the load sooner: less force.
    assert!(last(&free, "bead_force_uN") < last(&sealed, "bead_force_uN"));
    // Without [drainage] the whole surface is sealed, as before: the fluid under the sphere
    // cannot leave at all, so its pressure and the force stay higher than with the top drained.
    let (none, _) = run_drained_top(&dir.join("none"), false, &[], &[]);
    assert!(last(&none, "p_pole") > p_pole, "sealed: p = {} kPa at the pole, {p_pole} drained", last(&none, "p_pole"));
    assert!(last(&none, "bead_force_uN") > last(&sealed, "bead_force_uN"));
}

/// Hu, Zhao, Vlassak & Suo's (2010) normalised force after a step indentation by a sphere,
/// g(τ) = (F − F∞)/(F₀ − F∞), τ = D t / a².
fn hu_g(tau: f64) -> f64 {
    0.491 * (-0.908 * tau.sqrt()).exp() + 0.509 * (-1.679 * tau).exp()
}

/// Poroelastic relaxation under a held sphere (tests/data/indent_relaxation.toml: δ = 0.25 µm,
/// a = 5 µm, ramp τ_r = 1e-3, held to τ = 10; sealed under the sphere, drained elsewhere on the
/// top), normalised by the same mesh's undrained and drained forces, follows Hu et al.'s master
/// curve at τ − 0.6 τ_r (the ramp's first-order shift) from τ = 10 τ_r to 10 within 0.09 of
/// F₀ − F∞. Measured (scripts/data/tools_relaxation.csv): the largest deviation is 0.048 here, at
/// τ ≈ 0.4 (the computed curve relaxes faster there and slower after τ ≈ 2); it grows to 0.069
/// with the contact's cells halved and by 0.008 with shorter steps, so the converged curve sits
/// about 0.08 from the fit, which bounds the assertion. Why is not known: the fit's own accuracy
/// and the paper's drainage conditions were not readable here (docs/verification.md). A wrong
/// time scale shows: D off by 30% moves g by 0.065 at τ = 0.3.
#[test]
#[ignore = "slow: three runs of the graded block, about 12 s"]
fn a_held_sphere_relaxes_as_hu_et_al_say() {
    let dir = scratch("tools_relaxation");
    let scene = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/indent_relaxation.toml");
    let (ramp, diffusivity, a2) = (0.009375, 8.0 / 3.0, 25.0);
    let force = |name: &str, sets: &[&str]| -> History {
        run_with_sets(1, &scene, &dir.join(name), &sets.iter().map(|s| s.to_string()).collect::<Vec<_>>())
    };
    let end = format!("time.t_end={ramp}");
    let last = |h: &History| 1e3 * *h.col("bead_force_uN").last().unwrap();
    let f0 = last(&force("undrained", &["material.permeability=1e-8", &end]));
    let drained_top = r#"bc=[{group="bottom",displacement={z=0.0}},{group="top",pressure=0.0}]"#;
    let f_inf = last(&force("drained", &["material.permeability=1e6", drained_top, &end]));
    // The limits themselves are Hertz's within the block's and the drained contact's known
    // offsets (a_sphere_indents_a_block_undrained_as_hertz_says and the drained test).
    assert!((f0 / 6.666_666_7 - 1.0).abs() < 0.01 && (f_inf / 4.166_666_7 - 1.0).abs() < 0.04, "{f0}, {f_inf}");
    let h = force("relaxation", &[]);
    let mut worst = (0.0f64, 0.0);
    for (t, f) in h.col("time").iter().zip(h.col("bead_force_uN")) {
        let tau = diffusivity * t / a2;
        if *t < 10.0 * ramp * (1.0 - 1e-9) {
            continue;
        }
        let g = (1e3 * f - f_inf) / (f0 - f_inf);
        let d = g - hu_g(diffusivity * (t - 0.6 * ramp) / a2);
        if d.abs() > worst.0.abs() {
            worst = (d, tau);
        }
    }
    assert!(diffusivity * h.col("time").last().unwrap() / a2 >= 10.0 - 1e-9);
    assert!(worst.0.abs() <= 0.09, "largest g − g_Hu = {:.4} at τ = {:.3}", worst.0, worst.1);
}
