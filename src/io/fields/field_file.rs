//! The open pair `fields.h5` + `fields.xdmf` ([`FieldFile`]): created or reopened, a step written
//! at a time, closed; its backup, and the restore of a damaged file from it (see the folder's
//! documentation for the layout, the parallel I/O and the handling of failures).

use super::checks::{check_mesh, check_name, check_tiling, same_everywhere};
use super::h5::{self, h5err, Datasets};
use super::layout::{cell_type, Field, FieldKind, OutputMesh, StepRecord, H5_NAME, XDMF_NAME};
use super::xdmf::{self, Shape};

use crate::error::{Error, Result};
use crate::files::{copy_atomically, write_text_atomically};
use crate::hash::Fnv;
use crate::parallel::{agree, on_root};
use hdf5_metno as hdf5;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// An open `fields.h5` + `fields.xdmf` pair; see the module documentation.
pub struct FieldFile {
    // Field order matters for Drop: datasets are closed before the file, the communicator last.
    time_ds: hdf5::Dataset,
    /// `/step_mesh`: the mesh group of every step.
    step_mesh_ds: hdf5::Dataset,
    file: hdf5::File,
    comm: SimpleCommunicator,
    h5_path: PathBuf,
    xdmf_path: PathBuf,
    n_global_nodes: usize,
    node_offset: usize,
    n_local_nodes: usize,
    n_global_cells: usize,
    cell_offset: usize,
    n_local_cells: usize,
    /// XDMF topology type and nodes per cell.
    cell_type: (&'static str, usize),
    kinds: BTreeMap<String, FieldKind>,
    steps: Vec<StepRecord>,
    xdmf_grids: String,
    /// The mesh group this run's numbering is written in.
    mesh: i64,
}

impl FieldFile {
    /// Creates (truncating) `dir/fields.h5` and `dir/fields.xdmf` and writes the mesh. Collective
    /// over `comm`; `dir` must exist and be the same shared directory on every rank.
    pub fn create(dir: &Path, comm: &SimpleCommunicator, mesh: &OutputMesh) -> Result<Self> {
        let comm = comm.duplicate();
        let h5_path = dir.join(H5_NAME);
        let xdmf_path = dir.join(XDMF_NAME);

        // Local checks, then global ones: counts agree on every rank and the pieces add up.
        let local = check_mesh(mesh, dir).map_err(|m| Error::io(&h5_path, m));
        let sig = Fnv::new().u64(mesh.n_global_nodes as u64).u64(mesh.n_global_cells as u64).finish();
        let same = same_everywhere(&comm, &h5_path, sig, "global node and cell counts");
        agree(&comm, local.and(same))?;
        check_tiling(&comm, mesh, &h5_path)?;

        let (file, datasets) = h5::create(&comm, &h5_path)?;
        h5::write_mesh(&file, &comm, &h5_path, mesh, 0)?;
        FieldFile::assemble(file, comm, (h5_path, xdmf_path), datasets, mesh, (BTreeMap::new(), Vec::new()), 0)
    }

    /// Reopens the pair in `dir` written by [`create`](Self::create) to continue a run after
    /// its first `keep` steps (collective): later steps are removed, and the next step is
    /// number `keep`. If this run numbers the mesh differently (another rank count), its mesh
    /// is written as a new group `/mesh_g` that the following steps use.
    pub(crate) fn reopen(dir: &Path, comm: &SimpleCommunicator, mesh: &OutputMesh, keep: usize) -> Result<Self> {
        let comm = comm.duplicate();
        let h5_path = dir.join(H5_NAME);
        let xdmf_path = dir.join(XDMF_NAME);
        let local = check_mesh(mesh, dir).map_err(|m| Error::io(&h5_path, m));
        agree(&comm, local)?;
        let (file, datasets, written) = h5::open(&comm, &h5_path)?;
        let (times, meshes) = (&written.times, &written.meshes);
        if times.len() < keep || meshes.len() < keep {
            return Err(Error::io(&h5_path, format!("has {} steps, the checkpoint needs {keep}", times.len())));
        }
        let mut steps: Vec<StepRecord> =
            (0..keep).map(|k| StepRecord { time: times[k], fields: vec![], mesh: meshes[k] }).collect();
        let kinds = h5::keep_steps(&comm, (&file, &datasets, &h5_path), &written, mesh.n_global_nodes, &mut steps)?;
        let last = meshes[..keep].iter().copied().max().unwrap_or(0);
        let group = h5::mesh_group_for(&comm, (&file, &h5_path), mesh, last)?;
        FieldFile::assemble(file, comm, (h5_path, xdmf_path), datasets, mesh, (kinds, steps), group)
    }

