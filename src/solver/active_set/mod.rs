//! Active-set Newton for the contact variational inequality, on the full-size system.
//!
//! The plates are bounds l ≤ x ≤ u on the surface u_z dofs. Each iteration splits the dofs at
//! the current iterate into the active set A — at a bound with the residual pushing into it,
//! PETSc's vinewtonrsls test: x_i ≤ l_i + 1e-8 and F_i > 0, or x_i ≥ u_i − 1e-8 and F_i < 0 —
//! and the free rest; it solves the Newton system with the rows and columns of A replaced by a
//! scaled identity (the step moves those dofs exactly onto their bound) and projects the new
//! iterate onto the bounds. Convergence is measured on the free residual.
//!
//! Why not vinewtonrsls: it is the same step algebraically, but rsls solves a new, smaller
//! matrix (a `MatCreateSubMatrix` copy) whenever the active set changes, so nothing of the
//! preconditioner survives — the AMG hierarchy is rebuilt from scratch, a direct solver redoes
//! its symbolic analysis, the block size and the rigid-body near-null space are lost. Here the
//! matrix keeps its size, block size and sparsity pattern ("workaround B" of the PETSc notes),
//! so the preconditioner setup reuses what it can, and it may be lagged ([`Lag`]).
//!
//! The files: the solver and its Newton loop (`newton`); `convergence` the tests that stop
//! it; `bounds` the bounds and the active-set split; `reuse` the decisions to reuse an operator or
//! preconditioner ([`Lag`]); `frames` the per-node rotated frames of contact on curved tools and
//! `contact` a node's split and curvature in its frame (issue 53, not yet wired in).

mod border;
mod bounds;
mod contact;
mod convergence;
mod curved;
mod frames;
#[cfg(test)]
mod frames_tests;
mod newton;
mod reuse;

pub(crate) use border::{Border, Moves, PositionUnknown, Positions, SharedPositions};
pub(crate) use contact::{CurvedContact, NodeContact};
pub(crate) use frames::Frame;
pub(crate) use newton::ActiveSetNewton;
pub(crate) use reuse::Lag;
