//! Post-processing of a converged state: the reactions (the raw residual with no constraint
//! rows) and their pressure part, the cell fields and the volume integrals the observers read.

use super::PoroProblem;
use crate::error::Result;
use crate::fem::assembly::QpStateUse;
use crate::petsc::Vector;

/// Post-processing of a converged state.
pub struct Post {
    /// The state, owned + ghost entries (local layout).
    pub local: Vec<f64>,
    /// Raw residual — internal minus external forces on u rows, mass balance on p rows — with
    /// no constraint rows: the reactions of constrained and contact dofs. Owned entries.
    pub reaction: Vec<f64>,
    /// The pressure part of the u-row reactions (p entries zero). Owned entries.
    pub reaction_pressure: Vec<f64>,
    /// Per local element: J, porosity, von Mises, Darcy flux (3 per element).
    pub cell_j: Vec<f64>,
    pub cell_porosity: Vec<f64>,
    pub cell_von_mises: Vec<f64>,
    pub cell_darcy: Vec<f64>,
    /// Per local element: mean ‖E_p‖ (empty without qp state).
    pub cell_norm_ep: Vec<f64>,
    /// Σ over local elements of ∫ J dV.
    pub volume_j: f64,
    /// Σ over local elements of ∫ dV, ∫ σ_sc dV and ∫ ‖E_p‖ dV.
    pub volume: f64,
    pub int_cauchy: [[f64; 3]; 3],
    pub int_norm_ep: f64,
    /// Largest von Mises stress, ‖E_p‖ and |det B_p − 1| at the local quadrature points.
    pub max_von_mises: f64,
    pub max_norm_ep: f64,
    pub max_det_bp_dev: f64,
    /// The adhesion's pull on the [lower, upper] plate, this rank's faces (nN; 0 without
    /// adhesion): a force on the plates besides the contact reactions
    /// (`SurfaceTension::plate_pull`).
    pub adhesion_pull: [f64; 2],
}

impl PoroProblem {
    /// Reactions (the surface tension's included), their pressure part and cell fields at the
    /// state (U, U̇) at time t after a step of size dt.
    pub fn post_process(&mut self, t: f64, dt: f64, u: &Vector, udot: &Vector) -> Result<Post> {
        self.load_state(u, udot)?;
        let n_el = self.disc.mesh.cells.len();
        let mut post = Post {
            local: self.u_loc.read()?.to_vec(),
            reaction: Vec::new(),
            reaction_pressure: Vec::new(),
            cell_j: Vec::with_capacity(n_el),
            cell_porosity: Vec::with_capacity(n_el),
            cell_von_mises: Vec::with_capacity(n_el),
            cell_darcy: Vec::with_capacity(3 * n_el),
            cell_norm_ep: Vec::new(),
            volume_j: 0.0,
            volume: 0.0,
            int_cauchy: [[0.0; 3]; 3],
            int_norm_ep: 0.0,
            max_von_mises: 0.0,
            max_norm_ep: 0.0,
            max_det_bp_dev: 0.0,
            adhesion_pull: [0.0; 2],
        };
        let planes = self.plate_planes(t);
        let with_qp_state = !self.disc.qp_state.is_empty();
        let n_local = self.disc.dofs.n_local();
        let mut pres_loc = Vector::seq(n_local)?;
        let outcome = {
            let udl = self.udot_loc.read()?;
            let mut fl = self.f_loc.write()?;
            let mut pl = pres_loc.write()?;
            fl.iter_mut().for_each(|x| *x = 0.0);
            pl.iter_mut().for_each(|x| *x = 0.0);
            let disc = &self.disc;
            let (kernel, n, nu) = (disc.kernel(), disc.ndof(), disc.dofs.nc * disc.family().cell_nodes());
            let mut run = || -> Result<()> {
                // The end-of-step qp state is already committed: hold it.
                disc.each_element(&post.local, &udl, dt, QpStateUse::Held, |_, d, input| {
                    let ep = kernel.post(input)?;
                    for k in 0..n {
                        fl[d[k]] += ep.r[k];
                    }
                    for k in 0..nu {
                        pl[d[k]] += ep.r_pressure[k];
                    }
                    post.cell_j.push(ep.j);
                    post.cell_porosity.push(ep.porosity);
                    post.cell_von_mises.push(ep.von_mises);
                    post.cell_darcy.extend(ep.darcy);
                    post.volume_j += ep.volume_j;
                    post.volume += ep.volume;
                    for (a, b) in post.int_cauchy.iter_mut().flatten().zip(ep.int_cauchy.iter().flatten()) {
                        *a += b;
                    }
                    post.int_norm_ep += ep.norm_ep * ep.volume;
                    post.max_von_mises = post.max_von_mises.max(ep.max_von_mises);
                    post.max_norm_ep = post.max_norm_ep.max(ep.max_norm_ep);
                    post.max_det_bp_dev = post.max_det_bp_dev.max(ep.max_det_bp_dev);
                    if with_qp_state {
                        post.cell_norm_ep.push(ep.norm_ep);
                    }
                    Ok(())
                })
            };
            let r = run();
            // The surface tension's forces on the nodes, on the plates' too (the residual's).
            if let Some(st) = &self.surface {
                st.add_residual(&disc.mesh, &disc.dofs, &post.local, planes, &mut fl);
                post.adhesion_pull = st.plate_pull(&disc.mesh, &disc.dofs, &post.local, planes);
            }
            for (x, ext) in fl.iter_mut().zip(&self.external) {
                *x -= ext;
            }
            r
        };
        self.collective(outcome)?;
        let mut g = u.duplicate()?;
        g.zero()?;
        self.scatter.reverse_add(&self.f_loc, &mut g)?;
        post.reaction = g.read()?.to_vec();
        g.zero()?;
        self.scatter.reverse_add(&pres_loc, &mut g)?;
        post.reaction_pressure = g.read()?.to_vec();
        Ok(post)
    }

    /// Local copy (owned + ghost) of a global vector, for post-processing.
    pub fn localize(&mut self, u: &Vector) -> Result<Vec<f64>> {
        self.scatter.forward(u, &mut self.u_loc)?;
        Ok(self.u_loc.read()?.to_vec())
    }
}
