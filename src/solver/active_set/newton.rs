//! The active-set Newton solver and its Newton loop: the step (a chord iteration on the kept
//! operator, through a low-rank update of it, or a new Jacobian), its Anderson mixing, the line
//! search, and the solver state a checkpoint keeps.

use super::border::Border;
use super::bounds::{symmetric_difference, Bounds};
use super::contact::CurvedContact;
use super::convergence::{residual_test, stagnates};
use super::curved::{split, CurvedStep};
use super::reuse::{Lag, Step};
use crate::error::Result;
use crate::parallel::sum_slice;
use crate::petsc::{ffi, Int, Ksp, Mat, ShellSolve, Snes, SolverState, Vector};
use crate::solver::anderson::Anderson;
use crate::solver::woodbury::ActiveSetUpdate;
use crate::solver::FreeRigidModes;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::cell::RefCell;
use std::rc::Rc;

/// Halvings of a Newton step that leaves the admissible domain (or fails the Armijo test when
/// backtracking).
const STEP_HALVINGS: i32 = 5;

/// The active-set Newton solver (a SNESSHELL inside TS).
pub(crate) struct ActiveSetNewton {
    world: SimpleCommunicator,
    bounds: Bounds,
    /// Diagonal of the identity rows of active dofs (the scale of a u row of the Jacobian).
    diag: f64,
    lag: Lag,
    f: Vector,
    rhs: Vector,
    /// Newton step, and the step of the active dofs onto their bound.
    step: Vector,
    to_bound: Vector,
    trial: Vector,
    /// Global indices of the active dofs of the current iterate.
    active: Vec<Int>,
    /// Active set of the last preconditioner setup, and how often that setup has been reused.
    /// With chord iterations every assembly sets up anew, so this is also the active set of the
    /// assembled operator.
    pc_active: Option<Vec<Int>>,
    pc_uses: usize,
    /// The next setup builds the preconditioner afresh, as a new solver would (after
    /// [`restart`](ShellSolve::restart): what the block preconditioners kept, e.g. GAMG's
    /// interpolation, cannot be saved in a checkpoint).
    fresh_pc: bool,
    /// With chord iterations on a direct factorisation: the last Jacobian before its active
    /// rows were replaced, and the low-rank update of its factorisation to the current active
    /// set (if that differs from `pc_active`).
    jac: Option<Mat>,
    update: Option<ActiveSetUpdate>,
    last_krylov: usize,
    /// The step length of the last iteration (1: a full step; halved for admissibility).
    last_lambda: f64,
    newton: usize,
    krylov: usize,
    /// A checkpoint's state, set up at the start of the next solve.
    pending: Option<SolverState>,
    /// Print each iteration on rank 0 (`-poroplast_newton_monitor`).
    pub(crate) monitor: bool,
    /// Acceleration of the chord iterations (`-poroplast_anderson M`).
    pub(crate) anderson: Anderson,
    /// The active set of the last chord iteration (the map `anderson` has a history of).
    chord_active: Option<Vec<Int>>,
    /// Free rigid modes taken as each Jacobian's null space (None when there are none, or when
    /// they are pinned: [`set_free_modes`](Self::set_free_modes)).
    free_modes: Option<FreeRigidModes>,
    /// Contact with curved tools, if the scene has them ([`set_curved`](Self::set_curved)).
    curved: Option<CurvedStep>,
    /// Force-controlled positions (`border`): None without any.
    border: Option<Border>,
}

impl ActiveSetNewton {
    /// A solver for the bounds `lower`, `upper` (shared: updates to them are seen).
    pub(crate) fn new(
        world: &SimpleCommunicator,
        lower: &Vector,
        upper: &Vector,
        diag: f64,
        lag: Lag,
    ) -> Result<ActiveSetNewton> {
        Ok(ActiveSetNewton {
            world: world.duplicate(),
            bounds: Bounds { lower: lower.clone_ref()?, upper: upper.clone_ref()?, pinned: Vec::new() },
            diag,
            lag,
            f: lower.duplicate()?,
            rhs: lower.duplicate()?,
            step: lower.duplicate()?,
            to_bound: lower.duplicate()?,
            trial: lower.duplicate()?,
            active: Vec::new(),
            pc_active: None,
            pc_uses: 0,
            fresh_pc: false,
            jac: None,
            update: None,
            last_krylov: 0,
            last_lambda: 1.0,
            newton: 0,
            krylov: 0,
            pending: None,
            monitor: false,
            anderson: Anderson::new(0),
            chord_active: None,
            free_modes: None,
            curved: None,
            border: None,
        })
    }

