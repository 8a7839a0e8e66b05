//! The per-rank view of a partitioned mesh: owned and ghost nodes, rank-contiguous global numbering of
//! nodes, vertices (P1 pressure nodes) and elements, local faces and groups, and the node-neighbour graph
//! for exact matrix preallocation. A pure function of (mesh, partition): every rank computes its own piece
//! and the pieces agree without communication.

use super::{Family, Mesh, MAX_CELL_NODES, MAX_FACE_NODES};
use crate::error::{Error, Result};

/// One rank's part of the mesh. See [`distribute`] for the numbering rules.
#[derive(Debug, Clone, Default)]
pub struct LocalMesh {
    /// The element family (as the file's [`Mesh`]).
    pub family: Family,
    pub rank: usize,
    pub nranks: usize,
    /// Coordinates of the local nodes (owned first, then ghosts).
    pub coords: Vec<[f64; 3]>,
    pub n_owned_nodes: usize,
    /// Local node -> global (rank-contiguous) node id.
    pub node_global: Vec<u32>,
    /// Local node -> node index in the file's [`Mesh`].
    pub node_original: Vec<u32>,
    /// This rank owns global nodes `node_offset .. node_offset + n_owned_nodes`.
    pub node_offset: usize,
    pub n_global_nodes: usize,
    /// Local node -> owning rank.
    pub node_owner: Vec<u32>,
    /// Local node -> local vertex index, or -1 for a mid-edge node.
    pub vertex_of_node: Vec<i32>,
    /// Local vertex -> local node.
    pub vertex_node: Vec<u32>,
    pub n_owned_vertices: usize,
    /// Local vertex -> global (rank-contiguous) vertex id.
    pub vertex_global: Vec<u32>,
    pub vertex_offset: usize,
    pub n_global_vertices: usize,
    /// The cells of this part, in increasing original index, with local node ids (see [`Mesh::cells`]).
    pub cells: Vec<[u32; MAX_CELL_NODES]>,
    /// Local tet -> tet index in the file's [`Mesh`].
    pub cell_original: Vec<u32>,
    /// Local tet `i` has global (output) id `elem_offset + i`; ids are contiguous per rank.
    pub elem_offset: usize,
    pub n_global_elems: usize,
    /// Boundary faces whose tet is local (local node ids, outward).
    pub faces: Vec<[u32; MAX_FACE_NODES]>,
    /// Local face -> (local tet, local face index of that tet).
    pub face_cell: Vec<(u32, u8)>,
    /// Every physical surface of the file (even if empty here) -> local face indices.
    pub face_groups: Vec<(String, Vec<u32>)>,
    /// Every physical volume of the file -> local tet indices.
    pub volume_groups: Vec<(String, Vec<u32>)>,
    /// Every physical point group of the file -> local node indices (only nodes present locally).
    pub point_groups: Vec<(String, Vec<u32>)>,
    /// CSR over OWNED nodes: sorted global ids of all nodes sharing a tet with the node (itself included),
    /// over the whole mesh. Row `i` is `node_nbr[node_nbr_offsets[i]..node_nbr_offsets[i + 1]]`.
    pub node_nbr_offsets: Vec<usize>,
    pub node_nbr: Vec<u32>,
    /// Parallel to `node_nbr`: the neighbour is a vertex (carries a pressure dof).
    pub node_nbr_is_vertex: Vec<bool>,
    /// Parallel to `node_nbr`: the neighbour's global vertex id, or -1.
    pub node_nbr_vertex_global: Vec<i32>,
    /// Rank r owns global nodes `node_ranges[r]..node_ranges[r + 1]` (length nranks + 1).
    pub node_ranges: Vec<usize>,
    /// Rank r owns global vertices `vertex_ranges[r]..vertex_ranges[r + 1]` (length nranks + 1).
    pub vertex_ranges: Vec<usize>,
}

impl LocalMesh {
    /// Whether local node `local` is owned by this rank (owned nodes come first).
    pub fn is_owned_node(&self, local: usize) -> bool {
        local < self.n_owned_nodes
    }

