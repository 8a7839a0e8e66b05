//! The compression–release experiment (finite-strain biphasic aggregate between rigid plates,
//! SNESVI contact, drainage that follows contact) on a coarse version of the shipped reference
//! scene: ramp 2 s to ũ = 0.3, hold to 8 s, release by 10 s, rest to 12 s; h = 40, h_pole = 12.
//! Checks the protocol's behaviour, exact balances (fluid mass, weight), non-penetration,
//! 1 vs 2 ranks, quarter vs mirrored full sphere, the long-hold drained limit, the assembled
//! Jacobian against central differences, and quadratic Newton convergence; and the same protocol,
//! balances and Jacobian with equal-order P1–P1 (contact on the vertices).

use crate::common::*;
use std::path::Path;

/// Edits that turn the shipped reference scene into the coarse, short test scene.
const COARSE: &[(&str, &str)] = &[
    COARSE_SIZES,
    ("ramp = 5.0", "ramp = 2.0"),
    ("hold = 30.0", "hold = 6.0"),
    ("release = 5.0", "release = 2.0"),
    ("t_end = 100.0", "t_end = 12.0"),
];

/// The coarse mesh: h = 40, h_pole = 12 µm (R = 100 µm).
const COARSE_SIZES: (&str, &str) = (
    "relative_sizes = { h = 0.2, h_pole = 0.03, r_pole = 0.5 }",
    "relative_sizes = { h = 0.4, h_pole = 0.12, r_pole = 0.5 }",
);

/// The reference scene's quarter model with the symmetry rollers replaced by the full sphere's
/// rigid-mode locks, on the quarter mesh mirrored across both symmetry planes.
const MIRRORED: &[(&str, &str)] = &[
    ("r_pole = 0.5 }", "r_pole = 0.5 }\nmirror = [\"symmetry_x\", \"symmetry_y\"]"),
    (
        "[[bc]]\ngroup = \"symmetry_x\"\nroller = true\ngeometry = \"solid\"\n\n[[bc]]\ngroup = \"symmetry_y\"\nroller = true\ngeometry = \"solid\"\n",
        "[[bc]]\ngroup = \"pole_bottom\"\ndisplacement = { x = 0.0, y = 0.0 }\n\n\
         [[bc]]\ngroup = \"pole_top\"\ndisplacement = { x = 0.0, y = 0.0 }\n\n\
         [[bc]]\ngroup = \"equator_y\"\ndisplacement = { x = 0.0 }\n",
    ),
];

fn coarse_scene(dir: &Path, extra: &[(&str, &str)]) -> String {
    let edits: Vec<(&str, &str)> = COARSE.iter().chain(extra).copied().collect();
    scene_variant("reference", dir, &edits)
}

fn run_in(np: usize, sc: &str, dir: &Path, petsc: &[&str]) -> String {
    let mut args = vec!["run", sc, "--out", dir.to_str().unwrap(), "-q", "--"];
    args.extend(petsc);
    run_ok(np, &args)
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max)
}

/// The peak force (mg) of the coarse scene on the meridian (axisymmetric) model with a 5× finer
/// mesh (h = 8, h_pole = 1 µm), 1 rank: an independent discretisation of the same experiment, run
/// once per test process.
fn meridian_peak() -> f64 {
    static PEAK: std::sync::OnceLock<f64> = std::sync::OnceLock::new();
    *PEAK.get_or_init(|| {
        let dir = scratch("plates-meridian-reference");
        let sc = coarse_scene(&dir, &[]);
        let meridian = dir.join("meridian");
        // To just past the peak (at the end of the ramp, 2 s): the rest of the run cannot change it.
        let axi = [
            "--set",
            "mesh.geometry=axisymmetric",
            "--set",
            "mesh.params.h=8",
            "--set",
            "mesh.params.h_pole=1",
            "--set",
            "time.t_end=2.5",
            "--set",
            "output.fields=false",
        ];
        let mut args = vec!["run", sc.as_str(), "--out", meridian.to_str().unwrap(), "-q"];
        args.extend(axi);
        run_ok(1, &args);
        History::read(&meridian).col("force_total_mg").into_iter().fold(0.0, f64::max)
    })
}

/// The coarse scene (P2–P1, active-set Newton, MUMPS) on 2 ranks, run once per test process,
/// with the fields of every step (for the summary's largest p): its run directory.
fn coarse_two_ranks() -> &'static Path {
    static RUN: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    RUN.get_or_init(|| {
        let dir = scratch("plates-coarse");
        run_in(2, &coarse_scene(&dir, &[("fields_every = 5", "fields_every = 1")]), &dir.join("np2"), &[]);
        dir.join("np2")
    })
}

/// Quasi-static balance at every row: the lower plate carries the upper force plus the weight of
/// the mixture, ϱ g ∫J dV (ϱs = ϱf = 1000 kg/m³: 1e-9 mg per µm³).
fn assert_weight_carried(t: &[f64], upper: &[f64], lower: &[f64], volume: &[f64]) {
    for i in 0..t.len() {
        let w = 1e-9 * volume[i];
        assert!(
            (lower[i] - upper[i] - w).abs() < 1e-3 * w,
            "t = {}: lower {} - upper {} != weight {w}",
            t[i],
            lower[i],
            upper[i]
        );
    }
}

const FORCES: [&str; 4] = ["force_total_mg", "force_constitutive_mg", "force_pressure_mg", "force_lower_mg"];

