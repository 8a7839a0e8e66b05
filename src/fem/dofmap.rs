//! Degrees of freedom of Taylor–Hood P2–P1 on the distributed mesh.
//!
//! Global layout: rank r owns one contiguous block [u of its owned nodes (nc per node: xyz, or
//! rz on the meridian, interleaved) | p of its owned vertices]. So the u and p index sets are
//! contiguous per rank, the u block has block size nc (for AMG with rigid-body modes), and a
//! global node g owned by rank s has u dofs nc g + `vertex_ranges[s]` + c, a global vertex v owned
//! by s has p dof nc node_ranges[s+1] + v.
//! Local layout (what elements read and write): u of local node n at nc n + c, then p of local
//! vertex m at nc n_nodes + m; owned entries come first in each part.

use super::element::{ElementDofs, MAX_DOF};
use crate::mesh::dist::LocalMesh;
use crate::petsc::Int;

pub(crate) struct DofMap {
    pub(crate) rank: usize,
    /// Displacement components per node (3, or 2 on the meridian: u_r, u_z); z is the last.
    pub(crate) nc: usize,
    /// Local nodes / vertices (owned + ghost).
    pub(crate) n_nodes: usize,
    pub(crate) n_owned_nodes: usize,
    pub(crate) n_owned_vertices: usize,
    /// Dofs owned here, first owned global dof, total.
    pub(crate) n_owned: usize,
    pub(crate) offset: usize,
    pub(crate) n_global: usize,
    /// Local dof → global dof.
    pub(crate) l2g: Vec<Int>,
    node_ranges: Vec<usize>,
    vertex_ranges: Vec<usize>,
}

impl DofMap {
    pub(crate) fn new(m: &LocalMesh) -> DofMap {
        let (nr, vr) = (&m.node_ranges, &m.vertex_ranges);
        let n_nodes = m.coords.len();
        let n_vertices = m.vertex_node.len();
        let nc = m.family.components();
        let mut d = DofMap {
            rank: m.rank,
            nc,
            n_nodes,
            n_owned_nodes: m.n_owned_nodes,
            n_owned_vertices: m.n_owned_vertices,
            n_owned: nc * m.n_owned_nodes + m.n_owned_vertices,
            offset: nc * nr[m.rank] + vr[m.rank],
            n_global: nc * nr[m.nranks] + vr[m.nranks],
            l2g: Vec::with_capacity(nc * n_nodes + n_vertices),
            node_ranges: nr.clone(),
            vertex_ranges: vr.clone(),
        };
        for n in 0..n_nodes {
            let g = m.node_global[n] as usize;
            for c in 0..nc {
                d.l2g.push(d.u_global(g, c) as Int);
            }
        }
        for v in 0..n_vertices {
            d.l2g.push(d.p_global(m.vertex_global[v] as usize) as Int);
        }
        d
    }

    /// Local dofs of cell `e` of `m` in the kernel's order (`fem::element`): u of node a,
    /// component c at nc a + c, then p of vertex m.
    pub(crate) fn element_dofs(&self, m: &LocalMesh, e: usize) -> ElementDofs {
        let (nn, nv, nc) = (m.family.cell_nodes(), m.family.cell_vertices(), self.nc);
        let t = &m.cells[e];
        let mut d = [0usize; MAX_DOF];
        for a in 0..nn {
            for c in 0..nc {
                d[nc * a + c] = self.u_local(t[a] as usize, c);
            }
        }
        for v in 0..nv {
            d[nc * nn + v] = self.p_local(m.vertex_of_node[t[v] as usize] as usize);
        }
        d
    }

    fn owner(ranges: &[usize], g: usize) -> usize {
        ranges.partition_point(|&s| s <= g) - 1
    }

    /// Global u dof of global node `g`, component `c`.
    pub(crate) fn u_global(&self, g: usize, c: usize) -> usize {
        self.nc * g + self.vertex_ranges[Self::owner(&self.node_ranges, g)] + c
    }

    /// Global p dof of global vertex `v`.
    pub(crate) fn p_global(&self, v: usize) -> usize {
        self.nc * self.node_ranges[Self::owner(&self.vertex_ranges, v) + 1] + v
    }

    /// Local u dof of local node n.
    #[inline]
    pub(crate) fn u_local(&self, n: usize, c: usize) -> usize {
        self.nc * n + c
    }
    /// Local u_z dof of local node n (z is the last component).
    #[inline]
    pub(crate) fn uz_local(&self, n: usize) -> usize {
        self.nc * n + self.nc - 1
    }
    /// Number of local u dofs (owned + ghost nodes).
    #[inline]
    pub(crate) fn n_u_local(&self) -> usize {
        self.nc * self.n_nodes
    }
    /// Number of owned u dofs.
    #[inline]
    pub(crate) fn n_u_owned(&self) -> usize {
        self.nc * self.n_owned_nodes
    }
    /// Local p dof of local vertex m.
    #[inline]
    pub(crate) fn p_local(&self, m: usize) -> usize {
        self.nc * self.n_nodes + m
    }
    /// Size of the local (owned + ghost) vector.
    pub(crate) fn n_local(&self) -> usize {
        self.l2g.len()
    }

