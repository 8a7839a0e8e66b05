//! Post-processing of a converged state ([`Post`], made by `PoroProblem::post_process`): the
//! reactions (the raw residual with no constraint rows) and their pressure part, the cell
//! fields and the volume integrals the observers read; the backward-Euler rate they take.

use crate::error::Result;
use crate::fem::kernel::ElementPost;
use crate::petsc::Vector;

/// Post-processing of a converged state.
pub(crate) struct Post {
    /// The state, owned + ghost entries (local layout).
    pub(crate) local: Vec<f64>,
    /// Raw residual — internal minus external forces on u rows, mass balance on p rows — with
    /// no constraint rows: the reactions of constrained and contact dofs. Owned entries.
    pub(crate) reaction: Vec<f64>,
    /// The pressure part of the u-row reactions (p entries zero). Owned entries.
    pub(crate) reaction_pressure: Vec<f64>,
    /// Per local element: J, porosity, von Mises, Darcy flux (3 per element).
    pub(crate) cell_j: Vec<f64>,
    pub(crate) cell_porosity: Vec<f64>,
    pub(crate) cell_von_mises: Vec<f64>,
    pub(crate) cell_darcy: Vec<f64>,
    /// Per local element: mean ‖E_p‖ (empty without qp state).
    pub(crate) cell_norm_ep: Vec<f64>,
    /// Σ over local elements of ∫ J dV.
    pub(crate) volume_j: f64,
    /// Σ over local elements of ∫ dV, ∫ σ_sc dV and ∫ ‖E_p‖ dV.
    pub(crate) volume: f64,
    pub(crate) int_cauchy: [[f64; 3]; 3],
    pub(crate) int_norm_ep: f64,
    /// Largest von Mises stress, ‖E_p‖ and |det B_p − 1| at the local quadrature points.
    pub(crate) max_von_mises: f64,
    pub(crate) max_norm_ep: f64,
    pub(crate) max_det_bp_dev: f64,
    /// The adhesion's pull on the [lower, upper] plate, this rank's faces (nN; 0 without
    /// adhesion): a force on the plates besides the contact reactions
    /// (`SurfaceTension::plate_pull`).
    pub(crate) adhesion_pull: [f64; 2],
    /// The medium's drag on this rank's faces (nN, the rule's coordinates).
    pub(crate) drag: [f64; 3],
    /// The upper plate's displacement at this state (0 without plates): the observers run
    /// after later solves may have moved it.
    pub(crate) upper_d: f64,
    /// The tools' positions along their axes at the state (empty without tools).
    pub(crate) tool_d: Vec<f64>,
}

impl Post {
    /// Nothing yet summed, at the local state `local`, for `n_el` local elements.
    pub(super) fn new(local: Vec<f64>, n_el: usize) -> Post {
        Post {
            local,
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
            drag: [0.0; 3],
            upper_d: 0.0,
            tool_d: Vec::new(),
        }
    }

    /// Adds the next local element's cell fields and integrals (its ‖E_p‖ too `with_qp_state`).
    pub(super) fn add_element(&mut self, ep: &ElementPost, with_qp_state: bool) {
        self.cell_j.push(ep.j);
        self.cell_porosity.push(ep.porosity);
        self.cell_von_mises.push(ep.von_mises);
        self.cell_darcy.extend(ep.darcy);
        self.volume_j += ep.volume_j;
        self.volume += ep.volume;
        for (a, b) in self.int_cauchy.iter_mut().flatten().zip(ep.int_cauchy.iter().flatten()) {
            *a += b;
        }
        self.int_norm_ep += ep.norm_ep * ep.volume;
        self.max_von_mises = self.max_von_mises.max(ep.max_von_mises);
        self.max_norm_ep = self.max_norm_ep.max(ep.max_norm_ep);
        self.max_det_bp_dev = self.max_det_bp_dev.max(ep.max_det_bp_dev);
        if with_qp_state {
            self.cell_norm_ep.push(ep.norm_ep);
        }
    }
}

/// The backward-Euler rate (u − prev) / dt of a step.
pub(crate) fn backward_euler_rate(u: &Vector, prev: &Vector, dt: f64) -> Result<Vector> {
    let mut r = u.copy()?;
    r.axpy(-1.0, prev)?;
    r.scale(1.0 / dt)?;
    Ok(r)
}