    /// The open pair with its steps so far (kinds and records) and the mesh group of this
    /// numbering; the XDMF is written for those steps.
    fn assemble(
        file: hdf5::File,
        comm: SimpleCommunicator,
        (h5_path, xdmf_path): (PathBuf, PathBuf),
        datasets: Datasets,
        mesh: &OutputMesh,
        (kinds, steps): (BTreeMap<String, FieldKind>, Vec<StepRecord>),
        group: i64,
    ) -> Result<Self> {
        let mut ff = FieldFile {
            time_ds: datasets.time,
            step_mesh_ds: datasets.step_mesh,
            file,
            comm,
            h5_path,
            xdmf_path,
            n_global_nodes: mesh.n_global_nodes,
            node_offset: mesh.node_offset,
            n_local_nodes: mesh.coords.len(),
            n_global_cells: mesh.n_global_cells,
            cell_offset: mesh.cell_offset,
            n_local_cells: mesh.cells.len(),
            cell_type: cell_type(mesh.family),
            kinds,
            steps,
            xdmf_grids: String::new(),
            mesh: group,
        };
        ff.xdmf_grids = (0..ff.steps.len()).map(|k| ff.step_grid(k)).collect();
        ff.flush_and_index()?;
        Ok(ff)
    }

    /// Number of steps written so far.
    pub(crate) fn n_steps(&self) -> usize {
        self.steps.len()
    }

    /// Appends one time step with the given fields. Collective: every rank passes the same `time`
    /// and the same field names and kinds in the same order, each with its own values. `time` must
    /// exceed the previous step's; a field keeps its kind across steps but may be left out of some.
    /// The data are flushed and the XDMF rewritten before returning.
    pub fn write_step(&mut self, time: f64, fields: &[Field]) -> Result<()> {
        let k = self.steps.len();
        let path = self.h5_path.clone();

        // Local checks and the cross-rank signature of the call.
        let mut sig = Fnv::new();
        sig.u64(time.to_bits());
        for f in fields {
            sig.bytes(f.name.as_bytes()).u64(0xff).u64(f.kind.code());
        }
        let local = (|| -> std::result::Result<(), String> {
            if !time.is_finite() {
                return Err(format!("step {k}: time is {time}"));
            }
            if let Some(last) = self.steps.last() {
                if time <= last.time {
                    return Err(format!("step {k}: time {time} does not follow the previous step's {}", last.time));
                }
            }
            for (i, f) in fields.iter().enumerate() {
                check_name(f.name)?;
                if fields[..i].iter().any(|g| g.name == f.name) {
                    return Err(format!("field {:?} given twice", f.name));
                }
                if let Some(&old) = self.kinds.get(f.name) {
                    if old != f.kind {
                        return Err(format!("field {:?} was {old:?}, now {:?}", f.name, f.kind));
                    }
                }
                let rows = if f.kind.on_nodes() { self.n_local_nodes } else { self.n_local_cells };
                let want = rows * f.kind.components();
                if f.data.len() != want {
                    return Err(format!(
                        "field {:?} ({:?}) has {} values on this rank, expected {want}",
                        f.name,
                        f.kind,
                        f.data.len()
                    ));
                }
            }
            Ok(())
        })()
        .map_err(|m| Error::io(&path, m));
        let same =
            same_everywhere(&self.comm, &path, sig.finish(), &format!("step {k}: time or field names and kinds"));
        agree(&self.comm, local.and(same))?;

        // Collective metadata: extend /time, create this step's datasets.
        let created = (|| -> hdf5::Result<Vec<hdf5::Dataset>> {
            self.time_ds.resize(k + 1)?;
            self.step_mesh_ds.resize(k + 1)?;
            let mut out = Vec::with_capacity(fields.len());
            for f in fields {
                let group = match self.kinds.contains_key(f.name) {
                    true => self.file.group(&format!("fields/{}", f.name))?,
                    false => self.file.create_group(&format!("fields/{}", f.name))?,
                };
                let rows = if f.kind.on_nodes() { self.n_global_nodes } else { self.n_global_cells };
                let b = group.new_dataset::<f64>();
                let ds = match f.kind.components() {
                    1 => b.shape([rows]).create(format!("{k:06}").as_str())?,
                    c => b.shape([rows, c]).create(format!("{k:06}").as_str())?,
                };
                out.push(ds);
            }
            Ok(out)
        })()
        .map_err(|e| h5err(&path, &format!("step {k}: cannot create datasets"), e));
        let datasets = agree(&self.comm, created)?;
        for f in fields {
            self.kinds.insert(f.name.to_string(), f.kind);
        }

        // Independent raw data.
        let written = (|| -> hdf5::Result<()> {
            if self.comm.rank() == 0 {
                self.time_ds.write_slice(&[time][..], k..k + 1)?;
                self.step_mesh_ds.write_slice(&[self.mesh][..], k..k + 1)?;
            }
            for (f, ds) in fields.iter().zip(&datasets) {
                let (off, n) = if f.kind.on_nodes() {
                    (self.node_offset, self.n_local_nodes)
                } else {
                    (self.cell_offset, self.n_local_cells)
                };
                if n == 0 {
                    continue;
                }
                if f.kind.components() == 1 {
                    ds.write_slice(f.data, off..off + n)?;
                } else {
                    let (rows, _) = f.data.as_chunks::<3>();
                    ds.write_slice::<_, f64, _, _>(rows, (off..off + n, ..))?;
                }
            }
            Ok(())
        })()
        .map_err(|e| h5err(&path, &format!("step {k}: cannot write data"), e));
        agree(&self.comm, written)?;
        drop(datasets);

        self.steps.push(StepRecord {
            time,
            fields: fields.iter().map(|f| (f.name.to_string(), f.kind)).collect(),
            mesh: self.mesh,
        });
        let grid = self.step_grid(k);
        self.xdmf_grids.push_str(&grid);
        self.flush_and_index()
    }