#[test]
fn compression_release_protocol() {
    let dir = scratch("plates-protocol");
    let sc = coarse_scene(&dir, &[]);
    run_in(1, &sc, &dir.join("np1"), &[]);
    let h = History::read(coarse_two_ranks());
    let col = |c: &str| h.col(c);
    let (t, f, fc, fp, flow) = (
        col("time"),
        col("force_total_mg"),
        col("force_constitutive_mg"),
        col("force_pressure_mg"),
        col("force_lower_mg"),
    );
    let (pp, pen, vol, out) = (col("probe_p"), col("max_penetration"), col("fluid_volume"), col("outflow_total"));
    let n = t.len();
    // The force rises during the ramp, peaks at its end (ramp 2 s), relaxes while held,
    // and is zero once the upper contact has opened after the release.
    let ipk = (0..n).max_by(|&a, &b| f[a].total_cmp(&f[b])).unwrap();
    assert!((t[ipk] - 2.0).abs() < 0.3, "peak force at t = {} s", t[ipk]);
    // The peak against an independent discretisation of the same experiment: the meridian
    // (axisymmetric) model on a 5x finer mesh, itself 0.4% from h = 4 µm. Measured: the coarse
    // 3-D mesh is 3.97% low at h = 40 µm (4.9% before enclosed contact vertices stopped
    // draining; the shipped mesh is 0.54% low, docs/performance.md).
    let f_ref = meridian_peak();
    let err = f[ipk] / f_ref - 1.0;
    println!("peak {} mg, {:+.2}% from the meridian's {f_ref} mg", f[ipk], 100.0 * err);
    assert!(err < 0.0 && err > -0.045, "peak force {} mg, {:+.2}% from the meridian's {f_ref} mg", f[ipk], 100.0 * err);
    let ramp: Vec<usize> = (0..n).filter(|&i| t[i] <= 2.0 + 1e-9).collect();
    assert!(ramp.windows(2).all(|w| f[w[1]] >= f[w[0]] - 1e-9), "force not rising during the ramp");
    let hold: Vec<usize> = (0..n).filter(|&i| t[i] > 2.0 + 1e-9 && t[i] <= 8.0 + 1e-9).collect();
    assert!(hold.windows(2).all(|w| f[w[1]] <= f[w[0]] + 1e-9), "force not relaxing during the hold");
    let end_hold = *hold.last().unwrap();
    assert!(f[end_hold] < 0.95 * f[ipk], "no relaxation: {} of peak {}", f[end_hold], f[ipk]);
    assert_eq!(f[n - 1], 0.0, "upper contact still closed at the end");
    // The split into constitutive and pressure parts is exact.
    for i in 0..n {
        assert!((f[i] - fc[i] - fp[i]).abs() <= 1e-9 * f[ipk], "step {i}: total != constitutive + pressure");
    }
    // p(X_U) stays positive while held (no backflow without remodelling).
    for &i in &hold {
        assert!(pp[i] > 0.0, "p(X_U) = {} kPa at t = {}", pp[i], t[i]);
    }
    // Quasi-static balance: the lower plate carries the upper force plus the weight.
    assert_weight_carried(&t, &f, &flow, &vol);
    // Fluid mass: the change of ∫J dV is the time-integrated outflow, to solver tolerance.
    let dv_max = vol.iter().map(|v| (v - vol[0]).abs()).fold(0.0, f64::max);
    assert!(dv_max > 0.02 * vol[0], "almost no fluid exchanged: {dv_max}");
    let mass = (0..n).map(|i| (vol[i] - vol[0] + out[i]).abs()).fold(0.0, f64::max);
    assert!(mass < 1e-8 * dv_max, "mass balance error {mass:e} of {dv_max:e} µm³");
    // Non-penetration: nodes satisfy the bounds exactly; between nodes the quadratic faces may
    // bulge across a plate by a discretisation error (measured 0.67 µm = 0.67% R on this mesh,
    // shrinking under refinement: docs/verification.md, mesh refinement).
    let pen_max = pen.iter().cloned().fold(0.0, f64::max);
    assert!(pen_max < 1.0, "penetration {pen_max} µm (R = 100 µm)");
    // 1 rank and 2 ranks: the same steps and the same forces to solver tolerance.
    let h1 = History::read(&dir.join("np1"));
    assert_eq!(h1.col("time"), t, "1-rank and 2-rank runs took different steps");
    for c in FORCES.iter().chain(&["probe_p", "fluid_volume", "height", "width"]) {
        let scale = h.col(c).iter().map(|x| x.abs()).fold(1e-3, f64::max);
        let d = max_abs_diff(&h1.col(c), &h.col(c));
        assert!(d < 1e-6 * scale, "{c}: 1 vs 2 ranks differ by {d:e} (scale {scale})");
    }
}

/// Equal-order P1–P1 (`fem::equal_order`) instead of Taylor–Hood.
const P1P1: (&str, &str) = ("[fem]", "[fem]\nelement = \"P1-P1\"");

/// The active-set size of the final Newton iterate of every accepted step, from the
/// `-poroplast_newton_monitor` lines before each `step` line (step 1 first).
fn final_active_sets(stdout: &str) -> Vec<f64> {
    let mut last = f64::NAN;
    let mut out = Vec::new();
    for l in stdout.lines() {
        if let Some(p) = l.find(" active ") {
            last = l[p + 8..].split_whitespace().next().unwrap().parse().unwrap();
        } else if l.starts_with("step ") {
            out.push(last);
        }
    }
    out
}

