//! Element partitioning with METIS k-way on the face-adjacency dual graph (tets sharing a triangle,
//! meridian triangles sharing an edge).
//!
//! The dual graph is built here rather than with METIS' `part_dual`, which links elements sharing a node
//! and so over-connects the graph. The result is deterministic: the graph is built by sorting, and METIS
//! runs with a fixed seed.

use super::face_match::{sorted_cell_faces, unpack_face};
use super::Mesh;
use crate::error::{Error, Result};
use metis::Idx;

/// Part (0..nparts) of each cell of `mesh`. Every part is non-empty.
pub(crate) fn partition(mesh: &Mesh, nparts: usize) -> Result<Vec<u32>> {
    let n = mesh.cells.len();
    let err = |msg: String| Error::mesh("partition", msg);
    if nparts == 0 {
        return Err(err("number of parts must be at least 1".into()));
    }
    if nparts == 1 {
        return Ok(vec![0; n]);
    }
    if nparts > n {
        return Err(err(format!("cannot split {n} cells into {nparts} non-empty parts")));
    }
    let (xadj, adjncy) = dual_graph(mesh).map_err(err)?;
    let nparts_idx = Idx::try_from(nparts).map_err(|_| err(format!("too many parts: {nparts}")))?;
    let mut part: Vec<Idx> = vec![0; n];
    metis::Graph::new(1, nparts_idx, &xadj, &adjncy)
        .map_err(|e| err(format!("METIS rejected the dual graph: {e}")))?
        .set_option(metis::option::Seed(1))
        .part_kway(&mut part)
        .map_err(|e| err(format!("METIS k-way partitioning into {nparts} parts failed: {e}")))?;

    let mut count = vec![0usize; nparts];
    let mut out = Vec::with_capacity(n);
    for &p in &part {
        let p =
            usize::try_from(p).ok().filter(|&p| p < nparts).ok_or_else(|| err(format!("METIS returned part {p}")))?;
        count[p] += 1;
        out.push(p as u32);
    }
    if let Some(empty) = count.iter().position(|&c| c == 0) {
        return Err(err(format!(
            "METIS left part {empty} of {nparts} empty ({n} cells): use fewer ranks or a finer mesh"
        )));
    }
    Ok(out)
}

/// CSR dual graph (xadj, adjncy): cells are adjacent when they share a face.
pub(crate) fn dual_graph(mesh: &Mesh) -> std::result::Result<(Vec<Idx>, Vec<Idx>), String> {
    let n = mesh.cells.len();
    if n >= 1 << 30 {
        return Err(format!("mesh too large ({n} cells)"));
    }
    let faces = sorted_cell_faces(mesh.family, &mesh.cells);
    // Interior faces appear as two consecutive entries with the same vertex triple.
    let mut pairs: Vec<(u32, u32)> = Vec::new();
    let mut degree = vec![0usize; n];
    for (i, w) in faces.windows(2).enumerate() {
        if w[0] >> 32 == w[1] >> 32 {
            if faces.get(i + 2).is_some_and(|&k| k >> 32 == w[0] >> 32) {
                let (key, a, _) = unpack_face(w[0]);
                return Err(format!("non-manifold mesh: face {key:?} is shared by 3 or more cells (first {a})"));
            }
            let (a, b) = (unpack_face(w[0]).1, unpack_face(w[1]).1);
            pairs.push((a, b));
            degree[a as usize] += 1;
            degree[b as usize] += 1;
        }
    }
    let too_large = || format!("dual graph too large for METIS ({n} cells)");
    let mut xadj: Vec<Idx> = Vec::with_capacity(n + 1);
    let mut acc = 0usize;
    xadj.push(0);
    for d in &degree {
        acc += d;
        xadj.push(Idx::try_from(acc).map_err(|_| too_large())?);
    }
    let mut fill: Vec<usize> = xadj[..n].iter().map(|&x| x as usize).collect();
    let mut adjncy: Vec<Idx> = vec![0; acc];
    for &(a, b) in &pairs {
        adjncy[fill[a as usize]] = Idx::try_from(b).map_err(|_| too_large())?;
        fill[a as usize] += 1;
        adjncy[fill[b as usize]] = Idx::try_from(a).map_err(|_| too_large())?;
        fill[b as usize] += 1;
    }
    // Sorted neighbour lists: a canonical input whatever the face order.
    for t in 0..n {
        adjncy[xadj[t] as usize..xadj[t + 1] as usize].sort_unstable();
    }
    Ok((xadj, adjncy))
}
