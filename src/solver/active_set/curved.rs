//! The active-set Newton's side of contact with curved tools (issue 53): at each iterate the
//! split of the curved nodes in their frames, the assembled operator rotated to the same frames
//! with the contact's curvature on the active nodes' tangents, the step rotated back, and the
//! projection of an iterate onto the tools. The problem gives the frames ([`CurvedContact`]);
//! plane-only scenes never build this.

use super::bounds::Bounds;
use super::contact::{split_curved, CurvedContact, NodeContact};
use super::frames::{rotate_matrix, rotate_owned, Frame, FrameIndex};
use crate::error::Result;
use crate::petsc::{Int, Mat, Vector};
use mpi::topology::SimpleCommunicator;
use std::cell::RefCell;
use std::rc::Rc;

/// The curved contact of the iterate being solved.
pub(super) struct CurvedStep {
    contact: Rc<RefCell<dyn CurvedContact>>,
    /// Where the candidates' rows and columns sit in the assembled matrix (built at the first
    /// rotation: the pattern is fixed then).
    index: Option<FrameIndex>,
    /// The owned framed nodes of the last split, and their contact forces (0 when free).
    nodes: Vec<NodeContact>,
    lambda: Vec<f64>,
    /// Whether any rank has a framed candidate at the last split (the rotation is collective).
    rotated: bool,
    /// The first owned global dof.
    first: usize,
}

impl CurvedStep {
    pub(super) fn new(contact: Rc<RefCell<dyn CurvedContact>>) -> CurvedStep {
        CurvedStep { contact, index: None, nodes: Vec::new(), lambda: Vec::new(), rotated: false, first: 0 }
    }

    /// The curved nodes' part of the split of the iterate last evaluated (after the plane split:
    /// `split_curved`); `c` the scale of a u row, `first` the first owned global dof. Collective.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn split(
        &mut self,
        world: &SimpleCommunicator,
        c: f64,
        first: usize,
        f: &Vector,
        rhs: &mut Vector,
        to_bound: &mut Vector,
        active: &mut Vec<Int>,
    ) -> Result<()> {
        self.first = first;
        {
            let contact = self.contact.borrow();
            self.nodes.clear();
            self.nodes.extend_from_slice(contact.nodes());
            let framed_here = contact.frames().iter().any(Option::is_some);
            self.rotated = crate::parallel::any(world, framed_here);
        }
        let (fv, mut r, mut d) = (f.read()?, rhs.write()?, to_bound.write()?);
        split_curved(&self.nodes, c, first, &fv, &mut r, &mut d, active, &mut self.lambda)
    }

    /// B = QᵀAQ with the frames of the last split, plus −λ τᵀ∇²φ τ on the tangents of its
    /// active nodes, assembled. Collective; nothing when no rank has a framed node.
    pub(super) fn rotate(&mut self, a: &mut Mat) -> Result<()> {
        if !self.rotated {
            return Ok(());
        }
        let contact = self.contact.borrow();
        if self.index.is_none() {
            let (nc, candidates) = (contact.components(), contact.candidates());
            self.index = Some(a.with_local_csr(|csr| FrameIndex::build(csr, nc, candidates))?);
        }
        let Some(index) = &self.index else { return Ok(()) };
        rotate_matrix(a, index, contact.frames(), false)?;
        for (node, &lambda) in self.nodes.iter().zip(&self.lambda) {
            if lambda == 0.0 {
                continue;
            }
            let nc = node.frame.components();
            let block = node.curvature(lambda);
            let first = (self.first + nc * node.node) as Int;
            let dofs: Vec<Int> = (0..nc as Int - 1).map(|i| first + i).collect();
            let vals: Vec<f64> = (0..nc - 1).flat_map(|i| (0..nc - 1).map(move |j| block[i][j])).collect();
            a.add_values(&dofs, &dofs, &vals)?;
        }
        a.assemble()
    }

    /// The step solved in the frames back to Cartesian components (owned nodes; local).
    pub(super) fn rotate_back(&self, step: &mut Vector) -> Result<()> {
        if self.nodes.is_empty() {
            return Ok(());
        }
        let framed: Vec<(usize, Frame)> = self.nodes.iter().map(|n| (n.node, n.frame)).collect();
        rotate_owned(&mut step.write()?, &framed, true);
        Ok(())
    }

    /// Projects `x` onto the tools (the problem's projection); whether a node of any rank went
    /// deeper than half a tool's thickness (collective).
    pub(super) fn project(&self, world: &SimpleCommunicator, x: &mut Vector) -> Result<bool> {
        let depth = self.contact.borrow().project(x)?;
        Ok(crate::parallel::max(world, depth) > 1.0)
    }
}

/// The active-set split of the iterate `x` with residual `f` (`Bounds::split`), then the curved
/// tools' nodes in their frames; returns the free residual norm. Without curved tools, exactly
/// the plane split.
#[allow(clippy::too_many_arguments)]
pub(super) fn split(
    bounds: &Bounds,
    curved: Option<&mut CurvedStep>,
    world: &SimpleCommunicator,
    diag: f64,
    x: &Vector,
    f: &Vector,
    rhs: &mut Vector,
    to_bound: &mut Vector,
    active: &mut Vec<Int>,
) -> Result<f64> {
    let Some(c) = curved else { return bounds.split(x, f, rhs, to_bound, active) };
    bounds.split_dofs(x, f, rhs, to_bound, active)?;
    c.split(world, diag, x.ownership_start(), f, rhs, to_bound, active)?;
    rhs.norm2()
}
