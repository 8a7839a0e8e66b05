//! The fixed-stress Schur approximation Ŝ on the pressure space (`solver`'s Schur fieldsplit
//! preconditions the Schur complement with it): assembled with the Jacobian when the
//! preconditioner uses it, else never.

use crate::error::Result;
use crate::petsc::{Int, Mat};

/// The Schur approximation's matrix and whether the preconditioner uses it.
pub(super) struct SchurApprox {
    mat: Mat,
    used: bool,
}

impl SchurApprox {
    /// The approximation in `mat` (preallocated on the owned vertices), assembled until the
    /// solver says whether it uses it ([`SchurApprox::set_used`]).
    pub(crate) fn new(mat: Mat) -> SchurApprox {
        SchurApprox { mat, used: true }
    }

    /// The matrix, for the preconditioner.
    pub(crate) fn mat(&self) -> &Mat {
        &self.mat
    }

    /// Whether the preconditioner reads the matrix (else it is not assembled).
    pub(crate) fn set_used(&mut self, used: bool) {
        self.used = used;
    }

    /// The matrix for the element loop to add to, if used.
    pub(crate) fn active(&mut self) -> Option<&mut Mat> {
        self.used.then_some(&mut self.mat)
    }

    /// Starts an assembly.
    pub(crate) fn zero(&mut self) -> Result<()> {
        match self.active() {
            Some(m) => m.zero_entries(),
            None => Ok(()),
        }
    }

    /// Adds `value` to the diagonal entry of global pressure row `row`.
    pub(crate) fn add_diagonal(&mut self, row: Int, value: f64) -> Result<()> {
        match self.active() {
            Some(m) => m.add_values(&[row], &[row], &[value]),
            None => Ok(()),
        }
    }

    /// Ends an assembly.
    pub(crate) fn assemble(&mut self) -> Result<()> {
        match self.active() {
            Some(m) => m.assemble(),
            None => Ok(()),
        }
    }
}
