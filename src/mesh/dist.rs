//! The per-rank view of a partitioned mesh: owned and ghost nodes, rank-contiguous global numbering of
//! nodes, vertices (P1 pressure nodes) and elements, local faces and groups, and the node-neighbour graph
//! for exact matrix preallocation. A pure function of (mesh, partition): every rank computes its own piece
//! and the pieces agree without communication.

use super::Mesh;
use crate::error::{Error, Result};
use crate::reference_cell::{Family, MAX_CELL_NODES, MAX_FACE_NODES};
use mpi::topology::SimpleCommunicator;

/// One rank's part of the mesh. See [`distribute`] for the numbering rules.
#[derive(Debug, Clone, Default)]
pub(crate) struct LocalMesh {
    /// The element family (as the file's [`Mesh`]).
    pub(crate) family: Family,
    pub(crate) rank: usize,
    pub(crate) nranks: usize,
    /// Coordinates of the local nodes (owned first, then ghosts).
    pub(crate) coords: Vec<[f64; 3]>,
    pub(crate) n_owned_nodes: usize,
    /// Local node -> global (rank-contiguous) node id.
    pub(crate) node_global: Vec<u32>,
    /// Local node -> node index in the file's [`Mesh`].
    pub(crate) node_original: Vec<u32>,
    /// This rank owns global nodes `node_offset .. node_offset + n_owned_nodes`.
    pub(crate) node_offset: usize,
    pub(crate) n_global_nodes: usize,
    /// Local node -> owning rank.
    #[cfg(test)]
    pub(crate) node_owner: Vec<u32>,
    /// Local node -> local vertex index, or -1 for a mid-edge node.
    pub(crate) vertex_of_node: Vec<i32>,
    /// Local vertex -> local node.
    pub(crate) vertex_node: Vec<u32>,
    pub(crate) n_owned_vertices: usize,
    /// Local vertex -> global (rank-contiguous) vertex id.
    pub(crate) vertex_global: Vec<u32>,
    #[cfg(test)]
    pub(crate) vertex_offset: usize,
    pub(crate) n_global_vertices: usize,
    /// The cells of this part, in increasing original index, with local node ids (see [`Mesh::cells`]).
    pub(crate) cells: Vec<[u32; MAX_CELL_NODES]>,
    /// Local tet -> tet index in the file's [`Mesh`].
    pub(crate) cell_original: Vec<u32>,
    /// Local tet `i` has global (output) id `elem_offset + i`; ids are contiguous per rank.
    pub(crate) elem_offset: usize,
    pub(crate) n_global_elems: usize,
    /// Boundary faces whose tet is local (local node ids, outward).
    pub(crate) faces: Vec<[u32; MAX_FACE_NODES]>,
    /// Local face -> (local tet, local face index of that tet).
    pub(crate) face_cell: Vec<(u32, u8)>,
    /// Every physical surface of the file (even if empty here) -> local face indices.
    pub(crate) face_groups: Vec<(String, Vec<u32>)>,
    /// Every physical volume of the file -> local tet indices.
    #[cfg(test)]
    pub(crate) volume_groups: Vec<(String, Vec<u32>)>,
    /// Every physical point group of the file -> local node indices (only nodes present locally).
    pub(crate) point_groups: Vec<(String, Vec<u32>)>,
    /// CSR over OWNED nodes: sorted global ids of all nodes sharing a tet with the node (itself included),
    /// over the whole mesh. Row `i` is `node_nbr[node_nbr_offsets[i]..node_nbr_offsets[i + 1]]`.
    pub(crate) node_nbr_offsets: Vec<usize>,
    pub(crate) node_nbr: Vec<u32>,
    /// Parallel to `node_nbr`: the neighbour's global vertex id, or -1.
    pub(crate) node_nbr_vertex_global: Vec<i32>,
    /// Rank r owns global nodes `node_ranges[r]..node_ranges[r + 1]` (length nranks + 1).
    pub(crate) node_ranges: Vec<usize>,
    /// Rank r owns global vertices `vertex_ranges[r]..vertex_ranges[r + 1]` (length nranks + 1).
    pub(crate) vertex_ranges: Vec<usize>,
}

impl LocalMesh {
    /// Whether local node `local` is owned by this rank (owned nodes come first).
    #[cfg(test)]
    pub(crate) fn is_owned_node(&self, local: usize) -> bool {
        local < self.n_owned_nodes
    }

