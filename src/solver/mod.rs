//! Solver policy: default PETSc options per preset, chosen by problem size unless the scene
//! names one; the nonlinear solver set up on a run's time stepper ([`configure`]); the u/p field decomposition handed to PCFIELDSPLIT through a DMShell (with the
//! rigid-body near-null space on u); the fixed-stress Schur approximation as the user Schur
//! preconditioner; and, for contact, the active-set Newton with its chord and preconditioner lag.
//!
//! * "direct": FGMRES preconditioned by a MUMPS LU factorisation. With contact, the active-set
//!   Newton keeps a Jacobian and its factorisation for chord iterations (one residual and one
//!   pair of triangular solves each) across iterations and time steps while they contract the
//!   residual by 0.3 or better and the active set stays, or changes by at most 8 dofs (a
//!   low-rank update of the factorisation, [`ActiveSetUpdate`]) ([`Lag::chord`]), the chord
//!   steps Anderson-mixed ([`anderson`]); otherwise it assembles and factorises anew. On small
//!   systems the factorisation is cheap and every Krylov iteration is two triangular solves,
//!   where an AMG V-cycle is latency-bound.
//! * "fieldsplit": FGMRES on the full u–p system, preconditioned by an upper Schur
//!   factorisation; the u block by one GAMG V-cycle (block size 3, six rigid-body modes, the
//!   interpolation reused across setups), the Schur complement by one BoomerAMG V-cycle on
//!   Ŝ = K_darcy + (shift/K_dr) M_p, which stays spectrally equivalent to the true Schur
//!   complement as Δt → 0 and as k → 0. Memory and time grow about linearly with size.
//! * "lu": MUMPS direct solve of every Newton system (the reference for solver studies).
//! * "auto" (default): "direct" up to [`DIRECT_MAX_DOFS`], "fieldsplit" above.
//!
//! Every default is overridable from the command line (`-- -pc_type ...`); the chord by
//! `-poroplast_chord RATE` (0: a new Jacobian every iteration), the mixing by
//! `-poroplast_anderson M`, the largest active-set change a kept Jacobian or preconditioner
//! absorbs (the chord's low-rank update; the lagged preconditioner's rebuild threshold) by
//! `-poroplast_pc_rebuild_changes N`, and with the chord off the preconditioner lag by
//! `-poroplast_pc_reuse N` (0: a new setup for every Jacobian) and `-poroplast_pc_rebuild_its N`
//! (see [`Lag`]).

pub mod active_set;
pub mod anderson;
mod configure;
mod fields;
pub mod program_options;
mod rigid;
pub mod woodbury;

pub use active_set::{ActiveSetNewton, Lag};
pub use configure::{configure, jacobian_check_step, ProblemView};
pub use fields::Fields;
pub use rigid::FreeRigidModes;
pub use woodbury::ActiveSetUpdate;

use crate::error::{Error, Result};
use crate::petsc::{options, Ksp, Mat, Snes, Vector};

/// Largest system the "auto" preset solves with the lagged direct factorisation (2 ranks: at
/// 47 613 dofs the contact ramp took 155 s direct against 317 s with fieldsplit).
pub const DIRECT_MAX_DOFS: usize = 60_000;

/// The linear-solver preset a scene names (`[solver] preset`; module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Preset {
    /// "direct" up to [`DIRECT_MAX_DOFS`], "fieldsplit" above.
    #[default]
    Auto,
    Direct,
    Fieldsplit,
    Lu,
}

/// The linear solver chosen for a run.
#[derive(Debug, Clone)]
pub struct Policy {
    /// The preset in effect ("direct", "fieldsplit" or "lu").
    pub preset: &'static str,
    /// When the active-set Newton rebuilds its preconditioner.
    pub lag: Lag,
}

impl Policy {
    /// One line for the run log.
    pub fn describe(&self, n_dofs: usize, auto: bool) -> String {
        let what = match self.preset {
            "direct" => "FGMRES + MUMPS LU; with contact, chord iterations on a kept Jacobian and factorisation",
            "fieldsplit" => "FGMRES + Schur fieldsplit (GAMG on u, BoomerAMG on the Schur approximation)",
            _ => "MUMPS LU for every Newton system",
        };
        let why =
            if auto { format!(", chosen for {n_dofs} dofs (direct up to {DIRECT_MAX_DOFS})") } else { String::new() };
        format!("linear solver: {} ({what}){why}", self.preset)
    }
}

