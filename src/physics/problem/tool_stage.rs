//! The tools in the steps ([`ToolStage`]): the tool set shared with the active-set Newton, which
//! reads the contact of each iterate from it; the tools moved to each stage time; and, without
//! plates, the infinite bounds the Newton needs as its plane bounds.

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
        Ok(ToolStage { set: Rc::new(RefCell::new(set)), free })
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

    /// The tools at the stage time t.
    pub(super) fn move_to(&self, t: f64) {
        self.set.borrow_mut().move_to(t);
    }

    /// The contact data of the iterate whose local state is `u`.
    pub(super) fn update(&self, u: &[f64], dofs: &crate::fem::dofmap::DofMap) {
        self.set.borrow_mut().update(u, dofs);
    }
}