/// Equal-order P1–P1 with plates (`fem::equal_order`): the bounds sit on the contact surface's
/// vertices only, the mid-edge nodes follow their edges. The coarse protocol runs; the force
/// splits exactly into its constitutive and pressure parts and the lower plate carries the
/// upper force plus the weight (the reactions include what the tie rows move to the vertices);
/// no mid-edge node is ever active (the final active set of every step is at most the vertices
/// in contact, and those are about a third of Taylor–Hood's contact nodes, which count the
/// mid-edge nodes too); the peak force against the meridian model on a 5× finer mesh.
/// Measured: peak 18.74 mg, 0.4% below the meridian's 18.81 (Taylor–Hood on this mesh: 4.9%
/// below); contact nodes at the peak 12 + 12 against Taylor–Hood's 39 + 39; penetration between
/// nodes 1.5 µm, the reference sagitta h²/8R ≤ 2 µm of the contact faces (the geometry is
/// curved, the displacement linear). Slow tier: P1–P1's Jacobian stays in the default tier.
#[test]
#[ignore = "slow tier: the P1-P1 protocol on 2 ranks (about 25 s of the default tier's 2 cores)"]
fn equal_order_compression_release_protocol() {
    let dir = scratch("plates-p1p1");
    let sc = coarse_scene(&dir, &[P1P1]);
    let out = dir.join("run");
    let stdout = run_ok(2, &["run", &sc, "--out", out.to_str().unwrap(), "--", "-poroplast_newton_monitor"]);
    let h = History::read(&out);
    let col = |c: &str| h.col(c);
    let (t, f, fc, fp, flow, vol) = (
        col("time"),
        col("force_total_mg"),
        col("force_constitutive_mg"),
        col("force_pressure_mg"),
        col("force_lower_mg"),
        col("fluid_volume"),
    );
    let n = t.len();
    let ipk = (0..n).max_by(|&a, &b| f[a].total_cmp(&f[b])).unwrap();
    assert!((t[ipk] - 2.0).abs() < 0.3, "peak force at t = {} s", t[ipk]);
    let hold: Vec<usize> = (0..n).filter(|&i| t[i] > 2.0 + 1e-9 && t[i] <= 8.0 + 1e-9).collect();
    assert!(hold.windows(2).all(|w| f[w[1]] <= f[w[0]] + 1e-9), "force not relaxing during the hold");
    assert_eq!(f[n - 1], 0.0, "upper contact still closed at the end");
    for i in 0..n {
        assert!((f[i] - fc[i] - fp[i]).abs() <= 1e-9 * f[ipk], "step {i}: total != constitutive + pressure");
    }
    assert_weight_carried(&t, &f, &flow, &vol);
    let mass = (0..n).map(|i| (vol[i] - vol[0] + col("outflow_total")[i]).abs()).fold(0.0, f64::max);
    assert!(mass < 1e-8 * vol[0], "mass balance error {mass:e} µm³");
    // No mid-edge node active: every step's final active set is within its contact vertices.
    let (up, lo) = (col("contact_nodes_upper"), col("contact_nodes_lower"));
    let active = final_active_sets(&stdout);
    assert_eq!(active.len(), n - 1, "one final active set per step");
    for (i, a) in active.iter().enumerate() {
        assert!(
            *a <= up[i + 1] + lo[i + 1],
            "t = {}: {a} active dofs, {} + {} contact vertices",
            t[i + 1],
            up[i + 1],
            lo[i + 1]
        );
    }
    assert!(up[ipk] >= 3.0 && lo[ipk] >= 3.0, "contact at the peak: {} + {} vertices", up[ipk], lo[ipk]);
    let h2 = History::read(coarse_two_ranks());
    let (up2, lo2) = (h2.col("contact_nodes_upper"), h2.col("contact_nodes_lower"));
    let i2 = h2.col("time").iter().position(|&x| (x - t[ipk]).abs() < 1e-9).expect("the peak's time in P2-P1");
    assert!(
        up[ipk] < 0.5 * up2[i2] && lo[ipk] < 0.5 * lo2[i2],
        "P1-P1 {} + {} vs P2-P1 {} + {} contact nodes",
        up[ipk],
        lo[ipk],
        up2[i2],
        lo2[i2]
    );
    let pen = col("max_penetration").into_iter().fold(0.0, f64::max);
    assert!(pen < 2.0, "penetration {pen} µm beyond the contact faces' sagitta");
    let f_ref = meridian_peak();
    let err = f[ipk] / f_ref - 1.0;
    println!("peak {} mg, {:+.2}% from the meridian's {f_ref} mg", f[ipk], 100.0 * err);
    println!("P1-P1 peak {:.4} mg, {:+.2}% from the meridian's {f_ref:.4} mg; contact nodes {} + {} (P2-P1 {} + {}); penetration {pen:.3} µm",
        f[ipk], 100.0 * err, up[ipk], lo[ipk], up2[i2], lo2[i2]);
    assert!(err.abs() < 0.02, "peak force {} mg, {:+.2}% from the meridian's {f_ref} mg", f[ipk], 100.0 * err);
}

/// P1–P1's assembled Jacobian (tie rows, the P1 combination of the rows, contact on vertices,
/// drainage, the constant stabilisation) against central differences, ε = 1e-7, with the
/// default predicted drainage gap (2 ranks). Measured: u rows 1.3e-9, p rows 3.9e-10.
#[test]
fn equal_order_jacobian_matches_central_differences() {
    let (u, p, n) = jacobian_check(2, "plates-p1p1-jacobian", &[P1P1], "1e-7");
    println!("P1-P1: predicted gap u rows {u:.2e}, p rows {p:.2e} ({n} checks)");
    assert!(n > 10, "{n} checks");
    assert!(u < 1e-8 && p < 1e-8, "u rows: {u}, p rows: {p}");
}

/// As above with the implicit drainage (1 rank). Measured: u rows 1.5e-9, p rows 2.0e-5 (the
/// implicit drainage's p rows carry the difference formula's O(ε) at vertices on a plate, as for
/// Taylor–Hood, whose implicit drainage the default tier checks).
#[test]
#[ignore = "slow tier: P1-P1's implicit-drainage Jacobian check (the default tier checks its predicted gap, and Taylor-Hood's implicit one)"]
fn equal_order_implicit_drainage_jacobian_matches_central_differences() {
    let (u, p, n) = jacobian_check(1, "plates-p1p1-jacobian-implicit", &[P1P1, IMPLICIT_DRAINAGE], "1e-7");
    println!("P1-P1: implicit u rows {u:.2e}, p rows {p:.2e} ({n} checks)");
    assert!(n > 10, "{n} checks");
    assert!(u < 1e-8, "u rows: {u}");
    assert!(p < 1e-4, "p rows (implicit drainage): {p}");
}

