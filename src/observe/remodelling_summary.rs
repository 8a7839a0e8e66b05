//! Whole-body observables of a remodelling scene (post-processing, not the remodelling law,
//! which is `material::remodelling`), one history.csv row per step (collective):
//!
//! * the volume-averaged Cauchy stress of the solid, (1/V) ∫ σ_sc dV over the reference volume
//!   (kPa, tension positive; for the homogeneous 0-D relaxation this is σ_sc itself);
//! * the largest von Mises stress √(3/2)‖dev σ_sc‖ at any quadrature point;
//! * the largest and the volume-averaged remodelling strain ‖E_p‖, E_p = ½(B_p⁻¹ − I);
//! * the largest |det B_p − 1| (the integrator keeps it at round-off).

use crate::parallel::{max_slice, sum_slice};
use crate::physics::problem::Post;
use mpi::topology::SimpleCommunicator;

/// history.csv columns of [`observe`], in order.
pub const COLUMNS: [&str; 7] =
    ["stress_xx", "stress_yy", "stress_zz", "max_von_mises", "max_norm_ep", "mean_norm_ep", "det_bp_max_dev"];

/// The row of [`COLUMNS`] for a post-processed state (all ranks).
pub fn observe(post: &Post, world: &SimpleCommunicator) -> [f64; 7] {
    let local = [post.volume, post.int_cauchy[0][0], post.int_cauchy[1][1], post.int_cauchy[2][2], post.int_norm_ep];
    let tot = sum_slice(world, &local);
    let top = max_slice(world, &[post.max_von_mises, post.max_norm_ep, post.max_det_bp_dev]);
    let v = tot[0];
    [tot[1] / v, tot[2] / v, tot[3] / v, top[0], top[1], tot[4] / v, top[2]]
}
