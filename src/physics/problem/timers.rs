//! Wall-clock totals of the problem's expensive callbacks, for `timings.txt`.

/// Wall-clock totals of the expensive callbacks.
#[derive(Debug, Default, Clone, Copy)]
pub(crate) struct Timers {
    pub(crate) residual_s: f64,
    pub(crate) residual_n: usize,
    pub(crate) jacobian_s: f64,
    pub(crate) jacobian_n: usize,
    /// Committing the qp state of accepted steps (timings.txt: `history_commit`).
    pub(crate) qp_commit_s: f64,
}
