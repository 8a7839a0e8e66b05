//! The fieldsplit preconditioner adjusted once PETSc has set it from the options: the user
//! Schur matrix, and SOR on the u block's finest multigrid level. (The fields it splits:
//! `fields`.)

use super::program_options;
use crate::error::Result;
use crate::petsc::{options, Ksp, Mat, Snes};

/// Uses `schur` as the Schur-complement preconditioner if the PC is a Schur fieldsplit and the
/// user did not choose another (`-pc_fieldsplit_schur_precondition`). Returns whether it does
/// (else nothing needs to assemble it).
pub(super) fn use_schur_matrix(snes: &Snes, schur: &Mat) -> Result<bool> {
    let pc = snes.ksp()?.pc()?;
    let used = pc.type_name()? == "fieldsplit" && !options::has("pc_fieldsplit_schur_precondition")?;
    if used {
        pc.set_schur_pre_user(schur)?;
    }
    Ok(used)
}

/// Whether the u block's finest multigrid level is smoothed by SOR ([`finest_level_sor`]; on
/// unless `-poroplast_finest_sor 0`).
pub(super) fn finest_sor_enabled() -> Result<bool> {
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
pub(super) fn finest_level_sor(ksp: Ksp) -> Result<()> {
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