    /// Whether local vertex `local` is owned by this rank (owned vertices come first).
    pub fn is_owned_vertex(&self, local: usize) -> bool {
        local < self.n_owned_vertices
    }

    /// Rank owning global node `g` (`g < n_global_nodes`).
    pub fn owner_of_global_node(&self, g: usize) -> usize {
        owner_in(&self.node_ranges, g)
    }

    /// Rank owning global vertex `g` (`g < n_global_vertices`).
    pub fn owner_of_global_vertex(&self, g: usize) -> usize {
        owner_in(&self.vertex_ranges, g)
    }

    /// The nodes of local cell e.
    pub fn cell(&self, e: usize) -> &[u32] {
        &self.cells[e][..self.family.cell_nodes()]
    }

    /// The nodes of local face f.
    pub fn face(&self, f: usize) -> &[u32] {
        &self.faces[f][..self.family.face_nodes()]
    }

    /// Number of local nodes (owned + ghost).
    pub fn n_nodes(&self) -> usize {
        self.coords.len()
    }

    /// Number of local vertices (owned + ghost).
    pub fn n_vertices(&self) -> usize {
        self.vertex_node.len()
    }

    /// Local face indices of the physical surface `name` (error lists the available groups).
    pub fn face_group(&self, name: &str) -> Result<&[u32]> {
        super::find_group(&self.face_groups, name, "surface")
    }

    /// Local node indices of the physical point `name` present on this rank.
    pub fn point_group(&self, name: &str) -> Result<&[u32]> {
        super::find_group(&self.point_groups, name, "point")
    }
}

/// Index r with ranges[r] <= g < ranges[r + 1] (empty ranks are skipped).
fn owner_in(ranges: &[usize], g: usize) -> usize {
    ranges.partition_point(|&s| s <= g).saturating_sub(1)
}