    /// Whether local vertex `local` is owned by this rank (owned vertices come first).
    #[cfg(test)]
    pub(crate) fn is_owned_vertex(&self, local: usize) -> bool {
        local < self.n_owned_vertices
    }

    /// Rank owning global node `g` (`g < n_global_nodes`).
    #[cfg(test)]
    pub(crate) fn owner_of_global_node(&self, g: usize) -> usize {
        owner_in(&self.node_ranges, g)
    }

    /// Rank owning global vertex `g` (`g < n_global_vertices`).
    #[cfg(test)]
    pub(crate) fn owner_of_global_vertex(&self, g: usize) -> usize {
        owner_in(&self.vertex_ranges, g)
    }

    /// The nodes of local cell e.
    pub(crate) fn cell(&self, e: usize) -> &[u32] {
        &self.cells[e][..self.family.cell_nodes()]
    }

    /// The nodes of local face f.
    pub(crate) fn face(&self, f: usize) -> &[u32] {
        &self.faces[f][..self.family.face_nodes()]
    }

    /// Number of local nodes (owned + ghost).
    pub(crate) fn n_nodes(&self) -> usize {
        self.coords.len()
    }

    /// Number of local vertices (owned + ghost).
    pub(crate) fn n_vertices(&self) -> usize {
        self.vertex_node.len()
    }
}

/// Index r with ranges[r] <= g < ranges[r + 1] (empty ranks are skipped).
#[cfg(test)]
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
pub(crate) fn distribute(mesh: &Mesh, part: &[u32], nranks: usize, rank: usize) -> Result<LocalMesh> {
    check_partition(mesh, part, nranks, rank)?;
    let nt = mesh.cells.len();
    let r32 = rank as u32;
    let num = Numbering::new(mesh, part, nranks)?;

    // Local cells.
    let cell_original: Vec<u32> = (0..nt as u32).filter(|&t| part[t as usize] == r32).collect();
    let elem_offset = part.iter().filter(|&&p| p < r32).count();

    let nodes = LocalNodes::new(mesh, &num, &cell_original, r32);
    let local_of = &nodes.local_of;
    let coords: Vec<[f64; 3]> = nodes.original.iter().map(|&n| mesh.coords[n as usize]).collect();
    let node_global: Vec<u32> = nodes.original.iter().map(|&n| num.gnode[n as usize]).collect();
    #[cfg(test)]
    let node_owner: Vec<u32> = nodes.original.iter().map(|&n| num.owner[n as usize]).collect();
    let vertices = LocalVertices::new(mesh, &num, &nodes);

    let relabel = |n: u32| if n == u32::MAX { n } else { local_of[n as usize] };
    let cells: Vec<[u32; MAX_CELL_NODES]> =
        cell_original.iter().map(|&t| mesh.cells[t as usize].map(relabel)).collect();
    let mut local_tet = vec![u32::MAX; nt];
    for (l, &t) in cell_original.iter().enumerate() {
        local_tet[t as usize] = l as u32;
    }
    let faces = LocalFaces::new(mesh, &local_tet, relabel)?;
    let face_groups = map_groups(&mesh.face_groups, &faces.local_of);
    let point_groups = map_groups(&mesh.point_groups, local_of);
    let graph = NeighbourGraph::new(mesh, &num, &nodes);

    Ok(LocalMesh {
        family: mesh.family,
        rank,
        nranks,
        coords,
        n_owned_nodes: nodes.n_owned,
        node_global,
        node_original: nodes.original,
        node_offset: num.node_ranges[rank],
        n_global_nodes: mesh.coords.len(),
        #[cfg(test)]
        node_owner,
        vertex_of_node: vertices.of_node,
        vertex_node: vertices.node,
        n_owned_vertices: vertices.n_owned,
        vertex_global: vertices.global,
        #[cfg(test)]
        vertex_offset: num.vertex_ranges[rank],
        n_global_vertices: num.vertex_ranges[nranks],
        cells,
        cell_original,
        elem_offset,
        n_global_elems: nt,
        faces: faces.faces,
        face_cell: faces.face_cell,
        face_groups,
        #[cfg(test)]
        volume_groups: map_groups(&mesh.volume_groups, &local_tet),
        point_groups,
        node_nbr_offsets: graph.offsets,
        node_nbr: graph.nbr,
        node_nbr_vertex_global: graph.vertex_global,
        node_ranges: num.node_ranges,
        vertex_ranges: num.vertex_ranges,
    })
}

fn err(msg: String) -> Error {
    Error::mesh("distribute", msg)
}

