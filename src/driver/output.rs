//! The run directory's outputs and the run log: opening the directory (or reopening it to
//! resume), the rows and fields of the steps (observed by `observe::observers`, written by
//! `io::recorder`), the progress lines and `timings.txt`.

use super::progress::{Progress, Stages, Step};
use super::run::Run;
use crate::error::{Error, Result};
use crate::io::checkpoint::{self, Counters};
use crate::io::recorder::{Recorder, StepRow};
use crate::io::rundir;
use crate::observe::observers::Sample;
use crate::parallel::{agree, on_root};
use crate::petsc::options;
use crate::scene::explain::explain;
use mpi::traits::*;
use std::path::{Path, PathBuf};
use std::time::Instant;

impl<'w> Run<'w> {
    /// The run directory: --out, or runs/<scene>-<UTC time> chosen by rank 0's clock.
    pub(super) fn out_dir(&self) -> PathBuf {
        match &self.args.out {
            Some(o) => o.clone(),
            None => crate::parallel::broadcast_path(self.world, Some(&rundir::default_run_dir(&self.scene.scene.name))),
        }
    }

    /// Creates the run directory and its files (nothing is written before this point).
    pub(super) fn open_output(&mut self, dir: &Path) -> Result<Recorder> {
        agree(self.world, rundir::prepare(dir, self.args.force, self.rank0()))?;
        if self.lock.is_none() {
            self.lock = Some(agree(self.world, rundir::lock(dir, self.rank0()))?);
        }
        // Rank 0 writes; every rank learns whether it could (else the others would go on into
        // the collective creation of the fields file, and wait there).
        let options = options::dump()?;
        on_root(self.world, || {
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
            let scene = format!("# resolved from {}\n{}", self.scene.source, explain(&self.scene)?);
            rundir::write_text(dir, "scene.toml", &scene)?;
            rundir::write_text(dir, "petsc_options.txt", &(options + "\n"))?;
            self.write_record(dir)
        })?;
        let obs = &self.observers;
        Recorder::create(self.world, dir, self.ts.problem().mesh(), &obs.columns(), obs.fields)
    }

    /// Reopens the run directory of a run resumed from the checkpoint with counters `c`:
    /// history.csv and the fields continue after its step (later rows and steps, from after the
    /// checkpoint, are dropped).
    pub(super) fn reopen_output(&mut self, dir: &Path, c: &Counters) -> Result<Recorder> {
        // The options given to `resume` join the record, for the next resume.
        on_root(self.world, || self.write_record(dir))?;
        let obs = &self.observers;
        // Rows of steps 0..=step.
        let counts = (c.step + 1, c.fields_written);
        let backup = checkpoint::fields_backup(dir);
        let mesh = self.ts.problem().mesh();
        let (rec, warning) = Recorder::reopen(self.world, dir, mesh, (&obs.columns(), obs.fields), counts, &backup)?;
        if let Some(w) = warning {
            self.warn(&w);
        }
        Ok(rec)
    }

    /// The run log's opening lines (rank 0).
    pub(super) fn announce(&self, out: &Path) {
        let mesh = self.ts.problem().mesh();
        self.say(&format!(
            "poroplast: scene {} on {} rank(s): {} {}, {} nodes, {} dofs ({} u + {} p), output {}",
            self.scene.scene.name,
            self.world.size(),
            mesh.n_global_elems,
            mesh.family.cells_name(),
            mesh.n_global_nodes,
            self.setup.n_global_dofs,
            mesh.family.components() * mesh.n_global_nodes,
            mesh.n_global_vertices,
            out.display()
        ));
        if !self.scene.overrides.is_empty() {
            self.say(&format!("overrides: --set {}", self.scene.overrides.join(" --set ")));
        }
        let s = &self.scene.scene;
        self.say(&super::resolved::discretisation(s, mesh.family, mesh.n_global_elems));
        if let Some(m) = super::resolved::moduli(s) {
            self.say(&m);
        }
        if let Some(a) = super::resolved::accuracy_class(self) {
            self.say(&a);
        }
        self.say(&self.setup.solver_line);
        if let Some(w) = &self.setup.ellipticity {
            self.say(&format!("warning: {w}"));
        }
    }

    /// The row and fields of the initial state, sampled before the first step; observed after
    /// it (the experiment's outflow takes the drainage gaps of the last step solved).
    pub(super) fn write_initial(
        &mut self,
        rec: &mut Recorder,
        sample: Sample,
        t_start: Instant,
        stages: Stages,
    ) -> Result<()> {
        let _g = stages.output.push();
        let observed = self.observers.observe(self.world, self.ts.problem(), sample, 0.0, 0.0, true);
        let row = StepRow { step: 0, t: 0.0, dt: 0.0, its: (0, 0), wall: t_start.elapsed().as_secs_f64() };
        rec.record(self.world, &row, &observed)
    }

