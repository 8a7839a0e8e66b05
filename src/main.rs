//! poroplast binary: CLI → MPI → PETSc → driver; any error becomes one message and a non-zero exit.

use clap::Parser;
use poroplast::cli::{Cli, Command};
use poroplast::console;
use poroplast::driver::{self, RunArgs};
use poroplast::scene::BUILTIN;
use poroplast::sweep::{self, SweepArgs};

fn main() {
    let cli = Cli::parse();
    // From here on a stop signal to a command on MPI ranks is a request, set-up included
    // (`driver::signals`): never the default action, which would kill a rank mid-way (and its
    // mpirun job with "exited on signal"). The launcher and the listings keep the defaults.
    let _stop = matches!(
        cli.command,
        Command::Run { .. } | Command::Resume { .. } | Command::Check { .. } | Command::Sweep { .. }
    )
    .then(|| match poroplast::driver::signals::StopRequest::install() {
        Ok(s) => s,
        Err(e) => {
            eprintln!("poroplast: error: {e}");
            std::process::exit(1);
        }
    });
    if let Command::Scenes { keys } = cli.command {
        if keys {
            console::print(&poroplast::scene::reference::reference());
            return;
        }
        for (name, text) in BUILTIN {
            let desc = text.lines().find_map(|l| l.strip_prefix("description = ")).unwrap_or("").trim_matches('"');
            console::line(&format!("{name:20} {desc}"));
        }
        return;
    }
    if let Command::Plot { args } = &cli.command {
        exit_with(poroplast::plot::plot(args));
    }
    if let Command::Columns { scene, table, set } = &cli.command {
        let Some(scene) = scene.as_ref().filter(|_| !*table) else {
            console::print(&poroplast::history_column_table());
            return;
        };
        // No MPI: loading a scene is serial.
        let names = poroplast::scene::LoadedScene::load(scene, set).and_then(|s| poroplast::history_column_names(&s));
        match names {
            Ok(names) => console::print(&names.iter().map(|n| format!("{n}\n")).collect::<String>()),
            Err(e) => {
                eprintln!("poroplast: error: {e}");
                std::process::exit(1);
            }
        }
        return;
    }
    if let Command::Case { scene, set, cases_dir, petsc } = &cli.command {
        // No MPI: a case's identity is its scene's text and its arguments.
        match sweep::find::describe(scene, set, petsc, cases_dir.as_deref()) {
            Ok(text) => console::print(&text),
            Err(e) => {
                eprintln!("poroplast: error: {e}");
                std::process::exit(1);
            }
        }
        return;
    }
    if let Command::Mpirun { np, mpirun_args, command } = &cli.command {
        // No MPI here: the ranks are mpirun's.
        exit_with(poroplast::launch::mpirun(*np, mpirun_args, command));
    }
    if let Command::Show { name, explain, set } = &cli.command {
        if *explain {
            // No MPI: loading a scene is serial.
            let loaded = poroplast::scene::LoadedScene::load(name, set);
            match loaded.and_then(|s| poroplast::scene::explain::explain(&s).map(|text| (s, text))) {
                Ok((s, text)) => {
                    for n in &s.notes {
                        eprintln!("poroplast: note: {}: {n}", s.source);
                    }
                    print!("# {} as resolved: every value a run uses\n{text}", s.source);
                }
                Err(e) => {
                    eprintln!("poroplast: error: {e}");
                    std::process::exit(1);
                }
            }
            return;
        }
        match BUILTIN.iter().find(|(n, _)| n == name) {
            Some((_, text)) => console::print(text),
            None => {
                eprintln!("poroplast: no shipped scene named \"{name}\" (see `poroplast scenes`; `show --explain` also reads files)");
                std::process::exit(2);
            }
        }
        return;
    }
    if let Some(kernel) = poroplast::petsc::blas::better_kernel() {
        // OpenBLAS chose its kernels when it was loaded: start again with the right ones.
        use std::os::unix::process::CommandExt;
        if let Ok(exe) = std::env::current_exe() {
            let err = std::process::Command::new(exe)
                .args(std::env::args_os().skip(1))
                .env("OPENBLAS_CORETYPE", kernel)
                .exec();
            eprintln!("poroplast: note: could not restart with OPENBLAS_CORETYPE={kernel} ({err}); continuing");
        }
    }
    // Past the re-exec: this process catches stop signals for good (see `launch`).
    poroplast::launch::mark_ready();
    singleton_defaults();
    let Some(universe) = mpi::initialize() else {
        eprintln!("poroplast: MPI could not be initialised");
        std::process::exit(1);
    };
    let world = universe.world();
    let rank0 = mpi::traits::Communicator::rank(&world) == 0;
    let result = match cli.command {
        Command::Run { scene, set, out, force, quiet, petsc } => {
            driver::run(&world, &RunArgs { scene, set, out, force, petsc, log: log_level(quiet) })
                .map(|dir| dir.display().to_string())
        }
        Command::Resume { dir, quiet, petsc } => {
            driver::resume(&world, &dir, &petsc, log_level(quiet)).map(|dir| dir.display().to_string())
        }
        Command::Check { scene, set, petsc } => driver::check(&world, &scene, &set, &petsc),
        Command::Sweep { study, ranks_per_case, out, cases_dir, quiet, petsc } => {
            let args = SweepArgs { study, ranks_per_case, out, cases_dir, petsc, progress: !quiet };
            sweep::sweep(&world, &args).map(|dir| format!("summary: {}", dir.join("summary.csv").display()))
        }
        // Answered above, before MPI.
        Command::Scenes { .. }
        | Command::Show { .. }
        | Command::Mpirun { .. }
        | Command::Plot { .. }
        | Command::Columns { .. }
        | Command::Case { .. } => return,
    };
    let code = match result {
        Ok(msg) => {
            if rank0 {
                console::line(&msg);
            }
            0
        }
        Err(e @ poroplast::error::Error::Stopped(_)) => {
            if rank0 {
                eprintln!("poroplast: {e}");
            }
            driver::EXIT_STOPPED
        }
        Err(e @ poroplast::error::Error::StoppedInSetup(_)) => {
            if rank0 {
                eprintln!("poroplast: {e}");
            }
            driver::EXIT_STOPPED_IN_SETUP
        }
        Err(e) => {
            if rank0 {
                eprintln!("poroplast: error: {e}");
            }
            1
        }
    };
    drop(world);
    drop(universe);
    std::process::exit(code);
}

