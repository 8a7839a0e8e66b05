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
//! bare mesh. Rank 0 rewrites it after every step, to `fields.xdmf.<pid>.tmp` then renamed over
//! `fields.xdmf`, and only after the step's data were flushed, so a run that is still going or has
//! crashed can be opened and shows every completed step.
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

use std::collections::BTreeMap;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use hdf5_metno as hdf5;

use crate::reference_cell::Family;
use mpi::collective::SystemOperation;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

use crate::error::{Error, Result};
use crate::io::fmt_real;
use crate::io::rundir::write_atomically;
use crate::parallel::{agree, on_root};

/// Name of the HDF5 file inside the run directory.
pub const H5_NAME: &str = "fields.h5";
/// Name of the XDMF file inside the run directory.
pub const XDMF_NAME: &str = "fields.xdmf";
/// XDMF topology type written for 10-node tetrahedra (accepted by ParaView's XDMF 2 and XDMF 3 readers).
pub const XDMF_TOPOLOGY_TYPE: &str = "Tetrahedron_10";
/// XDMF topology type written for the 6-node triangles of a meridian mesh.
pub const XDMF_TOPOLOGY_TYPE_TRI6: &str = "Triangle_6";

/// The XDMF topology type and nodes per cell of a family.
fn cell_type(family: Family) -> (&'static str, usize) {
    match family {
        Family::Tet10 => (XDMF_TOPOLOGY_TYPE, 10),
        Family::Tri6 => (XDMF_TOPOLOGY_TYPE_TRI6, 6),
    }
}
/// `xdmf[i] = gmsh[GMSH_TO_XDMF_TET10[i]]`: GMSH `Tetrahedron10` order to XDMF/VTK quadratic-tet
/// order (the mid-nodes of edges (2,3) and (1,3) swap places). The permutation is its own inverse.
pub const GMSH_TO_XDMF_TET10: [usize; 10] = [0, 1, 2, 3, 4, 5, 6, 7, 9, 8];

/// The part of the mesh this rank writes.
pub struct OutputMesh<'a> {
    /// Number of nodes over all ranks.
    pub n_global_nodes: usize,
    /// This rank owns global nodes `[node_offset, node_offset + coords.len())`.
    pub node_offset: usize,
    /// Coordinates of the owned nodes only.
    pub coords: &'a [[f64; 3]],
    /// Number of cells over all ranks.
    pub n_global_cells: usize,
    /// This rank writes cells `[cell_offset, cell_offset + cells.len())`.
    pub cell_offset: usize,
    /// Global node ids of each cell, GMSH `Tetrahedron10` order: 4 vertices, then mid-edge nodes on
    /// edges (0,1),(1,2),(0,2),(0,3),(2,3),(1,3); or GMSH `Triangle6` order in the first 6 slots.
    pub cells: &'a [[u32; 10]],
    /// The cell family.
    pub family: Family,
}

/// Where a field lives and how many components it has.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FieldKind {
    /// One value per node.
    NodeScalar,
    /// Three values per node, interleaved `x y z`.
    NodeVector,
    /// One value per cell.
    CellScalar,
    /// Three values per cell, interleaved `x y z`.
    CellVector,
}

impl FieldKind {
    fn on_nodes(self) -> bool {
        matches!(self, FieldKind::NodeScalar | FieldKind::NodeVector)
    }
    fn components(self) -> usize {
        match self {
            FieldKind::NodeScalar | FieldKind::CellScalar => 1,
            FieldKind::NodeVector | FieldKind::CellVector => 3,
        }
    }
    fn code(self) -> u64 {
        match self {
            FieldKind::NodeScalar => 1,
            FieldKind::NodeVector => 2,
            FieldKind::CellScalar => 3,
            FieldKind::CellVector => 4,
        }
    }
}

/// One field of one step: this rank's values, for its owned nodes (`coords.len()` values, ×3 for
/// vectors, interleaved `x y z`) or its cells (`cells.len()` values, ×3 for vectors).
pub struct Field<'a> {
    /// Name in the file and in ParaView; ASCII letters, digits, `_`, `-`, `.`; not starting with `.`.
    pub name: &'a str,
    /// Node or cell, scalar or vector.
    pub kind: FieldKind,
    /// This rank's values.
    pub data: &'a [f64],
}