    /// Rigid modes the bounds leave free: with a direct factorisation (`pin`) locked at as many
    /// dofs, else attached to each Jacobian as its null space (module docs of `solver::rigid`).
    /// Collective.
    pub(crate) fn set_free_modes(&mut self, modes: FreeRigidModes, pin: bool) {
        if pin {
            self.bounds.pinned = modes.pins(self.bounds.lower.ownership_start());
        } else {
            self.free_modes = Some(modes);
        }
    }

    /// Contact with curved tools: their nodes split in their frames, the operator rotated.
    pub(crate) fn set_curved(&mut self, contact: Rc<RefCell<dyn CurvedContact>>) {
        self.curved = Some(CurvedStep::new(contact));
    }

    /// The split of the iterate `x` whose residual is in `f` ([`split`]).
    fn split(&mut self, x: &Vector) -> Result<f64> {
        let Self { bounds, curved, world, diag, f, rhs, to_bound, active, .. } = self;
        split(bounds, curved.as_mut(), world, *diag, x, f, rhs, to_bound, active)
    }

    /// The split of the trial iterate.
    fn split_trial(&mut self) -> Result<f64> {
        let Self { bounds, curved, world, diag, f, rhs, to_bound, active, trial, .. } = self;
        split(bounds, curved.as_mut(), world, *diag, trial, f, rhs, to_bound, active)
    }

    /// Force-controlled positions as extra unknowns (`border`).
    pub(crate) fn set_border(&mut self, border: Border) {
        self.border = Some(border);
    }

    /// Force control (border): whether a position is force-controlled now.
    fn bordered(&self) -> bool {
        self.border.as_ref().is_some_and(Border::active)
    }

    /// Force control (border): the free residual norm `n` with the positions' equations.
    fn with_border(&mut self, n: f64) -> Result<f64> {
        match &mut self.border {
            Some(b) if b.active() => Ok(n.hypot(b.residual(&self.f)?)),
            _ => Ok(n),
        }
    }

    /// Force control (border): the positions and bounds at the accepted ones plus λΔd.
    fn move_positions(&mut self, lambda: f64) -> Result<()> {
        match &mut self.border {
            Some(b) if b.active() => b.move_to(lambda, (&mut self.bounds.lower, &mut self.bounds.upper)),
            _ => Ok(()),
        }
    }

    /// Whether the preconditioner of the last setup may serve the current Jacobian (the same
    /// decision on every rank: the setup is collective).
    fn reuse_pc(&self) -> bool {
        self.lag.reuse_pc(self.changes_since_setup(), self.pc_uses, self.last_krylov)
    }

    /// How many dofs entered or left the active set since the last preconditioner setup, on all
    /// ranks (None without one). Collective.
    fn changes_since_setup(&self) -> Option<usize> {
        let here = symmetric_difference(self.pc_active.as_ref()?, &self.active);
        Some(sum_slice(&self.world, &[here])[0])
    }
}

impl ActiveSetNewton {
    /// Whether the assembled operator and its preconditioner may serve this iteration (a chord
    /// iteration): the last iteration contracted by `lag.chord` or better, and the active set
    /// is the one they were set up with on every rank ([`Step::Chord`]) or differs from it in at
    /// most `lag.max_changes` dofs with a kept Jacobian for the update ([`Step::Updated`]).
    fn choose_step(&self, contraction: f64) -> Step {
        // Force control (border): chords need the kept columns; no low-rank updates of them.
        let bordered = self.bordered();
        if !self.lag.chord_allowed(contraction) || bordered && !self.border.as_ref().is_some_and(Border::ready) {
            return Step::Assemble;
        }
        self.lag.chord_step(self.changes_since_setup(), self.jac.is_some() && !bordered)
    }

