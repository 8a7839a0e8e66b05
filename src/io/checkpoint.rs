//! The checkpoint files of a run directory: their layout, writing and reading them, and the
//! checks that a file fits the run resuming from it. What goes in (the run state captured from
//! a run, and applied to one) is the driver's (`driver::state`).
//!
//! The state is stored by the mesh file's numbering (original node and element ids), not by
//! the partition's, so a run can resume on another rank count. Rank 0 writes and reads the
//! files (gathered with a reduction, scattered with a broadcast): a checkpoint is a few MB.
//!
//! Files: `DIR/checkpoints/step-NNNNNNNN.h5`, written to a `.tmp` name and renamed, the last two
//! kept (a damaged last one is passed over for the one before), with the ranks' solver states
//! `step-NNNNNNNN.solver.rRofN` and one copy of `fields.h5` as of the last checkpoint.
//! Datasets: `counters` (see [`Counters`]), `state` (4 values per original node: u, then p
//! or 0 at a mid-edge node), `velocity` (the same layout, absent after a kink), `history`
//! (the qp state: per original element, its points' values).

use crate::error::{Error, Result};
use crate::io::rundir::write_atomically;
use crate::mesh::dist::LocalMesh;
use crate::petsc::SolverState;
use hdf5_metno as hdf5;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::{Path, PathBuf};

/// Format of the checkpoint files (the first counter).
const FORMAT: f64 = 1.0;
/// Checkpoints kept in a run directory.
const KEEP: usize = 2;
/// Sub-directory of the run directory that holds them.
pub(crate) const DIR: &str = "checkpoints";

/// Where the time loop stands, and what has been counted and written so far.
#[derive(Debug, Clone, Default, PartialEq)]
pub(crate) struct Counters {
    pub(crate) step: usize,
    pub(crate) t: f64,
    /// The nominal size of the next step (the schedule's growth or error control).
    pub(crate) nominal: f64,
    pub(crate) newton: usize,
    pub(crate) ksp: usize,
    /// Steps rejected by the error estimate.
    pub(crate) rejected: usize,
    /// Steps cut by failed solves.
    pub(crate) cuts: usize,
    pub(crate) solve_s: f64,
    pub(crate) output_s: f64,
    /// Wall time of the run so far (setup included), over all its sessions.
    pub(crate) wall_s: f64,
    /// Steps written to the fields file.
    pub(crate) fields_written: usize,
    /// Time-integrated outflow of the experiment so far.
    pub(crate) outflow: f64,
    /// The largest nodal p so far, its time and place (`observe::pressure_peak`: p, t, x, y, z;
    /// p = −∞ in a checkpoint of an earlier version, which did not keep it).
    pub(crate) pressure_peak: [f64; 5],
}

impl Counters {
    fn to_vec(&self) -> Vec<f64> {
        vec![
            FORMAT,
            self.step as f64,
            self.t,
            self.nominal,
            self.newton as f64,
            self.ksp as f64,
            self.rejected as f64,
            self.cuts as f64,
            self.solve_s,
            self.output_s,
            self.wall_s,
            self.fields_written as f64,
            self.outflow,
            self.pressure_peak[0],
            self.pressure_peak[1],
            self.pressure_peak[2],
            self.pressure_peak[3],
            self.pressure_peak[4],
        ]
    }

    fn from_slice(v: &[f64]) -> Option<Counters> {
        // 13 counters in checkpoints of earlier versions, 18 with the pressure peak.
        if !(v.len() == 13 || v.len() == 18) || v[0] != FORMAT {
            return None;
        }
        let unknown = [f64::NEG_INFINITY, f64::NAN, f64::NAN, f64::NAN, f64::NAN];
        let n = |x: f64| x as usize;
        Some(Counters {
            step: n(v[1]),
            t: v[2],
            nominal: v[3],
            newton: n(v[4]),
            ksp: n(v[5]),
            rejected: n(v[6]),
            cuts: n(v[7]),
            solve_s: v[8],
            output_s: v[9],
            wall_s: v[10],
            fields_written: n(v[11]),
            outflow: v[12],
            pressure_peak: v.get(13..18).map_or(unknown, |p| [p[0], p[1], p[2], p[3], p[4]]),
        })
    }
}

