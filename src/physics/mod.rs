//! Physics: the equations. The pointwise models (biphasic, linear), boundary conditions, the
//! rigid plates' contact and drainage, the model built from a scene, and the discrete problem
//! TS integrates. What a run observes of its states is `observe`.

pub(crate) mod bc;
pub(crate) mod biphasic;
pub(crate) mod contact;
pub(crate) mod drag;
pub(crate) mod drainage;
pub(crate) mod factory;
pub(crate) mod linear;
pub(crate) mod medium;
pub(crate) mod problem;
pub(crate) mod suction;
pub(crate) mod surface_geometry;
pub(crate) mod surface_tension;
pub(crate) mod tools;

#[cfg(test)]
mod assembly_tests;
#[cfg(test)]
pub(crate) mod kernel_tests;
#[cfg(test)]
mod mms_tests;
