//! Checkpoints in a running run ([`Checkpoints`]): when one is due (every N steps, every M
//! minutes, on a stop signal), and writing it — the run state, the solver's state and a copy of
//! the fields. The files are `io::checkpoint`'s.

use super::progress::Progress;
use super::step::Stepper;
use crate::error::Result;
use crate::io::checkpoint::{self, Counters, FileLayout};
use crate::io::recorder::Recorder;
use crate::parallel::agree;
use crate::scene::OutputSpec;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::PathBuf;
use std::time::Instant;

/// When checkpoints are due, and the numbering they are written in.
pub(super) struct Checkpoints {
    /// Every N steps (0: never).
    every: usize,
    /// Every M minutes of wall time (≤ 0: never), counted from `started` until the first.
    minutes: f64,
    started: Instant,
    /// The mesh file's node and element counts: the numbering of the run state.
    layout: FileLayout,
}

/// Why a checkpoint is written after a step.
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Due {
    /// Every N steps (every run of the scene takes these at the same steps).
    Periodic,
    /// By wall time, or asked by a stop signal.
    Other,
}

impl Checkpoints {
    /// The scene's checkpoints (`output.checkpoint_every`, `output.checkpoint_minutes`) of a
    /// run set up from `started` in the numbering `layout`.
    pub(crate) fn new(spec: &OutputSpec, started: Instant, layout: FileLayout) -> Checkpoints {
        Checkpoints { every: spec.checkpoint_every, minutes: spec.checkpoint_minutes, started, layout }
    }

    /// The numbering of the run state.
    pub(crate) fn layout(&self) -> FileLayout {
        self.layout
    }

    /// Whether a checkpoint is due after the step just recorded (`stopping`: a stop signal
    /// asks for one). Collective: rank 0's clock decides.
    pub(crate) fn due(&self, world: &SimpleCommunicator, pg: &Progress, stopping: bool) -> Option<Due> {
        if self.every > 0 && pg.c.step.is_multiple_of(self.every) {
            return Some(Due::Periodic);
        }
        (stopping || self.due_by_time(world, pg)).then_some(Due::Other)
    }

    /// `minutes` after the last checkpoint (rank 0's clock decides).
    fn due_by_time(&self, world: &SimpleCommunicator, pg: &Progress) -> bool {
        if self.minutes <= 0.0 {
            return false;
        }
        let since = pg.checkpointed.map_or(self.started.elapsed(), |c| c.elapsed()).as_secs_f64();
        let mut due = u8::from(since >= 60.0 * self.minutes);
        world.process_at_rank(0).broadcast_into(&mut due);
        due == 1
    }

    /// Writes the run state after the step just recorded with `counters` (collective), and
    /// makes the next solve start as it would after resuming from this checkpoint, so that a
    /// resumed run repeats the uninterrupted one. Returns the checkpoint's path.
    pub(crate) fn write(
        &self,
        world: &SimpleCommunicator,
        stepper: &mut Stepper,
        rec: &Recorder,
        counters: Counters,
        due: Due,
    ) -> Result<PathBuf> {
        let step = counters.step;
        let state = stepper.capture(world, self.layout, counters)?;
        // The solver's state between steps (the kept factorised Jacobian), per rank: a run
        // resumed on as many ranks continues exactly as this one. Where it cannot be saved the
        // solver starts afresh here, as a resumed run will.
        let solver = agree(world, stepper.solver_state())?;
        let saved = crate::parallel::all(world, solver.is_some());
        let solver_written = match (&solver, saved) {
            (Some(s), true) => checkpoint::write_solver(&rec.dir, step, world.rank(), world.size(), s),
            _ => Ok(()),
        };
        agree(world, solver_written)?;
        // The fields as of now, for a resume that finds fields.h5 damaged; before the state,
        // so that every checkpoint has a copy with at least its steps.
        rec.backup_fields(&checkpoint::fields_backup(&rec.dir))?;
        // Only at the checkpoints every N steps, which every run of the scene takes at the same
        // steps: restarting at wall-clock ones would make uninterrupted runs differ.
        if !saved && due == Due::Periodic {
            stepper.restart_solver();
        }
        crate::parallel::path_from_root(world, || state.write(&rec.dir))
    }
}