    /// A chord step for an active set that differs from the factorised operator's: through the
    /// low-rank update, built anew when the active set moved since the last one. Returns false
    /// (assemble instead) if the update is singular.
    fn updated_solve(&mut self, ksp: &Ksp) -> Result<bool> {
        let (Some(jac), Some(pc_active)) = (&self.jac, &self.pc_active) else { return Ok(false) };
        let pc = ksp.pc()?;
        let stale_here = self.update.as_ref().is_none_or(|u| u.active != self.active);
        if crate::parallel::any(&self.world, stale_here) {
            self.update = ActiveSetUpdate::new(&self.world, jac, pc, pc_active, &self.active, self.diag)?;
        }
        let Some(update) = &self.update else { return Ok(false) };
        update.solve(&self.world, pc, &self.rhs, &mut self.step)?;
        self.last_krylov = 1;
        self.krylov += 1;
        Ok(true)
    }

    /// Keeps a copy of the Jacobian `a` before its active rows are replaced, for updates of its
    /// factorisation: with chord iterations, `max_changes` > 0 and a direct factorisation of a
    /// nonsingular operator (a is its own preconditioning matrix; no free rigid modes, which
    /// make it singular). Drops the update of the earlier one.
    fn keep_jacobian(&mut self, a: &Mat, ksp: &Ksp, same: bool) -> Result<()> {
        self.update = None;
        if self.lag.chord <= 0.0
            || self.lag.max_changes == 0
            || !same
            || self.free_modes.is_some()
            || self.curved.is_some()
            || ksp.pc()?.type_name()? != "lu"
        {
            self.jac = None;
            return Ok(());
        }
        match &mut self.jac {
            Some(j) => j.copy_values_from(a),
            None => {
                self.jac = Some(a.duplicate_with_values()?);
                Ok(())
            }
        }
    }

    /// The operator and factorisation of a checkpoint: its Jacobian with the active rows of
    /// its active set replaced, factorised (as they were when the checkpoint was written).
    fn set_up_saved(&mut self, snes: &Snes, ksp: &Ksp, x: &Vector, state: SolverState) -> Result<()> {
        // An assembly gives the matrix its pattern; its values are then the saved ones — if
        // the saved state fits on every rank (else the solve starts afresh, on every rank).
        let (mut a, _) = snes.compute_jacobian(x)?;
        let fits = state.counters.len() == 2 && a.local_values()?.len() == state.values.len();
        if !crate::parallel::all(&self.world, fits) {
            return Ok(());
        }
        a.set_local_values(&state.values)?;
        self.jac = Some(a.duplicate_with_values()?);
        // Force control (border): its columns, recomputed from the saved operator.
        let columns = match &mut self.border {
            Some(b) if b.active() => {
                Some(b.prepare(&a, x, (&self.bounds.lower, &self.bounds.upper), &state.indices, self.diag)?)
            }
            _ => None,
        };
        a.zero_rows_columns(&state.indices, self.diag, None)?;
        ksp.set_reuse_preconditioner(false)?;
        ksp.set_operators(&a, &a)?;
        ksp.set_up()?;
        if let (Some(b), Some(w)) = (&mut self.border, columns) {
            b.solve(ksp, w)?;
        }
        self.pc_active = Some(state.indices);
        self.pc_uses = state.counters[0] as usize;
        self.last_krylov = state.counters[1] as usize;
        Ok(())
    }

    /// One monitor line: iteration, free residual norm, active set size and how many dofs
    /// entered and left it, Krylov iterations of the last solve (and whether it was a chord, and
    /// one through an update of how many dofs).
    fn print_iteration(&self, it: usize, fnorm: f64, prev: &[Int], chord: bool, updated: Option<usize>) {
        let entered = self.active.iter().filter(|i| prev.binary_search(i).is_err()).count();
        let left = prev.iter().filter(|i| self.active.binary_search(i).is_err()).count();
        let tot = sum_slice(&self.world, &[self.active.len(), entered, left]);
        if self.world.rank() == 0 {
            let chord = match (chord, updated) {
                (true, Some(k)) => format!(", chord, update of {k}"),
                (true, None) => ", chord".to_string(),
                _ => String::new(),
            };
            let step = if self.last_lambda < 1.0 { format!(", step {}", self.last_lambda) } else { String::new() };
            let k = if it == 0 { String::new() } else { format!(", krylov {}{chord}{step}", self.last_krylov) };
            crate::console::line(&format!(
                "    newton {it:2}  |F| {fnorm:.3e}  active {} (+{} -{}){k}",
                tot[0], tot[1], tot[2]
            ));
        }
    }