/// The mesh file's node and element counts: the numbering of the run state.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FileLayout {
    pub(crate) n_nodes: usize,
    pub(crate) n_elems: usize,
}

/// The step state by original numbering (complete on rank 0 where a run captured it, on every
/// rank after [`RunState::read`]).
pub(crate) struct Snapshot {
    /// 4 values per original node: u_x, u_y, u_z, p (0 at mid-edge nodes).
    pub(crate) u: Vec<f64>,
    /// The last step's velocity in the same layout and its step size (None after a kink).
    pub(crate) velocity: Option<(Vec<f64>, f64)>,
    /// Per original element, its points' committed qp state (empty without; dataset `history`).
    pub(crate) qp_state: Vec<f64>,
    /// The tools' state between steps (dataset `tools`): 4 values (position, rate, protocol
    /// segment, held position) for the upper plate, then for each `[[tools]]` entry in order.
    /// Shorter in earlier checkpoints (none for plates before force control, none for the
    /// tools before theirs), whose missing entries were displacement-controlled: their protocols
    /// give them.
    pub(crate) tools: Vec<f64>,
}

/// Everything a restart needs, the content of a checkpoint file: the counters and a snapshot of
/// the step state.
pub(crate) struct RunState {
    pub(crate) counters: Counters,
    pub(crate) snapshot: Snapshot,
    /// [`mesh_fingerprint`] of the mesh it was written on.
    pub(crate) mesh: f64,
}

/// A fingerprint of the mesh by the file's numbering (collective): Σ (o + 1)(x + 2y + 3z) over
/// the nodes o. A mesh regenerated or edited since the checkpoint, with the same counts, moves
/// it.
pub(crate) fn mesh_fingerprint(world: &SimpleCommunicator, mesh: &LocalMesh) -> f64 {
    let local: f64 = (0..mesh.n_owned_nodes)
        .map(|n| {
            let x = mesh.coords[n];
            (mesh.node_original[n] as f64 + 1.0) * (x[0] + 2.0 * x[1] + 3.0 * x[2])
        })
        .sum();
    crate::parallel::sum(world, local)
}

impl RunState {
    /// Writes the checkpoint of step `counters.step` into `run_dir/checkpoints/` (rank 0; the
    /// result is agreed by the caller): to a temporary name, renamed, older ones beyond the last
    /// two removed. Returns its path.
    pub(crate) fn write(&self, run_dir: &Path) -> Result<PathBuf> {
        let dir = run_dir.join(DIR);
        let path = dir.join(format!("step-{:08}.h5", self.counters.step));
        write_atomically(&path, |tmp| {
            let h5 = |e: hdf5::Error| Error::io(tmp, format!("cannot write checkpoint: {e}"));
            let f = hdf5::File::create(tmp).map_err(h5)?;
            let put = |name: &str, v: &[f64]| -> hdf5::Result<()> {
                f.new_dataset::<f64>().shape([v.len()]).create(name)?.write_raw(v)
            };
            put("counters", &self.counters.to_vec()).map_err(h5)?;
            put("state", &self.snapshot.u).map_err(h5)?;
            if let Some((v, dt)) = &self.snapshot.velocity {
                put("velocity", v).map_err(h5)?;
                put("velocity_dt", &[*dt]).map_err(h5)?;
            }
            put("history", &self.snapshot.qp_state).map_err(h5)?;
            if !self.snapshot.tools.is_empty() {
                put("tools", &self.snapshot.tools).map_err(h5)?;
            }
            put("mesh_fingerprint", &[self.mesh]).map_err(h5)?;
            f.close().map_err(h5)
        })?;
        let mut all = list(run_dir)?;
        while all.len() > KEEP {
            let old = all.remove(0);
            std::fs::remove_file(&old).map_err(|e| Error::io(&old, e))?;
            // ... and its solver states (step-N.solver.*).
            let stem = old.file_stem().and_then(|s| s.to_str()).unwrap_or("").to_string();
            for e in std::fs::read_dir(&dir).map_err(|e| Error::io(&dir, e))?.flatten() {
                if e.file_name().to_str().is_some_and(|n| n.starts_with(&format!("{stem}.solver."))) {
                    let _ = std::fs::remove_file(e.path());
                }
            }
        }
        Ok(path)
    }