/// Runs the coarse quarter model and a full sphere from `full_edits` on 2 ranks, and asserts that
/// they take the same steps and give the same results (reported for the full sphere) to solver
/// tolerance. Both with the constant stabilisation: with the scene's faded one, the free-rotation
/// full sphere (direct preset) needs one step cut near the end of the release that the quarter
/// does not (measured: 9.49 → 10 s split in three), so the rows no longer pair up; what these
/// runs check, the symmetry reduction and the rigid modes, does not depend on the stabilisation.
fn assert_full_matches_quarter(name: &str, quarter: &Path, full_edits: &[(&str, &str)], petsc: &[&str]) {
    let dir = scratch(name);
    let full_dir = dir.join("full-scene");
    std::fs::create_dir_all(&full_dir).unwrap();
    let edits: Vec<(&str, &str)> = COARSE.iter().chain(full_edits).chain([&CONSTANT]).copied().collect();
    let full = scene_variant("reference", &full_dir, &edits);
    // On 1 rank: the quarter's 2 ranks take the same steps (meridian_one_and_two_ranks_agree).
    run_in(1, &full, &dir.join("full"), petsc);
    let (hq, hf) = (History::read(quarter), History::read(&dir.join("full")));
    // The full run may end early (a shortened run): its rows are the quarter's first ones.
    let n = hf.rows.len();
    assert_eq!(hq.col("time")[..n], hf.col("time")[..], "the full sphere's steps differ from the quarter's");
    let peak = hq.col("force_total_mg").iter().cloned().fold(0.0, f64::max);
    for c in FORCES {
        let d = max_abs_diff(&hq.col(c)[..n], &hf.col(c));
        assert!(d < 1e-2 * peak, "{c}: quarter and full differ by {d} mg (peak {peak})");
        assert!(d < 1e-6 * peak, "{c}: quarter and full differ by {d:e} mg, beyond solver tolerance");
    }
    let v0 = hq.col("fluid_volume")[0];
    assert!(max_abs_diff(&hq.col("fluid_volume")[..n], &hf.col("fluid_volume")) < 1e-8 * v0);
}

/// The stabilisation at full weight (see [`assert_full_matches_quarter`]): faded by neither the
/// drainage nor the steps' growth.
const CONSTANT: (&str, &str) = ("stabilisation_fade = 0.03", "stabilisation_fade = 1e9\nstabilisation_steps = 1e9");

/// The coarse quarter with the constant stabilisation through the ramp (to 2 s), run once per
/// test process: the run directory (the default tier's full-sphere comparisons read it).
fn constant_quarter_ramp() -> &'static Path {
    static RUN: std::sync::OnceLock<std::path::PathBuf> = std::sync::OnceLock::new();
    RUN.get_or_init(|| constant_quarter("plates-constant-quarter-ramp", &[RAMP]))
}

/// Ends the coarse experiment with its ramp.
const RAMP: (&str, &str) = ("t_end = 12.0", "t_end = 2.0");

/// The coarse quarter with the constant stabilisation and `edits`, on 2 ranks, in `name`.
fn constant_quarter(name: &str, edits: &[(&str, &str)]) -> std::path::PathBuf {
    let dir = scratch(name);
    let q = coarse_scene(&dir, &[&[CONSTANT][..], edits].concat());
    run_in(2, &q, &dir.join("quarter"), &[]);
    dir.join("quarter")
}

/// A full sphere made of the quarter mesh mirrored across both symmetry planes, with the rigid
/// modes locked on the axis and at (0, R, R), gives the quarter model's results (reported for
/// the full sphere) to solver tolerance: symmetry reduction and rigid-mode locks are exact. By
/// default the mirrored sphere runs with free rigid modes through the ramp (below).
#[test]
#[ignore = "slow tier: the full sphere through the whole coarse experiment (9 s)"]
fn quarter_and_full_sphere_agree() {
    let quarter = constant_quarter("plates-constant-quarter", &[]);
    assert_full_matches_quarter("plates-full", &quarter, MIRRORED, &[]);
}

/// The same mirrored full sphere with only the poles held in x and y: the rotation about z is
/// free (`solver::FreeRigidModes`); the AMG fieldsplit takes it as the Jacobian's null space
/// (from the first Newton iteration on: the loading ramp shows it).
#[test]
#[ignore = "slow tier: the full sphere through the ramp (25 core-s); the free modes' projection is unit-tested (solver::rigid)"]
fn full_sphere_with_free_rigid_modes_agrees() {
    let amg: Vec<(&str, &str)> =
        FREE.iter().copied().chain([("[output]", "[solver]\npreset = \"fieldsplit\"\n\n[output]"), RAMP]).collect();
    assert_full_matches_quarter("plates-full-free-amg", constant_quarter_ramp(), &amg, &[]);
}

/// The free full sphere with the direct preset, which locks the rotation at one dof, through the
/// ramp (the hold and the release are the locked sphere's, `quarter_and_full_sphere_agree`).
#[test]
#[ignore = "slow tier: a second full-sphere run of the free modes (7 core-s), the direct preset's lock"]
fn full_sphere_with_free_rigid_modes_agrees_direct() {
    let direct: Vec<(&str, &str)> = FREE.iter().copied().chain([RAMP]).collect();
    assert_full_matches_quarter("plates-full-free", constant_quarter_ramp(), &direct, &[]);
}