struct StepRecord {
    time: f64,
    fields: Vec<(String, FieldKind)>,
    /// The mesh group its grid uses (0: `/mesh`, g: `/mesh_g`; see [`FieldFile::reopen`]).
    mesh: i64,
}

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

fn h5err(path: &Path, what: &str, e: hdf5::Error) -> Error {
    Error::io(path, format!("{what}: {e}"))
}

/// Collective: `Err` on every rank unless `sig` is the same on all ranks.
fn same_everywhere(comm: &SimpleCommunicator, path: &Path, sig: u64, what: &str) -> Result<()> {
    let send = [sig, !sig];
    let mut recv = [0u64; 2];
    comm.all_reduce_into(&send[..], &mut recv[..], SystemOperation::max());
    if recv[0] != sig || !recv[1] != sig {
        return Err(Error::io(path, format!("{what}: ranks passed different arguments to this collective call")));
    }
    Ok(())
}

/// FNV-1a, for cheap cross-rank comparison of arguments.
struct Fnv(u64);
impl Fnv {
    fn new() -> Self {
        Fnv(0xcbf2_9ce4_8422_2325)
    }
    fn bytes(&mut self, b: &[u8]) -> &mut Self {
        for &x in b {
            self.0 ^= u64::from(x);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
        self
    }
    fn u64(&mut self, v: u64) -> &mut Self {
        self.bytes(&v.to_le_bytes())
    }
}

fn check_name(name: &str) -> std::result::Result<(), String> {
    let ok = !name.is_empty()
        && !name.starts_with('.')
        && name.bytes().all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.'));
    if ok {
        Ok(())
    } else {
        Err(format!("invalid field name {name:?} (use ASCII letters, digits, '_', '-', '.')"))
    }
}

fn xml_escape(s: &str) -> String {
    let mut o = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => o.push_str("&amp;"),
            '<' => o.push_str("&lt;"),
            '>' => o.push_str("&gt;"),
            '"' => o.push_str("&quot;"),
            '\'' => o.push_str("&apos;"),
            _ => o.push(c),
        }
    }
    o
}

fn check_mesh(mesh: &OutputMesh, dir: &Path) -> std::result::Result<(), String> {
    if mesh.n_global_nodes == 0 || mesh.n_global_cells == 0 {
        return Err(format!("empty mesh ({} nodes, {} cells)", mesh.n_global_nodes, mesh.n_global_cells));
    }
    if mesh.node_offset + mesh.coords.len() > mesh.n_global_nodes {
        return Err(format!(
            "owned nodes [{}, {}) exceed the {} global nodes",
            mesh.node_offset,
            mesh.node_offset + mesh.coords.len(),
            mesh.n_global_nodes
        ));
    }
    if mesh.cell_offset + mesh.cells.len() > mesh.n_global_cells {
        return Err(format!(
            "cells [{}, {}) exceed the {} global cells",
            mesh.cell_offset,
            mesh.cell_offset + mesh.cells.len(),
            mesh.n_global_cells
        ));
    }
    for (i, c) in mesh.cells.iter().enumerate() {
        if let Some(&id) = c.iter().find(|&&id| id as usize >= mesh.n_global_nodes) {
            return Err(format!("cell {} refers to node {id} of {}", mesh.cell_offset + i, mesh.n_global_nodes));
        }
    }
    if !dir.is_dir() {
        return Err("directory does not exist".into());
    }
    Ok(())
}

/// The extendible per-step datasets: `/time` and `/step_mesh`.
struct Datasets {
    time: hdf5::Dataset,
    step_mesh: hdf5::Dataset,
}

/// Name of mesh group g.
fn mesh_group(g: i64) -> String {
    if g == 0 {
        "mesh".into()
    } else {
        format!("mesh_{g}")
    }
}

