//! Per-node rotated frames for contact on curved tools (issue 53, design §3.2–3.3): a node in
//! contact with a tool of normal n̂ gets the rotation Q (columns: tangents, then n̂) that takes
//! e_z to n̂, so that its last rotated unknown Qᵀu is the normal one and the contact stays a
//! bound on a single unknown. The assembled matrix is rotated in place, B = QᵀAQ with Q block
//! diagonal (Q_n at framed nodes, the identity elsewhere), through its local CSR blocks: no new
//! matrix, the same pattern, block size and Mat object for the preconditioner.
//!
//! What makes the in-place rotation a local operation: the Jacobian's pattern holds full element
//! blocks, so the nc u rows of a node have one column list, and every row holding one u column
//! of a node holds all nc of them, adjacent (also in the off-diagonal block: garray is sorted).
//! [`FrameIndex::build`] checks both and fails otherwise. Ghost nodes' frames are computed
//! from ghost values on every rank that holds them, so the column rotation needs no
//! communication.

// Wired into the active-set Newton in stage b (issue 53): until then only the tests use it.
#![allow(dead_code)]

use crate::error::{Error, Result};
use crate::petsc::{CsrBlock, Int, LocalCsr, Mat};
use std::collections::HashMap;

/// A node's rotation Q (nc × nc, nc = 2 on the meridian or 3; row-major, the unused entries of
/// a 2 × 2 frame zero): its columns are the tangents and, last, the contact normal n̂.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Frame {
    q: [[f64; 3]; 3],
    nc: usize,
}

impl Frame {
    /// The meridian frame of the unit normal n̂ = (n_r, n_z): Q = [[n_z, n_r], [−n_r, n_z]], the
    /// 3-D one ([`Frame::spatial`]) restricted to the (r, z) plane. n̂ = e_z gives the identity
    /// bit for bit.
    pub(crate) fn meridian(n: [f64; 2]) -> Frame {
        let [nr, nz] = n;
        Frame { q: [[nz, nr, 0.0], [-nr, nz, 0.0], [0.0; 3]], nc: 2 }
    }

    /// The rotation taking e_z to the unit normal n̂ about k = e_z × n̂ (Rodrigues):
    /// Q = I + [k]× + [k]×² / (1 + n_z). n̂ = e_z gives k = 0 and the identity bit for bit.
    /// Needs n_z > −1 (the caller's choice of the normal's sign keeps n_z ≥ −½).
    pub(crate) fn spatial(n: [f64; 3]) -> Frame {
        let [nx, ny, nz] = n;
        let (kx, ky) = (-ny, nx);
        let c = 1.0 / (1.0 + nz);
        // [k]× with k = (kx, ky, 0), and [k]×² = k kᵀ − |k|² I.
        let kk = kx * kx + ky * ky;
        let q = [
            [1.0 + c * (kx * kx - kk), c * kx * ky, ky],
            [c * kx * ky, 1.0 + c * (ky * ky - kk), -kx],
            [-ky, kx, 1.0 - c * kk],
        ];
        Frame { q, nc: 3 }
    }

    pub(crate) fn components(&self) -> usize {
        self.nc
    }

    /// Whether Q is exactly the identity (then rotating by it is skipped, which keeps the
    /// arithmetic of the plates' frames bit for bit).
    pub(crate) fn is_identity(&self) -> bool {
        (0..self.nc).all(|i| (0..self.nc).all(|j| self.q[i][j] == if i == j { 1.0 } else { 0.0 }))
    }

    /// Qᵀ, the inverse rotation.
    pub(crate) fn transposed(&self) -> Frame {
        Frame { q: std::array::from_fn(|i| std::array::from_fn(|j| self.q[j][i])), nc: self.nc }
    }

    /// Q's entry (i, j).
    pub(crate) fn entry(&self, i: usize, j: usize) -> f64 {
        self.q[i][j]
    }

