//! The build steps the tetrahedral and the meridian mesh share: keeping the used nodes,
//! promoting linear cells, and assembling the mesh with its named groups.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use super::msh41::Raw;
use crate::error::{Error, Result};
use crate::mesh::Mesh;
use crate::reference_cell::Family;

/// The nodes used by the first `n` slots of `cells`, in file order: (file node -> compact id,
/// u32::MAX if unused; the compact nodes' coordinates).
pub(super) fn used_nodes<const N: usize>(
    coords: &[[f64; 3]],
    cells: &[[u32; N]],
    n: usize,
) -> (Vec<u32>, Vec<[f64; 3]>) {
    let mut new_id = vec![u32::MAX; coords.len()];
    for cell in cells {
        for &k in &cell[..n] {
            new_id[k as usize] = 0;
        }
    }
    let mut used = Vec::with_capacity(coords.len());
    for (i, id) in new_id.iter_mut().enumerate() {
        if *id == 0 {
            *id = used.len() as u32;
            used.push(coords[i]);
        }
    }
    (new_id, used)
}

/// A mesh's compacted nodes, oriented cells, attached faces and face groups, before the rest.
pub(super) struct Parts {
    pub(super) coords: Vec<[f64; 3]>,
    pub(super) cells: Vec<[u32; 10]>,
    pub(super) faces: Vec<[u32; 6]>,
    pub(super) face_cell: Vec<(u32, u8)>,
    /// Physical tag -> face indices.
    pub(super) face_groups: BTreeMap<i32, Vec<u32>>,
    /// File-order node -> compact node id (u32::MAX: not a node of any cell).
    pub(super) new_id: Vec<u32>,
}

/// The mesh from its parts: cell groups (from the cells' entities `cell_entity`), point groups,
/// named face groups and the vertex flags, for a mesh of `family`.
pub(super) fn finish(path: &Path, raw: &Raw, family: Family, cell_entity: &[i32], p: Parts) -> Result<Mesh> {
    let dim = match family {
        Family::Tet10 => 3,
        Family::Tri6 => 2,
    };
    let mut volume_groups: BTreeMap<i32, Vec<u32>> = BTreeMap::new();
    for (t, e) in cell_entity.iter().enumerate() {
        for &g in raw.entity_phys[dim].get(e).map_or(&[][..], |v| v) {
            volume_groups.entry(g).or_default().push(t as u32);
        }
    }
    let mut point_groups: BTreeMap<i32, Vec<u32>> = BTreeMap::new();
    for &(n, e, etag) in &raw.points {
        let Some(phys) = raw.entity_phys[0].get(&e) else { continue };
        let id = p.new_id[n as usize];
        if id == u32::MAX {
            return Err(Error::mesh(
                path,
                format!(
                    "physical point element {etag} (node tag {}) is not a node of any {}",
                    raw.node_tags[n as usize],
                    family.cell_name()
                ),
            ));
        }
        for &g in phys {
            point_groups.entry(g).or_default().push(id);
        }
    }
    let mut is_vertex = vec![false; p.coords.len()];
    for cell in &p.cells {
        for &n in &cell[..family.cell_vertices()] {
            is_vertex[n as usize] = true;
        }
    }
    Ok(Mesh {
        family,
        coords: p.coords,
        cells: p.cells,
        faces: p.faces,
        face_cell: p.face_cell,
        volume_groups: named_groups(&raw.phys_names, dim, volume_groups),
        face_groups: named_groups(&raw.phys_names, dim - 1, p.face_groups),
        point_groups: named_groups(&raw.phys_names, 0, point_groups),
        is_vertex,
    })
}

/// Insert one straight mid-edge node per distinct edge of a linear mesh (shared between cells): the
/// mid-node of edge k of a cell goes to slot `family.cell_vertices() + k`.
/// Edges are numbered in sorted (vertex, vertex) order so the result is deterministic.
pub(super) fn promote(
    family: Family,
    cells: &mut [[u32; 10]],
    coords: &mut Vec<[f64; 3]>,
) -> std::result::Result<(), String> {
    let (edges_of, nv) = (family.edges(), family.cell_vertices());
    let ne = edges_of.len();
    let mut edges: Vec<(u64, u32)> = Vec::with_capacity(cells.len() * ne);
    for (t, tet) in cells.iter().enumerate() {
        for (k, &(a, b)) in edges_of.iter().enumerate() {
            let (a, b) = (tet[a].min(tet[b]) as u64, tet[a].max(tet[b]) as u64);
            edges.push(((a << 32) | b, (t * ne + k) as u32));
        }
    }
    edges.sort_unstable();
    let mut last = u64::MAX;
    for &(key, slot) in &edges {
        if key != last {
            if coords.len() >= u32::MAX as usize {
                return Err("too many nodes after promotion to quadratic".into());
            }
            let (a, b) = ((key >> 32) as usize, (key & 0xffff_ffff) as usize);
            let (xa, xb) = (coords[a], coords[b]);
            coords.push([0.5 * (xa[0] + xb[0]), 0.5 * (xa[1] + xb[1]), 0.5 * (xa[2] + xb[2])]);
            last = key;
        }
        let (t, k) = (slot as usize / ne, slot as usize % ne);
        cells[t][nv + k] = (coords.len() - 1) as u32;
    }
    Ok(())
}

/// Turn physical tag -> members into (name, sorted members), including named groups that are empty;
/// unnamed groups are called by their tag; groups sharing a name are merged.
pub(super) fn named_groups(
    names: &HashMap<(usize, i32), String>,
    dim: usize,
    mut groups: BTreeMap<i32, Vec<u32>>,
) -> Vec<(String, Vec<u32>)> {
    for (&(d, tag), _) in names.iter() {
        if d == dim {
            groups.entry(tag).or_default();
        }
    }
    let mut out: Vec<(String, Vec<u32>)> = Vec::new();
    for (tag, members) in groups {
        let name = names.get(&(dim, tag)).cloned().unwrap_or_else(|| tag.to_string());
        match out.iter_mut().find(|(n, _)| *n == name) {
            Some((_, m)) => m.extend(members),
            None => out.push((name, members)),
        }
    }
    for (_, m) in &mut out {
        m.sort_unstable();
        m.dedup();
    }
    out
}
