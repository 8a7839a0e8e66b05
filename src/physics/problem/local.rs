//! The rank-local work vectors of the assembly: U, U̇ and F over this rank's owned and ghost
//! dofs (the local layout), and the scatter between them and the distributed vectors.

use crate::error::Result;
use crate::fem::dofmap::DofMap;
use crate::petsc::{ffi::MPI_Comm, IndexSet, Scatter, Vector};

/// U, U̇ and F in the local layout, with the scatter to and from the distributed layout.
pub(super) struct LocalVectors {
    scatter: Scatter,
    u: Vector,
    udot: Vector,
    f: Vector,
}

impl LocalVectors {
    /// Work vectors for the local dofs of `dofs`, scattering from vectors like `template`.
    pub(crate) fn new(comm: MPI_Comm, dofs: &DofMap, template: &Vector) -> Result<LocalVectors> {
        let n_local = dofs.n_local();
        let from = IndexSet::general(comm, &dofs.l2g)?;
        let u = Vector::seq(n_local)?;
        let scatter = Scatter::new(template, &from, &u)?;
        let (udot, f) = (Vector::seq(n_local)?, Vector::seq(n_local)?);
        Ok(LocalVectors { scatter, u, udot, f })
    }

    /// local ← global (owned and ghost values).
    pub(crate) fn gather(&self, global: &Vector, local: &mut Vector) -> Result<()> {
        self.scatter.forward(global, local)
    }

    /// global += local (ghost contributions included).
    pub(crate) fn add_to(&self, local: &Vector, global: &mut Vector) -> Result<()> {
        self.scatter.reverse_add(local, global)
    }

    /// Scatters U and U̇ to the local work vectors.
    pub(crate) fn load(&mut self, u: &Vector, udot: &Vector) -> Result<()> {
        self.scatter.forward(u, &mut self.u)?;
        self.scatter.forward(udot, &mut self.udot)
    }

    /// Scatters a state `x` to the local U (U̇ untouched).
    pub(crate) fn load_u(&mut self, x: &Vector) -> Result<()> {
        self.scatter.forward(x, &mut self.u)
    }

    /// The local U and U̇ as loaded, and the local F zeroed, for an assembly to fill.
    pub(crate) fn with_zeroed_f<R>(&mut self, f: impl FnOnce(&[f64], &[f64], &mut [f64]) -> R) -> Result<R> {
        let (ul, udl, mut fl) = (self.u.read()?, self.udot.read()?, self.f.write()?);
        fl.iter_mut().for_each(|x| *x = 0.0);
        Ok(f(&ul, &udl, &mut fl))
    }

    /// Reads the local U and U̇ as loaded.
    pub(crate) fn with_state<R>(&self, f: impl FnOnce(&[f64], &[f64]) -> R) -> Result<R> {
        Ok(f(&self.u.read()?, &self.udot.read()?))
    }

    /// Reads the local U as loaded.
    pub(crate) fn with_u<R>(&self, f: impl FnOnce(&[f64]) -> R) -> Result<R> {
        Ok(f(&self.u.read()?))
    }

    /// Edits the local U as loaded.
    pub(crate) fn with_u_mut<R>(&mut self, f: impl FnOnce(&mut [f64]) -> R) -> Result<R> {
        Ok(f(&mut self.u.write()?))
    }

    /// A copy of the local U as loaded.
    pub(crate) fn u(&self) -> Result<Vec<f64>> {
        Ok(self.u.read()?.to_vec())
    }

    /// global ← the local F summed over the ranks holding each dof.
    pub(crate) fn sum_f_into(&self, global: &mut Vector) -> Result<()> {
        global.zero()?;
        self.scatter.reverse_add(&self.f, global)
    }
}
