//! Physics: pointwise models, boundary conditions, the discrete problem, observables and exact
//! solutions for verification.

pub mod analytic;
pub mod bc;
pub mod biphasic;
pub mod contact;
pub mod experiment;
pub mod factory;
pub mod linear;
pub mod observables;
pub mod observers;
pub mod probe;
pub mod problem;
pub mod verification;

#[cfg(test)]
mod assembly_tests;
#[cfg(test)]
pub(crate) mod kernel_tests;
#[cfg(test)]
mod mms_tests;