/// Rank `rank`'s piece of `mesh` partitioned by `part` (tet -> rank, all < `nranks`).
///
/// * Node owner = the smallest part among the cells containing the node; rank r owns the global node ids
///   `node_ranges[r]..node_ranges[r + 1]`, assigned in increasing original node id. Vertices likewise.
/// * Local nodes: owned (in global order), then ghosts (nodes of local cells owned elsewhere) by global id.
///   Local vertices: owned, then ghosts, in the same order.
/// * Local cells: those of part `rank` in increasing original index; global element ids are contiguous per
///   rank (`elem_offset` = number of cells in lower parts).
pub fn distribute(mesh: &Mesh, part: &[u32], nranks: usize, rank: usize) -> Result<LocalMesh> {
    let err = |msg: String| Error::mesh("distribute", msg);
    let nn = mesh.coords.len();
    let nt = mesh.cells.len();
    if part.len() != nt {
        return Err(err(format!("partition has {} entries for {nt} cells", part.len())));
    }
    if rank >= nranks {
        return Err(err(format!("rank {rank} out of range (nranks = {nranks})")));
    }
    if mesh.is_vertex.len() != nn {
        return Err(err(format!("is_vertex has {} entries for {nn} nodes", mesh.is_vertex.len())));
    }
    if let Some(t) = part.iter().position(|&p| p as usize >= nranks) {
        return Err(err(format!("tet {t} assigned to part {} >= nranks = {nranks}", part[t])));
    }
    let r32 = rank as u32;

    // Owners, per-rank counts and global numbering (identical on every rank).
    let ncn = mesh.family.cell_nodes();
    let mut owner = vec![u32::MAX; nn];
    for (tet, &p) in mesh.cells.iter().zip(part) {
        for &n in &tet[..ncn] {
            let o = owner.get_mut(n as usize).ok_or_else(|| err(format!("tet references node {n} >= {nn}")))?;
            *o = (*o).min(p);
        }
    }
    if let Some(n) = owner.iter().position(|&o| o == u32::MAX) {
        return Err(err(format!("node {n} belongs to no cell")));
    }
    let mut node_ranges = vec![0usize; nranks + 1];
    let mut vertex_ranges = vec![0usize; nranks + 1];
    for (n, &o) in owner.iter().enumerate() {
        node_ranges[o as usize + 1] += 1;
        if mesh.is_vertex[n] {
            vertex_ranges[o as usize + 1] += 1;
        }
    }
    for r in 0..nranks {
        node_ranges[r + 1] += node_ranges[r];
        vertex_ranges[r + 1] += vertex_ranges[r];
    }
    let mut next_node = node_ranges[..nranks].to_vec();
    let mut next_vertex = vertex_ranges[..nranks].to_vec();
    let mut gnode = vec![0u32; nn];
    let mut gvertex = vec![-1i32; nn];
    for (n, &o) in owner.iter().enumerate() {
        gnode[n] = next_node[o as usize] as u32;
        next_node[o as usize] += 1;
        if mesh.is_vertex[n] {
            gvertex[n] = next_vertex[o as usize] as i32;
            next_vertex[o as usize] += 1;
        }
    }

    // Local cells.
    let cell_original: Vec<u32> = (0..nt as u32).filter(|&t| part[t as usize] == r32).collect();
    let elem_offset = part.iter().filter(|&&p| p < r32).count();

    // Local nodes: owned in original (= global) order, then ghosts sorted by global id.
    let mut local_of = vec![u32::MAX; nn];
    let mut node_original: Vec<u32> = (0..nn as u32).filter(|&n| owner[n as usize] == r32).collect();
    let n_owned_nodes = node_original.len();
    let mut ghosts: Vec<u32> = Vec::new();
    for &t in &cell_original {
        for &n in mesh.cell(t as usize) {
            if owner[n as usize] != r32 {
                ghosts.push(n);
            }
        }
    }
    ghosts.sort_unstable_by_key(|&n| gnode[n as usize]);
    ghosts.dedup();
    node_original.extend_from_slice(&ghosts);
    drop(ghosts);
    for (l, &n) in node_original.iter().enumerate() {
        local_of[n as usize] = l as u32;
    }
    let coords: Vec<[f64; 3]> = node_original.iter().map(|&n| mesh.coords[n as usize]).collect();
    let node_global: Vec<u32> = node_original.iter().map(|&n| gnode[n as usize]).collect();
    let node_owner: Vec<u32> = node_original.iter().map(|&n| owner[n as usize]).collect();

    // Local vertices: ghost nodes are in (owner, original id) order, which is also global vertex order.
    let mut vertex_of_node = vec![-1i32; node_original.len()];
    let mut vertex_node = Vec::new();
    let mut vertex_global = Vec::new();
    let mut n_owned_vertices = 0;
    for (l, &n) in node_original.iter().enumerate() {
        if mesh.is_vertex[n as usize] {
            vertex_of_node[l] = vertex_node.len() as i32;
            vertex_node.push(l as u32);
            vertex_global.push(gvertex[n as usize] as u32);
            if l < n_owned_nodes {
                n_owned_vertices += 1;
            }
        }
    }

    let relabel = |n: u32| if n == u32::MAX { n } else { local_of[n as usize] };
    let cells: Vec<[u32; MAX_CELL_NODES]> =
        cell_original.iter().map(|&t| mesh.cells[t as usize].map(relabel)).collect();
    let mut local_tet = vec![u32::MAX; nt];
    for (l, &t) in cell_original.iter().enumerate() {
        local_tet[t as usize] = l as u32;
    }

    // Faces of local cells, in increasing global face index.
    let mut local_face = vec![u32::MAX; mesh.faces.len()];
    let mut faces = Vec::new();
    let mut face_cell = Vec::new();
    for (f, (face, &(t, lf))) in mesh.faces.iter().zip(&mesh.face_cell).enumerate() {
        let lt = *local_tet.get(t as usize).ok_or_else(|| err(format!("face {f} references tet {t} >= {nt}")))?;
        if lt != u32::MAX {
            local_face[f] = faces.len() as u32;
            faces.push(face.map(relabel));
            face_cell.push((lt, lf));
        }
    }
    let face_groups = map_groups(&mesh.face_groups, &local_face);
    let volume_groups = map_groups(&mesh.volume_groups, &local_tet);
    let point_groups = map_groups(&mesh.point_groups, &local_of);

    // Neighbour graph of owned nodes over the whole mesh: owned node -> cells containing it -> their nodes.
    let mut tet_start = vec![0usize; n_owned_nodes + 1];
    for tet in &mesh.cells {
        for &n in &tet[..ncn] {
            let l = local_of[n as usize] as usize;
            if l < n_owned_nodes {
                tet_start[l + 1] += 1;
            }
        }
    }
    for i in 0..n_owned_nodes {
        tet_start[i + 1] += tet_start[i];
    }
    let mut fill = tet_start[..n_owned_nodes].to_vec();
    let mut tets_of = vec![0u32; tet_start[n_owned_nodes]];
    for (t, tet) in mesh.cells.iter().enumerate() {
        for &n in &tet[..ncn] {
            let l = local_of[n as usize] as usize;
            if l < n_owned_nodes {
                tets_of[fill[l]] = t as u32;
                fill[l] += 1;
            }
        }
    }
    drop(fill);
    let mut node_nbr_offsets = Vec::with_capacity(n_owned_nodes + 1);
    node_nbr_offsets.push(0);
    let mut node_nbr = Vec::with_capacity(n_owned_nodes * 20);
    let mut node_nbr_vertex_global = Vec::with_capacity(n_owned_nodes * 20);
    // mark[n] = last row that listed node n: dedup before sorting keeps the sorts short.
    let mut mark = vec![u32::MAX; nn];
    let mut row: Vec<(u32, i32)> = Vec::new();
    for i in 0..n_owned_nodes {
        row.clear();
        for &t in &tets_of[tet_start[i]..tet_start[i + 1]] {
            for &n in mesh.cell(t as usize) {
                if mark[n as usize] != i as u32 {
                    mark[n as usize] = i as u32;
                    row.push((gnode[n as usize], gvertex[n as usize]));
                }
            }
        }
        row.sort_unstable();
        node_nbr.extend(row.iter().map(|e| e.0));
        node_nbr_vertex_global.extend(row.iter().map(|e| e.1));
        node_nbr_offsets.push(node_nbr.len());
    }
    let node_nbr_is_vertex: Vec<bool> = node_nbr_vertex_global.iter().map(|&v| v >= 0).collect();

    Ok(LocalMesh {
        family: mesh.family,
        rank,
        nranks,
        coords,
        n_owned_nodes,
        node_global,
        node_original,
        node_offset: node_ranges[rank],
        n_global_nodes: nn,
        node_owner,
        vertex_of_node,
        vertex_node,
        n_owned_vertices,
        vertex_global,
        vertex_offset: vertex_ranges[rank],
        n_global_vertices: vertex_ranges[nranks],
        cells,
        cell_original,
        elem_offset,
        n_global_elems: nt,
        faces,
        face_cell,
        face_groups,
        volume_groups,
        point_groups,
        node_nbr_offsets,
        node_nbr,
        node_nbr_is_vertex,
        node_nbr_vertex_global,
        node_ranges,
        vertex_ranges,
    })
}

/// Keep the members present locally (`local[i] != u32::MAX`), renumbered; every group name is kept.
fn map_groups(groups: &[(String, Vec<u32>)], local: &[u32]) -> Vec<(String, Vec<u32>)> {
    groups
        .iter()
        .map(|(name, members)| {
            let mut m: Vec<u32> =
                members.iter().filter_map(|&i| local.get(i as usize).copied().filter(|&l| l != u32::MAX)).collect();
            m.sort_unstable();
            (name.clone(), m)
        })
        .collect()
}
