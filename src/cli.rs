//! Command line:
//! - `poroplast run [SCENE] [--set KEY=VALUE ...] [--out DIR] [--force] [-q] [-- PETSC OPTIONS]`
//! - `poroplast resume DIR [-q] [-- PETSC OPTIONS]` (continue from the last checkpoint)
//! - `poroplast check SCENE [--set KEY=VALUE ...] [-- PETSC OPTIONS]`
//! - `poroplast sweep STUDY.toml [--ranks-per-case k] [--out DIR] [--cases-dir DIR] [-q] [-- PETSC OPTIONS]`
//! - `poroplast plot DIR [ARGS]` (scripts/plot_run.py), `poroplast columns SCENE [--set KEY=VALUE ...]`,
//!   `poroplast columns --table`
//! - `poroplast scenes [--keys]`, `poroplast show NAME`, `poroplast show --explain NAME|FILE [--set KEY=VALUE ...]`
//!
//! The `///` comments below are clap's help text, printed as written: brackets and angle
//! brackets there are for the terminal, not rustdoc links or HTML.
#![allow(rustdoc::broken_intra_doc_links, rustdoc::invalid_html_tags)]

use clap::{Parser, Subcommand};
use std::path::PathBuf;

/// Parallel finite-strain biphasic solver for multicellular aggregates compressed between
/// plates (PETSc + MPI). Run under `mpirun -n N`. Units: µm, kPa, s (forces in nN).
#[derive(Debug, Parser)]
#[command(name = "poroplast", version, about, long_about = None)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

