//! Field output for ParaView: one HDF5 file (`fields.h5`) and one XDMF index (`fields.xdmf`) per run,
//! written collectively by all ranks of a communicator.
//!
//! # Layout of `fields.h5`
//! * `/mesh/coordinates`: `f64`, N×3, global node coordinates (row = global node id).
//! * `/mesh/topology`: `i64`, M×10, global node ids of each quadratic tetrahedron **in VTK/XDMF order**
//!   (see below), row = global cell id; M×6 for the 6-node triangles of a meridian (axisymmetric)
//!   mesh, whose GMSH `Triangle6` order is VTK's `VTK_QUADRATIC_TRIANGLE` order (XDMF `Triangle_6`).
//!   A meridian lies in the x–z plane, and its vector fields are written with a zero y component.
//! * `/time`: `f64`, 1-D, extendible; `time[k]` is the time of step `k`.
//! * `/step_mesh`: `i64`, 1-D, extendible: the mesh group step `k` uses, 0 for `/mesh`, g for
//!   `/mesh_g` — a run resumed on another rank count numbers the nodes differently and writes
//!   its mesh again ([`FieldFile::reopen`]).
//! * `/fields/<name>/<k as 6 digits>`: `f64`; N (node scalar), N×3 (node vector), M (cell scalar) or
//!   M×3 (cell vector) values of field `<name>` at step `k`. A field may be absent from some steps.
//!
//! # Node order of the 10-node tetrahedron
//! The mesh comes in GMSH `Tetrahedron10` order: vertices 0–3, then mid-edge nodes on edges
//! (0,1),(1,2),(0,2),(0,3),(2,3),(1,3). XDMF's `Tetrahedron_10` is handed by ParaView's XDMF readers
//! unchanged to VTK's `VTK_QUADRATIC_TETRA` (cell type 24), whose order is vertices, then edges
//! (0,1),(1,2),(0,2),(0,3),(1,3),(2,3). So the last two mid-edge nodes are swapped when writing
//! ([`GMSH_TO_XDMF_TET10`]); `/mesh/topology` is stored in the XDMF/VTK order.
//!
//! The topology name is `Tetrahedron_10`: ParaView 5.11's `Xdmf3ReaderS`/`Xdmf3ReaderT` (XDMF 3) reject
//! `Tet_10` ("Invalid Type selected in XdmfTopologyType::New"), and its legacy `XDMFReader`
//! (XDMF 2) accepts both. Both were checked to produce VTK cell type 24 with the connectivity as written.
//!
//! # The XDMF file
//! A `Temporal` collection with one `Uniform` grid per step. Every grid points at the same
//! `/mesh/coordinates` and `/mesh/topology` datasets (the mesh is stored once) and at that step's
//! `/fields/...` datasets. Before the first step the XDMF holds a single `Uniform` grid with the
//! bare mesh. Rank 0 rewrites it after every step, to a temporary `fields.xdmf.<pid>-<n>.tmp`
//! then renamed over `fields.xdmf`, and only after the step's data were flushed, so a run that is
//! still going or has crashed can be opened and shows every completed step.
//!
//! # Parallel I/O and failures
//! The file is opened once with HDF5's MPI-IO driver and stays open. Metadata operations
//! (creating the file, groups and datasets, extending `/time`, flushing, closing) are collective, as
//! parallel HDF5 requires: every rank makes the same calls with the same arguments. Raw data is
//! written with hyperslab selections by each rank for the rows it owns, using **independent**
//! transfers: hdf5-metno 0.9 always passes `H5P_DEFAULT` as the transfer property list and has no
//! way to request `H5FD_MPIO_COLLECTIVE` (that would need raw `hdf5-sys` calls). A rank that owns
//! no rows simply makes no data call, so zero-size pieces are fine.
//!
//! Error handling: arguments are checked locally and compared across ranks (counts, time, field
//! names and kinds, via a hash) *before* any collective HDF5 call, and after each phase every rank's
//! outcome is combined collectively (same semantics as `crate::parallel::agree`): if any rank
//! failed, every rank returns `Err` (the failing rank its own error, the others
//! `Error::Elsewhere` with the lowest failing rank's message) and no rank goes on to the next
//! collective call, so nobody is left waiting. What this cannot cover is a failure *inside* one of
//! HDF5's own collective calls on only some ranks; there we rely on HDF5's collective semantics (it
//! normally fails on all ranks alike). After an error, drop the `FieldFile` on all ranks; steps
//! completed before remain readable (a failed `write_step` is not listed in the XDMF).
//!
//! Drop (or [`FieldFile::close`]) the `FieldFile` on all ranks, before MPI is finalized (that is,
//! before the `mpi::environment::Universe` is dropped).
//!
//! # Where things are
//! This module holds the [`FieldFile`] API (create, reopen, write a step, close) and the backup
//! and restore of the file; `layout` the names, types and node order of what is written; `h5`
//! the HDF5 calls of the file, its datasets and mesh groups; `xdmf` the index's text (pure);
//! `checks` the checks of a collective call's arguments.

mod checks;
mod h5;
mod layout;
mod xdmf;

pub use layout::{
    Field, FieldKind, OutputMesh, GMSH_TO_XDMF_TET10, H5_NAME, XDMF_NAME, XDMF_TOPOLOGY_TYPE, XDMF_TOPOLOGY_TYPE_TRI6,
};

use checks::{check_mesh, check_name, check_tiling, same_everywhere};
use h5::{h5err, Datasets};
use layout::{cell_type, StepRecord};
use xdmf::Shape;

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
    pub fn reopen(dir: &Path, comm: &SimpleCommunicator, mesh: &OutputMesh, keep: usize) -> Result<Self> {
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
    pub fn n_steps(&self) -> usize {
        self.steps.len()
    }

    /// Path of the HDF5 file.
    pub fn h5_path(&self) -> &Path {
        &self.h5_path
    }

    /// Path of the XDMF file.
    pub fn xdmf_path(&self) -> &Path {
        &self.xdmf_path
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
    pub fn backup(&self, to: &Path) -> Result<()> {
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

/// kept as `fields.damaged.h5` (or `fields.damaged-N.h5`); returns that name. Rank 0 only.
pub fn restore_backup(dir: &Path, backup: &Path) -> Result<PathBuf> {
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
