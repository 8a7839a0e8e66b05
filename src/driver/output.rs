//! The run directory's outputs ([`Output`]): opening the directory (or reopening it to resume)
//! under its lock, and the rows and fields of the steps — observed by `observe::observers`,
//! written by `io::recorder` — at the times the scene's `[output]` asks for.

use super::record::RunRecord;
use super::voice::Voice;
use crate::error::{Error, Result};
use crate::io::checkpoint::{self, Counters};
use crate::io::recorder::{Observed, Recorder};
use crate::io::rundir;
use crate::observe::observers::{Observers, Sample};
use crate::observe::pressure_peak::PressurePeak;
use crate::parallel::{agree, on_root};
use crate::petsc::options;
use crate::physics::problem::PoroProblem;
use crate::scene::explain::explain;
use crate::scene::{LoadedScene, OutputSpec};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::Path;

/// The observers, when they write, and the run directory's lock.
pub(super) struct Output {
    /// Probes, experiment, exact columns: what the rows and fields record.
    observers: Observers,
    /// The scene's `[output]`.
    spec: OutputSpec,
    /// The run directory's lock, once it is opened.
    lock: Option<rundir::RunLock>,
}

impl Output {
    /// The outputs of `observers` as `spec` asks, under `lock` if the run directory was
    /// locked before the run was set up (a resume).
    pub(crate) fn new(observers: Observers, spec: OutputSpec, lock: Option<rundir::RunLock>) -> Output {
        Output { observers, spec, lock }
    }

    pub(crate) fn observers(&self) -> &Observers {
        &self.observers
    }

    /// Creates the run directory `dir` and its files (nothing is written before this point):
    /// the scene resolved, the PETSc options, the run record, and the history and fields of
    /// the problem's mesh.
    pub(crate) fn open(
        &mut self,
        world: &SimpleCommunicator,
        dir: &Path,
        force: bool,
        scene: &LoadedScene,
        record: &RunRecord,
        problem: &PoroProblem,
    ) -> Result<Recorder> {
        let rank0 = world.rank() == 0;
        agree(world, rundir::prepare(dir, force, rank0))?;
        if self.lock.is_none() {
            self.lock = Some(agree(world, rundir::lock(dir, rank0))?);
        }
        // Rank 0 writes; every rank learns whether it could (else the others would go on into
        // the collective creation of the fields file, and wait there).
        let options = options::dump()?;
        on_root(world, || {
            // An earlier run's checkpoints and status (--force) are not this run's.
            let old = dir.join(checkpoint::DIR);
            if old.is_dir() {
                std::fs::remove_dir_all(&old).map_err(|e| Error::io(&old, e))?;
            }
            let status = dir.join("status.txt");
            if status.exists() {
                std::fs::remove_file(&status).map_err(|e| Error::io(&status, e))?;
            }
            // Explained: each key's meaning, unit and range as a comment (the values are `to_toml`'s).
            let text = format!("# resolved from {}\n{}", scene.source, explain(scene)?);
            rundir::write_text(dir, "scene.toml", &text)?;
            rundir::write_text(dir, "petsc_options.txt", &(options + "\n"))?;
            record.write(dir)
        })?;
        let obs = &self.observers;
        Recorder::create(world, dir, problem.mesh(), &obs.columns(), obs.fields)
    }

    /// Reopens the run directory of a run resumed from the checkpoint with counters `c`:
    /// history.csv and the fields continue after its step (later rows and steps, from after the
    /// checkpoint, are dropped).
    pub(crate) fn reopen(
        &self,
        voice: &Voice,
        dir: &Path,
        c: &Counters,
        record: &RunRecord,
        problem: &PoroProblem,
    ) -> Result<Recorder> {
        let world = voice.world();
        // The options given to `resume` join the record, for the next resume.
        on_root(world, || record.write(dir))?;
        let obs = &self.observers;
        // Rows of steps 0..=step.
        let counts = (c.step + 1, c.fields_written);
        let backup = checkpoint::fields_backup(dir);
        let (rec, warning) =
            Recorder::reopen(world, dir, problem.mesh(), (&obs.columns(), obs.fields), counts, &backup)?;
        if let Some(w) = warning {
            voice.warn(&w);
        }
        Ok(rec)
    }

    /// The observed values (and fields, if `fields`) of `sample`, the problem's state at time t
    /// after a step of size dt (0: the initial state). Collective.
    pub(crate) fn observe(
        &mut self,
        world: &SimpleCommunicator,
        problem: &PoroProblem,
        sample: Sample,
        t: f64,
        dt: f64,
        fields: bool,
    ) -> Observed {
        self.observers.observe(world, problem, sample, t, dt, fields)
    }

    /// Whether the step `step` ending at t writes fields: every `fields_every` steps, at the
    /// `fields_at` times and at the end (`last`); `t_end` the run's end.
    pub(crate) fn writes_fields(&self, step: usize, t: f64, last: bool, t_end: f64) -> bool {
        let every = self.spec.fields_every;
        let listed = self.spec.fields_at.iter().any(|&a| (t - a).abs() <= 1e-10 * t_end);
        last || (every > 0 && step.is_multiple_of(every)) || listed
    }

    /// The counters of a checkpoint: `c`, with the observers' cumulative values.
    pub(crate) fn counters(&self, c: Counters) -> Counters {
        Counters { outflow: self.observers.outflow(), pressure_peak: self.observers.pressure_peak.to_array(), ..c }
    }

    /// Restores the observers' cumulative values from a checkpoint's counters.
    pub(crate) fn restore(&mut self, c: &Counters) {
        self.observers.set_outflow(c.outflow);
        self.observers.pressure_peak = PressurePeak::from_array(c.pressure_peak);
    }
}
