//! Test fixture of the element loops: the `Discretization` on a structured mesh of either family
//! (`mesh::test_util`), one rank, nothing constrained.

use super::assembly::Discretization;
use super::dofmap::DofMap;
use super::element::tabulate_cell;
use super::kernel::Stabilisation;
use super::point::PointModel;
use super::qp_store::QpStore;
use super::quadrature;
use crate::mesh::{dist, test_util::structured};
use crate::reference_cell::Family;

/// The element loops' input on the mesh of n (one rank, nothing constrained) for `model`: its
/// qp state at the model's initial value, evolving.
pub(crate) fn discretization(
    family: Family,
    n: usize,
    model: Box<dyn PointModel>,
    stab: Stabilisation,
    q: &quadrature::Quadrature,
) -> Discretization {
    discretization_of(structured(family, n), model, stab, q)
}

/// As [`discretization`] on the mesh `global`.
pub(crate) fn discretization_of(
    global: crate::mesh::Mesh,
    model: Box<dyn PointModel>,
    stab: Stabilisation,
    q: &quadrature::Quadrature,
) -> Discretization {
    let local = dist::distribute(&global, &vec![0; global.cells.len()], 1, 0).unwrap();
    let dofs = DofMap::new(&local);
    let n_local = dofs.n_local();
    let len = model.qp_state_len();
    Discretization {
        dofs,
        tab: tabulate_cell(global.family, q),
        xi: q.points.clone(),
        constrained: vec![false; n_local],
        stab,
        qp_state: QpStore::new(local.cells.len(), q.len(), len, |s| model.initial_qp_state(s)),
        equal_order: false,
        evolve: true,
        mesh: local,
        model,
    }
}
