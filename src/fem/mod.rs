//! Finite elements: quadrature, reference shape functions and isoparametric maps, the
//! Taylor–Hood dof map, and the element kernel of the u–p weak form.

pub mod assembly;
pub mod cell;
pub mod dofmap;
pub mod element;
pub mod equal_order;
pub mod insert;
pub mod kernel;
pub mod point;
pub mod qp_store;
pub mod quadrature;
pub mod surface;

#[cfg(test)]
mod mms_tests;