    /// v ← Qᵀ v on the nc entries of `v` (Cartesian to rotated components).
    pub(crate) fn frame_components(&self, v: &mut [f64]) {
        let w: [f64; 3] = std::array::from_fn(|j| (0..self.nc).map(|i| self.q[i][j] * v[i]).sum());
        v[..self.nc].copy_from_slice(&w[..self.nc]);
    }

    /// v ← Q v on the nc entries of `v` (rotated to Cartesian components).
    pub(crate) fn cartesian_components(&self, v: &mut [f64]) {
        let w: [f64; 3] = std::array::from_fn(|i| (0..self.nc).map(|j| self.q[i][j] * v[j]).sum());
        v[..self.nc].copy_from_slice(&w[..self.nc]);
    }
}

/// Where a value sits in the local CSR blocks.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Pos {
    Diag(usize),
    Off(usize),
}

/// The positions of each candidate node's rows and column segments in the local CSR blocks of
/// an assembled matrix, found once (the pattern is fixed after the first assembly, as for
/// `fem::insert::ElementInserter`).
pub(crate) struct FrameIndex {
    nc: usize,
    /// Per candidate node: its first local row (owned nodes only).
    rows: Vec<Option<usize>>,
    /// Per candidate node: the first value of each nc-entry segment of its u columns, in every
    /// local row.
    cols: Vec<Vec<Pos>>,
}

impl FrameIndex {
    /// The index for the candidate nodes whose first global u dof is `first_dofs[i]` (owned and
    /// ghost nodes; each node's u dofs are nc consecutive global indices). Fails if the pattern
    /// of `csr` breaks the assumptions of the module docs.
    pub(crate) fn build(csr: &LocalCsr, nc: usize, first_dofs: &[Int]) -> Result<FrameIndex> {
        let err = |what: String| Error::Internal(format!("contact frames: matrix pattern: {what}"));
        // Each u dof of a candidate → (candidate, component).
        let mut dof_of: HashMap<Int, (usize, usize)> = HashMap::with_capacity(nc * first_dofs.len());
        for (i, &g) in first_dofs.iter().enumerate() {
            for c in 0..nc {
                if dof_of.insert(g + c as Int, (i, c)).is_some() {
                    return Err(err(format!("candidate node {i} given twice")));
                }
            }
        }
        let n_rows = csr.diag.ia.len() - 1;
        let owned = |g: Int| (csr.row_start..csr.row_start + n_rows).contains(&(g as usize));
        let rows: Vec<Option<usize>> =
            first_dofs.iter().map(|&g| owned(g).then(|| g as usize - csr.row_start)).collect();
        let mut cols = vec![Vec::new(); first_dofs.len()];
        let diag_col = |j: Int| j + csr.col_start as Int;
        scan_block(&csr.diag, &dof_of, nc, diag_col, Pos::Diag, &mut cols).map_err(err)?;
        if let Some(off) = &csr.off {
            scan_block(off, &dof_of, nc, |j| csr.garray[j as usize], Pos::Off, &mut cols).map_err(err)?;
        }
        // The nc rows of an owned candidate share one column list.
        let same_list = |b: &CsrBlock, r: usize| {
            let list = |r: usize| &b.ja[b.ia[r] as usize..b.ia[r + 1] as usize];
            (1..nc).all(|c| list(r + c) == list(r))
        };
        for (i, r) in rows.iter().enumerate() {
            if let Some(r) = *r {
                if !same_list(&csr.diag, r) || csr.off.as_ref().is_some_and(|o| !same_list(o, r)) {
                    return Err(err(format!("the u rows of candidate node {i} differ in their columns")));
                }
            }
        }
        Ok(FrameIndex { nc, rows, cols })
    }

    /// B = QᵀAQ in place, `frames[i]` the frame of candidate node i (None: the identity, skipped).
    pub(crate) fn rotate(&self, csr: &mut LocalCsr, frames: &[Option<Frame>]) {
        self.apply(csr, frames, false);
    }

    /// A = QBQᵀ in place: undoes [`rotate`](Self::rotate) with the same frames.
    pub(crate) fn rotate_back(&self, csr: &mut LocalCsr, frames: &[Option<Frame>]) {
        self.apply(csr, frames, true);
    }

