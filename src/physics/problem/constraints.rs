//! The constraint rows and the tie of equal order: prescribed dofs known on every rank holding
//! a copy, the scale of their rows, and the mid-edge displacements tied to their edges.

use super::PoroProblem;
use crate::error::Result;
use crate::fem::equal_order;
use crate::petsc::{Scatter, Vector};
use crate::physics::bc::Constraint;

impl PoroProblem {
    /// Scale of the u and p constraint rows at time-derivative shift `shift`.
    pub(super) fn scales(&self, shift: f64) -> (f64, f64) {
        let m = &self.disc.model;
        let su = m.p_wave_modulus() * self.h;
        let sp = m.conductivity() * self.h + shift * self.h.powi(3) / m.drained_bulk_modulus();
        (su, sp)
    }

    /// Scale of a u row of the Jacobian (for rows replaced by the identity).
    pub fn u_row_scale(&self) -> f64 {
        self.scales(0.0).0
    }

    pub(super) fn scale_of(&self, local: usize, scales: (f64, f64)) -> f64 {
        if local < self.disc.dofs.n_u_local() {
            scales.0
        } else {
            scales.1
        }
    }

    /// Switches to equal-order P1–P1 (`fem::equal_order`): ties the displacement's mid-edge
    /// nodes to their edges' vertices and moves their loads there. Before the first assembly.
    pub fn tie_displacement(&mut self) {
        self.disc.equal_order = true;
        equal_order::tie_loads(&mut self.external, &self.disc.mesh);
    }

    /// Equal order: puts the mid-edge displacements of `x` (owned entries) back on their edges,
    /// where the plates' predictor moved only vertices (`fem::equal_order::tie_nodes`). Why:
    /// the tie rows would restore them in the first Newton step anyway, but the guess's
    /// compaction check and first residual would see elements bent by the predictor's jump.
    /// Nothing for Taylor–Hood.
    pub(super) fn retie(&mut self, x: &mut Vector) -> Result<()> {
        if !self.disc.equal_order {
            return Ok(());
        }
        self.scatter.forward(x, &mut self.u_loc)?;
        let mut ul = self.u_loc.write()?;
        equal_order::tie_nodes(&mut ul, &self.disc.mesh);
        let mut xw = x.write()?;
        for (l, &v) in ul.iter().enumerate().take(self.disc.dofs.n_u_local()) {
            if let Some(i) = self.disc.dofs.local_to_owned(l) {
                xw[i] = v;
            }
        }
        Ok(())
    }

    /// Constraints are found from this rank's boundary faces, but every rank holding a copy of a
    /// constrained dof must know (its elements drop that row and column): sum flags and values
    /// over the copies through the global vector and read them back.
    pub(super) fn synced(
        scatter: &Scatter,
        template: &Vector,
        n_local: usize,
        raw: &[Constraint],
    ) -> Result<Vec<Constraint>> {
        let (mut flag_l, mut val_l) = (Vector::seq(n_local)?, Vector::seq(n_local)?);
        {
            let (mut f, mut v) = (flag_l.write()?, val_l.write()?);
            f.iter_mut().for_each(|x| *x = 0.0);
            v.iter_mut().for_each(|x| *x = 0.0);
            for c in raw {
                f[c.local] += 1.0;
                v[c.local] += c.value;
            }
        }
        let (mut flag_g, mut val_g) = (template.duplicate()?, template.duplicate()?);
        flag_g.zero()?;
        val_g.zero()?;
        scatter.reverse_add(&flag_l, &mut flag_g)?;
        scatter.reverse_add(&val_l, &mut val_g)?;
        scatter.forward(&flag_g, &mut flag_l)?;
        scatter.forward(&val_g, &mut val_l)?;
        let (f, v) = (flag_l.read()?, val_l.read()?);
        Ok((0..n_local).filter(|&l| f[l] > 0.0).map(|l| Constraint { local: l, value: v[l] / f[l] }).collect())
    }
}
