//! The Krylov and Newton tolerances the options set, checked before the first solve.

use crate::error::{Error, Result};
use crate::petsc::{options, Snes};

/// The Krylov and Newton tolerances as the options set them: PETSc takes a negative count or
/// tolerance without complaint and then fails every solve, so name the option here.
pub(super) fn check_tolerances(snes: &Snes) -> Result<()> {
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