    /// Reads a checkpoint on rank 0 and broadcasts it (collective): `layout`, `per_elem` and
    /// `fingerprint` are this run's mesh, which the file must match. A file that
    /// cannot be read (cut short, damaged) is `Ok(Checkpoint::Damaged)`, so that the caller can
    /// take the one before; one that does not match this run is an error.
    pub(crate) fn read(
        world: &SimpleCommunicator,
        path: &Path,
        layout: FileLayout,
        per_elem: usize,
        fingerprint: f64,
    ) -> Result<Checkpoint> {
        let mut buf: Vec<Vec<f64>> = vec![vec![]; 7];
        let mut damaged = vec![0u8];
        let r = if world.rank() == 0 {
            let h5 = |e: hdf5::Error| Error::io(path, format!("cannot read checkpoint: {e}"));
            let read = (|| -> hdf5::Result<()> {
                let f = hdf5::File::open(path)?;
                for (i, name) in
                    ["counters", "state", "velocity", "velocity_dt", "history", "mesh_fingerprint", "tools"]
                        .iter()
                        .enumerate()
                {
                    if let Ok(ds) = f.dataset(name) {
                        buf[i] = ds.read_raw()?;
                    }
                }
                Ok(())
            })();
            match read {
                Err(e) => {
                    damaged[0] = 1;
                    Err(h5(e))
                }
                Ok(()) => Self::check(&buf, path, layout, per_elem, fingerprint),
            }
        } else {
            Ok(())
        };
        crate::parallel::broadcast_vec(world, 0, &mut damaged);
        match crate::parallel::agree(world, r) {
            Err(e) if damaged[0] == 1 => return Ok(Checkpoint::Damaged(e)),
            r => r?,
        }
        for b in buf.iter_mut() {
            crate::parallel::broadcast_vec(world, 0, b);
        }
        // Rank 0 checked the counters before the broadcast; this catches a broken broadcast.
        let counters = Counters::from_slice(&buf[0]).ok_or_else(|| {
            Error::io(path, "checkpoint: the counters received from rank 0 are not in a known format")
        })?;
        let velocity = if buf[2].is_empty() { None } else { Some((std::mem::take(&mut buf[2]), buf[3][0])) };
        let snapshot = Snapshot {
            u: std::mem::take(&mut buf[1]),
            velocity,
            qp_state: std::mem::take(&mut buf[4]),
            tools: std::mem::take(&mut buf[6]),
        };
        Ok(Checkpoint::Read(RunState { counters, snapshot, mesh: fingerprint }))
    }

    /// Rank 0: the datasets read from `path` fit this run's mesh and qp state.
    fn check(
        buf: &[Vec<f64>],
        path: &Path,
        FileLayout { n_nodes, n_elems }: FileLayout,
        per_elem: usize,
        fingerprint: f64,
    ) -> Result<()> {
        let bad = |what: &str| Err(Error::io(path, format!("checkpoint does not match this run: {what}")));
        if Counters::from_slice(&buf[0]).is_none() {
            return bad("unknown format");
        }
        if buf[1].len() != 4 * n_nodes {
            return bad(&format!("{} nodes, the mesh has {n_nodes}", buf[1].len() / 4));
        }
        if !buf[2].is_empty() && (buf[2].len() != 4 * n_nodes || buf[3].len() != 1) {
            return bad("velocity");
        }
        let fp = buf[5].first().copied().unwrap_or(f64::NAN);
        let same_mesh = (fp - fingerprint).abs() <= 1e-12 * fingerprint.abs().max(1.0);
        if !same_mesh {
            return bad("the mesh has changed since (same counts, other nodes)");
        }
        if buf[4].len() != n_elems * per_elem {
            return bad(&format!(
                "{} qp-state values, the run keeps {} ({n_elems} elements)",
                buf[4].len(),
                n_elems * per_elem
            ));
        }
        Ok(())
    }
}

