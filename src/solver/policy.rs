//! The linear-solver presets (module docs of `solver`): the PETSc options each sets by default,
//! the contact defaults set before them, and the policy a run logs.

use super::program_options;
use crate::error::Result;
use crate::petsc::options;
use crate::solver::Lag;

/// Largest system the "auto" preset solves with the lagged direct factorisation (2 ranks: at
/// 47 613 dofs the contact ramp took 155 s direct against 317 s with fieldsplit).
pub(crate) const DIRECT_MAX_DOFS: usize = 60_000;

/// The linear-solver preset a scene names (`[solver] preset`; module docs).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Deserialize, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum Preset {
    /// "direct" up to [`DIRECT_MAX_DOFS`], "fieldsplit" above.
    #[default]
    Auto,
    Direct,
    Fieldsplit,
    Lu,
}

/// The linear solver chosen for a run.
#[derive(Debug, Clone)]
pub(crate) struct Policy {
    /// The preset in effect ("direct", "fieldsplit" or "lu").
    pub(crate) preset: &'static str,
    /// When the active-set Newton rebuilds its preconditioner.
    pub(crate) lag: Lag,
}

impl Policy {
    /// One line for the run log.
    pub(crate) fn describe(&self, n_dofs: usize, auto: bool) -> String {
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

/// Defaults for contact: the active-set Newton of [`active_set`](super::active_set) (unless
/// -snes_type names a PETSc VI solver, e.g. vinewtonrsls) with full Newton steps — with the
/// active set and the drainage switching, the residual is only piecewise smooth and backtracking
/// stalls; a failed step is cut by TS instead — and up to 50 iterations (each change of the
/// active set costs one; a step still cycling after 50 is cut). Set before the preset's, which
/// they override.
pub(crate) fn set_contact_defaults() -> Result<()> {
    options::set_default("snes_linesearch_type", Some("basic"))?;
    options::set_default("snes_max_it", Some("50"))
}

/// The preset's defaults (see [`set_default_options`]) and the run log's solver line (with the
/// BLAS kernels MUMPS runs in).
pub(crate) fn policy(preset: Preset, n_dofs: usize) -> Result<(Policy, String)> {
    let policy = set_default_options(preset, n_dofs)?;
    let mut line = policy.describe(n_dofs, preset == Preset::Auto);
    if let Some(k) = crate::petsc::blas::kernel() {
        let why = if std::env::var_os("OPENBLAS_CORETYPE").is_some() { " (OPENBLAS_CORETYPE)" } else { "" };
        line.push_str(&format!("; BLAS: OpenBLAS {k} kernels{why}"));
    }
    Ok((policy, line))
}

/// Sets the defaults of a preset (only options the user has not set) and returns the policy.
fn set_default_options(preset: Preset, n_dofs: usize) -> Result<Policy> {
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