/// The mirrored full sphere's edits with only the poles held in x and y.
const FREE: [(&str, &str); 2] = [
    MIRRORED[0],
    (
        "[[bc]]\ngroup = \"symmetry_x\"\nroller = true\ngeometry = \"solid\"\n\n[[bc]]\ngroup = \"symmetry_y\"\nroller = true\ngeometry = \"solid\"\n",
        "[[bc]]\ngroup = \"pole_bottom\"\ndisplacement = { x = 0.0, y = 0.0 }\n\n\
         [[bc]]\ngroup = \"pole_top\"\ndisplacement = { x = 0.0, y = 0.0 }\n",
    ),
];

/// The active-set Newton (full-size system, `solver::active_set`) against PETSc's own
/// reduced-space VI Newton (`vinewtonrsls`, MUMPS) on the coarse scene: through the ramp and the
/// hold they take the same steps and give the same forces to solver tolerance. (In the release
/// their step cuts differ: ours halves steps into inadmissible states, rsls cannot.)
#[test]
fn active_set_newton_matches_petsc_vi() {
    let dir = scratch("plates-vi");
    let sc = coarse_scene(&dir, &[]);
    run_in(2, &sc, &dir.join("rsls"), &["-snes_type", "vinewtonrsls", "-ksp_type", "preonly"]);
    let (a, b) = (History::read(coarse_two_ranks()), History::read(&dir.join("rsls")));
    let (ta, tb) = (a.col("time"), b.col("time"));
    let same = ta.iter().zip(&tb).take_while(|(x, y)| x == y).count();
    assert!(ta[same - 1] >= 8.0, "the solvers' steps differ from t = {} (before the release at 8 s)", ta[same - 1]);
    let peak = a.col("force_total_mg").iter().cloned().fold(0.0, f64::max);
    for c in FORCES {
        let d = max_abs_diff(&a.col(c)[..same], &b.col(c)[..same]);
        assert!(d < 1e-6 * peak, "{c}: active-set Newton and vinewtonrsls differ by {d:e} mg (peak {peak})");
    }
}

/// Held long enough, the poroelastic force relaxes to the drained skeleton's force at the same
/// plate position, computed directly with no fluid (`drained = true`: p ≡ 0, static steps).
#[test]
fn long_hold_reaches_the_drained_static_force() {
    let dir = scratch("plates-drained");
    let hold = scene_variant(
        "reference",
        &dir,
        &[
            COARSE_SIZES,
            ("hold = 30.0", "hold = 100000.0"),
            ("t_end = 100.0", "t_end = 800.0"),
            ("dt_max = 2.0", "dt_max = 100.0"),
        ],
    );
    run_in(1, &hold, &dir.join("hold"), &[]);
    let ddir = dir.join("drained-scene");
    std::fs::create_dir_all(&ddir).unwrap();
    let drained = scene_variant(
        "reference",
        &ddir,
        &[
            COARSE_SIZES,
            ("gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, -9.81]\ndrained = true"),
            ("hold = 30.0", "hold = 100000.0"),
            ("t_end = 100.0", "t_end = 5.0"),
            ("dt = 0.02 ", "dt = 0.5 "),
        ],
    );
    run_in(1, &drained, &dir.join("drained"), &[]);
    let (hh, hd) = (History::read(&dir.join("hold")), History::read(&dir.join("drained")));
    let fd = *hd.col("force_total_mg").last().unwrap();
    assert!(hd.col("force_pressure_mg").iter().all(|&x| x == 0.0), "drained run has pressure");
    let fh = hh.col("force_total_mg");
    let peak = fh.iter().cloned().fold(0.0, f64::max);
    let plateau = *fh.last().unwrap();
    // Measured: peak 16.9, plateau at 800 s 11.355 mg, drained 11.324 mg (0.3%).
    assert!(peak > 1.3 * fd, "no poroelastic overshoot: peak {peak}, drained {fd}");
    assert!((plateau - fd).abs() < 0.01 * fd, "plateau {plateau} mg vs drained static {fd} mg");
}

/// A soft aggregate (µ = 3 kPa) on the default mesh: full Newton steps of the gravity settling
/// overshoot at the point contact (J < Φs); the active-set Newton halves such steps (before it
/// did, the driver had to retry the settling with backtracking), and the settled state carries
/// its weight on the lower plate (t = 0 row: lower force = ϱ g ∫J dV).
#[test]
fn soft_aggregate_settles() {
    let dir = scratch("plates-soft-settle");
    let sc = scene_variant("reference", &dir, &[("mu = 20.0", "mu = 3.0"), ("t_end = 100.0", "t_end = 0.05")]);
    let full = poroplast(2, &["run", &sc, "--out", dir.join("run").to_str().unwrap()]);
    let stdout = String::from_utf8_lossy(&full.stdout);
    assert!(full.status.success(), "{stdout}");
    let h = History::read(&dir.join("run"));
    let (lower, vol) = (h.col("force_lower_mg")[0], h.col("fluid_volume")[0]);
    let weight = 1e-9 * vol;
    println!("settled: lower plate {lower:.6} mg, weight {weight:.6} mg");
    assert!((lower - weight).abs() < 1e-3 * weight, "lower {lower} vs weight {weight}");
}

/// Remodelling switched on with λp ten times Table 1's (0.01 (kPa s)⁻¹), so that the flow is
/// well under way within the short test protocol.
const REMODELLING: (&str, &str) =
    ("gravity = [0.0, 0.0, -9.81]", "gravity = [0.0, 0.0, -9.81]\nremodelling = { lambda_p = 0.01, sigma_y = 2.0 }");

