//! When the Newton loop stops: the residual tests, and the stagnation of a residual that cycles.

use crate::petsc::ffi;

/// True if the free residual norms (one per iterate) have stopped decreasing: after
/// `STALL_WINDOW` more iterations than that, the best of the last `STALL_WINDOW` is not 10×
/// below the best before them. Seen where a node's drainage switches as its gap closes: Newton
/// then cycles at a fixed residual, and a shorter time step is the cure, found sooner.
pub(super) fn stagnates(norms: &[f64]) -> bool {
    const STALL_WINDOW: usize = 6;
    let n = norms.len();
    if n <= 2 * STALL_WINDOW {
        return false;
    }
    let best = |s: &[f64]| s.iter().copied().fold(f64::INFINITY, f64::min);
    best(&norms[n - STALL_WINDOW..]) > 0.1 * best(&norms[..n - STALL_WINDOW])
}

/// The residual tests at the start of iteration `it` (free residual norm `fnorm`, `fnorm0` at
/// the start): the reason to stop, or None to iterate.
pub(super) fn residual_test(
    it: usize,
    fnorm: f64,
    fnorm0: f64,
    atol: f64,
    rtol: f64,
    max_it: usize,
) -> Option<ffi::SNESConvergedReason> {
    use ffi::SNESConvergedReason as R;
    if !fnorm.is_finite() {
        Some(R::SNES_DIVERGED_FUNCTION_DOMAIN)
    } else if fnorm <= atol {
        Some(R::SNES_CONVERGED_FNORM_ABS)
    } else if it > 0 && fnorm <= rtol * fnorm0 {
        Some(R::SNES_CONVERGED_FNORM_RELATIVE)
    } else if it >= max_it {
        Some(R::SNES_DIVERGED_MAX_IT)
    } else {
        None
    }
}

#[cfg(test)]
mod tests {
    use super::stagnates;

    #[test]
    fn stagnation_is_a_residual_that_stopped_falling() {
        // Quadratic convergence never stagnates, however many iterations.
        let fast: Vec<f64> = (0..20).map(|k| 10f64.powi(-k)).collect();
        assert!(!stagnates(&fast));
        // Slow but steady (×0.6 per iteration: ×0.047 per window) is progress.
        let slow: Vec<f64> = (0..30).map(|k| 0.6f64.powi(k)).collect();
        assert!(!stagnates(&slow));
        // The contact-onset cycle seen on the default scene: 855 → ~5, then bouncing.
        let mut cyc = vec![855.0, 280.0, 105.0, 22.0, 4.75];
        cyc.extend([5.8, 4.1, 10.6, 4.07, 14.3, 4.9, 5.1, 4.9, 5.1].iter());
        assert!(!stagnates(&cyc[..12]));
        assert!(stagnates(&cyc));
    }
}
