//! The residual F(t, U, U̇) of a step: the element loop, the surface tension, the drainage
//! through the surface off the plates, the external loads, and the constraint rows s (U_i − g_i).

use super::PoroProblem;
use crate::error::Result;
use crate::petsc::Vector;
use crate::physics::surface_tension::PlatePlanes;
use std::time::Instant;

impl PoroProblem {
    /// Residual of the current step at (t, U, U̇) with step size dt.
    pub fn assemble_residual(&mut self, t: f64, dt: f64, u: &Vector, udot: &Vector, f: &mut Vector) -> Result<()> {
        let t0 = Instant::now();
        self.load_state(u, udot)?;
        let r = self.residual_with(t, dt, f);
        self.timers.residual_s += t0.elapsed().as_secs_f64();
        self.timers.residual_n += 1;
        r
    }

    fn residual_with(&mut self, t: f64, dt: f64, f: &mut Vector) -> Result<()> {
        let planes = self.plate_planes(t);
        let outcome = {
            let ul = self.u_loc.read()?;
            let udl = self.udot_loc.read()?;
            let mut fl = self.f_loc.write()?;
            fl.iter_mut().for_each(|x| *x = 0.0);
            let disc = &self.disc;
            let res = disc.add_residual(&ul, &udl, dt, &mut fl);
            // Surface tension: γ ∂A/∂x of the boundary's nodes (with the adhesion to the plates
            // where they are at time t).
            if let Some(st) = &self.surface {
                st.add_residual(&disc.mesh, &disc.dofs, &ul, planes, &mut fl);
            }
            // Drainage through the surface off the plates: outflow c(g) p (contact module).
            if let Some(pl) = &self.plates {
                for d in pl.drainage(&disc.mesh, &disc.dofs, self.predicted.as_deref().unwrap_or(&ul), t) {
                    fl[d.p] += d.conductance * ul[d.p];
                }
            }
            for (l, x) in fl.iter_mut().enumerate() {
                if disc.constrained[l] {
                    *x = 0.0;
                } else {
                    *x -= self.external[l];
                }
            }
            res
        };
        self.collective(outcome)?;
        f.zero()?;
        self.scatter.reverse_add(&self.f_loc, f)?;
        let scales = self.scales(1.0 / dt);
        {
            let ul = self.u_loc.read()?;
            let mut fw = f.write()?;
            for &(i, ref c) in &self.constraints {
                fw[i] = self.scale_of(c.local, scales) * (ul[c.local] - c.value);
            }
        }
        Ok(())
    }

    /// The plates' faces at time t, for the surface's adhesion (None without plates).
    pub(super) fn plate_planes(&self, t: f64) -> Option<PlatePlanes> {
        self.plates.as_ref().map(|p| PlatePlanes { lower: p.z_lower(t), upper: p.z_upper })
    }
}