/// The partition covers every cell with a part below `nranks`, and `rank` is one of them.
fn check_partition(mesh: &Mesh, part: &[u32], nranks: usize, rank: usize) -> Result<()> {
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
    Ok(())
}

/// Owners, per-rank counts and the global numbering of nodes and vertices (identical on every
/// rank), indexed by the file's node.
struct Numbering {
    /// Owning rank of each node.
    owner: Vec<u32>,
    node_ranges: Vec<usize>,
    vertex_ranges: Vec<usize>,
    /// Global node id of each node.
    gnode: Vec<u32>,
    /// Global vertex id of each node, -1 for a mid-edge node.
    gvertex: Vec<i32>,
}

impl Numbering {
    fn new(mesh: &Mesh, part: &[u32], nranks: usize) -> Result<Numbering> {
        let nn = mesh.coords.len();
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
        Ok(Numbering { owner, node_ranges, vertex_ranges, gnode, gvertex })
    }
}

/// A rank's nodes: owned in original (= global) order, then ghosts sorted by global id.
struct LocalNodes {
    /// Local node -> file node.
    original: Vec<u32>,
    n_owned: usize,
    /// File node -> local node, or u32::MAX.
    local_of: Vec<u32>,
}

impl LocalNodes {
    fn new(mesh: &Mesh, num: &Numbering, cell_original: &[u32], rank: u32) -> LocalNodes {
        let nn = mesh.coords.len();
        let mut local_of = vec![u32::MAX; nn];
        let mut original: Vec<u32> = (0..nn as u32).filter(|&n| num.owner[n as usize] == rank).collect();
        let n_owned = original.len();
        let mut ghosts: Vec<u32> = Vec::new();
        for &t in cell_original {
            for &n in mesh.cell(t as usize) {
                if num.owner[n as usize] != rank {
                    ghosts.push(n);
                }
            }
        }
        ghosts.sort_unstable_by_key(|&n| num.gnode[n as usize]);
        ghosts.dedup();
        original.extend_from_slice(&ghosts);
        for (l, &n) in original.iter().enumerate() {
            local_of[n as usize] = l as u32;
        }
        LocalNodes { original, n_owned, local_of }
    }
}

/// A rank's vertices, in local node order: ghost nodes are in (owner, original id) order, which
/// is also global vertex order.
struct LocalVertices {
    /// Local node -> local vertex, or -1.
    of_node: Vec<i32>,
    /// Local vertex -> local node.
    node: Vec<u32>,
    /// Local vertex -> global vertex.
    global: Vec<u32>,
    n_owned: usize,
}

impl LocalVertices {
    fn new(mesh: &Mesh, num: &Numbering, nodes: &LocalNodes) -> LocalVertices {
        let mut v =
            LocalVertices { of_node: vec![-1i32; nodes.original.len()], node: vec![], global: vec![], n_owned: 0 };
        for (l, &n) in nodes.original.iter().enumerate() {
            if mesh.is_vertex[n as usize] {
                v.of_node[l] = v.node.len() as i32;
                v.node.push(l as u32);
                v.global.push(num.gvertex[n as usize] as u32);
                if l < nodes.n_owned {
                    v.n_owned += 1;
                }
            }
        }
        v
    }
}

/// The boundary faces of the local cells, in increasing file face index, with local node ids.
struct LocalFaces {
    faces: Vec<[u32; MAX_FACE_NODES]>,
    /// Local face -> (local cell, local face index of that cell).
    face_cell: Vec<(u32, u8)>,
    /// File face -> local face, or u32::MAX.
    local_of: Vec<u32>,
}

impl LocalFaces {
    /// `local_tet`: file cell -> local cell or u32::MAX; `relabel`: file node -> local node.
    fn new(mesh: &Mesh, local_tet: &[u32], relabel: impl Fn(u32) -> u32) -> Result<LocalFaces> {
        let nt = mesh.cells.len();
        let mut f = LocalFaces { faces: vec![], face_cell: vec![], local_of: vec![u32::MAX; mesh.faces.len()] };
        for (i, (face, &(t, lf))) in mesh.faces.iter().zip(&mesh.face_cell).enumerate() {
            let lt = *local_tet.get(t as usize).ok_or_else(|| err(format!("face {i} references tet {t} >= {nt}")))?;
            if lt != u32::MAX {
                f.local_of[i] = f.faces.len() as u32;
                f.faces.push(face.map(&relabel));
                f.face_cell.push((lt, lf));
            }
        }
        Ok(f)
    }
}

