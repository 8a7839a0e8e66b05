//! The checks of a collective call's arguments, made before any collective HDF5 call: each
//! rank's own (names, counts, ranges), and that the ranks passed the same ones (a hash compared
//! across ranks) and pieces of the mesh that tile it.

use super::layout::OutputMesh;
use crate::error::{Error, Result};
use crate::parallel::same_on_all;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::Path;

/// A field name that is a valid HDF5 link and XDMF attribute name.
pub(super) fn check_name(name: &str) -> std::result::Result<(), String> {
    let ok = !name.is_empty()
        && !name.starts_with('.')
        && name.bytes().all(|b| b.is_ascii_alphanumeric() || matches!(b, b'_' | b'-' | b'.'));
    if ok {
        Ok(())
    } else {
        Err(format!("invalid field name {name:?} (use ASCII letters, digits, '_', '-', '.')"))
    }
}

/// This rank's piece of the mesh: within the global counts, cells referring to existing nodes;
/// and the directory exists.
pub(super) fn check_mesh(mesh: &OutputMesh, dir: &Path) -> std::result::Result<(), String> {
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

/// Collective: `Err` on every rank unless `hash` (of the arguments `what`) is the same on all
/// ranks.
pub(super) fn same_everywhere(comm: &SimpleCommunicator, path: &Path, hash: u64, what: &str) -> Result<()> {
    if same_on_all(comm, hash) {
        Ok(())
    } else {
        Err(Error::io(path, format!("{what}: ranks passed different arguments to this collective call")))
    }
}

/// Collective: the ranks' owned nodes and cells tile [0, N) and [0, M) exactly (the same verdict
/// on every rank).
pub(super) fn check_tiling(comm: &SimpleCommunicator, mesh: &OutputMesh, h5_path: &Path) -> Result<()> {
    let mine = [mesh.node_offset as u64, mesh.coords.len() as u64, mesh.cell_offset as u64, mesh.cells.len() as u64];
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
                    h5_path,
                    format!("the ranks' {what} do not tile [0, {total}): gap or overlap at {}", lo.min(next)),
                ));
            }
            next = hi;
        }
        if next != total as u64 {
            return Err(Error::io(h5_path, format!("the ranks own {next} {what}, the mesh declares {total}")));
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::check_name;

    #[test]
    fn field_names() {
        for ok in ["u", "p", "phi_s", "sigma-vm", "J.e", "A1"] {
            check_name(ok).unwrap();
        }
        for bad in ["", ".x", "a/b", "a b", "a:b", "é", "a<b"] {
            assert!(check_name(bad).is_err(), "{bad:?}");
        }
    }
}