/// The largest u-row and p-row errors of `-poroplast_check_jacobian eps` over a 3 s coarse run on
/// `np` ranks.
fn jacobian_check(np: usize, name: &str, extra: &[(&str, &str)], eps: &str) -> (f64, f64, usize) {
    let dir = scratch(name);
    let mut edits = vec![RAMP];
    edits.extend(extra);
    let sc = coarse_scene(&dir, &edits);
    let e = jacobian_errors(&run_in(np, &sc, &dir.join("run"), &["-poroplast_check_jacobian", eps]));
    let max = |k: usize| e.iter().map(|x| if k == 0 { x.0 } else { x.1 }).fold(0.0, f64::max);
    (max(0), max(1), e.len())
}

/// Drainage opened by the Newton iterate's own gap (differentiated exactly), not the default
/// predicted gap (fixed within a step).
const IMPLICIT_DRAINAGE: (&str, &str) = ("release = 2.0", "release = 2.0\ndrainage_gap = \"current\"");

/// The assembled Jacobian (finite strain, gravity, contact, drainage, stabilisation) against
/// central differences of the assembled residual along a fixed random direction, at every step
/// of the experiment, with the implicit drainage (whose derivative dc/du_z the Jacobian holds).
/// With 10× smaller ε the error drops about 10×: it is the difference formula's (O(ε) at
/// vertices lying exactly on a plate), not the Jacobian's. The smaller ε on 2 ranks (the
/// assembly across the partition), the larger on 1; the other checks on 1 rank.
#[test]
fn jacobian_matches_central_differences() {
    let (ua, pa, na) = jacobian_check(1, "plates-jacobian-a", &[IMPLICIT_DRAINAGE], "1e-6");
    let (ub, pb, nb) = jacobian_check(2, "plates-jacobian-b", &[IMPLICIT_DRAINAGE], "1e-7");
    assert!(na > 10 && na == nb, "{na} and {nb} checks");
    // Measured: u rows 4.2e-10 / 4.3e-9 (round-off), p rows 1.9e-4 / 1.2e-5.
    println!("u rows {ua:.2e} / {ub:.2e}, p rows {pa:.2e} / {pb:.2e}");
    assert!(ub < 1e-8, "u rows: {ub}");
    assert!(pb < 1e-4, "p rows: {pb}");
    assert!(pb < 0.2 * pa, "p-row error does not shrink with ε: {pa:e} → {pb:e}");
}

/// With the default predicted drainage gap the conductances are fixed within a step, so the
/// residual has no kink at the contact edge and the Jacobian (without dc/du_z) matches central
/// differences up to the difference formula's O(ε) at vertices on a plate. Measured (ε = 1e-7):
/// u rows 4.1e-9, p rows 2.2e-10; the implicit drainage's p rows are at 1.2e-5 there, and a
/// stray dc/du_z term would be of that size or more.
#[test]
fn jacobian_with_predicted_drainage_matches_central_differences() {
    let (u, p, n) = jacobian_check(1, "plates-jacobian-predicted", &[], "1e-7");
    println!("u rows {u:.2e}, p rows {p:.2e} over {n} checks");
    assert!(n > 10, "{n} checks");
    assert!(u < 1e-8, "u rows: {u}");
    assert!(p < 1e-8, "p rows: {p}");
}

/// The same check with remodelling active: the Jacobian holds the consistent tangent of the
/// local B_p update (through stress and permeability), so the u rows stay at the difference
/// formula's error. Measured: u rows 4.2e-9, p rows 2.4e-10 (predicted drainage gap); with the
/// chain terms left out (B_p frozen in the tangent) the u rows are off by 5.9e-2.
#[test]
fn jacobian_matches_central_differences_with_remodelling() {
    let (ub, pb, n) = jacobian_check(1, "plates-jacobian-remodelling", &[REMODELLING], "1e-7");
    println!("with remodelling: {n} checks, u rows {ub:.2e}, p rows {pb:.2e}");
    assert!(n > 10);
    assert!(ub < 1e-8, "u rows: {ub}");
    // The same bound as without remodelling (predicted gap): the p rows hold the permeability's
    // B_p chain too, and a missing term there would be far above the difference formula's error.
    assert!(pb < 1e-8, "p rows: {pb}");
}

/// Newton with exact linear solves (MUMPS) on the 3 s coarse run: for each converged solve the
/// order estimate log(r_n / r_{n-1}) / log(r_{n-1} / r_{n-2}) of its last three residuals (where
/// they are well below the first), and the residual history of the longest such solve.
fn newton_orders(name: &str, extra: &[(&str, &str)]) -> (Vec<f64>, Vec<f64>) {
    let dir = scratch(name);
    let mut edits = vec![RAMP];
    edits.extend(extra);
    let sc = coarse_scene(&dir, &edits);
    let out = run_in(
        1,
        &sc,
        &dir.join("run"),
        &[
            "-ksp_type",
            "preonly",
            "-pc_type",
            "lu",
            "-pc_factor_mat_solver_type",
            "mumps",
            "-snes_monitor",
            "-snes_converged_reason",
        ],
    );
    let mut orders = Vec::new();
    let mut norms: Vec<f64> = Vec::new();
    let mut longest: Vec<f64> = Vec::new();
    for l in out.lines() {
        if let Some(p) = l.find("SNES Function norm") {
            let r: f64 = l[p + 18..].trim().parse().unwrap();
            if l.trim_start().starts_with("0 ") {
                norms.clear();
            }
            norms.push(r);
        } else if l.contains("Nonlinear solve converged") && norms.len() >= 4 {
            let k = norms.len();
            let (a, b, c) = (norms[k - 3], norms[k - 2], norms[k - 1]);
            if b < 1e-2 * norms[0] && c > 0.0 {
                orders.push((c / b).ln() / (b / a).ln());
                if norms.len() > longest.len() {
                    longest = norms.clone();
                }
            }
        }
    }
    orders.sort_by(f64::total_cmp);
    (orders, longest)
}

