//! The finite-difference check of the assembled Jacobian (`-poroplast_check_jacobian`).

use super::poro_problem::PoroProblem;
use super::post::backward_euler_rate;
use crate::error::Result;
use crate::petsc::{Mat, Vector};

impl PoroProblem {
    /// Directional finite-difference check of the assembled Jacobian at state `u` of a backward
    /// Euler step of size dt from `prev`: ‖J v − (F(u + εv) − F(u − εv)) / 2ε‖ / ‖J v‖ over the u
    /// rows and over the p rows, for a fixed pseudo-random direction v (all unconstrained dofs;
    /// contact and drainage included), ε = `rel_eps` ‖u‖∞. Central differences: truncation
    /// O(ε²) where F is smooth, but O(ε) at vertices exactly on a plate, where the drainage
    /// smoothstep's second derivative jumps; round-off O(1e-16 / ε). A wrong Jacobian entry
    /// shows as an error that does not shrink with ε.
    /// `jac` must be the matrix of the solves (assembly reuses its pattern).
    pub(crate) fn jacobian_error(
        &mut self,
        t: f64,
        dt: f64,
        u: &Vector,
        prev: &Vector,
        jac: &mut Mat,
        rel_eps: f64,
    ) -> Result<(f64, f64)> {
        let dofs = self.dofs();
        let (offset, u_end) = (dofs.offset, dofs.u_range().1);
        let mut v = u.duplicate()?;
        {
            let mut w = v.write()?;
            for (i, x) in w.iter_mut().enumerate() {
                // A fixed hash of the global index: the same direction on any number of ranks.
                let h = ((offset + i) as u64 + 1).wrapping_mul(0x9E37_79B9_7F4A_7C15);
                *x = (h >> 11) as f64 / (1u64 << 53) as f64 * 2.0 - 1.0;
            }
            // Constrained dofs never move (their Jacobian columns are dropped, module docs).
            for (l, _) in self.constrained().iter().enumerate().filter(|(_, &c)| c) {
                if let Some(i) = dofs.local_to_owned(l) {
                    w[i] = 0.0;
                }
            }
        }
        let eps = rel_eps * u.norm_inf()?.max(1.0);
        // F at u + s v, with udot = (u + s v − prev) / dt.
        let mut eval = |s: f64, out: &mut Vector| -> Result<()> {
            let mut x = u.copy()?;
            x.axpy(s, &v)?;
            self.assemble_residual(t, dt, &x, &backward_euler_rate(&x, prev, dt)?, out)
        };
        let (mut fp, mut fm) = (u.duplicate()?, u.duplicate()?);
        eval(eps, &mut fp)?;
        eval(-eps, &mut fm)?;
        self.assemble_jacobian(t, dt, 1.0 / dt, u, &backward_euler_rate(u, prev, dt)?, jac)?;
        let mut jv = u.duplicate()?;
        jac.mult(&v, &mut jv)?;
        let mut sums = [0.0f64; 4]; // |Jv − fd|² and |Jv|² on u rows, then on p rows
        {
            let (jv, fp, fm) = (jv.read()?, fp.read()?, fm.read()?);
            for i in 0..jv.len() {
                let fd = (fp[i] - fm[i]) / (2.0 * eps);
                let k = if offset + i < u_end { 0 } else { 2 };
                sums[k] += (jv[i] - fd).powi(2);
                sums[k + 1] += jv[i].powi(2);
            }
        }
        let tot = crate::parallel::sum_slice(self.world(), &sums);
        Ok(((tot[0] / tot[1]).sqrt(), (tot[2] / tot[3].max(f64::MIN_POSITIVE)).sqrt()))
    }
}