    /// Rotates the local rows and columns by each frame's Q (`back`: by Qᵀ).
    fn apply(&self, csr: &mut LocalCsr, frames: &[Option<Frame>], back: bool) {
        let nc = self.nc;
        debug_assert_eq!(frames.len(), self.rows.len());
        let framed = frames.iter().enumerate().filter_map(|(i, f)| f.filter(|f| !f.is_identity()).map(|f| (i, f)));
        for (i, f) in framed {
            let f = if back { f.transposed() } else { f };
            debug_assert_eq!(f.components(), nc);
            // Rows: each column position j of the node's nc rows, [a_0j … a_{nc−1}j] ← Qᵀ[…].
            if let Some(r) = self.rows[i] {
                for block in std::iter::once(&mut csr.diag).chain(csr.off.as_mut()) {
                    let starts: [usize; 3] = std::array::from_fn(|c| block.ia[r + c.min(nc - 1)] as usize);
                    let len = block.ia[r + 1] as usize - starts[0];
                    for k in 0..len {
                        let mut v: [f64; 3] = std::array::from_fn(|c| block.vals[starts[c] + k]);
                        f.frame_components(&mut v);
                        for c in 0..nc {
                            block.vals[starts[c] + k] = v[c];
                        }
                    }
                }
            }
            // Columns: every row's nc-entry segment s of this node, s ← s Q (Qᵀ sᵀ).
            for &p in &self.cols[i] {
                let seg = match p {
                    Pos::Diag(k) => &mut csr.diag.vals[k..k + nc],
                    Pos::Off(k) => match csr.off.as_mut() {
                        Some(o) => &mut o.vals[k..k + nc],
                        None => continue,
                    },
                };
                f.frame_components(seg);
            }
        }
    }
}

/// Records in `cols` the start of each candidate's column segment in every row of `block`
/// (`global(j)`: the global column of compressed column j); fails where a row holds a
/// candidate's u columns other than as one complete, adjacent segment.
fn scan_block(
    block: &CsrBlock,
    dof_of: &HashMap<Int, (usize, usize)>,
    nc: usize,
    global: impl Fn(Int) -> Int,
    pos: fn(usize) -> Pos,
    cols: &mut [Vec<Pos>],
) -> std::result::Result<(), String> {
    for r in 0..block.ia.len() - 1 {
        let (start, end) = (block.ia[r] as usize, block.ia[r + 1] as usize);
        let mut k = start;
        while k < end {
            let g = global(block.ja[k]);
            match dof_of.get(&g) {
                None => k += 1,
                Some(&(i, 0)) => {
                    let whole = k + nc <= end && (1..nc).all(|c| global(block.ja[k + c]) == g + c as Int);
                    if !whole {
                        return Err(format!("local row {r} holds part of candidate node {i}'s u columns"));
                    }
                    cols[i].push(pos(k));
                    k += nc;
                }
                Some(&(i, c)) => {
                    return Err(format!("local row {r} holds candidate node {i}'s u column {c} without the first"))
                }
            }
        }
    }
    Ok(())
}

/// Rotates the assembled matrix `a` in place (B = QᵀAQ; `back`: the inverse) and assembles it,
/// which bumps its state so that a preconditioner set up on it sees the new values.
pub(crate) fn rotate_matrix(a: &mut Mat, index: &FrameIndex, frames: &[Option<Frame>], back: bool) -> Result<()> {
    a.with_local_csr(|csr| {
        index.apply(csr, frames, back);
        Ok(())
    })?;
    a.assemble()
}

/// Rotates the owned u entries of a vector's local array `v` to the frames (Qᵀ; `back`: Q):
/// `framed` holds (owned local node, its frame). Local: no communication.
pub(crate) fn rotate_owned(v: &mut [f64], framed: &[(usize, Frame)], back: bool) {
    for (n, f) in framed {
        let nc = f.components();
        let u = &mut v[nc * n..nc * n + nc];
        if back {
            f.cartesian_components(u)
        } else {
            f.frame_components(u)
        }
    }
}