/// Defaults for contact: the active-set Newton of [`active_set`] (unless -snes_type names a
/// PETSc VI solver, e.g. vinewtonrsls) with full Newton steps — with the active set and the
/// drainage switching, the residual is only piecewise smooth and backtracking stalls; a failed
/// step is cut by TS instead — and up to 50 iterations (each change of the active set costs
/// one; a step still cycling after 50 is cut). Set before the preset's, which they override.
pub fn set_contact_defaults() -> Result<()> {
    options::set_default("snes_linesearch_type", Some("basic"))?;
    options::set_default("snes_max_it", Some("50"))
}

/// The Krylov and Newton tolerances as the options set them: PETSc takes a negative count or
/// tolerance without complaint and then fails every solve, so name the option here.
pub fn check_tolerances(snes: &Snes) -> Result<()> {
    let (rtol, atol, dtol, max_it) = snes.ksp()?.tolerances()?;
    let (satol, srtol, stol, smax_it) = snes.tolerances()?;
    let bad = |opt: &str, v: String, want: &str| Err(Error::Options(format!("-{opt} {v}: must be {want}")));
    for (opt, v) in
        [("ksp_rtol", rtol), ("ksp_atol", atol), ("snes_rtol", srtol), ("snes_atol", satol), ("snes_stol", stol)]
    {
        if !(v.is_finite() && v >= 0.0) {
            return bad(opt, format!("{v}"), ">= 0");
        }
    }
    if !(dtol.is_finite() && dtol > 0.0) && dtol != -1.0 {
        return bad("ksp_divtol", format!("{dtol}"), "> 0");
    }
    if max_it < 0 {
        return bad("ksp_max_it", format!("{max_it}"), "a non-negative integer");
    }
    if smax_it == 0 {
        // (PETSc stores a negative count as 0: quote what was given.)
        let given = options::get_string("snes_max_it")?.unwrap_or_else(|| "0".into());
        return bad("snes_max_it", given, "a positive integer");
    }
    Ok(())
}

/// The preset's defaults (see [`set_default_options`]) and the run log's solver line (with the
/// BLAS kernels MUMPS runs in).
pub fn policy(preset: Preset, n_dofs: usize) -> Result<(Policy, String)> {
    let policy = set_default_options(preset, n_dofs)?;
    let mut line = policy.describe(n_dofs, preset == Preset::Auto);
    if let Some(k) = crate::petsc::blas::kernel() {
        let why = if std::env::var_os("OPENBLAS_CORETYPE").is_some() { " (OPENBLAS_CORETYPE)" } else { "" };
        line.push_str(&format!("; BLAS: OpenBLAS {k} kernels{why}"));
    }
    Ok((policy, line))
}

/// Depth of the Anderson mixing of chord iterations ([`anderson`]; `-poroplast_anderson M`, 0:
/// off).
pub fn anderson_depth() -> Result<usize> {
    program_options::count("poroplast_anderson", 2)
}

/// Whether the u block's finest multigrid level is smoothed by SOR ([`finest_level_sor`]; on
/// unless `-poroplast_finest_sor 0`).
pub fn finest_sor_enabled() -> Result<bool> {
    program_options::switch("poroplast_finest_sor", true, "1 or 0")
}

/// Before each solve (a KSP pre-solve hook): with a fieldsplit whose first (u) block is GAMG,
/// smooths that block's finest level by Richardson with SOR, two forward sweeps over each
/// rank's rows (PCMG's default count), instead of Chebyshev/Jacobi. Measured
/// (docs/performance.md): Cryer at 85k dofs 33 → 29 Krylov iterations per solve and about 15%
/// less time per step (symmetric sweeps: 28, no time gained); the contact ramp 28.7 → 24.0
/// (quarter) and 48.6 → 37.7 (full sphere) per Newton iteration. Only the finest level: GAMG's
/// coarser levels of a block with constrained dofs have zero rows (aggregates whose
/// near-null-space modes vanish there), which SOR cannot take; and a hook because which level
/// is the finest is known only once GAMG has built its hierarchy (a full setup resets the
/// smoothers, so this runs before every solve; the check is cheap).
pub fn finest_level_sor(ksp: Ksp) -> Result<()> {
    let pc = ksp.pc()?;
    if pc.type_name()? != "fieldsplit" {
        return Ok(());
    }
    ksp.set_up()?;
    let Some(u) = pc.split_ksps()?.first().copied() else { return Ok(()) };
    let upc = u.pc()?;
    if upc.type_name()? != "gamg" {
        return Ok(());
    }
    u.set_up()?;
    let levels = upc.mg_levels()?;
    if levels < 2 {
        return Ok(());
    }
    let finest = upc.mg_smoother(levels - 1)?;
    if finest.type_name()? != "richardson" {
        finest.set_type("richardson")?;
        let pc = finest.pc()?;
        pc.set_type("sor")?;
        pc.set_sor_local_forward()?;
    }
    Ok(())
}