#[test]
fn newton_converges_quadratically() {
    let (orders, _) = newton_orders("plates-newton", &[]);
    assert!(orders.len() >= 5, "too few converged solves to judge: {orders:?}");
    let median = orders[orders.len() / 2];
    assert!(median > 1.6, "median convergence order {median} (orders {orders:?})");
}

/// Quadratic convergence is kept while remodelling is active (consistent tangent). Measured:
/// median order 1.99 over 14 solves; e.g. 2.1e3, 1.6e3, 8.8e2, 2.4e2, 2.9e2, 44, 1.9, 3.8e-3, 1.6e-8
/// (the first iterations change the contact set).
#[test]
fn newton_converges_quadratically_with_remodelling() {
    let (orders, history) = newton_orders("plates-newton-remodelling", &[REMODELLING]);
    let hist: Vec<String> = history.iter().map(|r| format!("{r:.2e}")).collect();
    println!(
        "with remodelling: {} solves, median order {:.2}; a residual history: {}",
        orders.len(),
        orders[orders.len() / 2],
        hist.join(", ")
    );
    assert!(orders.len() >= 5, "too few converged solves to judge: {orders:?}");
    let median = orders[orders.len() / 2];
    assert!(median > 1.6, "median convergence order {median} (orders {orders:?})");
}

/// A solid law that loses strong ellipticity (Holmes–Mow with ν = 0.45 > 1/3: beyond 11.8%
/// isochoric compression) cannot be squeezed far: the solve stops converging at the contact
/// edge on any mesh. The run must end promptly with an error naming the cause — not crawl on
/// with ever shorter steps — while the same ramp with ν = 0.3 (elliptic) completes.
#[test]
fn non_elliptic_solid_fails_promptly_naming_the_cause() {
    let dir = scratch("plates-non-elliptic");
    let run = |nu: &str, name: &str| {
        let nu_set = format!("material.nu={nu}");
        let args = [
            "run",
            "reference",
            "--set",
            "material.mu=3",
            "--set",
            nu_set.as_str(),
            "--set",
            "mesh.params.h=30",
            "--set",
            "time.t_end=3",
            "--set",
            "time.dt_min=1e-2",
            "--set",
            "output.fields=false",
            "--out",
        ];
        let out_dir = dir.join(name);
        let mut full = args.to_vec();
        full.push(out_dir.to_str().unwrap());
        poroplast(1, &full)
    };
    let ok = run("0.3", "nu03");
    assert!(ok.status.success(), "{}", String::from_utf8_lossy(&ok.stderr));
    let bad = run("0.45", "nu045");
    let stderr = String::from_utf8_lossy(&bad.stderr);
    assert!(!bad.status.success());
    let line = stderr.lines().find(|l| l.starts_with("poroplast: error:")).expect("an error line");
    assert!(line.contains("below time.dt_min = 1.000e-2 s"), "{line}");
    assert!(line.contains("loses strong ellipticity beyond 11.8% isochoric compression"), "{line}");
    // The run directory says why it stopped, and keeps what was computed.
    let failed = dir.join("nu045");
    let status = std::fs::read_to_string(failed.join("status.txt")).expect("status.txt");
    assert!(status.starts_with("failed after step") && status.contains("below time.dt_min"), "{status}");
    assert!(failed.join("timings.txt").exists() && failed.join("history.csv").exists());
}

/// Stability (c) and (d): remodelling, a 400 s hold with steps up to 50 s (400× the seed
/// paper's 0.125 s limit), then the release and a rest: the run completes, the upper contact
/// opens (no force), B_p stays isochoric, and the aggregate keeps its remodelled shape
/// (measured on this h = 40 mesh: 90 steps, H/W 0.742 at 420 s on the meridian and in 3-D,
/// |det B_p − 1| 6e-15). The meridian (2 s) here; the quarter (12 s) in the slow tier.
#[test]
fn long_hold_with_long_steps_then_release_completes() {
    long_hold_with_long_steps("axisymmetric");
}

#[test]
#[ignore = "slow tier: the 3-D quarter of the long-step hold (12 s; the meridian runs by default)"]
fn long_hold_with_long_steps_then_release_completes_in_3d() {
    long_hold_with_long_steps("solid");
}

fn long_hold_with_long_steps(geometry: &str) {
    let dir = scratch(&format!("plates-long-hold-release-{geometry}"));
    let out = dir.join("run");
    let geometry = format!("mesh.geometry={geometry}");
    let args = [
        "run",
        "remodel_40",
        "--set",
        &geometry,
        "--set",
        "mesh.params.h=40",
        "--set",
        "mesh.params.h_pole=12",
        "--set",
        "plates.t_end=405",
        "--set",
        "time.t_end=420",
        "--set",
        "time.dt_max=50",
        "--set",
        "output.fields=false",
        "--set",
        "output.fields_at=[]",
        "--out",
        out.to_str().unwrap(),
        "-q",
    ];
    run_ok(1, &args);
    let h = History::read(&out);
    let dt_max = h.col("dt").iter().cloned().fold(0.0, f64::max);
    assert!(dt_max >= 50.0 - 1e-9, "largest step {dt_max} s");
    let last = h.col("time").len() - 1;
    assert!((h.col("time")[last] - 420.0).abs() < 1e-9);
    assert_eq!(h.col("contact_nodes_upper")[last], 0.0, "upper contact still closed after the release");
    assert!(h.col("force_total_mg")[last].abs() < 1e-9);
    let hw = h.col("height")[last] / h.col("width")[last];
    assert!(hw < 0.8, "H/W after the release {hw}: the remodelled shape should persist");
    let det = h.col("det_bp_max_dev").iter().cloned().fold(0.0, f64::max);
    assert!(det < 1e-10, "det B_p drifted by {det}");
}

