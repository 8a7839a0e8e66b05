//! Where the time loop stands ([`Progress`]: the counters a checkpoint keeps, the ETA's recent
//! step times), a step taken ([`Step`]) and the PETSc log stages of the loop ([`Stages`]).

use crate::error::Result;
use crate::io::checkpoint::Counters;
use crate::petsc::Stage;
use std::collections::VecDeque;
use std::time::Instant;

/// The PETSc log stages of the loop.
#[derive(Clone, Copy)]
pub(super) struct Stages {
    pub(crate) solve: Stage,
    pub(crate) output: Stage,
}

impl Stages {
    pub(crate) fn register() -> Result<Stages> {
        Ok(Stages { solve: Stage::register("Solve")?, output: Stage::register("Output")? })
    }
}

/// A step taken: its size and its Newton and Krylov iterations.
#[derive(Clone, Copy)]
pub(super) struct Step {
    pub(crate) dt: f64,
    pub(crate) its: (usize, usize),
}

/// Where the time loop stands.
pub(super) struct Progress {
    /// The counters a checkpoint keeps. Of them `cuts` and `wall_s` count the sessions before
    /// this one (a resume), `solve_s` and `output_s` this session (timings.txt gives this
    /// session's stage times, with the whole run's counts and total), and `fields_written` and
    /// `outflow` are not kept here (the recorder and the experiment keep them).
    pub(crate) c: Counters,
    /// The solver's iteration totals after the last step (this process), to count a step's.
    pub(crate) totals: (usize, usize),
    /// Wall time of the last checkpoint (this process).
    pub(crate) checkpointed: Option<Instant>,
    /// Wall times of the last steps, for the ETA.
    pub(crate) recent: VecDeque<f64>,
}

impl Progress {
    /// At t = 0, with a first step of nominal size `dt0`.
    pub(crate) fn start(dt0: f64) -> Progress {
        Progress::resumed(&Counters { nominal: dt0, ..Default::default() })
    }

    /// The loop's position after a resume from `c` (stage times count again).
    pub(crate) fn resumed(c: &Counters) -> Progress {
        let c = Counters { solve_s: 0.0, output_s: 0.0, ..c.clone() };
        Progress { c, totals: (0, 0), checkpointed: None, recent: VecDeque::new() }
    }
}
