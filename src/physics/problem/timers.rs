//! Wall-clock totals of the problem's expensive callbacks, for `timings.txt`.

/// Wall-clock totals of the expensive callbacks.
#[derive(Debug, Default, Clone, Copy)]
pub struct Timers {
    pub residual_s: f64,
    pub residual_n: usize,
    pub jacobian_s: f64,
    pub jacobian_n: usize,
    /// Committing the qp state of accepted steps (timings.txt: `history_commit`).
    pub qp_commit_s: f64,
}
