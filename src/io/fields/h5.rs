//! `fields.h5` through HDF5's MPI-IO driver: the file created or opened with its per-step
//! datasets, the mesh written as a group, and on reopening the steps after a checkpoint removed
//! and the mesh group of this run's numbering found (or written). Every function is collective
//! and returns the same outcome on every rank (`crate::parallel::agree`).

use super::layout::{cell_type, mesh_group, FieldKind, OutputMesh, StepRecord, GMSH_TO_XDMF_TET10};
use crate::error::{Error, Result};
use crate::parallel::agree;
use crate::reference_cell::Family;
use hdf5_metno as hdf5;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::collections::BTreeMap;
use std::path::Path;

/// An HDF5 error on `path` while doing `what`.
pub(super) fn h5err(path: &Path, what: &str, e: hdf5::Error) -> Error {
    Error::io(path, format!("{what}: {e}"))
}

/// The extendible per-step datasets: `/time` and `/step_mesh`.
pub(super) struct Datasets {
    pub(super) time: hdf5::Dataset,
    pub(super) step_mesh: hdf5::Dataset,
}

/// A new (truncated) file at `h5_path` with its `/fields` group and per-step datasets.
pub(super) fn create(comm: &SimpleCommunicator, h5_path: &Path) -> Result<(hdf5::File, Datasets)> {
    let file = hdf5::File::with_options()
        .with_fapl(|p| p.mpio(comm.as_raw(), None))
        .create(h5_path)
        .map_err(|e| h5err(h5_path, "cannot create HDF5 file", e));
    let file = agree(comm, file)?;
    let made = (|| -> hdf5::Result<(hdf5::Dataset, hdf5::Dataset)> {
        file.create_group("fields")?;
        let time = file.new_dataset::<f64>().chunk(256).shape((0..,)).create("time")?;
        let step_mesh = file.new_dataset::<i64>().chunk(256).shape((0..,)).create("step_mesh")?;
        Ok((time, step_mesh))
    })()
    .map_err(|e| h5err(h5_path, "cannot create datasets", e));
    let (time, step_mesh) = agree(comm, made)?;
    Ok((file, Datasets { time, step_mesh }))
}

/// What a file holds: the steps' times and mesh groups, and the names of its fields.
pub(super) struct Written {
    pub(super) times: Vec<f64>,
    pub(super) meshes: Vec<i64>,
    pub(super) fields: Vec<String>,
}

/// The file at `h5_path` opened for writing, with what it holds.
pub(super) fn open(comm: &SimpleCommunicator, h5_path: &Path) -> Result<(hdf5::File, Datasets, Written)> {
    let file = hdf5::File::with_options()
        .with_fapl(|p| p.mpio(comm.as_raw(), None))
        .open_rw(h5_path)
        .map_err(|e| h5err(h5_path, "cannot open HDF5 file", e));
    let file = agree(comm, file)?;
    let read = (|| -> hdf5::Result<(Datasets, Written)> {
        let time = file.dataset("time")?;
        let step_mesh = file.dataset("step_mesh")?;
        let times: Vec<f64> = time.read_raw()?;
        let meshes: Vec<i64> = step_mesh.read_raw()?;
        let fields = file.group("fields")?.member_names()?;
        Ok((Datasets { time, step_mesh }, Written { times, meshes, fields }))
    })()
    .map_err(|e| h5err(h5_path, "cannot read the steps written", e));
    let (datasets, written) = agree(comm, read)?;
    Ok((file, datasets, written))
}

/// Removes the steps from `keep` on; records the kept steps' fields in `steps` (the first
/// `keep` of `written`) and returns every field's kind.
pub(super) fn keep_steps(
    comm: &SimpleCommunicator,
    (file, datasets, h5_path): (&hdf5::File, &Datasets, &Path),
    written: &Written,
    n_global_nodes: usize,
    steps: &mut [StepRecord],
) -> Result<BTreeMap<String, FieldKind>> {
    let keep = steps.len();
    let mut kinds = BTreeMap::new();
    let trimmed = (|| -> hdf5::Result<()> {
        for name in &written.fields {
            let g = file.group(&format!("fields/{name}"))?;
            for ds_name in g.member_names()? {
                let k: usize = ds_name.parse().unwrap_or(usize::MAX);
                if k >= keep {
                    g.unlink(&ds_name)?;
                    continue;
                }
                let shape = g.dataset(&ds_name)?.shape();
                let on_nodes = shape[0] == n_global_nodes;
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
        datasets.time.resize(keep)?;
        datasets.step_mesh.resize(keep)?;
        Ok(())
    })()
    .map_err(|e| h5err(h5_path, "cannot remove the steps after the checkpoint", e));
    agree(comm, trimmed)?;
    Ok(kinds)
}

/// The mesh group of this run's numbering: the last one used (`last`), if it holds this rank's
/// rows as they are here on every rank; else the next one, written now.
pub(super) fn mesh_group_for(
    comm: &SimpleCommunicator,
    (file, h5_path): (&hdf5::File, &Path),
    mesh: &OutputMesh,
    last: i64,
) -> Result<i64> {
    let same = (|| -> hdf5::Result<bool> {
        let g = file.group(&mesh_group(last))?;
        let xyz: Vec<f64> = g.dataset("coordinates")?.read_raw()?;
        let mine = xyz.get(3 * mesh.node_offset..3 * (mesh.node_offset + mesh.coords.len()));
        Ok(mine.is_some_and(|m| m.chunks(3).zip(mesh.coords).all(|(a, b)| a == b.as_slice())))
    })()
    .map_err(|e| h5err(h5_path, "cannot read the mesh", e));
    let same = crate::parallel::all(comm, agree(comm, same)?);
    let group = if same { last } else { last + 1 };
    if group != last {
        // A group of that name left by a later session that was cut off: no kept step uses it.
        let stale = (|| -> hdf5::Result<()> {
            if file.member_names()?.contains(&mesh_group(group)) {
                file.unlink(&mesh_group(group))?;
            }
            Ok(())
        })()
        .map_err(|e| h5err(h5_path, "cannot remove a stale mesh group", e));
        agree(comm, stale)?;
        write_mesh(file, comm, h5_path, mesh, group)?;
    }
    Ok(group)
}

/// Writes the mesh as group `g` (collective: the datasets; independent: each rank's rows).
pub(super) fn write_mesh(
    file: &hdf5::File,
    comm: &SimpleCommunicator,
    path: &Path,
    mesh: &OutputMesh,
    g: i64,
) -> Result<()> {
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
