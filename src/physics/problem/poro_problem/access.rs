//! What the driver, the solver set-up and the output read of a [`PoroProblem`], and what they
//! tell it between steps (a child of `poro_problem`, which keeps the fields private).

use super::*;

/// What the driver, the solver set-up and the output read of the problem, and the committed qp
/// state the problem holds for its assembly (captured into and applied from a checkpoint
/// through these).
impl PoroProblem {
    pub(crate) fn world(&self) -> &SimpleCommunicator {
        &self.world
    }

    pub(crate) fn mesh(&self) -> &LocalMesh {
        &self.disc.mesh
    }

    pub(crate) fn dofs(&self) -> &DofMap {
        &self.disc.dofs
    }

    pub(crate) fn model(&self) -> &dyn PointModel {
        self.disc.model.as_ref()
    }

    /// Whether each local dof is constrained.
    pub(crate) fn constrained(&self) -> &[bool] {
        &self.disc.constrained
    }

    /// The medium, if the scene has it.
    pub(crate) fn medium(&self) -> Option<&Medium> {
        self.medium.as_ref()
    }

    /// Moves the medium's suctions to time t, each pipette where its tool is then.
    pub(super) fn move_medium(&mut self, t: f64) {
        let positions = self.tools.as_ref().map(|ts| ts.set().positions()).unwrap_or_default();
        if let Some(m) = &mut self.medium {
            m.move_to(t, &positions);
        }
    }

    /// The solver's part of the upper plate's force control (None without it, or once taken).
    pub(crate) fn take_border(&mut self) -> Option<crate::solver::active_set::Border> {
        self.border.take()
    }

    /// The upper plate between steps (None without plates), for a checkpoint.
    pub(crate) fn upper_plate(&self) -> Option<super::super::contact_stage::Upper> {
        self.contact.as_ref().map(ContactStage::upper)
    }

    /// Restores the upper plate of a checkpoint.
    pub(crate) fn set_upper_plate(&mut self, upper: super::super::contact_stage::Upper) {
        if let Some(c) = &mut self.contact {
            c.set_upper(upper);
        }
    }

    /// The tools between steps (empty without tools), for a checkpoint.
    pub(crate) fn tool_progress(&self) -> Vec<crate::physics::tools::protocol::Progress> {
        self.tools.as_ref().map_or_else(Vec::new, ToolStage::progress)
    }

    /// Restores the tools of a checkpoint written at time t (`saved` may be shorter: the rest
    /// from their protocols).
    pub(crate) fn set_tool_progress(&mut self, saved: &[crate::physics::tools::protocol::Progress], t: f64) {
        if let Some(ts) = &self.tools {
            ts.set_progress(saved, t);
        }
    }

    /// The plates, if the scene has them.
    pub(crate) fn plates(&self) -> Option<&Plates> {
        self.contact.as_ref().map(ContactStage::plates)
    }

    /// The contact bounds l ≤ x ≤ u, with plates (SNES keeps them: the problem moves them with
    /// the plates), or ±∞ with tools alone.
    pub(crate) fn bounds(&self) -> Option<(&Vector, &Vector)> {
        self.contact.as_ref().map(ContactStage::bounds).or_else(|| self.tools.as_ref()?.free_bounds())
    }

    /// The tools' contact as the solver reads it, if the scene has tools.
    pub(crate) fn curved_contact(&self) -> Option<Rc<RefCell<dyn CurvedContact>>> {
        self.tools.as_ref().map(ToolStage::contact)
    }