/// The run summary against the history and fields it summarises (the coarse protocol on 2
/// ranks: ramp to 2 s, hold to 8 s, release by 10 s): the peak force and its time to every
/// digit written, the force at the end of the hold interpolated between the rows around 8 s,
/// the contact opening at the first step of the release whose force vanishes, H/W, µN = 9.81 mg;
/// the largest p, its step and node those of the fields written at every step.
#[test]
fn the_summary_tells_the_history() {
    let run = coarse_two_ranks();
    let (h, s) = (History::read(run), Summary::read(run));
    let (t, f) = (h.col("time"), h.col("force_total_mg"));
    let num = |k: &str| s.num(k).unwrap_or_else(|| panic!("no {k} in summary.toml"));
    let ipk = (0..f.len()).fold(0, |b, i| if f[i] > f[b] { i } else { b });
    assert_eq!((num("plates.peak_force_mg"), num("plates.peak_force_time_s")), (f[ipk], t[ipk]));
    assert_eq!(num("plates.peak_force_uN"), f[ipk] * 9.81);
    assert_eq!((num("plates.ramp_end_s"), num("plates.hold_end_s"), num("plates.release_end_s")), (2.0, 8.0, 10.0));
    let i = t.iter().position(|&x| x >= 8.0).unwrap();
    let f8 = f[i - 1] + (8.0 - t[i - 1]) / (t[i] - t[i - 1]) * (f[i] - f[i - 1]);
    assert!((num("plates.hold_end_force_mg") - f8).abs() <= 1e-12 * f8, "F(8 s) = {f8}");
    assert!((num("plates.hold_end_force_uN") - 9.81 * f8).abs() <= 1e-12 * f8);
    let k = (0..t.len()).find(|&i| t[i] > 8.0 && f[i] == 0.0).expect("the force vanishes in the release");
    assert!(f[k - 1] > 0.0 && t[k] <= 10.0 + 1e-9, "opening at t = {}", t[k]);
    assert_eq!(num("plates.contact_opening_time_s"), t[k]);
    // Its one hold, 2–8 s at ũ = 0.3, read at 8 s; without surface tension no Laplace reading in
    // it and no liquid test; the µN column is the mg column × 9.81.
    let holds = s.array("hold");
    let hold = |k: &str| holds[0][k].as_float().unwrap_or_else(|| panic!("no {k} in {holds:?}"));
    assert_eq!((holds.len(), hold("start_s"), hold("end_s"), hold("compression")), (1, 2.0, 8.0, 0.3));
    assert!((hold("force_mg") - f8).abs() <= 1e-12 * f8 && hold("force_uN") == 9.81 * hold("force_mg"));
    assert!(!holds[0].contains_key("sigma_app_mN_m") && s.table("liquid_test").is_empty());
    assert_eq!(h.col("force_total_uN"), f.iter().map(|x| x * 9.81).collect::<Vec<_>>());
    let last = t.len() - 1;
    assert_eq!(num("plates.final_height_over_width"), h.col("height")[last] / h.col("width")[last]);
    assert_eq!(num("steps"), last as f64);
    assert_eq!(num("t_end_s"), t[last]);
    // The largest p of every step, against the fields of every step: the same value, step and node.
    let (p_max, p_t, p_at) = (num("pressure.max_p_kPa"), num("pressure.max_p_time_s"), s.max_p_at());
    let file = hdf5_metno::File::open(run.join("fields.h5")).unwrap();
    let x: Vec<f64> = file.dataset("mesh/coordinates").unwrap().read_raw().unwrap();
    let times: Vec<f64> = file.dataset("time").unwrap().read_raw().unwrap();
    assert_eq!(times, t, "fields of every step");
    let mut largest = (f64::MIN, 0.0, [0.0; 3]);
    for (k, &tk) in times.iter().enumerate() {
        let p: Vec<f64> = file.dataset(&format!("fields/p/{k:06}")).unwrap().read_raw().unwrap();
        let n = (0..p.len()).fold(0, |b, i| if p[i] > p[b] { i } else { b });
        if p[n] > largest.0 {
            largest = (p[n], tk, [x[3 * n], x[3 * n + 1], x[3 * n + 2]]);
        }
    }
    assert_eq!((p_max, p_t, p_at), largest, "the largest p, its time and place");
}

/// The shipped ramp–hold–release is the special case of a protocol table: `reference_axi` with
/// a 2-s hold, and the same protocol as `plates.table`, give the same history to round-off
/// (ramp, hold, release and rest: every row of the table a kink).
#[test]
fn the_phases_are_a_protocol_table() {
    let _cores = cores(1);
    let dir = scratch("plates-table");
    let phases = "compression = 0.3          # u_max = 0.3 * 2R = 60 um\nramp = 5.0                 # s: the plate rises\n\
                  hold = 30.0                # s: held\nrelease = 5.0              # s: the plate returns; then rest until time.t_end\n";
    let short = phases.replace("hold = 30.0", "hold = 2.0");
    let table = "table = [[0.0, 0.0], [5.0, 0.3], [7.0, 0.3], [12.0, 0.0]]\n";
    let mut histories = Vec::new();
    for (name, edit) in [("phases", short.as_str()), ("table", table)] {
        let sub = dir.join(name);
        std::fs::create_dir_all(&sub).unwrap();
        let sc = scene_variant("reference_axi", &sub, &[(phases, edit)]);
        let out = sub.join("run");
        run_ok(1, &["run", sc.as_str(), "--out", out.to_str().unwrap(), "-q", "--set", "time.t_end=15"]);
        histories.push(History::read(&out));
    }
    let (a, b) = (&histories[0], &histories[1]);
    assert_eq!(a.col("time"), b.col("time"));
    for col in ["force_total_mg", "probe_p", "height"] {
        let diff = a.col(col).iter().zip(b.col(col)).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
        assert!(diff < 1e-9, "{col}: {diff}");
    }
}
