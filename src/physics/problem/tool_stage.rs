//! The tools in the steps ([`ToolStage`]): the tool set shared with the active-set Newton, which
//! reads the contact of each iterate from it; the tools moved to each stage time (their targets
//! under force control) and committed with each step; and, without plates, the infinite bounds
//! the Newton needs as its plane bounds.

use super::contact_stage::INFINITY;
use crate::error::Result;
use crate::petsc::Vector;
use crate::physics::tools::ToolSet;
use crate::solver::active_set::CurvedContact;
use std::cell::RefCell;
use std::rc::Rc;

/// The tools and what the steps keep of them.
pub(super) struct ToolStage {
    set: Rc<RefCell<ToolSet>>,
    /// Bounds ±∞ for a scene without plates.
    free: Option<(Vector, Vector)>,
    /// Whether the predictor extrapolates with the last step's rate (force-controlled tools
    /// advance with theirs).
    extrapolating: bool,
}

impl ToolStage {
    /// `plates`: whether the plates' stage gives the bounds (else ±∞ ones like `template`).
    pub(super) fn new(set: ToolSet, plates: bool, template: &Vector) -> Result<ToolStage> {
        let free = if plates {
            None
        } else {
            let (mut lo, mut hi) = (template.duplicate()?, template.duplicate()?);
            lo.set(-INFINITY)?;
            hi.set(INFINITY)?;
            Some((lo, hi))
        };
        Ok(ToolStage { set: Rc::new(RefCell::new(set)), free, extrapolating: false })
    }

    /// The ±∞ bounds, without plates.
    pub(super) fn free_bounds(&self) -> Option<(&Vector, &Vector)> {
        self.free.as_ref().map(|(l, h)| (l, h))
    }

    /// The tool set as the solver reads it.
    pub(super) fn contact(&self) -> Rc<RefCell<dyn CurvedContact>> {
        self.set.clone()
    }

    pub(super) fn set(&self) -> std::cell::Ref<'_, ToolSet> {
        self.set.borrow()
    }

    /// The tools at the stage time t of the step from `start`.
    pub(super) fn move_to(&self, start: f64, t: f64) {
        self.set.borrow_mut().stage(start, t, self.extrapolating);
    }

    /// Whether the next steps' predictor extrapolates with the last step's rate.
    pub(super) fn set_extrapolating(&mut self, on: bool) {
        self.extrapolating = on;
    }

    /// Commits the tools' positions of the accepted step of size dt.
    pub(super) fn commit(&self, dt: f64, keep_rate: bool) {
        self.set.borrow_mut().commit(dt, keep_rate);
    }

    /// At the first stage of a step: a tool switched to force control must touch the body at
    /// the step's start `x0` (owned entries); `t` the step's start.
    pub(super) fn check_touch(&self, x0: &[f64], t: f64) -> Result<()> {
        self.set.borrow().check_touch(x0, t)
    }

    /// The force-controlled tools as the solver's positions.
    pub(super) fn border_unknowns(&self) -> Vec<crate::solver::active_set::PositionUnknown> {
        self.set.borrow().border_unknowns()
    }

    /// The tools between steps (a checkpoint's), and restoring them at time t.
    pub(super) fn progress(&self) -> Vec<crate::physics::tools::protocol::Progress> {
        self.set.borrow().progress().to_vec()
    }

    pub(super) fn set_progress(&self, saved: &[crate::physics::tools::protocol::Progress], t: f64) {
        self.set.borrow_mut().set_progress(saved, t);
    }

    /// The contact data of the iterate whose local state is `u`.
    pub(super) fn update(&self, u: &[f64], dofs: &crate::fem::dofmap::DofMap) {
        self.set.borrow_mut().update(u, dofs);
    }
}
