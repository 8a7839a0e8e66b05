//! The Jacobian dF/dU + shift dF/dU̇ of a step and the fixed-stress Schur approximation: the
//! element loop (the first assembly inserts sorted rows and fixes the pattern, later ones write
//! into the CSR arrays), the surface tension's face blocks, the drainage rows, and the
//! constraint rows on the diagonal.

use super::PoroProblem;
use crate::error::Result;
use crate::fem::element::MAX_DOF;
use crate::fem::insert::ElementInserter;
use crate::petsc::{Int, Mat, Vector};
use std::time::Instant;

impl PoroProblem {
    /// Jacobian dF/dU + shift dF/dU̇ into `jac`, and the Schur approximation into `self.schur`
    /// if the preconditioner uses it (`schur_needed`).
    /// The first assembly inserts through `MatSetValues` and fixes the pattern; later ones
    /// write into the CSR arrays directly (see `fem::insert`).
    pub fn assemble_jacobian(
        &mut self,
        t: f64,
        dt: f64,
        shift: f64,
        u: &Vector,
        udot: &Vector,
        jac: &mut Mat,
    ) -> Result<()> {
        // A linear model's Jacobian depends only on the shift (unless contact changes the
        // drained set, or the surface tension's geometry moves): leaving the matrix untouched
        // lets PETSc keep the preconditioner too.
        if self.disc.model.is_linear()
            && self.plates.is_none()
            && self.surface.is_none()
            && self.assembled_shift == Some(shift)
        {
            return Ok(());
        }
        let t0 = Instant::now();
        self.load_state(u, udot)?;
        let r = self.jacobian_with(t, dt, shift, jac);
        self.timers.jacobian_s += t0.elapsed().as_secs_f64();
        self.timers.jacobian_n += 1;
        r
    }

    fn jacobian_with(&mut self, t: f64, dt: f64, shift: f64, jac: &mut Mat) -> Result<()> {
        jac.zero_entries()?;
        let needed = self.schur_needed;
        if needed {
            self.schur.zero_entries()?;
        }
        let outcome = {
            let ul = self.u_loc.read()?;
            let udl = self.udot_loc.read()?;
            let (disc, ghosts) = (&self.disc, &mut self.ghosts);
            let schur = needed.then_some(&mut self.schur);
            match &self.inserter {
                Some(ins) => jac.with_local_csr(|csr| {
                    disc.jacobian_loop(&ul, &udl, dt, shift, schur, |e, d, k| {
                        ins.add(csr, e, d, &disc.dofs.l2g, k, ghosts)
                    })
                }),
                None => {
                    let n = disc.ndof();
                    let mut rows = [0 as Int; MAX_DOF];
                    let mut sorted = vec![0.0; n * n];
                    disc.jacobian_loop(&ul, &udl, dt, shift, schur, |_, d, k| {
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
        };
        self.collective(outcome)?;
        self.ghosts.flush(jac)?;
        let scales = self.scales(shift);
        // Surface tension: γ ∂²A/∂x² of each face (with the adhesion to the plates at time t),
        // constrained rows and columns dropped as the element loop drops them.
        if let Some(st) = &self.surface {
            let ul = self.u_loc.read()?;
            let (disc, l2g) = (&self.disc, &self.disc.dofs.l2g);
            st.for_each_block(&disc.mesh, &disc.dofs, &ul, self.plate_planes(t), |idx, block| {
                let keep: Vec<usize> = (0..idx.len()).filter(|&k| !disc.constrained[idx[k]]).collect();
                let rows: Vec<Int> = keep.iter().map(|&k| l2g[idx[k]]).collect();
                let vals: Vec<f64> =
                    keep.iter().flat_map(|&a| keep.iter().map(move |&b| block[a * idx.len() + b])).collect();
                jac.add_values(&rows, &rows, &vals)
            })?;
        }
        // Drainage: d(c p)/dp = c on the diagonal, d(c p)/du_z = c' p (not with the predicted
        // gap, fixed during the step); and c in the Schur block.
        if let Some(pl) = &self.plates {
            let ul = self.u_loc.read()?;
            let l2g = &self.disc.dofs.l2g;
            let gaps = self.predicted.as_deref();
            for d in pl.drainage(&self.disc.mesh, &self.disc.dofs, gaps.unwrap_or(&ul), t) {
                if self.disc.constrained[d.p] {
                    continue;
                }
                let dc_du = if gaps.is_some() { 0.0 } else { d.d_conductance * ul[d.p] };
                jac.add_values(&[l2g[d.p]], &[l2g[d.p], l2g[d.uz]], &[d.conductance, dc_du])?;
                let gv = self.disc.mesh.vertex_global[d.p - self.disc.dofs.n_u_local()] as Int;
                if needed {
                    self.schur.add_values(&[gv], &[gv], &[d.conductance])?;
                }
            }
        }
        let rows: Vec<usize> = self.constraints.iter().map(|(_, c)| c.local).collect();
        for l in rows {
            let g = self.disc.dofs.l2g[l];
            let s = self.scale_of(l, scales);
            jac.add_values(&[g], &[g], &[s])?;
            if l >= self.disc.dofs.n_u_local() {
                let lv = l - self.disc.dofs.n_u_local();
                let gv = self.disc.mesh.vertex_global[lv] as Int;
                if needed {
                    self.schur.add_values(&[gv], &[gv], &[s])?;
                }
            }
        }
        jac.assemble()?;
        if needed {
            self.schur.assemble()?;
        }
        if self.inserter.is_none() {
            let disc = &self.disc;
            self.inserter = Some(ElementInserter::build(jac, &disc.dofs, disc.family(), disc.mesh.cells.len(), |e| {
                disc.element_dofs(e)
            })?);
        }
        self.assembled_shift = Some(shift);
        Ok(())
    }
}