    /// Solves for the step with the KSP's operators; `leash`: the preconditioner was not set up
    /// for this operator, so the solve is capped at twice the rebuild threshold. Returns whether
    /// it converged.
    fn krylov_solve(&mut self, ksp: &Ksp, leash: bool) -> Result<bool> {
        let max_it = ksp.max_it()?;
        if leash {
            ksp.set_max_it((2 * self.lag.max_krylov).clamp(1, max_it))?;
        }
        ksp.solve(&self.rhs, &mut self.step)?;
        if leash {
            ksp.set_max_it(max_it)?;
        }
        self.last_krylov = ksp.iterations()?;
        self.krylov += self.last_krylov;
        Ok(ksp.converged_reason()? > 0)
    }
}

impl ShellSolve for ActiveSetNewton {
    fn totals(&self) -> (usize, usize) {
        (self.newton, self.krylov)
    }

    fn restart(&mut self) {
        // (A preconditioner that was never set up has nothing to forget.)
        self.fresh_pc |= self.pc_active.is_some();
        self.pc_active = None;
        self.pc_uses = 0;
        self.jac = None;
        self.update = None;
        self.last_krylov = 0;
        self.pending = None;
        if let Some(b) = &mut self.border {
            b.forget();
        }
    }

    /// With chord iterations the next solve starts from the kept Jacobian, factorised with the
    /// active rows of `pc_active` replaced: that (and the counters) is the state. The
    /// low-rank update is rebuilt from it when needed, as it would be anyway.
    fn saved_state(&mut self) -> Result<Option<SolverState>> {
        match (&mut self.jac, &self.pc_active) {
            (Some(jac), Some(active)) => Ok(Some(SolverState {
                values: jac.local_values()?,
                indices: active.clone(),
                counters: vec![self.pc_uses as u64, self.last_krylov as u64],
            })),
            (None, None) => Ok(Some(SolverState { values: vec![], indices: vec![], counters: vec![] })),
            _ => Ok(None),
        }
    }

    fn restore_state(&mut self, state: SolverState) {
        self.restart();
        if !state.counters.is_empty() {
            self.pending = Some(state);
        }
    }

