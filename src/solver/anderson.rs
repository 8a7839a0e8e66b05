//! Anderson acceleration of chord iterations.
//!
//! A chord iteration x ← x + d, d = −P⁻¹F(x) with a kept operator P, converges linearly; on the
//! default scene's hold and rest phases at a steady rate of 0.23–0.29 per iteration, so a step
//! took 12–13 of them to reduce its residual 1e8-fold. The error is then dominated by a few
//! modes (those where the kept Jacobian differs from the current one), which Anderson mixing
//! over the last m iterates removes: with ΔX, ΔD the differences of the last m + 1 iterates and
//! their chord steps, γ = argmin ‖d − ΔD γ‖ and the step becomes d − (ΔX + ΔD) γ (Anderson's
//! type II, as in Walker & Ni, SIAM J. Numer. Anal. 49, 2011). It needs no residual or solve
//! beyond the chord's: m + 1 vectors of history and m² + m dot products per iteration.
//!
//! The history holds only iterations of one map: it is cleared when the active set changes
//! (the bounds make the map another one) and after a Newton iteration (a new operator).
//! Measured (default scene, 2 ranks, depth 2, the default): 859 → 753 nonlinear iterations,
//! 5% less time in alternating runs, the observables unchanged to 7 digits; remodel_40 713 →
//! 631, the full sphere 846 → 755 (docs/performance.md). Depth 3 or 5 did no better (770).

use super::program_options;
use crate::error::Result;
use crate::petsc::Vector;
use nalgebra::{DMatrix, DVector};
use std::collections::VecDeque;

/// Anderson mixing of depth m over the chord iterations of one active set.
pub struct Anderson {
    depth: usize,
    /// The last iterate and its (unmixed) chord step.
    last: Option<(Vector, Vector)>,
    /// (ΔX, ΔD) of the last `depth` iterations, newest last.
    history: VecDeque<(Vector, Vector)>,
}

impl Anderson {
    /// Mixing over the last `depth` iterations (0: off).
    pub fn new(depth: usize) -> Anderson {
        Anderson { depth, last: None, history: VecDeque::new() }
    }

    /// Forgets the history (a new operator, a cut step, a new solve).
    pub(crate) fn reset(&mut self) {
        self.last = None;
        self.history.clear();
    }

    /// Replaces the chord step `d` taken at `x` by the mixed step; `same_map`: the previous
    /// iteration was a chord iteration of the same operator and active set (else the history
    /// restarts here). Collective (global dot products); `same_map` must agree on all ranks.
    pub fn mix(&mut self, x: &Vector, d: &mut Vector, same_map: bool) -> Result<()> {
        if self.depth == 0 {
            return Ok(());
        }
        if !same_map {
            self.reset();
        }
        if let Some((mut dx, mut dd)) = self.last.take() {
            // ΔX = x − x_prev, ΔD = d − d_prev, in the vectors that held x_prev and d_prev.
            dx.scale(-1.0)?;
            dx.axpy(1.0, x)?;
            dd.scale(-1.0)?;
            dd.axpy(1.0, d)?;
            if self.history.len() == self.depth {
                self.history.pop_front();
            }
            self.history.push_back((dx, dd));
        }
        self.last = Some((x.copy()?, d.copy()?));
        let m = self.history.len();
        if m == 0 {
            return Ok(());
        }
        // Normal equations of the m-column least-squares problem (m ≤ depth, small).
        let mut g = DMatrix::zeros(m, m);
        let mut b = DVector::zeros(m);
        for i in 0..m {
            let di = &self.history[i].1;
            b[i] = di.dot(d)?;
            for j in 0..=i {
                let v = di.dot(&self.history[j].1)?;
                g[(i, j)] = v;
                g[(j, i)] = v;
            }
        }
        // A column (nearly) dependent on the others makes G singular: drop the history.
        let scale = (0..m).map(|i| g[(i, i)]).fold(0.0, f64::max);
        for i in 0..m {
            g[(i, i)] += 1e-12 * scale;
        }
        let Some(gamma) = g.cholesky().map(|c| c.solve(&b)) else {
            self.reset();
            return Ok(());
        };
        for (i, (dx, dd)) in self.history.iter().enumerate() {
            d.axpy(-gamma[i], dx)?;
            d.axpy(-gamma[i], dd)?;
        }
        Ok(())
    }
}

/// Depth of the Anderson mixing of chord iterations (`-poroplast_anderson M`, 0: off).
pub(super) fn anderson_depth() -> Result<usize> {
    program_options::count("poroplast_anderson", 2)
}