#[derive(Debug, Subcommand)]
pub enum Command {
    /// Run a scene and write its results into a run directory.
    ///
    /// Writes DIR/history.csv (one row per step), DIR/fields.h5 + DIR/fields.xdmf (open the
    /// .xdmf in ParaView), DIR/scene.toml (the resolved scene), DIR/petsc_options.txt,
    /// DIR/timings.txt and, at the end, DIR/summary.toml (peak force, force at the end of the
    /// hold, contact opening, H/W, largest p; draw the run with `poroplast plot DIR`). PETSc
    /// options go after `--`, e.g.
    /// `mpirun -n 2 poroplast run cryer -- -ksp_monitor -log_view`.
    Run {
        /// A scene file (.toml) or the name of a shipped scene (see `poroplast scenes`).
        #[arg(default_value = "reference")]
        scene: String,
        /// Override a scene value, e.g. `--set material.mu=3 --set mesh.params.h=10` (a dotted
        /// key into the scene; `bc.0.group` for the first [[bc]]; repeatable, applied in order).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Run directory (default: runs/<scene>-<UTC timestamp>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Overwrite a non-empty run directory.
        #[arg(long)]
        force: bool,
        /// No per-step progress lines.
        #[arg(long, short)]
        quiet: bool,
        /// PETSc options, after `--`.
        #[arg(last = true, allow_hyphen_values = true)]
        petsc: Vec<String>,
    },
    /// Continue a run from the last checkpoint in its run directory.
    ///
    /// The run continues with the scene, overrides and PETSc options it was started with (PETSc
    /// options given here are added); history.csv and the fields continue after the
    /// checkpoint's step. Any rank count works.
    Resume {
        /// The run directory.
        dir: PathBuf,
        /// No per-step progress lines.
        #[arg(long, short)]
        quiet: bool,
        /// PETSc options, after `--`.
        #[arg(last = true, allow_hyphen_values = true)]
        petsc: Vec<String>,
    },
    /// Validate a scene as `run` would — set-up and first step, nothing written.
    Check {
        /// A scene file (.toml) or the name of a shipped scene.
        scene: String,
        /// Override a scene value (as for `run`).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// PETSc options, after `--` (checked as `run` checks them).
        #[arg(last = true, allow_hyphen_values = true)]
        petsc: Vec<String>,
    },
    /// Run the cases of a study (a base scene and a grid or list of overrides) under one mpirun.
    ///
    /// The MPI ranks form groups of k (--ranks-per-case); each group runs one case at a time,
    /// taking the next free case when it is done. Writes DIR/summary.csv (one row per case:
    /// overrides, status, wall time, dofs, steps, iterations, observables, error, directory)
    /// and DIR/cases/<case>-<key>/ (each case's run directory, named after what it runs). The
    /// same command with --out DIR continues an interrupted sweep: completed cases are skipped,
    /// interrupted ones resume from their checkpoints. See docs/reference-sweep.md for the
    /// STUDY.toml format.
    Sweep {
        /// The study file (.toml).
        study: PathBuf,
        /// MPI ranks per case (must divide the number of ranks).
        #[arg(long, short = 'k', default_value_t = 1)]
        ranks_per_case: usize,
        /// Sweep directory (default: runs/sweep-<study name>-<UTC timestamp>); give it to continue a sweep.
        #[arg(long)]
        out: Option<PathBuf>,
        /// Case store shared with other sweeps (default: DIR/cases): a case any of them completed
        /// (same scene, overrides and PETSc options) is not run again.
        #[arg(long, value_name = "DIR")]
        cases_dir: Option<PathBuf>,
        /// No progress lines.
        #[arg(long, short)]
        quiet: bool,
        /// PETSc options for every case, after `--` (after the study's own).
        #[arg(last = true, allow_hyphen_values = true)]
        petsc: Vec<String>,
    },
    /// Print a case as the sweeps know it and, with --cases-dir, whether a case store holds it.
    ///
    /// A case is what it runs: its scene (a shipped scene's name or the file's absolute path,
    /// and a hash of the file's text: an edited scene is another case), its overrides in order
    /// and its PETSc options. Prints TOML: the case's `key` (its run directory is
    /// `<case>-<key>`) and that signature, as its case.toml records it; with --cases-dir also its
    /// `status` in the store (ok, failed, unfinished or absent), its `dir` and a failed case's
    /// `error`. The overrides are checked against the scene as `sweep` checks them. No MPI.
    Case {
        /// A scene file (.toml) or the name of a shipped scene.
        scene: String,
        /// An override, as for `run` (in the order the case applies them: a study's `set`
        /// first, then the case's own).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// The case store to look in: a sweep's DIR/cases, or its --cases-dir.
        #[arg(long, value_name = "DIR")]
        cases_dir: Option<PathBuf>,
        /// The case's PETSc options, after `--` (a study's, then the sweep's command line's).
        #[arg(last = true, allow_hyphen_values = true)]
        petsc: Vec<String>,
    },
    /// Run a poroplast command on N MPI ranks under `mpirun`, stopped like one process.
    ///
    /// `poroplast mpirun -n 4 run my.toml` is `mpirun -n 4 poroplast run my.toml`, except that
    /// Ctrl-C (SIGINT), SIGTERM and SIGUSR1 reach the ranks as a stop: they write a checkpoint and
    /// the exit code is 75 (continue with `poroplast resume DIR`). Open MPI's `mpirun` itself exits 1
    /// on them and kills the ranks a second later. `mpirun` is `$POROPLAST_MPIRUN` if set.
    Mpirun {
        /// Number of ranks.
        #[arg(short = 'n', long = "np", value_name = "N", value_parser = clap::value_parser!(u32).range(1..))]
        np: u32,
        /// An option for `mpirun` itself (repeatable; one word each): `--mpirun-arg=--bind-to --mpirun-arg=core`.
        #[arg(long = "mpirun-arg", value_name = "WORD", allow_hyphen_values = true)]
        mpirun_args: Vec<String>,
        /// The poroplast command and its arguments: run, resume, sweep, check.
        #[arg(trailing_var_arg = true, allow_hyphen_values = true, required = true, value_name = "COMMAND")]
        command: Vec<String>,
    },
    /// Draw a run or sweep directory into PNGs beside it (runs `python3 scripts/plot_run.py`).
    ///
    /// The history (force in µN and mg, probe pressure, H/W against time, the protocol's phases
    /// shaded) and, where the run wrote fields, pictures of p, σ_VM and the porosity: on the
    /// meridian, or on slices of a 3-D run. No ParaView and no display needed. Arguments after
    /// DIR go to the script, e.g. `poroplast plot runs/x --times 5,35`; `poroplast plot --help`
    /// lists them. The script is found beside this build's sources, or at `$POROPLAST_SCRIPTS`.
    Plot {
        /// The run or sweep directory, then the script's own options.
        #[arg(trailing_var_arg = true, allow_hyphen_values = true, required = true, value_name = "DIR [ARGS]")]
        args: Vec<String>,
    },
    /// Print the columns of the history.csv a run of the scene writes, one per line.
    ///
    /// The scene is loaded and validated with its overrides, as `run` would (no mesh is built):
    /// scripts check the names of observables and fitted columns with it before running anything.
    /// With --table (no scene): every column a run can write, with its unit and meaning, as
    /// Markdown: the table of docs/reference-run-directory.md.
    Columns {
        /// A scene file (.toml) or the name of a shipped scene.
        #[arg(required_unless_present = "table")]
        scene: Option<String>,
        /// Print the reference table of every column instead.
        #[arg(long, conflicts_with_all = ["scene", "set"])]
        table: bool,
        /// Override a scene value (as for `run`).
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
    /// List the scenes shipped in the binary.
    Scenes {
        /// Print every scene key instead (unit, default, valid range, description) as Markdown:
        /// the text of docs/scene-reference.md.
        #[arg(long)]
        keys: bool,
    },
    /// Print a shipped scene's TOML (a starting point for your own).
    ///
    /// With --explain: the scene as a run resolves it (every default written out), each key with
    /// its meaning, unit, default and valid range as a comment above it.
    Show {
        /// Name of a shipped scene (with --explain, also a scene file).
        name: String,
        /// Print the resolved scene with each key explained.
        #[arg(long)]
        explain: bool,
        /// Override a scene value (with --explain; as for `run`).
        #[arg(long = "set", value_name = "KEY=VALUE", requires = "explain")]
        set: Vec<String>,
    },
}