/// Writes the mesh as group `g` (collective: the datasets; independent: each rank's rows).
fn write_mesh(file: &hdf5::File, comm: &SimpleCommunicator, path: &Path, mesh: &OutputMesh, g: i64) -> Result<()> {
    let made = (|| -> hdf5::Result<(hdf5::Dataset, hdf5::Dataset)> {
        let grp = file.create_group(&mesh_group(g))?;
        let xyz = grp.new_dataset::<f64>().shape([mesh.n_global_nodes, 3]).create("coordinates")?;
        let topo =
            grp.new_dataset::<i64>().shape([mesh.n_global_cells, cell_type(mesh.family).1]).create("topology")?;
        Ok((xyz, topo))
    })()
    .map_err(|e| h5err(path, "cannot create mesh datasets", e));
    let (xyz_ds, topo_ds) = agree(comm, made)?;
    let written = (|| -> hdf5::Result<()> {
        if !mesh.coords.is_empty() {
            let r = mesh.node_offset..mesh.node_offset + mesh.coords.len();
            xyz_ds.write_slice::<_, f64, _, _>(mesh.coords, (r, ..))?;
        }
        if !mesh.cells.is_empty() {
            let r = mesh.cell_offset..mesh.cell_offset + mesh.cells.len();
            match mesh.family {
                Family::Tet10 => {
                    let topo: Vec<[i64; 10]> = mesh
                        .cells
                        .iter()
                        .map(|c| std::array::from_fn(|i| i64::from(c[GMSH_TO_XDMF_TET10[i]])))
                        .collect();
                    topo_ds.write_slice::<_, i64, _, _>(topo.as_slice(), (r, ..))?;
                }
                Family::Tri6 => {
                    let topo: Vec<[i64; 6]> =
                        mesh.cells.iter().map(|c| std::array::from_fn(|i| i64::from(c[i]))).collect();
                    topo_ds.write_slice::<_, i64, _, _>(topo.as_slice(), (r, ..))?;
                }
            }
        }
        Ok(())
    })()
    .map_err(|e| h5err(path, "cannot write mesh", e));
    agree(comm, written)
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
        let sig = Fnv::new().u64(mesh.n_global_nodes as u64).u64(mesh.n_global_cells as u64).0;
        let same = same_everywhere(&comm, &h5_path, sig, "global node and cell counts");
        agree(&comm, local.and(same))?;
        // The pieces must tile [0, N) and [0, M) exactly (same verdict on every rank).
        let mine =
            [mesh.node_offset as u64, mesh.coords.len() as u64, mesh.cell_offset as u64, mesh.cells.len() as u64];
        let mut all = vec![0u64; 4 * comm.size() as usize];
        comm.all_gather_into(&mine[..], &mut all[..]);
        let pieces: Vec<&[u64]> = all.chunks(4).collect();
        for (what, col, total) in [("nodes", 0, mesh.n_global_nodes), ("cells", 2, mesh.n_global_cells)] {
            let mut ranges: Vec<(u64, u64)> =
                pieces.iter().filter(|p| p[col + 1] > 0).map(|p| (p[col], p[col] + p[col + 1])).collect();
            ranges.sort_unstable();
            let mut next = 0;
            for &(lo, hi) in &ranges {
                if lo != next {
                    return Err(Error::io(
                        &h5_path,
                        format!("the ranks' {what} do not tile [0, {total}): gap or overlap at {}", lo.min(next)),
                    ));
                }
                next = hi;
            }
            if next != total as u64 {
                return Err(Error::io(&h5_path, format!("the ranks own {next} {what}, the mesh declares {total}")));
            }
        }

        // Collective: open the file with the MPI-IO driver.
        let file = hdf5::File::with_options()
            .with_fapl(|p| p.mpio(comm.as_raw(), None))
            .create(&h5_path)
            .map_err(|e| h5err(&h5_path, "cannot create HDF5 file", e));
        let file = agree(&comm, file)?;

        // Collective: groups and datasets.
        let made = (|| -> hdf5::Result<(hdf5::Dataset, hdf5::Dataset)> {
            file.create_group("fields")?;
            let time = file.new_dataset::<f64>().chunk(256).shape((0..,)).create("time")?;
            let step_mesh = file.new_dataset::<i64>().chunk(256).shape((0..,)).create("step_mesh")?;
            Ok((time, step_mesh))
        })()
        .map_err(|e| h5err(&h5_path, "cannot create datasets", e));
        let (time_ds, step_mesh_ds) = agree(&comm, made)?;
        write_mesh(&file, &comm, &h5_path, mesh, 0)?;

        let datasets = Datasets { time: time_ds, step_mesh: step_mesh_ds };
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
        let file = hdf5::File::with_options()
            .with_fapl(|p| p.mpio(comm.as_raw(), None))
            .open_rw(&h5_path)
            .map_err(|e| h5err(&h5_path, "cannot open HDF5 file", e));
        let file = agree(&comm, file)?;
        // Collective metadata: the steps kept, and the mesh groups.
        type Written = (hdf5::Dataset, hdf5::Dataset, Vec<f64>, Vec<i64>, Vec<String>);
        let read = (|| -> hdf5::Result<Written> {
            let time_ds = file.dataset("time")?;
            let step_mesh_ds = file.dataset("step_mesh")?;
            let times: Vec<f64> = time_ds.read_raw()?;
            let meshes: Vec<i64> = step_mesh_ds.read_raw()?;
            Ok((time_ds, step_mesh_ds, times, meshes, file.group("fields")?.member_names()?))
        })()
        .map_err(|e| h5err(&h5_path, "cannot read the steps written", e));
        let (time_ds, step_mesh_ds, times, meshes, names) = agree(&comm, read)?;
        if times.len() < keep || meshes.len() < keep {
            return Err(Error::io(&h5_path, format!("has {} steps, the checkpoint needs {keep}", times.len())));
        }
        let mut steps: Vec<StepRecord> =
            (0..keep).map(|k| StepRecord { time: times[k], fields: vec![], mesh: meshes[k] }).collect();
        let mut kinds = BTreeMap::new();
        let trimmed = (|| -> hdf5::Result<()> {
            for name in &names {
                let g = file.group(&format!("fields/{name}"))?;
                for ds_name in g.member_names()? {
                    let k: usize = ds_name.parse().unwrap_or(usize::MAX);
                    if k >= keep {
                        g.unlink(&ds_name)?;
                        continue;
                    }
                    let shape = g.dataset(&ds_name)?.shape();
                    let on_nodes = shape[0] == mesh.n_global_nodes;
                    let kind = match (on_nodes, shape.len()) {
                        (true, 1) => FieldKind::NodeScalar,
                        (true, _) => FieldKind::NodeVector,
                        (false, 1) => FieldKind::CellScalar,
                        (false, _) => FieldKind::CellVector,
                    };
                    kinds.insert(name.clone(), kind);
                    steps[k].fields.push((name.clone(), kind));
                }
            }
            time_ds.resize(keep)?;
            step_mesh_ds.resize(keep)?;
            Ok(())
        })()
        .map_err(|e| h5err(&h5_path, "cannot remove the steps after the checkpoint", e));
        agree(&comm, trimmed)?;
        // The mesh group of this numbering: the last one, if it holds this rank's rows as they
        // are here on every rank; else a new one.
        let last = meshes[..keep].iter().copied().max().unwrap_or(0);
        let same = (|| -> hdf5::Result<bool> {
            let g = file.group(&mesh_group(last))?;
            let xyz: Vec<f64> = g.dataset("coordinates")?.read_raw()?;
            let mine = xyz.get(3 * mesh.node_offset..3 * (mesh.node_offset + mesh.coords.len()));
            Ok(mine.is_some_and(|m| m.chunks(3).zip(mesh.coords).all(|(a, b)| a == b.as_slice())))
        })()
        .map_err(|e| h5err(&h5_path, "cannot read the mesh", e));
        let same = crate::parallel::all(&comm, agree(&comm, same)?);
        let group = if same { last } else { last + 1 };
        if group != last {
            // A group of that name left by a later session that was cut off: no kept step uses it.
            let stale = (|| -> hdf5::Result<()> {
                if file.member_names()?.contains(&mesh_group(group)) {
                    file.unlink(&mesh_group(group))?;
                }
                Ok(())
            })()
            .map_err(|e| h5err(&h5_path, "cannot remove a stale mesh group", e));
            agree(&comm, stale)?;
            write_mesh(&file, &comm, &h5_path, mesh, group)?;
        }
        let datasets = Datasets { time: time_ds, step_mesh: step_mesh_ds };
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
        let same = same_everywhere(&self.comm, &path, sig.0, &format!("step {k}: time or field names and kinds"));
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

    fn data_item(&self, dims: &str, number_type: &str, h5_object: &str) -> String {
        let h5 = xml_escape(H5_NAME);
        format!(
            "<DataItem Dimensions=\"{dims}\" NumberType=\"{number_type}\" Precision=\"8\" Format=\"HDF\">{h5}:{h5_object}</DataItem>"
        )
    }

    fn mesh_xml(&self, indent: &str, group: i64) -> String {
        let (n, m) = (self.n_global_nodes, self.n_global_cells);
        let g = mesh_group(group);
        let (ty, npe) = self.cell_type;
        format!(
            "{indent}<Topology TopologyType=\"{ty}\" NumberOfElements=\"{m}\" NodesPerElement=\"{npe}\">\n\
             {indent}  {}\n\
             {indent}</Topology>\n\
             {indent}<Geometry GeometryType=\"XYZ\">\n\
             {indent}  {}\n\
             {indent}</Geometry>\n",
            self.data_item(&format!("{m} {npe}"), "Int", &format!("/{g}/topology")),
            self.data_item(&format!("{n} 3"), "Float", &format!("/{g}/coordinates")),
        )
    }

    fn step_grid(&self, k: usize) -> String {
        let step = &self.steps[k];
        let mut s = String::new();
        let _ = writeln!(s, "      <Grid Name=\"step_{k:06}\" GridType=\"Uniform\">");
        let _ = writeln!(s, "        <Time Value=\"{}\"/>", fmt_real(step.time));
        s.push_str(&self.mesh_xml("        ", step.mesh));
        for (name, kind) in &step.fields {
            let rows = if kind.on_nodes() { self.n_global_nodes } else { self.n_global_cells };
            let (ty, dims) = match kind.components() {
                1 => ("Scalar", format!("{rows}")),
                c => ("Vector", format!("{rows} {c}")),
            };
            let center = if kind.on_nodes() { "Node" } else { "Cell" };
            let name = xml_escape(name);
            let _ = writeln!(s, "        <Attribute Name=\"{name}\" AttributeType=\"{ty}\" Center=\"{center}\">");
            let _ = writeln!(s, "          {}", self.data_item(&dims, "Float", &format!("/fields/{name}/{k:06}")));
            let _ = writeln!(s, "        </Attribute>");
        }
        s.push_str("      </Grid>\n");
        s
    }

    fn xdmf_text(&self) -> String {
        let mut s = String::from("<?xml version=\"1.0\" encoding=\"utf-8\"?>\n<Xdmf Version=\"3.0\">\n  <Domain>\n");
        if self.steps.is_empty() {
            s.push_str("    <Grid Name=\"mesh\" GridType=\"Uniform\">\n");
            s.push_str(&self.mesh_xml("      ", self.mesh));
            s.push_str("    </Grid>\n");
        } else {
            s.push_str("    <Grid Name=\"fields\" GridType=\"Collection\" CollectionType=\"Temporal\">\n");
            s.push_str(&self.xdmf_grids);
            s.push_str("    </Grid>\n");
        }
        s.push_str("  </Domain>\n</Xdmf>\n");
        s
    }

    fn write_xdmf(&self) -> Result<()> {
        write_atomically(&self.xdmf_path, |tmp| std::fs::write(tmp, self.xdmf_text()).map_err(|e| Error::io(tmp, e)))
    }
}