/// Exits with the code of a command run in a child process, or 1 and the error.
fn exit_with(code: poroplast::error::Result<i32>) -> ! {
    match code {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            eprintln!("poroplast: error: {e}");
            std::process::exit(1);
        }
    }
}

/// `-q` drops the per-step progress lines only: the scene's notes, the set-up and the summary stay.
fn log_level(quiet: bool) -> driver::Log {
    if quiet {
        driver::Log::Quiet
    } else {
        driver::Log::Steps
    }
}

/// Started without a launcher (no rank in the environment), this process is an MPI singleton:
/// Open MPI then forks a daemon and probes the network transports, 0.2 s of a run's start, for a
/// job that only ever talks to itself. Unless the user chose otherwise: no daemon, the ob1 pml
/// with the `self` transport only. Isolated singletons share one session directory (job family
/// 0), which the first to finish removes: so no component may create files there later, and
/// the shared-memory file pointers of MPI-IO (`sharedfp sm`, opened with each HDF5 file) did
/// ("unable to open file for mmap", a failed fields.h5, seen once in CI with runs side by side).
fn singleton_defaults() {
    const LAUNCHED: [&str; 3] = ["OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"];
    if LAUNCHED.iter().any(|v| std::env::var_os(v).is_some()) {
        return;
    }
    for (key, value) in [
        ("OMPI_MCA_ess_singleton_isolated", "1"),
        ("OMPI_MCA_pml", "ob1"),
        ("OMPI_MCA_btl", "self"),
        ("OMPI_MCA_sharedfp", "^sm"),
    ] {
        if std::env::var_os(key).is_none() {
            std::env::set_var(key, value);
        }
    }
}