/// Sets the defaults of a preset (only options the user has not set) and returns the policy.
pub fn set_default_options(preset: Preset, n_dofs: usize) -> Result<Policy> {
    let d = |k: &str, v: &str| options::set_default(k, Some(v));
    let preset: &'static str = match preset {
        Preset::Auto if n_dofs <= DIRECT_MAX_DOFS => "direct",
        Preset::Auto | Preset::Fieldsplit => "fieldsplit",
        Preset::Direct => "direct",
        Preset::Lu => "lu",
    };
    let lag = match preset {
        "lu" => {
            d("ksp_type", "preonly")?;
            d("pc_type", "lu")?;
            d("pc_factor_mat_solver_type", "mumps")?;
            Lag::NEVER
        }
        "direct" => {
            d("ksp_type", "fgmres")?;
            d("ksp_rtol", "1e-8")?;
            d("ksp_max_it", "200")?;
            d("ksp_gmres_restart", "100")?;
            d("pc_type", "lu")?;
            d("pc_factor_mat_solver_type", "mumps")?;
            // No MUMPS scaling: it is a preconditioner, and the scaling was 12% of the
            // factorisation time on the default scene (same Krylov counts and forces).
            d("mat_mumps_icntl_8", "0")?;
            Lag { max_reuse: 1000, max_krylov: 12, max_changes: 8, chord: 0.3 }
        }
        _ => {
            d("ksp_type", "fgmres")?;
            d("ksp_rtol", "1e-8")?;
            d("ksp_max_it", "400")?;
            d("ksp_gmres_restart", "100")?;
            d("pc_type", "fieldsplit")?;
            d("pc_fieldsplit_type", "schur")?;
            d("pc_fieldsplit_schur_fact_type", "upper")?;
            d("fieldsplit_u_ksp_type", "preonly")?;
            // Set explicitly: PETSc 3.18's SNESVI replaces a first-split PCBJACOBI by fixed
            // 101×101 blocks, which fails in parallel.
            d("fieldsplit_u_pc_type", "gamg")?;
            // The matrix keeps its pattern (also under contact, see `active_set`): keep the
            // aggregation and prolongators, redo only the Galerkin products.
            d("fieldsplit_u_pc_gamg_reuse_interpolation", "true")?;
            // Chebyshev smoothing over [0.05, 1.05] of the estimated largest eigenvalue instead
            // of PETSc's [0.1, 1.1]: Cryer at 85k dofs 6% faster per step (docs/performance.md).
            d("fieldsplit_u_mg_levels_ksp_chebyshev_esteig", "0,0.05,0,1.05")?;
            d("fieldsplit_p_ksp_type", "preonly")?;
            d("fieldsplit_p_pc_type", "hypre")?;
            Lag::NEVER
        }
    };
    d("snes_rtol", "1e-8")?;
    d("snes_atol", "1e-10")?;
    d("snes_max_it", "25")?;
    let lag = Lag {
        max_reuse: program_options::count("poroplast_pc_reuse", lag.max_reuse)?,
        max_krylov: program_options::count("poroplast_pc_rebuild_its", lag.max_krylov)?,
        max_changes: program_options::count("poroplast_pc_rebuild_changes", lag.max_changes)?,
        chord: program_options::value("poroplast_chord", lag.chord, "a contraction factor in [0, 1)", |v| {
            v.parse().ok().filter(|c: &f64| (0.0..1.0).contains(c))
        })?,
    };
    Ok(Policy { preset, lag })
}

/// Uses `schur` as the Schur-complement preconditioner if the PC is a Schur fieldsplit and the
/// user did not choose another (`-pc_fieldsplit_schur_precondition`). Returns whether it does
/// (else nothing needs to assemble it).
pub fn use_schur_matrix(snes: &Snes, schur: &Mat) -> Result<bool> {
    let pc = snes.ksp()?.pc()?;
    let used = pc.type_name()? == "fieldsplit" && !options::has("pc_fieldsplit_schur_precondition")?;
    if used {
        pc.set_schur_pre_user(schur)?;
    }
    Ok(used)
}

/// Modified Gram–Schmidt with global dot products.
pub(crate) fn orthonormalise(vs: &mut [Vector]) -> Result<()> {
    for i in 0..vs.len() {
        let (done, rest) = vs.split_at_mut(i);
        let v = &mut rest[0];
        for q in done.iter() {
            let d = v.dot(q)?;
            v.axpy(-d, q)?;
        }
        let n = v.norm2()?;
        if n > 0.0 {
            v.scale(1.0 / n)?;
        }
    }
    Ok(())
}
