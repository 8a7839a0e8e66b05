//! When the active-set Newton reuses what it set up: the lag of the preconditioner and the
//! chord iterations on a kept operator ([`Lag`]), as decisions on counts (no PETSc, no MPI).

/// When to rebuild the preconditioner. A preconditioner built for an earlier Jacobian (an
/// earlier iterate, or an earlier step) stays a good one while the Jacobian changes little;
/// the Krylov method then needs a few more iterations instead of a new setup. A change of the
/// active set by k dofs is a rank-2k change of the matrix, which costs a Krylov method up to
/// about 2k more iterations. The preconditioner is rebuilt when more than `max_changes` dofs
/// entered or left the active set since its setup, when the last solve needed more than
/// `max_krylov` iterations (or failed), or after `max_reuse` reuses.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Lag {
    /// Reuse a preconditioner at most this many times (0: rebuild for every Jacobian).
    pub(crate) max_reuse: usize,
    /// Rebuild after a solve that needed more Krylov iterations than this.
    pub(crate) max_krylov: usize,
    /// Rebuild when more dofs than this entered or left the active set since the setup. With
    /// chord iterations: the largest active-set change a chord iteration absorbs by a low-rank
    /// update of a direct factorisation ([`ActiveSetUpdate`](crate::solver::ActiveSetUpdate); 0: none).
    pub(crate) max_changes: usize,
    /// Chord iterations: keep the last assembled Jacobian and its preconditioner (no assembly,
    /// no setup) while each iteration reduces the free residual by at least this factor and
    /// the active set is the one it was assembled with — or, with a direct factorisation,
    /// differs from it in at most `max_changes` dofs. Such an iteration costs one residual and
    /// one pair of triangular solves. When > 0, every assembly sets up a new preconditioner
    /// (`max_reuse` and `max_krylov` apply only with 0: assemble at every iteration, and lag
    /// the preconditioner instead).
    pub(crate) chord: f64,
}

impl Lag {
    /// A new preconditioner for every Jacobian.
    pub(crate) const NEVER: Lag = Lag { max_reuse: 0, max_krylov: 0, max_changes: 0, chord: 0.0 };

    /// Whether the preconditioner of the last setup may serve the current Jacobian: it differs
    /// from the setup's active set in `changes` dofs (None: no setup), has served `uses` times,
    /// and its last solve took `last_krylov` iterations.
    pub(super) fn reuse_pc(&self, changes: Option<usize>, uses: usize, last_krylov: usize) -> bool {
        let Some(changed) = changes else { return false };
        changed <= self.max_changes && uses < self.max_reuse && last_krylov <= self.max_krylov
    }

    /// Whether the last iteration's residual `contraction` allows a chord iteration.
    pub(super) fn chord_allowed(&self, contraction: f64) -> bool {
        !(self.chord <= 0.0 || contraction > self.chord)
    }

    /// Where a chord iteration's step comes from ([`chord_allowed`](Self::chord_allowed)): the
    /// kept operator and preconditioner as they are if the active set is theirs on every rank
    /// (`changes` dofs differ; None: none kept), through a low-rank update of a `kept_jacobian`
    /// if it differs in at most `max_changes` dofs, else a new assembly.
    pub(super) fn chord_step(&self, changes: Option<usize>, kept_jacobian: bool) -> Step {
        match changes {
            Some(0) => Step::Chord,
            Some(k) if k <= self.max_changes && kept_jacobian => Step::Updated,
            _ => Step::Assemble,
        }
    }
}

/// Where an iteration's step comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Step {
    /// The kept operator and preconditioner, as they are.
    Chord,
    /// The kept factorisation with a low-rank update to the current active set.
    Updated,
    /// A new Jacobian (and preconditioner setup, unless lagged).
    Assemble,
}

#[cfg(test)]
mod tests {
    use super::{Lag, Step};

    const DIRECT: Lag = Lag { max_reuse: 1000, max_krylov: 12, max_changes: 8, chord: 0.3 };

    #[test]
    fn chord_iterations_while_the_residual_contracts_and_the_active_set_stays() {
        assert!(DIRECT.chord_allowed(0.0) && DIRECT.chord_allowed(0.3));
        assert!(!DIRECT.chord_allowed(0.31) && !DIRECT.chord_allowed(f64::INFINITY));
        assert!(!Lag::NEVER.chord_allowed(0.0), "no chord when it is off");
        assert_eq!(DIRECT.chord_step(Some(0), false), Step::Chord);
        assert_eq!(DIRECT.chord_step(Some(8), true), Step::Updated);
        assert_eq!(DIRECT.chord_step(Some(8), false), Step::Assemble, "no kept Jacobian to update");
        assert_eq!(DIRECT.chord_step(Some(9), true), Step::Assemble);
        assert_eq!(DIRECT.chord_step(None, true), Step::Assemble);
    }

    #[test]
    fn a_lagged_preconditioner_is_rebuilt_past_its_limits() {
        let lag = Lag { max_reuse: 3, max_krylov: 10, max_changes: 2, chord: 0.0 };
        assert!(lag.reuse_pc(Some(2), 2, 10));
        assert!(!lag.reuse_pc(None, 0, 0), "nothing set up");
        assert!(!lag.reuse_pc(Some(3), 0, 0), "too many active-set changes");
        assert!(!lag.reuse_pc(Some(0), 3, 0), "reused often enough");
        assert!(!lag.reuse_pc(Some(0), 0, 11), "the last solve took too long");
        assert!(!Lag::NEVER.reuse_pc(Some(0), 0, 0));
    }
}