    fn solve(&mut self, snes: Snes, x: &mut Vector) -> Result<()> {
        use ffi::SNESConvergedReason as R;
        let (atol, rtol, stol, max_it) = snes.tolerances()?;
        let backtrack = snes.line_search_type()? == "bt";
        let ksp = snes.ksp()?;
        self.bounds.project(x)?;
        if let Some(c) = &self.curved {
            c.project(&self.world, x)?;
        }
        if let Some(b) = &mut self.border {
            b.begin();
        }
        snes.compute_function(x, &mut self.f)?;
        if let Some(state) = self.pending.take() {
            // Assembled where the residual just was (the uninterrupted run evaluates there too).
            self.set_up_saved(&snes, &ksp, x, state)?;
        }
        let mut fnorm = self.split(x)?;
        fnorm = self.with_border(fnorm)?;
        let fnorm0 = fnorm;
        self.chord_active = None;
        let mut it = 0;
        let mut prev_active = Vec::new();
        let mut norms = vec![fnorm];
        // Residual reduction of the last iteration (none yet: the operator of the last step's
        // final iteration may serve the first chord iteration).
        let mut contraction = 0.0;
        let mut chord = false;
        let mut updated = None;
        let reason = loop {
            snes.set_iteration_number(it)?;
            snes.monitor(it, fnorm)?;
            if self.monitor {
                self.print_iteration(it, fnorm, &prev_active, chord, updated);
                prev_active.clone_from(&self.active);
            }
            if let Some(reason) = residual_test(it, fnorm, fnorm0, atol, rtol, max_it) {
                break reason;
            }
            (chord, updated) = self.newton_step(&snes, &ksp, x, contraction)?;
            self.newton += 1;
            it += 1;
            if ksp.converged_reason()? < 0 {
                self.last_krylov = usize::MAX;
                break R::SNES_DIVERGED_LINEAR_SOLVE;
            }
            self.accelerate(x, chord)?;
            let (trial_norm, lambda) = self.line_search(&snes, x, fnorm, backtrack)?;
            self.last_lambda = lambda;
            if chord && trial_norm.partial_cmp(&fnorm) != Some(std::cmp::Ordering::Less) {
                // A chord step that does not reduce the residual is discarded, and the iteration
                // assembles at x instead: from the iterate of a bad chord step (a kept operator
                // whose contact has since changed), Newton may not recover — on the release of
                // the default scene, and on the mirrored full sphere of tests/plates.rs.
                self.move_positions(0.0)?;
                snes.compute_function(x, &mut self.f)?;
                self.split(x)?;
                self.with_border(0.0)?;
                contraction = f64::INFINITY;
                continue;
            }
            norms.push(trial_norm);
            if stagnates(&norms) {
                break R::SNES_DIVERGED_DTOL;
            }
            let dx_norm = lambda * self.step.norm2()?;
            let x_norm = x.norm2()?;
            x.copy_from(&self.trial)?;
            if let Some(b) = &mut self.border {
                b.accept();
            }
            contraction = if lambda == 1.0 { trial_norm / fnorm } else { f64::INFINITY };
            fnorm = trial_norm;
            // Only after a full Newton step: a step shortened by halvings is small for another
            // reason, and a chord step is small while the residual still converges only
            // linearly (the residual tests decide then).
            // (Not with force control: a contact search step moves only the positions.)
            if fnorm.is_finite() && lambda == 1.0 && !chord && !self.bordered() && dx_norm <= stol * x_norm {
                snes.set_iteration_number(it)?;
                break R::SNES_CONVERGED_SNORM_RELATIVE;
            }
        };
        if reason.0 < 0 {
            // A failed attempt (cut step): its operator and preconditioner may come from a bad
            // iterate.
            self.pc_active = None;
            self.update = None;
            if let Some(b) = &mut self.border {
                b.forget();
            }
        }
        snes.set_converged_reason(reason)
    }
}

impl ActiveSetNewton {
    /// The Newton step at x into `step`: a chord iteration with the operator and preconditioner
    /// as they are (updated to the current active set) when the last iteration's `contraction`
    /// allows, else — or if that solve fails — one with a new Jacobian. Returns whether it was
    /// a chord iteration, and the size of the low-rank update it went through (if any).
    fn newton_step(&mut self, snes: &Snes, ksp: &Ksp, x: &Vector, contraction: f64) -> Result<(bool, Option<usize>)> {
        let how = self.choose_step(contraction);
        if how != Step::Assemble {
            // What MatZeroRowsColumns puts in the active rows of the right-hand side.
            self.rhs.axpy(self.diag, &self.to_bound)?;
        }
        let chord = match how {
            Step::Chord => {
                ksp.set_reuse_preconditioner(true)?;
                self.krylov_solve(ksp, true)?
            }
            Step::Updated => self.updated_solve(ksp)?,
            Step::Assemble => false,
        };
        let updated = if chord && how == Step::Updated { self.update.as_ref().map(|u| u.n_changed()) } else { None };
        if !chord {
            self.assembled_solve(snes, ksp, x)?;
        }
        if let Some(c) = &self.curved {
            c.rotate_back(&mut self.step)?;
        }
        if self.bordered() {
            let Some(b) = &mut self.border else { unreachable!() };
            b.correct(&mut self.step, x, (&self.bounds.lower, &self.bounds.upper))?;
        }
        Ok((chord, updated))
    }