/// `from` copied over `to` (atomically).
fn copy_atomically(from: &Path, to: &Path) -> Result<()> {
    write_atomically(to, |tmp| {
        std::fs::copy(from, tmp).map(drop).map_err(|e| Error::io(tmp, format!("cannot copy {}: {e}", from.display())))
    })
}

/// Puts the copy `backup` (of [`FieldFile::backup`]) in place of the `fields.h5` of `dir`, which is
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tet10_permutation_maps_gmsh_edges_to_vtk_edges() {
        let gmsh = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)];
        let vtk = [(0, 1), (1, 2), (0, 2), (0, 3), (1, 3), (2, 3)];
        assert_eq!(GMSH_TO_XDMF_TET10[..4], [0, 1, 2, 3]);
        for (e, edge) in vtk.iter().enumerate() {
            assert_eq!(gmsh[GMSH_TO_XDMF_TET10[4 + e] - 4], *edge);
        }
        for (i, &j) in GMSH_TO_XDMF_TET10.iter().enumerate() {
            assert_eq!(GMSH_TO_XDMF_TET10[j], i, "an involution");
        }
    }

    #[test]
    fn names_and_escaping() {
        for ok in ["u", "p", "phi_s", "sigma-vm", "J.e", "A1"] {
            check_name(ok).unwrap();
        }
        for bad in ["", ".x", "a/b", "a b", "a:b", "é", "a<b"] {
            assert!(check_name(bad).is_err(), "{bad:?}");
        }
        assert_eq!(xml_escape("a<&>\"'"), "a&lt;&amp;&gt;&quot;&apos;");
    }
}
