//! Checkpoints in a running run: when one is due (every N steps, every M minutes, on a stop
//! signal), writing it — the run state, the solver's state and a copy of the fields — and
//! restoring one for `resume`. The files are `io::checkpoint`'s.

use super::progress::Progress;
use super::run::Run;
use super::signals::StopRequest;
use crate::error::{Error, Result};
use crate::io::checkpoint::{self, Counters, RunState};
use crate::io::recorder::Recorder;
use crate::observe::pressure_peak::PressurePeak;
use crate::parallel::agree;
use mpi::traits::*;
use std::path::PathBuf;
use std::time::Instant;

impl<'w> Run<'w> {
    /// A checkpoint after the step just recorded, if one is due; a stop signal writes one and
    /// ends the run (`Error::Stopped`).
    pub(super) fn checkpoint_if_due(
        &mut self,
        rec: &Recorder,
        pg: &mut Progress,
        stop: &StopRequest,
        t_start: Instant,
    ) -> Result<()> {
        let stopping = stop.requested(self.world);
        let every = self.scene.scene.output.checkpoint_every;
        let periodic = every > 0 && pg.c.step.is_multiple_of(every);
        if !(stopping || periodic || self.checkpoint_due(pg)) {
            return Ok(());
        }
        let path = self.checkpoint(rec, pg, t_start, periodic)?;
        if !stopping {
            return Ok(());
        }
        Err(Error::Stopped(format!(
            "stopped by a signal after step {} (t = {} s); checkpoint {}; continue with `{}`",
            pg.c.step,
            crate::io::fmt_time(pg.c.t),
            path.display(),
            crate::launch::command(self.world.size() as usize, &["resume", &rec.dir.display().to_string()])
        )))
    }

    /// A checkpoint by wall time is due after this step: `output.checkpoint_minutes` after the
    /// last (rank 0's clock decides).
    fn checkpoint_due(&self, pg: &Progress) -> bool {
        let o = &self.scene.scene.output;
        if o.checkpoint_minutes <= 0.0 {
            return false;
        }
        let since = pg.checkpointed.map_or(self.setup.started.elapsed(), |c| c.elapsed()).as_secs_f64();
        let mut due = u8::from(since >= 60.0 * o.checkpoint_minutes);
        self.world.process_at_rank(0).broadcast_into(&mut due);
        due == 1
    }

    /// Writes the run state after the step just recorded (collective), and makes the next
    /// solve start as it would after resuming from this checkpoint, so that a resumed run
    /// repeats the uninterrupted one.
    fn checkpoint(&mut self, rec: &Recorder, pg: &mut Progress, t_start: Instant, periodic: bool) -> Result<PathBuf> {
        let counters = Counters {
            cuts: pg.c.cuts + self.ts.rejections()?,
            wall_s: self.wall_so_far(pg, t_start),
            fields_written: rec.fields_written(),
            outflow: self.observers.outflow(),
            pressure_peak: self.observers.pressure_peak.to_array(),
            ..pg.c.clone()
        };
        let state = self.state.capture(self.world, self.ts.problem_mut(), self.setup.layout, counters)?;
        // The solver's state between steps (the kept factorised Jacobian), per rank: a run
        // resumed on as many ranks continues exactly as this one. Where it cannot be saved the
        // solver starts afresh here, as a resumed run will.
        let solver = agree(self.world, self.ts.nonlinear_solver_state())?;
        let saved = crate::parallel::all(self.world, solver.is_some());
        let solver_written = match (&solver, saved) {
            (Some(s), true) => checkpoint::write_solver(&rec.dir, pg.c.step, self.world.rank(), self.world.size(), s),
            _ => Ok(()),
        };
        agree(self.world, solver_written)?;
        // The fields as of now, for a resume that finds fields.h5 damaged; before the state,
        // so that every checkpoint has a copy with at least its steps.
        rec.backup_fields(&checkpoint::fields_backup(&rec.dir))?;
        // Only at the checkpoints every N steps, which every run of the scene takes at the same
        // steps: restarting at wall-clock ones would make uninterrupted runs differ.
        if !saved && periodic {
            self.ts.restart_nonlinear_solver();
        }
        let path = crate::parallel::path_from_root(self.world, || state.write(&rec.dir))?;
        pg.checkpointed = Some(Instant::now());
        Ok(path)
    }

    /// Sets the run state of a checkpoint: the step state (U, its rate, the qp state), the
    /// experiment's outflow and t. Returns the counters.
    pub(super) fn restore(&mut self, state: RunState) -> Result<Counters> {
        let c = self.state.apply(self.ts.problem_mut(), state)?;
        self.observers.set_outflow(c.outflow);
        self.observers.pressure_peak = PressurePeak::from_array(c.pressure_peak);
        self.ts.set_time(c.t)?;
        Ok(c)
    }
}
