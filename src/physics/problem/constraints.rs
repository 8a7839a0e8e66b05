//! The constraint rows: the prescribed dofs (u components or p), known on every rank holding a
//! copy, whose rows of F are s (U_i − g_i) with a scale s comparable to the neighbouring
//! diagonal, and whose Jacobian rows are s on the diagonal (their columns are dropped, so the u
//! block stays symmetric for AMG).

use super::local::LocalVectors;
use super::schur::SchurApprox;
use crate::error::Result;
use crate::fem::dofmap::DofMap;
use crate::fem::point::PointModel;
use crate::mesh::dist::LocalMesh;
use crate::petsc::{Int, Mat, Vector};
use crate::physics::bc::Constraint;

/// The owned constrained dofs with their values, and the length their rows' scale takes.
pub(super) struct ConstraintRows {
    /// Each owned constrained dof with its position among the owned dofs.
    owned: Vec<(usize, Constraint)>,
    /// Mean element size h.
    h: f64,
}

impl ConstraintRows {
    /// The rows of the constraints `raw` (found from this rank's boundary faces) and, per local
    /// dof, whether it is constrained (every rank holding a copy of a constrained dof must
    /// know: its elements drop that row and column). `h`: the mean element size.
    pub(crate) fn new(
        raw: &[Constraint],
        local: &LocalVectors,
        template: &Vector,
        dofs: &DofMap,
        h: f64,
    ) -> Result<(ConstraintRows, Vec<bool>)> {
        let n_local = dofs.n_local();
        let synced = synced(local, template, n_local, raw)?;
        let mut constrained = vec![false; n_local];
        for c in &synced {
            constrained[c.local] = true;
        }
        let owned = synced.into_iter().filter_map(|c| dofs.local_to_owned(c.local).map(|i| (i, c))).collect();
        Ok((ConstraintRows { owned, h }, constrained))
    }

    /// The mean element size the scales take.
    pub(crate) fn h(&self) -> f64 {
        self.h
    }

    /// Scale of the u and p constraint rows at time-derivative shift `shift`.
    pub(crate) fn scales(&self, model: &dyn PointModel, shift: f64) -> (f64, f64) {
        let h = self.h;
        let su = model.p_wave_modulus() * h;
        let sp = model.conductivity() * h + shift * h.powi(3) / model.drained_bulk_modulus();
        (su, sp)
    }

    fn scale_of(dofs: &DofMap, local: usize, scales: (f64, f64)) -> f64 {
        if local < dofs.n_u_local() {
            scales.0
        } else {
            scales.1
        }
    }

    /// Sets the owned constraint rows of `f` (owned entries) to s (U_i − g_i), U the local `u`.
    pub(crate) fn set_residual_rows(&self, dofs: &DofMap, scales: (f64, f64), u: &[f64], f: &mut [f64]) {
        for &(i, ref c) in &self.owned {
            f[i] = Self::scale_of(dofs, c.local, scales) * (u[c.local] - c.value);
        }
    }

    /// Adds s on the diagonal of the constraint rows of `jac`, and of the Schur approximation's
    /// pressure rows.
    pub(crate) fn add_jacobian_rows(
        &self,
        mesh: &LocalMesh,
        dofs: &DofMap,
        scales: (f64, f64),
        jac: &mut Mat,
        schur: &mut SchurApprox,
    ) -> Result<()> {
        for (_, c) in &self.owned {
            let l = c.local;
            let g = dofs.l2g[l];
            let s = Self::scale_of(dofs, l, scales);
            jac.add_values(&[g], &[g], &[s])?;
            if l >= dofs.n_u_local() {
                let lv = l - dofs.n_u_local();
                schur.add_diagonal(mesh.vertex_global[lv] as Int, s)?;
            }
        }
        Ok(())
    }
}

/// The constraints known on every rank holding a copy of their dofs: flags and values summed
/// over the copies through the global vector and read back.
fn synced(local: &LocalVectors, template: &Vector, n_local: usize, raw: &[Constraint]) -> Result<Vec<Constraint>> {
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
    local.add_to(&flag_l, &mut flag_g)?;
    local.add_to(&val_l, &mut val_g)?;
    local.gather(&flag_g, &mut flag_l)?;
    local.gather(&val_g, &mut val_l)?;
    let (f, v) = (flag_l.read()?, val_l.read()?);
    Ok((0..n_local).filter(|&l| f[l] > 0.0).map(|l| Constraint { local: l, value: v[l] / f[l] }).collect())
}