    /// The tools, if the scene has them.
    pub(crate) fn tools(&self) -> Option<std::cell::Ref<'_, ToolSet>> {
        self.tools.as_ref().map(ToolStage::set)
    }

    /// The fixed-stress Schur approximation, for a Schur fieldsplit.
    pub(crate) fn schur(&self) -> &Mat {
        self.schur.mat()
    }

    /// Whether the preconditioner uses the Schur approximation (else it is not assembled).
    /// Told once the solver is configured: the preconditioner is read from the options by the
    /// time stepper, which holds the problem.
    pub(crate) fn set_schur_used(&mut self, used: bool) {
        self.schur.set_used(used);
    }

    /// Wall-clock totals of the residual, the Jacobian and the qp-state commits.
    pub(crate) fn timers(&self) -> Timers {
        self.timers
    }

    /// The pressure stabilisation the assembly uses.
    pub(crate) fn stabilisation(&self) -> Stabilisation {
        self.disc.stab
    }

    /// Scales the model's gravity (settling ramps it up).
    pub(crate) fn set_gravity_factor(&mut self, factor: f64) {
        self.disc.model.set_gravity_factor(factor);
        // The medium's hydrostatic pressure with it: the excess weight is what settles.
        if let Some(m) = &mut self.medium {
            m.set_gravity_factor(factor);
        }
    }

    /// Whether the model keeps qp state (remodelling).
    pub(crate) fn has_qp_state(&self) -> bool {
        !self.disc.qp_state.is_empty()
    }

    /// Holds the qp state at its committed value in the steps solved (settling before t = 0,
    /// where B_p(X, 0⁻) = I holds by definition), or lets it evolve.
    pub(crate) fn freeze_qp_state(&mut self, frozen: bool) {
        self.disc.evolve = !frozen;
    }

    /// Values of committed qp state per element (0 without).
    pub(crate) fn qp_state_per_elem(&self) -> usize {
        self.disc.qp_state.element(0).len()
    }

    /// The committed qp state of the local elements, by original element id.
    pub(crate) fn qp_state_by_original(&self) -> impl Iterator<Item = (u32, &[f64])> {
        self.disc.qp_state.export(&self.disc.mesh.cell_original)
    }

    /// Sets the committed qp state from all elements' values by original id
    /// ([`Self::qp_state_per_elem`] per element).
    pub(crate) fn set_qp_state_by_original(&mut self, values: &[f64]) -> Result<()> {
        let per_elem = self.qp_state_per_elem();
        if per_elem == 0 {
            return Ok(());
        }
        let disc = &mut self.disc;
        disc.qp_state.import(&disc.mesh.cell_original, |o| {
            values.get(o as usize * per_elem..(o as usize + 1) * per_elem).map(<[f64]>::to_vec)
        })
    }

    /// Scale of a u row of the Jacobian (for rows replaced by the identity).
    pub(crate) fn u_row_scale(&self) -> f64 {
        self.rows.scales(self.disc.model.as_ref(), 0.0).0
    }

    /// Sets the velocity the predictor of the next steps extrapolates with (copied; None: the
    /// previous state, as after a loading kink). Only the plates' predictor uses it.
    pub(crate) fn set_extrapolation(&mut self, velocity: Option<&Vector>) -> Result<()> {
        if let Some(ts) = &mut self.tools {
            ts.set_extrapolating(velocity.is_some());
        }
        match &mut self.contact {
            Some(c) => c.set_extrapolation(velocity),
            None => Ok(()),
        }
    }

    /// This rank's outflow through the drained surface at the local state `local` at time t,
    /// with the gaps the last step's residual used (the predictor's, with
    /// `DrainageGap::Predicted`; else the state's); 0 without drainage.
    pub(crate) fn drainage_outflow(&self, local: &[f64], t: f64) -> f64 {
        let Some(d) = &self.drainage else { return 0.0 };
        let set = self.tools.as_ref().map(ToolStage::set);
        d.outflow(&self.disc, local, t, seals(&self.contact, set.as_deref(), self.medium.as_ref()))
    }

    /// Local copy (owned + ghost) of a global vector, for post-processing.
    pub(crate) fn localize(&mut self, u: &Vector) -> Result<Vec<f64>> {
        self.local.load_u(u)?;
        self.local.u()
    }

    /// The plates' faces at time t, for the surface's adhesion (None without plates).
    pub(super) fn plate_planes(&self, t: f64) -> Option<PlatePlanes> {
        self.contact.as_ref().map(|c| c.planes(t))
    }
}