    /// Copies the file as it stands after its last step (flushed) to `to` (collective: rank 0
    /// copies it to a temporary name and renames it over `to`).
    pub(crate) fn backup(&self, to: &Path) -> Result<()> {
        on_root(&self.comm, || copy_atomically(&self.h5_path, to)).map(|_| ())
    }

    /// Flushes and closes the file (collective), reporting errors that `Drop` would swallow.
    pub fn close(self) -> Result<()> {
        let FieldFile { time_ds, step_mesh_ds, file, comm, h5_path, .. } = self;
        drop(time_ds);
        drop(step_mesh_ds);
        let r = file.close().map_err(|e| h5err(&h5_path, "cannot close", e));
        agree(&comm, r)
    }

    /// Collective flush of the HDF5 file, then rank 0 rewrites the XDMF atomically.
    fn flush_and_index(&mut self) -> Result<()> {
        let r = self.file.flush().map_err(|e| h5err(&self.h5_path, "cannot flush", e));
        agree(&self.comm, r)?;
        on_root(&self.comm, || self.write_xdmf()).map(|_| ())
    }

    /// The mesh the XDMF grids point at.
    fn shape(&self) -> Shape {
        Shape { n_nodes: self.n_global_nodes, n_cells: self.n_global_cells, cell_type: self.cell_type }
    }

    fn step_grid(&self, k: usize) -> String {
        xdmf::step_grid(&self.shape(), k, &self.steps[k])
    }

    fn write_xdmf(&self) -> Result<()> {
        let text = xdmf::xdmf_text(&self.shape(), self.steps.len(), &self.xdmf_grids, self.mesh);
        write_text_atomically(&self.xdmf_path, &text)
    }
}

/// Puts the copy `backup` (of [`FieldFile::backup`]) in place of the `fields.h5` of `dir`, which is
/// kept as `fields.damaged.h5` (or `fields.damaged-N.h5`); returns that name. Rank 0 only.
pub(crate) fn restore_backup(dir: &Path, backup: &Path) -> Result<PathBuf> {
    let h5 = dir.join(H5_NAME);
    let kept = (1..)
        .map(|n| dir.join(if n == 1 { "fields.damaged.h5".to_string() } else { format!("fields.damaged-{n}.h5") }))
        .take(1000)
        .find(|p| !p.exists())
        .ok_or_else(|| Error::io(dir, "1000 damaged fields files kept already: remove some"))?;
    if h5.exists() {
        std::fs::rename(&h5, &kept).map_err(|e| Error::io(&kept, e))?;
    }
    copy_atomically(backup, &h5)?;
    Ok(kept)
}
