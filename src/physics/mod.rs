//! Physics: the equations. The pointwise models (biphasic, linear), boundary conditions, the
//! rigid plates' contact and drainage, the model built from a scene, and the discrete problem
//! TS integrates. What a run observes of its states is `observe`.

pub mod bc;
pub mod biphasic;
pub mod contact;
pub mod factory;
pub mod linear;
pub mod problem;
pub mod surface_tension;
pub(crate) mod tools;

#[cfg(test)]
mod assembly_tests;
#[cfg(test)]
pub(crate) mod kernel_tests;
#[cfg(test)]
mod mms_tests;
