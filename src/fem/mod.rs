//! Finite elements of the u–p weak form on Taylor–Hood P2–P1 cells. Submodules:
//!
//! - `assembly`: the element loop over local cells (residual, Jacobian, qp-state commit,
//!   post-processing);
//! - `cell`: the two cell families (10-node tetrahedron, 6-node meridian triangle) as types;
//! - `dofmap`: the distributed P2–P1 dof layout (owned blocks, ghosts, u and p index sets);
//! - `element`: the isoparametric maps on the reference cells' shape functions
//!   ([`crate::reference_cell`]) tabulated at quadrature points, and the element dof layout;
//! - `equal_order`: equal-order P1–P1 (mid-edge nodes tied to their edge), the unstable contrast;
//! - `insert`: fast insertion of element Jacobians at precomputed positions in the matrix;
//! - `kernel`: element residual and Jacobian of the weak form for either cell family;
//! - `point`: the pointwise interface between assembly and the constitutive laws (`PointModel`);
//! - `qp_store`: the committed per-quadrature-point state of a model (e.g. B_p) as one flat array;
//! - `quadrature`: symmetric Gauss-type rules on the reference tetrahedron and triangle;
//! - `surface`: quadrature on boundary faces (loads, drainage areas, probes, contact);
//! - `test_util` (tests only): the discretisation on a structured mesh of either family.

pub(crate) mod assembly;
pub(crate) mod cell;
pub(crate) mod dofmap;
pub(crate) mod element;
pub(crate) mod equal_order;
pub(crate) mod insert;
pub(crate) mod kernel;
pub(crate) mod point;
pub(crate) mod qp_store;
pub(crate) mod quadrature;
pub(crate) mod surface;

#[cfg(test)]
pub(crate) mod test_util;