/// What reading a checkpoint file gave.
pub(crate) enum Checkpoint {
    Read(RunState),
    /// The file could not be read (why): cut short or damaged.
    Damaged(Error),
}

/// The solver-state file of rank `rank` of `size` at `step`.
fn solver_file(run_dir: &Path, step: usize, rank: i32, size: i32) -> PathBuf {
    run_dir.join(DIR).join(format!("step-{step:08}.solver.r{rank}of{size}"))
}

/// Writes this rank's solver state for the checkpoint of `step` (before the checkpoint itself,
/// whose rename commits both).
pub(crate) fn write_solver(run_dir: &Path, step: usize, rank: i32, size: i32, s: &SolverState) -> Result<()> {
    let path = solver_file(run_dir, step, rank, size);
    write_atomically(&path, |tmp| std::fs::write(tmp, s.to_bytes()).map_err(|e| Error::io(tmp, e)))
}

/// This rank's solver state of the checkpoint of `step`, if one was saved for `size` ranks.
pub(crate) fn read_solver(run_dir: &Path, step: usize, rank: i32, size: i32) -> Result<Option<SolverState>> {
    let path = solver_file(run_dir, step, rank, size);
    match std::fs::read(&path) {
        Ok(b) => SolverState::from_bytes(&b)
            .map(Some)
            .ok_or_else(|| Error::io(&path, "not a solver state written by this version")),
        Err(_) => Ok(None),
    }
}

/// The copy of the fields file taken at the last checkpoint: what `resume` continues from if
/// `fields.h5` itself was damaged (a kill in the middle of writing it).
pub(crate) fn fields_backup(run_dir: &Path) -> PathBuf {
    run_dir.join(DIR).join(crate::io::fields::H5_NAME)
}

/// The checkpoints of a run directory, oldest first.
pub(crate) fn list(run_dir: &Path) -> Result<Vec<PathBuf>> {
    let dir = run_dir.join(DIR);
    if !dir.is_dir() {
        return Ok(vec![]);
    }
    let mut out: Vec<PathBuf> = std::fs::read_dir(&dir)
        .map_err(|e| Error::io(&dir, e))?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| {
            p.file_name()
                .and_then(|n| n.to_str())
                .is_some_and(|n| n.starts_with("step-") && n.ends_with(".h5") && !n.ends_with(".tmp"))
        })
        .collect();
    out.sort();
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counters_round_trip_and_reject_other_formats() {
        let c = Counters {
            step: 17,
            t: 3.25,
            nominal: 0.5,
            newton: 90,
            ksp: 1234,
            rejected: 2,
            cuts: 3,
            solve_s: 1.5,
            output_s: 0.25,
            wall_s: 2.0,
            fields_written: 5,
            outflow: 7.5e3,
            pressure_peak: [4.5, 2.0, 10.0, 0.0, 190.0],
        };
        assert_eq!(Counters::from_slice(&c.to_vec()), Some(c.clone()));
        // A checkpoint of an earlier version (13 counters, no pressure peak) still reads.
        let old = Counters::from_slice(&c.to_vec()[..13]).unwrap();
        assert_eq!((old.step, old.outflow, old.pressure_peak[0]), (17, 7.5e3, f64::NEG_INFINITY));
        let mut v = c.to_vec();
        v[0] = 2.0;
        assert_eq!(Counters::from_slice(&v), None);
        assert_eq!(Counters::from_slice(&v[..5]), None);
    }
}
