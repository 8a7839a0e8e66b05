//! Whole-body observables of a remodelling scene (post-processing, not the remodelling law,
//! which is `material::remodelling`), one history.csv row per step (collective):
//!
//! * the volume-averaged Cauchy stress of the solid, (1/V) ∫ σ_sc dV over the reference volume
//!   (kPa, tension positive; for the homogeneous 0-D relaxation this is σ_sc itself);
//! * the largest von Mises stress √(3/2)‖dev σ_sc‖ at any quadrature point;
//! * the largest and the volume-averaged remodelling strain ‖E_p‖, E_p = ½(B_p⁻¹ − I);
//! * the largest |det B_p − 1| (the integrator keeps it at round-off).

use crate::io::recorder::Declared;
use crate::parallel::{max_slice, sum_slice};
use crate::physics::problem::Post;
use mpi::topology::SimpleCommunicator;

/// The `history.csv` columns of a [`Summary`] (with `material.remodelling`).
pub(crate) const COLUMNS: [Declared<Summary>; 7] = [
    Declared::real(
        "stress_xx",
        "kPa",
        "volume-averaged Cauchy stress of the solid, xx component, tension positive",
        |s| s.stress[0],
    ),
    Declared::real("stress_yy", "kPa", "the same, yy component", |s| s.stress[1]),
    Declared::real("stress_zz", "kPa", "the same, zz component", |s| s.stress[2]),
    Declared::real("max_von_mises", "kPa", "largest von Mises stress of the solid at a quadrature point", |s| {
        s.max_von_mises
    }),
    Declared::real(
        "max_norm_ep",
        "–",
        "largest ‖E_p‖ at a quadrature point, E_p = ½(B_p⁻¹ − I) (Frobenius)",
        |s| s.max_norm_ep,
    ),
    Declared::real("mean_norm_ep", "–", "volume-averaged ‖E_p‖", |s| s.mean_norm_ep),
    Declared::real("det_bp_max_dev", "–", "largest |det B_p − 1| (0 up to round-off)", |s| s.det_bp_max_dev),
];

/// The summary of a post-processed state.
pub(crate) struct Summary {
    /// The volume-averaged σ_sc's diagonal (xx, yy, zz).
    stress: [f64; 3],
    max_von_mises: f64,
    max_norm_ep: f64,
    mean_norm_ep: f64,
    det_bp_max_dev: f64,
}

/// The summary of a post-processed state (all ranks).
pub(crate) fn observe(post: &Post, world: &SimpleCommunicator) -> Summary {
    let local = [post.volume, post.int_cauchy[0][0], post.int_cauchy[1][1], post.int_cauchy[2][2], post.int_norm_ep];
    let tot = sum_slice(world, &local);
    let top = max_slice(world, &[post.max_von_mises, post.max_norm_ep, post.max_det_bp_dev]);
    let v = tot[0];
    Summary {
        stress: [tot[1] / v, tot[2] / v, tot[3] / v],
        max_von_mises: top[0],
        max_norm_ep: top[1],
        mean_norm_ep: tot[4] / v,
        det_bp_max_dev: top[2],
    }
}
