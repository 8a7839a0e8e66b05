//! The discrete u–p problem TS integrates ([`PoroProblem`], built whole from its
//! [`ProblemParts`]), its pieces a file each, its post-processing ([`Post`]) and the
//! finite-difference check of its Jacobian (`fd_check`).

mod constraints;
mod contact_stage;
mod drainage_stage;
mod fd_check;
mod insertion;
mod local;
mod parts;
mod poro_problem;
mod post;
mod schur;
mod timers;
mod tool_stage;

pub(crate) use contact_stage::untouched;
pub(crate) use parts::ProblemParts;
pub(crate) use poro_problem::{ErrorScales, PoroProblem};
pub(crate) use post::{backward_euler_rate, Post};