    /// Assembles the Jacobian at x, replaces its active rows and columns, and solves for the step
    /// with a new or (lagged) reused preconditioner.
    fn assembled_solve(&mut self, snes: &Snes, ksp: &Ksp, x: &Vector) -> Result<()> {
        let (mut a, mut p) = snes.compute_jacobian(x)?;
        if let Some(m) = &self.free_modes {
            a.set_null_space(&m.null_space(x)?)?;
        }
        let same = a.as_raw() == p.as_raw();
        self.keep_jacobian(&a, ksp, same)?;
        // Force control (border): its columns from the Jacobian before the rotation and the
        // replacement.
        let columns = match &mut self.border {
            Some(b) if b.active() => {
                Some(b.prepare(&a, x, (&self.bounds.lower, &self.bounds.upper), &self.active, self.diag)?)
            }
            _ => None,
        };
        if let Some(c) = &mut self.curved {
            if !same {
                return Err(crate::error::Error::Options(
                    "curved tools need the Jacobian as its own preconditioning matrix".into(),
                ));
            }
            c.rotate(&mut a)?;
        }
        a.zero_rows_columns(&self.active, self.diag, Some((&self.to_bound, &mut self.rhs)))?;
        if !same {
            p.zero_rows_columns(&self.active, self.diag, None)?;
        }
        // A reused preconditioner gets a short leash: if the Krylov method needs more than
        // twice the rebuild threshold, the same system is solved again with a new setup.
        // With chord iterations a new operator gets a new preconditioner (the chord
        // needs the pair exact: one triangular solve per iteration).
        let mut reuse = self.lag.chord <= 0.0 && self.reuse_pc();
        loop {
            ksp.set_reuse_preconditioner(reuse)?;
            if !reuse && std::mem::take(&mut self.fresh_pc) {
                ksp.pc()?.renew_split_preconditioners()?;
            }
            ksp.set_operators(&a, &p)?;
            if reuse {
                self.pc_uses += 1;
            } else {
                self.pc_active = Some(self.active.clone());
                self.pc_uses = 0;
            }
            if self.krylov_solve(ksp, reuse)? || !reuse {
                break;
            }
            reuse = false;
        }
        match (&mut self.border, columns) {
            (Some(b), Some(w)) => b.solve(ksp, w),
            _ => Ok(()),
        }
    }

    /// Anderson mixing of a chord step (its history kept while the active set stays the same on
    /// every rank); an assembled step resets it.
    fn accelerate(&mut self, x: &Vector, chord: bool) -> Result<()> {
        if chord {
            let same_here = self.chord_active.as_ref() == Some(&self.active);
            self.anderson.mix(x, &mut self.step, crate::parallel::all(&self.world, same_here))?;
            self.chord_active = Some(self.active.clone());
        } else {
            self.chord_active = None;
        }
        Ok(())
    }

    /// The trial iterate x + λ step in `trial` (projected onto the bounds), with its residual,
    /// split, in `f`, `rhs`, `to_bound` and `active`: a full step, or backtracking on the free
    /// residual norm (Armijo, halving); a step into an inadmissible state (J ≤ Φs: the residual
    /// is infinite) is halved in either mode, up to STEP_HALVINGS times, before TS has to cut
    /// the time step. Returns (free residual norm at the trial, λ).
    fn line_search(&mut self, snes: &Snes, x: &Vector, fnorm: f64, backtrack: bool) -> Result<(f64, f64)> {
        let mut lambda = 1.0;
        loop {
            self.trial.copy_from(x)?;
            self.trial.axpy(lambda, &self.step)?;
            self.move_positions(lambda)?;
            self.bounds.project(&mut self.trial)?;
            let tunnels = match &self.curved {
                Some(c) => c.project(&self.world, &mut self.trial)?,
                None => false,
            };
            if tunnels && lambda >= 0.5f64.powi(STEP_HALVINGS) {
                // A step that takes a node deeper into a tool than half its thickness may cross
                // it (its projection would land on the far side): halved, as an inadmissible one.
                lambda *= 0.5;
                continue;
            }
            snes.compute_function(&self.trial, &mut self.f)?;
            let n = self.split_trial()?;
            let n = self.with_border(n)?;
            let admissible = n.is_finite();
            let good = admissible && (!backtrack || n <= (1.0 - 1e-4 * lambda) * fnorm);
            if good || lambda < 0.5f64.powi(STEP_HALVINGS) {
                return Ok((n, lambda));
            }
            lambda *= 0.5;
        }
    }
}