/// The neighbour graph of the owned nodes over the whole mesh (owned node -> cells containing it
/// -> their nodes), as CSR rows of sorted global node ids (see [`LocalMesh::node_nbr`]).
struct NeighbourGraph {
    offsets: Vec<usize>,
    nbr: Vec<u32>,
    vertex_global: Vec<i32>,
}

impl NeighbourGraph {
    fn new(mesh: &Mesh, num: &Numbering, nodes: &LocalNodes) -> NeighbourGraph {
        let (n_owned, local_of) = (nodes.n_owned, &nodes.local_of);
        let ncn = mesh.family.cell_nodes();
        let mut tet_start = vec![0usize; n_owned + 1];
        for tet in &mesh.cells {
            for &n in &tet[..ncn] {
                let l = local_of[n as usize] as usize;
                if l < n_owned {
                    tet_start[l + 1] += 1;
                }
            }
        }
        for i in 0..n_owned {
            tet_start[i + 1] += tet_start[i];
        }
        let mut fill = tet_start[..n_owned].to_vec();
        let mut tets_of = vec![0u32; tet_start[n_owned]];
        for (t, tet) in mesh.cells.iter().enumerate() {
            for &n in &tet[..ncn] {
                let l = local_of[n as usize] as usize;
                if l < n_owned {
                    tets_of[fill[l]] = t as u32;
                    fill[l] += 1;
                }
            }
        }
        drop(fill);
        let mut offsets = Vec::with_capacity(n_owned + 1);
        offsets.push(0);
        let mut nbr = Vec::with_capacity(n_owned * 20);
        let mut vertex_global = Vec::with_capacity(n_owned * 20);
        // mark[n] = last row that listed node n: dedup before sorting keeps the sorts short.
        let mut mark = vec![u32::MAX; mesh.coords.len()];
        let mut row: Vec<(u32, i32)> = Vec::new();
        for i in 0..n_owned {
            row.clear();
            for &t in &tets_of[tet_start[i]..tet_start[i + 1]] {
                for &n in mesh.cell(t as usize) {
                    if mark[n as usize] != i as u32 {
                        mark[n as usize] = i as u32;
                        row.push((num.gnode[n as usize], num.gvertex[n as usize]));
                    }
                }
            }
            row.sort_unstable();
            nbr.extend(row.iter().map(|e| e.0));
            vertex_global.extend(row.iter().map(|e| e.1));
            offsets.push(nbr.len());
        }
        NeighbourGraph { offsets, nbr, vertex_global }
    }
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

/// Measures of the local cells' straight (vertex) shapes, over all ranks. The element kernel's
/// stabilisation length (`fem::cell::CellShape::h2`, the edge of the regular cell of a measure)
/// is another measure, per cell and on the current shape.
impl LocalMesh {
    /// Mean edge-length scale: volume^(1/3) of the vertex tetrahedra, area^(1/2) of the vertex
    /// triangles on the meridian; 1 for an empty mesh (collective).
    pub(crate) fn mean_size(&self, world: &SimpleCommunicator) -> f64 {
        let sum: f64 = (0..self.cells.len())
            .map(|e| {
                let m = self.straight_measure(e);
                match self.family {
                    Family::Tet10 => m.cbrt(),
                    Family::Tri6 => m.sqrt(),
                }
            })
            .sum();
        let global = crate::parallel::sum_slice(world, &[sum, self.cells.len() as f64]);
        if global[1] > 0.0 {
            global[0] / global[1]
        } else {
            1.0
        }
    }

    /// Volume of the straight (vertex) cells: tetrahedra, or the rings the meridian triangles
    /// sweep (Pappus: 2π × centroid radius × area) (collective).
    pub(crate) fn volume(&self, world: &SimpleCommunicator) -> f64 {
        let local: f64 = (0..self.cells.len())
            .map(|e| {
                let m = self.straight_measure(e);
                match self.family {
                    Family::Tet10 => m,
                    Family::Tri6 => {
                        let x = |i: usize| self.coords[self.cells[e][i] as usize];
                        2.0 * std::f64::consts::PI * (x(0)[0] + x(1)[0] + x(2)[0]) / 3.0 * m
                    }
                }
            })
            .sum();
        crate::parallel::sum(world, local)
    }

    /// Volume (area on the meridian) of the straight cell through local cell e's vertices.
    fn straight_measure(&self, e: usize) -> f64 {
        let t = &self.cells[e];
        crate::reference_cell::straight_measure(self.family, |i| self.coords[t[i] as usize])
    }
}
