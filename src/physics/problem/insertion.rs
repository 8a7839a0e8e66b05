//! How element matrices reach the Jacobian: the first assembly inserts sorted rows through
//! `MatSetValues` and fixes the pattern; later ones write into the CSR arrays directly through
//! offsets built after it (`fem::insert`), rows owned elsewhere collected and flushed. Also the
//! shift of the last assembly, which a linear model's Jacobian is reused at.

use crate::error::Result;
use crate::fem::assembly::Discretization;
use crate::fem::element::MAX_DOF;
use crate::fem::insert::{ElementInserter, GhostRows};
use crate::petsc::{Int, Mat};

/// The insertion state of the Jacobian's element loop.
#[derive(Default)]
pub(super) struct JacobianInsertion {
    /// Offsets for direct CSR insertion, built after the first assembly.
    inserter: Option<ElementInserter>,
    ghosts: GhostRows,
    /// Shift of the last assembled Jacobian.
    assembled_shift: Option<f64>,
}

impl JacobianInsertion {
    /// Whether the last assembly was at `shift`.
    pub(crate) fn assembled_at(&self, shift: f64) -> bool {
        self.assembled_shift == Some(shift)
    }

    /// The element loop of `disc` at the local state (`ul`, `udl`) into `jac` (and `schur`):
    /// the rows owned elsewhere are kept for [`JacobianInsertion::flush`].
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn add_elements(
        &mut self,
        disc: &Discretization,
        ul: &[f64],
        udl: &[f64],
        dt: f64,
        shift: f64,
        schur: Option<&mut Mat>,
        jac: &mut Mat,
    ) -> Result<()> {
        let ghosts = &mut self.ghosts;
        match &self.inserter {
            Some(ins) => jac.with_local_csr(|csr| {
                disc.jacobian_loop(ul, udl, dt, shift, schur, |e, d, k| ins.add(csr, e, d, &disc.dofs.l2g, k, ghosts))
            }),
            None => {
                let n = disc.ndof();
                let mut rows = [0 as Int; MAX_DOF];
                let mut sorted = vec![0.0; n * n];
                disc.jacobian_loop(ul, udl, dt, shift, schur, |_, d, k| {
                    // Increasing global indices let PETSc merge each row in one pass.
                    let mut order: Vec<usize> = (0..n).collect();
                    order.sort_unstable_by_key(|&a| disc.dofs.l2g[d[a]]);
                    for (a, &o) in order.iter().enumerate() {
                        rows[a] = disc.dofs.l2g[d[o]];
                        for (b, &c) in order.iter().enumerate() {
                            sorted[a * n + b] = k[o][c];
                        }
                    }
                    jac.add_values(&rows[..n], &rows[..n], &sorted)
                })
            }
        }
    }

    /// Adds the rows owned elsewhere that the element loop collected.
    pub(crate) fn flush(&mut self, jac: &mut Mat) -> Result<()> {
        self.ghosts.flush(jac)
    }

    /// After an assembly of `jac` at `shift`: the first one fixes the pattern the offsets
    /// point into.
    pub(crate) fn finish(&mut self, disc: &Discretization, shift: f64, jac: &mut Mat) -> Result<()> {
        if self.inserter.is_none() {
            self.inserter = Some(ElementInserter::build(jac, &disc.dofs, disc.family(), disc.mesh.cells.len(), |e| {
                disc.element_dofs(e)
            })?);
        }
        self.assembled_shift = Some(shift);
        Ok(())
    }
}