    /// Whether a local dof is owned here.
    #[inline]
    pub(crate) fn is_owned(&self, l: usize) -> bool {
        let nu = self.n_u_local();
        if l < nu {
            l < self.n_u_owned()
        } else {
            l - nu < self.n_owned_vertices
        }
    }
    /// Position of an owned local dof among the owned dofs (its global index minus offset).
    #[inline]
    pub(crate) fn local_to_owned(&self, l: usize) -> Option<usize> {
        if !self.is_owned(l) {
            return None;
        }
        let nu = self.n_u_local();
        Some(if l < nu { l } else { self.n_u_owned() + (l - nu) })
    }

    /// Global u range [start, end) owned here, and p range.
    pub(crate) fn u_range(&self) -> (usize, usize) {
        (self.offset, self.offset + self.n_u_owned())
    }
    pub(crate) fn p_range(&self) -> (usize, usize) {
        let s = self.offset + self.n_u_owned();
        (s, s + self.n_owned_vertices)
    }

    /// Exact nonzeros per owned row, in the diagonal and off-diagonal blocks, of the full u–p
    /// matrix and of the pressure-only Schur matrix, from the node neighbour graph.
    pub(crate) fn preallocation(&self, m: &LocalMesh) -> Preallocation {
        let (nlo, nhi) = (self.node_ranges[self.rank], self.node_ranges[self.rank + 1]);
        let (vlo, vhi) = (self.vertex_ranges[self.rank], self.vertex_ranges[self.rank + 1]);
        let mut node_counts = Vec::with_capacity(self.n_owned_nodes);
        for n in 0..self.n_owned_nodes {
            let (mut d, mut o, mut dv, mut ov) = (0, 0, 0, 0);
            for k in m.node_nbr_offsets[n]..m.node_nbr_offsets[n + 1] {
                let g = m.node_nbr[k] as usize;
                if (nlo..nhi).contains(&g) {
                    d += self.nc;
                } else {
                    o += self.nc;
                }
                let gv = m.node_nbr_vertex_global[k];
                if gv >= 0 {
                    if (vlo..vhi).contains(&(gv as usize)) {
                        dv += 1;
                    } else {
                        ov += 1;
                    }
                }
            }
            node_counts.push((d + dv, o + ov, dv, ov));
        }
        let mut p = Preallocation {
            d_nnz: Vec::with_capacity(self.n_owned),
            o_nnz: Vec::with_capacity(self.n_owned),
            schur_d: vec![],
            schur_o: vec![],
        };
        for &(d, o, _, _) in &node_counts {
            for _ in 0..self.nc {
                p.d_nnz.push(d as Int);
                p.o_nnz.push(o as Int);
            }
        }
        for v in 0..self.n_owned_vertices {
            let n = m.vertex_node[v] as usize;
            let (d, o, dv, ov) = node_counts[n];
            p.d_nnz.push(d as Int);
            p.o_nnz.push(o as Int);
            p.schur_d.push(dv as Int);
            p.schur_o.push(ov as Int);
        }
        p
    }
}

pub(crate) struct Preallocation {
    pub(crate) d_nnz: Vec<Int>,
    pub(crate) o_nnz: Vec<Int>,
    pub(crate) schur_d: Vec<Int>,
    pub(crate) schur_o: Vec<Int>,
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::mesh::dist;
    use crate::reference_cell::Family;

    /// The unit cube (and the meridian square) split over 3 ranks by blocks of cells, without MPI:
    /// the owned dofs of the ranks tile 0..n_global once each, in each rank's [offset, offset +
    /// n_owned) with u before p; a node or vertex shared by ranks has the same global dofs on
    /// each; and local_to_owned is the global index minus the offset.
    #[test]
    fn dofs_number_every_node_and_vertex_once_across_ranks() {
        for family in [Family::Tet10, Family::Tri6] {
            let mesh = crate::mesh::test_util::structured(family, 3);
            let (nranks, ncells) = (3, mesh.cells.len());
            let part: Vec<u32> = (0..ncells).map(|c| (c * nranks / ncells) as u32).collect();
            let locals: Vec<_> = (0..nranks).map(|r| dist::distribute(&mesh, &part, nranks, r).unwrap()).collect();
            let maps: Vec<_> = locals.iter().map(DofMap::new).collect();
            let nc = family.components();
            let total = nc * mesh.coords.len() + mesh.n_vertices();
            let mut owned_by = vec![usize::MAX; total];
            let mut of_node = std::collections::HashMap::new();
            for (r, (l, d)) in locals.iter().zip(&maps).enumerate() {
                assert_eq!(d.n_global, total);
                assert_eq!(d.u_range(), (d.offset, d.offset + d.n_u_owned()));
                assert_eq!(d.p_range().1, d.offset + d.n_owned);
                for i in 0..d.n_local() {
                    let g = d.l2g[i] as usize;
                    if let Some(k) = d.local_to_owned(i) {
                        assert_eq!(owned_by[g], usize::MAX, "global dof {g} owned twice");
                        owned_by[g] = r;
                        assert_eq!(k, g - d.offset);
                    }
                }
                for n in 0..l.coords.len() {
                    let dofs: Vec<Int> = (0..nc).map(|c| d.l2g[d.u_local(n, c)]).collect();
                    let v = l.vertex_of_node[n];
                    let p = (v >= 0).then(|| d.l2g[d.p_local(v as usize)]);
                    let seen = of_node.entry(l.node_original[n]).or_insert((dofs.clone(), p));
                    assert_eq!(*seen, (dofs, p), "node {} numbered differently on rank {r}", l.node_original[n]);
                }
            }
            assert!(owned_by.iter().all(|&r| r < nranks), "a global dof no rank owns");
            assert_eq!(of_node.len(), mesh.coords.len());
        }
    }
}
