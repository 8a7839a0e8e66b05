//! Solver policy: default PETSc options per preset, chosen by problem size unless the scene
//! names one; the nonlinear solver set up on a run's time stepper (`configure`); the u/p field decomposition handed to PCFIELDSPLIT through a DMShell (with the
//! rigid-body near-null space on u); the fixed-stress Schur approximation as the user Schur
//! preconditioner; and, for contact, the active-set Newton with its chord and preconditioner lag.
//!
//! * "direct": FGMRES preconditioned by a MUMPS LU factorisation. With contact, the active-set
//!   Newton keeps a Jacobian and its factorisation for chord iterations (one residual and one
//!   pair of triangular solves each) across iterations and time steps while they contract the
//!   residual by 0.3 or better and the active set stays, or changes by at most 8 dofs (a
//!   low-rank update of the factorisation, [`ActiveSetUpdate`]) (`Lag::chord`), the chord
//!   steps Anderson-mixed ([`anderson`]); otherwise it assembles and factorises anew. On small
//!   systems the factorisation is cheap and every Krylov iteration is two triangular solves,
//!   where an AMG V-cycle is latency-bound.
//! * "fieldsplit": FGMRES on the full u–p system, preconditioned by an upper Schur
//!   factorisation; the u block by one GAMG V-cycle (block size 3, six rigid-body modes, the
//!   interpolation reused across setups), the Schur complement by one BoomerAMG V-cycle on
//!   Ŝ = K_darcy + (shift/K_dr) M_p, which stays spectrally equivalent to the true Schur
//!   complement as Δt → 0 and as k → 0. Memory and time grow about linearly with size.
//! * "lu": MUMPS direct solve of every Newton system (the reference for solver studies).
//! * "auto" (default): "direct" up to `DIRECT_MAX_DOFS`, "fieldsplit" above.
//!
//! Every default is overridable from the command line (`-- -pc_type ...`); the chord by
//! `-poroplast_chord RATE` (0: a new Jacobian every iteration), the mixing by
//! `-poroplast_anderson M`, the largest active-set change a kept Jacobian or preconditioner
//! absorbs (the chord's low-rank update; the lagged preconditioner's rebuild threshold) by
//! `-poroplast_pc_rebuild_changes N`, and with the chord off the preconditioner lag by
//! `-poroplast_pc_reuse N` (0: a new setup for every Jacobian) and `-poroplast_pc_rebuild_its N`
//! (see `Lag`).

pub(crate) mod active_set;
pub mod anderson;
mod configure;
mod fields;
mod fieldsplit;
mod gram_schmidt;
mod policy;
pub(crate) mod program_options;
mod rigid;
mod tolerances;
pub(crate) mod woodbury;

pub(crate) use active_set::{ActiveSetNewton, Lag};
pub(crate) use configure::{configure, jacobian_check_step, ProblemView};
pub(crate) use fields::Fields;
pub(crate) use policy::{Policy, Preset};
pub(crate) use rigid::FreeRigidModes;
pub use woodbury::ActiveSetUpdate;

pub(crate) use policy::{policy, set_contact_defaults};