    /// The row of the step just taken, with fields every `fields_every` steps, at the
    /// `fields_at` times and at the end.
    pub(super) fn output_step(
        &mut self,
        rec: &mut Recorder,
        pg: &mut Progress,
        step: Step,
        t_start: Instant,
        stages: Stages,
    ) -> Result<()> {
        let o = Instant::now();
        {
            let _g = stages.output.push();
            let every = self.scene.scene.output.fields_every;
            let (n, t) = (pg.c.step, pg.c.t);
            let fields = self.schedule.done(t) || (every > 0 && n.is_multiple_of(every)) || self.output_time(t);
            let (u, prev) = (&self.state.u, &self.state.prev);
            let sample = self.observers.sample(self.ts.problem_mut(), u, prev, t, step.dt, fields)?;
            let observed = self.observers.observe(self.world, self.ts.problem(), sample, t, step.dt, fields);
            let wall = pg.c.wall_s + t_start.elapsed().as_secs_f64();
            let row = StepRow { step: n, t, dt: step.dt, its: step.its, wall };
            rec.record(self.world, &row, &observed)?;
        }
        pg.c.output_s += o.elapsed().as_secs_f64();
        Ok(())
    }

    /// t is one of the scene's `output.fields_at` times.
    fn output_time(&self, t: f64) -> bool {
        self.scene.scene.output.fields_at.iter().any(|&a| (t - a).abs() <= 1e-10 * self.schedule.t_end)
    }

    /// The progress line of a step (rank 0).
    pub(super) fn progress(&self, pg: &Progress, step: Step, t_start: Instant) {
        if self.args.log != super::run::Log::Steps {
            return;
        }
        let per_step = pg.recent.iter().sum::<f64>() / pg.recent.len().max(1) as f64;
        let eta = per_step * self.schedule.remaining(pg.c.t, pg.c.nominal) as f64;
        let (taken, its) = (step.dt, step.its);
        self.say(&format!(
            "step {:5}  t = {:.5e}  dt = {:.3e}  newton {:2}  ksp {:4} ({:5.1}/newton)  [{:.1} s, eta {}]",
            pg.c.step,
            pg.c.t,
            taken,
            its.0,
            its.1,
            its.1 as f64 / its.0.max(1) as f64,
            t_start.elapsed().as_secs_f64(),
            crate::io::fmt_duration(eta)
        ));
    }

    /// Wall time of the run so far (s): the set-up, the sessions before this one (a resume), and
    /// this one's loop since `t_start`.
    pub(super) fn wall_so_far(&self, pg: &Progress, t_start: Instant) -> f64 {
        pg.c.wall_s + t_start.elapsed().as_secs_f64() + self.setup.seconds
    }

    /// timings.txt, and the closing line of a completed run.
    pub(super) fn finish(&self, dir: &Path, pg: &Progress, t_start: Instant, completed: bool) -> Result<()> {
        let timers = self.ts.problem().timers;
        let cuts = pg.c.cuts + self.ts.rejections()?;
        let total = self.wall_so_far(pg, t_start);
        let assembly = timers.residual_s + timers.jacobian_s;
        let rss = crate::parallel::max(self.world, peak_rss_mib());
        let summary = format!(
            "# poroplast timings (seconds, rank 0; wall clock; after a resume the stage times are this session's,\n# the counts and the total the whole run's)\nranks = {}\ndofs = {}\nsteps = {}\nstep_cuts = {}\nerror_rejections = {}\nnewton_its = {}\nksp_its = {}\nsetup = {:.3}\nresidual_assembly = {:.3}\nresidual_evaluations = {}\njacobian_assembly = {:.3}\njacobian_evaluations = {}\nhistory_commit = {:.3}\nsolve_total = {:.3}\nlinear_solve_and_other = {:.3}\noutput = {:.3}\ntotal = {:.3}\nmax_rss_mib = {:.1}\n",
            self.world.size(),
            self.setup.n_global_dofs,
            pg.c.step,
            cuts,
            pg.c.rejected,
            pg.c.newton,
            pg.c.ksp,
            self.setup.seconds,
            timers.residual_s,
            timers.residual_n,
            timers.jacobian_s,
            timers.jacobian_n,
            timers.qp_commit_s,
            pg.c.solve_s,
            pg.c.solve_s - assembly,
            pg.c.output_s,
            total,
            rss
        );
        on_root(self.world, || rundir::write_text(dir, "timings.txt", &summary))?;
        if !completed {
            return Ok(());
        }
        self.say(&format!(
            "done: {} steps, {} Newton, {} Krylov iterations, {} step cuts, {} rejected by the error estimate, {:.1} s (setup {:.1}, assembly {:.1}, solve {:.1}, output {:.1})",
            pg.c.step,
            pg.c.newton,
            pg.c.ksp,
            cuts,
            pg.c.rejected,
            total,
            self.setup.seconds,
            assembly,
            pg.c.solve_s - assembly,
            pg.c.output_s
        ));
        Ok(())
    }
}

/// Peak resident memory of this process (MiB), from Linux's /proc/self/status (VmHWM); NaN
/// where that is not available.
fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines().find(|l| l.starts_with("VmHWM:")).and_then(|l| l.split_whitespace().nth(1)?.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kib| kib / 1024.0)
}
