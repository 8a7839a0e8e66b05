//! The nonlinear solver of a run, set up on its time stepper once PETSc has read the options:
//! with contact, the active-set Newton (or one of PETSc's VI solvers when `-snes_type` names
//! one) with the policy's lag, Anderson depth, monitor and treatment of the free rigid modes;
//! the finest-level SOR hook; the Schur matrix; the tolerances checked.

use super::active_set::CurvedContact;
use super::fieldsplit::{finest_level_sor, finest_sor_enabled, use_schur_matrix};
use super::tolerances::check_tolerances;
use super::{anderson, ActiveSetNewton, FreeRigidModes, Lag, Policy};
use crate::error::Result;
use crate::petsc::{options, Mat, Ts, TsProblem, Vector};
use mpi::topology::SimpleCommunicator;
use std::cell::RefCell;
use std::rc::Rc;

/// What the solver set-up reads of the problem.
pub(crate) struct ProblemView<'a> {
    /// With contact: the bounds l ≤ x ≤ u (shared: the problem moves them with the plates).
    pub(crate) bounds: Option<(&'a Vector, &'a Vector)>,
    /// The scale of a u row of the Jacobian (the diagonal of an active dof's identity row).
    pub(crate) u_row_scale: f64,
    /// The fixed-stress Schur approximation, for a Schur fieldsplit.
    pub(crate) schur: &'a Mat,
    /// Contact with curved tools, if the scene has tools.
    pub(crate) curved: Option<Rc<RefCell<dyn CurvedContact>>>,
}

/// Sets up `ts`'s nonlinear solver for the problem `view` shows of it, noting in `solver_line`
/// how the rigid modes the plates leave free (`free_modes`) are treated. Returns whether the
/// preconditioner uses the Schur matrix (else nothing needs to assemble it).
pub(crate) fn configure<P: TsProblem>(
    world: &SimpleCommunicator,
    ts: &mut Ts<P>,
    policy: &Policy,
    free_modes: Option<FreeRigidModes>,
    border: Option<super::active_set::Border>,
    solver_line: &mut String,
    view: impl for<'a> Fn(&'a P) -> ProblemView<'a>,
) -> Result<bool> {
    let snes = ts.snes()?;
    let problem = view(ts.problem());
    if let Some((lo, hi)) = problem.bounds {
        if options::has("snes_type")? {
            if border.is_some() {
                return Err(crate::error::Error::Options(
                    "force control (force rows of plates.upper or tools.protocol) needs the active-set Newton: drop -snes_type".into(),
                ));
            }
            if problem.curved.is_some() {
                return Err(crate::error::Error::Options(
                    "-snes_type: PETSc's VI solvers take bounds on single unknowns, which cannot hold a curved \
                     tool: leave -snes_type out with [[tools]]"
                        .into(),
                ));
            }
            snes.set_vi_bounds(lo, hi)?;
            if let Some(m) = free_modes {
                solver_line.push_str(&format!("\nrigid modes left free by the plates (not handled): {}", m.describe()));
                singular_factorisations()?;
            }
        } else {
            let ksp = snes.ksp()?;
            snes.lend_dm_to(&ksp)?;
            ksp.set_from_options()?;
            // Reusing a preconditioner needs a Krylov method to absorb the difference.
            let mut lag = if ksp.type_name()? == "preonly" { Lag::NEVER } else { policy.lag };
            // No chord iterations when the Jacobian check assembles into the solve matrix
            // between steps.
            if options::has("poroplast_check_jacobian")? {
                lag.chord = 0.0;
            }
            let mut newton = ActiveSetNewton::new(world, lo, hi, problem.u_row_scale, lag)?;
            if let Some(mut b) = border {
                if let Some(c) = problem.curved.clone() {
                    b.set_contact(c);
                }
                newton.set_border(b);
            }
            newton.monitor = options::has("poroplast_newton_monitor")?;
            newton.anderson = anderson::Anderson::new(anderson::anderson_depth()?);
            if let Some(c) = problem.curved.clone() {
                newton.set_curved(c);
            }
            if let Some(m) = free_modes {
                // A factorisation gets the modes locked (nonsingular, updatable); a Krylov
                // method with AMG their null space (a point lock defeats AMG).
                let pin = ksp.pc()?.type_name()? == "lu";
                let how = if pin { "locked at single dofs" } else { "the Jacobian's null space" };
                solver_line.push_str(&format!("\nrigid modes left free by the plates ({how}): {}", m.describe()));
                if !pin {
                    singular_factorisations()?;
                }
                newton.set_free_modes(m, pin);
            }
            ts.set_nonlinear_solver(Box::new(newton))?;
        }
    }
    if finest_sor_enabled()? {
        snes.ksp()?.set_pre_solve(finest_level_sor)?;
    }
    let schur_needed = use_schur_matrix(&snes, view(ts.problem()).schur)?;
    check_tolerances(&snes)?;
    Ok(schur_needed)
}

/// MUMPS, wherever it factors a block with the free rigid modes: leave the null pivots to the
/// Krylov method.
fn singular_factorisations() -> Result<()> {
    options::set_default("mat_mumps_icntl_24", Some("1"))
}

/// `-poroplast_check_jacobian [eps]`: the relative step of the per-step Jacobian check (1e-7
/// when given without one), None without the option.
pub(crate) fn jacobian_check_step() -> Result<Option<f64>> {
    super::program_options::optional("poroplast_check_jacobian", Some(1e-7), "a relative step like 1e-7", |v| {
        v.parse().ok()
    })
}
