//! Rigid tools of revolution (issue 53): each tool's profile, the section of a body of
//! revolution in its own (ρ, ζ) frame, with its exact signed distance φ (> 0 outside the tool,
//! on the body's side), its gradient, Hessian and closest point; and the tool placed in space,
//! which lifts them to 3-D and to the meridian. The scene's `[[tools]]` keys are
//! `scene::tools`.

// Wired into the contact in stage b (issue 53): until then only the tests use it (the
// re-exports included).
#![allow(dead_code, unused_imports)]

#[cfg(test)]
mod brute_force;
mod profile;
#[cfg(test)]
mod profile_tests;
pub(crate) mod protocol;
mod rounded_strip;
mod sdf;
mod set;
mod tool;
#[cfg(test)]
mod tool_tests;

pub(crate) use profile::Profile;
pub(crate) use sdf::Sdf2;
pub(crate) use set::{Nearest, ToolSet};
pub(crate) use tool::{Gap, Tool};
