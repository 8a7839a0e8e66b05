//! Tests of the frames and of the in-place rotation against dense computations, on one rank's
//! local CSR blocks built here as PETSc's MPIAIJ split holds them.

use super::frames::{rotate_owned, Frame, FrameIndex};
use crate::petsc::{CsrBlock, Int, LocalCsr};
use std::collections::BTreeSet;

/// Two ranks' dofs, `nc` u components per node: rank 0 owns nodes 0–2 then its p dof, rank 1
/// (the one under test) nodes 3–5 then its p dof. Returns (global first u dof of each node,
/// the p dofs, this rank's row range, the size).
fn layout(nc: usize) -> (Vec<Int>, [Int; 2], (usize, usize), usize) {
    let first: Vec<Int> = (0..6).map(|g| (nc * g + if g < 3 { 0 } else { 1 }) as Int).collect();
    let p = [(3 * nc) as Int, (6 * nc + 1) as Int];
    (first, p, (3 * nc + 1, 6 * nc + 2), 6 * nc + 2)
}

/// The full element pattern of four cells (their nodes' u dofs and one or two p dofs), with
/// deterministic non-symmetric values on it: the dense matrix, zero off the pattern.
fn dense(nc: usize) -> Vec<Vec<f64>> {
    let (first, p, _, n) = layout(nc);
    let cells: [(&[usize], &[Int]); 4] =
        [(&[0, 1, 3], &[p[0]]), (&[1, 3, 4], &[p[0], p[1]]), (&[2, 4, 5], &[p[1]]), (&[3, 4, 5], &[p[1]])];
    let mut a = vec![vec![0.0; n]; n];
    for (nodes, ps) in cells {
        let dofs: Vec<usize> = nodes
            .iter()
            .flat_map(|&g| {
                let g0 = first[g] as usize;
                (0..nc).map(move |c| g0 + c)
            })
            .chain(ps.iter().map(|&q| q as usize))
            .collect();
        for &i in &dofs {
            for &j in &dofs {
                a[i][j] = ((7 * i + 13 * j * j + 3) % 101) as f64 - 50.5;
            }
        }
    }
    a
}

/// This rank's rows of `a` in the MPIAIJ split: the diagonal block (columns local to the row
/// range) and the off-diagonal block compressed to the sorted global columns `garray`;
/// `keep(i, j)` says which entries of the pattern (nonzero) are stored.
struct Split {
    range: (usize, usize),
    diag: (Vec<Int>, Vec<Int>, Vec<f64>),
    off: (Vec<Int>, Vec<Int>, Vec<f64>),
    garray: Vec<Int>,
}

fn split(a: &[Vec<f64>], range: (usize, usize), keep: impl Fn(usize, usize) -> bool) -> Split {
    let (r0, r1) = range;
    let stored = |i: usize, j: usize| a[i][j] != 0.0 && keep(i, j);
    let garray: Vec<Int> = (r0..r1)
        .flat_map(|i| (0..a.len()).filter(move |&j| stored(i, j) && !(r0..r1).contains(&j)))
        .collect::<BTreeSet<_>>()
        .into_iter()
        .map(|j| j as Int)
        .collect();
    let (mut diag, mut off) = ((vec![0], vec![], vec![]), (vec![0], vec![], vec![]));
    for i in r0..r1 {
        for j in (0..a.len()).filter(|&j| stored(i, j)) {
            if (r0..r1).contains(&j) {
                diag.1.push((j - r0) as Int);
                diag.2.push(a[i][j]);
            } else {
                off.1.push(garray.binary_search(&(j as Int)).unwrap() as Int);
                off.2.push(a[i][j]);
            }
        }
        diag.0.push(diag.1.len() as Int);
        off.0.push(off.1.len() as Int);
    }
    Split { range, diag, off, garray }
}

impl Split {
    fn csr(&mut self) -> LocalCsr<'_> {
        LocalCsr {
            row_start: self.range.0,
            col_start: self.range.0,
            col_end: self.range.1,
            diag: CsrBlock { ia: &self.diag.0, ja: &self.diag.1, vals: &mut self.diag.2 },
            off: Some(CsrBlock { ia: &self.off.0, ja: &self.off.1, vals: &mut self.off.2 }),
            garray: &self.garray,
        }
    }

    /// The local rows as dense rows of global columns.
    fn rows(&self, n: usize) -> Vec<Vec<f64>> {
        let (r0, r1) = self.range;
        let mut out = vec![vec![0.0; n]; r1 - r0];
        for (r, row) in out.iter_mut().enumerate() {
            for k in self.diag.0[r] as usize..self.diag.0[r + 1] as usize {
                row[self.diag.1[k] as usize + r0] = self.diag.2[k];
            }
            for k in self.off.0[r] as usize..self.off.0[r + 1] as usize {
                row[self.garray[self.off.1[k] as usize] as usize] = self.off.2[k];
            }
        }
        out
    }
}

fn unit<const N: usize>(v: [f64; N]) -> [f64; N] {
    let n = v.iter().map(|x| x * x).sum::<f64>().sqrt();
    v.map(|x| x / n)
}

/// Normals of contact on a curved tool, in every octant, one near the −½ bound of n_z.
fn normals() -> Vec<[f64; 3]> {
    vec![unit([0.3, -0.2, 0.9]), unit([-0.7, 0.1, 0.2]), unit([0.5, 0.6, -0.45]), unit([1.0, 0.0, 0.0])]
}

fn frame(nc: usize, n: [f64; 3]) -> Frame {
    if nc == 3 {
        Frame::spatial(n)
    } else {
        Frame::meridian(unit([n[0], n[2]]))
    }
}

/// Q as a dense nc × nc array.
fn q_of(f: &Frame) -> Vec<Vec<f64>> {
    let nc = f.components();
    (0..nc).map(|i| (0..nc).map(|j| f.entry(i, j)).collect()).collect()
}

#[test]
fn a_frame_is_a_rotation_taking_e_z_to_the_normal() {
    for n in normals() {
        for f in [Frame::spatial(n), Frame::meridian(unit([n[0], n[2]]))] {
            let (q, nc) = (q_of(&f), f.components());
            let normal = if nc == 3 { n.to_vec() } else { unit([n[0], n[2]]).to_vec() };
            for i in 0..nc {
                assert!((q[i][nc - 1] - normal[i]).abs() < 1e-15, "{nc}-D frame of {n:?}: last column is not n̂");
                for j in 0..nc {
                    let qtq: f64 = (0..nc).map(|k| q[k][i] * q[k][j]).sum();
                    let id = if i == j { 1.0 } else { 0.0 };
                    // Rodrigues divides by 1 + n_z ≥ ½: a few ulp.
                    assert!((qtq - id).abs() <= 4.0 * f64::EPSILON, "{nc}-D frame of {n:?}: QᵀQ[{i}][{j}] = {qtq}");
                }
            }
            let det = if nc == 2 {
                q[0][0] * q[1][1] - q[0][1] * q[1][0]
            } else {
                (0..3)
                    .map(|i| q[0][i] * (q[1][(i + 1) % 3] * q[2][(i + 2) % 3] - q[1][(i + 2) % 3] * q[2][(i + 1) % 3]))
                    .sum()
            };
            assert!((det - 1.0).abs() < 1e-15, "{nc}-D frame of {n:?}: det {det}, not a rotation");
        }
        // The meridian frame is the 3-D one of a normal in the (x, z) plane, restricted to it.
        let m = unit([n[0], n[2]]);
        let (f2, f3) = (Frame::meridian(m), Frame::spatial([m[0], 0.0, m[1]]));
        for (i, si) in [(0, 0), (1, 2)] {
            for (j, sj) in [(0, 0), (1, 2)] {
                assert!((f2.entry(i, j) - f3.entry(si, sj)).abs() < 1e-15, "meridian frame of {m:?} at ({i}, {j})");
            }
        }
    }
    // The plates' normals: the identity, bit for bit.
    assert!(Frame::spatial([0.0, 0.0, 1.0]).is_identity() && Frame::meridian([0.0, 1.0]).is_identity());
    assert!(Frame::meridian([-0.0, 1.0]).is_identity(), "a signed zero in the normal");
    assert!(!Frame::spatial(unit([1e-9, 0.0, 1.0])).is_identity());
}

/// The candidates: node 1 (a ghost, columns only), 3 and 4 (owned), 5 (owned, a plate's
/// identity frame); nodes 0 and 2 are not candidates.
fn candidates(nc: usize) -> (Vec<Int>, Vec<Option<Frame>>) {
    let (first, ..) = layout(nc);
    let ns = normals();
    let frames =
        vec![Some(frame(nc, ns[0])), Some(frame(nc, ns[1])), Some(frame(nc, ns[2])), Some(frame(nc, [0.0, 0.0, 1.0]))];
    (vec![first[1], first[3], first[4], first[5]], frames)
}

/// Q of the whole system: block diagonal, the candidates' frames, the identity elsewhere.
fn q_full(nc: usize) -> Vec<Vec<f64>> {
    let (_, _, _, n) = layout(nc);
    let (firsts, frames) = candidates(nc);
    let mut q: Vec<Vec<f64>> = (0..n).map(|i| (0..n).map(|j| if i == j { 1.0 } else { 0.0 }).collect()).collect();
    for (g, f) in firsts.iter().zip(&frames) {
        let (g, qn) = (*g as usize, q_of(f.as_ref().unwrap()));
        for i in 0..nc {
            for j in 0..nc {
                q[g + i][g + j] = qn[i][j];
            }
        }
    }
    q
}

#[test]
fn the_rotation_in_place_is_q_transpose_a_q_and_rotating_back_restores_a() {
    for nc in [2, 3] {
        let (_, _, range, n) = layout(nc);
        let a = dense(nc);
        let mut m = split(&a, range, |_, _| true);
        let (firsts, frames) = candidates(nc);
        let index = FrameIndex::build(&m.csr(), nc, &firsts).unwrap();
        index.rotate(&mut m.csr(), &frames);
        let q = q_full(nc);
        let scale = a.iter().flatten().fold(0.0f64, |s, x| s.max(x.abs()));
        let got = m.rows(n);
        for (r, row) in got.iter().enumerate() {
            let i = range.0 + r;
            for (j, &b) in row.iter().enumerate() {
                let want: f64 = (0..n).map(|k| (0..n).map(|l| q[k][i] * a[k][l] * q[l][j]).sum::<f64>()).sum();
                assert!((b - want).abs() <= 1e-14 * scale, "nc {nc}: B[{i}][{j}] = {b}, QᵀAQ has {want}");
            }
        }
        assert!(got.iter().enumerate().any(|(r, row)| row != &a[range.0 + r]), "nc {nc}: nothing rotated");
        index.rotate_back(&mut m.csr(), &frames);
        for (r, row) in m.rows(n).iter().enumerate() {
            for (j, &b) in row.iter().enumerate() {
                let want = a[range.0 + r][j];
                assert!(
                    (b - want).abs() <= 4.0 * f64::EPSILON * scale,
                    "nc {nc}: back at ({}, {j}): {b} vs {want}",
                    range.0 + r
                );
            }
        }
    }
}

#[test]
fn identity_frames_leave_the_matrix_bit_identical() {
    for nc in [2, 3] {
        let (first, _, range, _) = layout(nc);
        let mut m = split(&dense(nc), range, |_, _| true);
        let before: Vec<u64> = m.diag.2.iter().chain(&m.off.2).map(|x| x.to_bits()).collect();
        let firsts = vec![first[1], first[3], first[4], first[5]];
        let plate = frame(nc, [0.0, 0.0, 1.0]);
        let frames = vec![Some(plate), Some(plate), None, Some(plate)];
        let index = FrameIndex::build(&m.csr(), nc, &firsts).unwrap();
        index.rotate(&mut m.csr(), &frames);
        let after: Vec<u64> = m.diag.2.iter().chain(&m.off.2).map(|x| x.to_bits()).collect();
        assert_eq!(before, after, "nc {nc}: a plate's frame changed the matrix");
    }
}

#[test]
fn a_pattern_without_a_nodes_whole_segment_is_refused() {
    let nc = 3;
    let (first, _, range, _) = layout(nc);
    let a = dense(nc);
    // Row of node 3's first u dof without node 4's second u column.
    let (row, col) = (first[3] as usize, first[4] as usize + 1);
    let mut m = split(&a, range, |i, j| (i, j) != (row, col));
    let e = FrameIndex::build(&m.csr(), nc, &[first[4]]).err().expect("a partial segment accepted");
    assert!(format!("{e}").contains("part of candidate node 0"), "{e}");
    // The same hole makes node 3's u rows differ in their columns.
    let e = FrameIndex::build(&m.csr(), nc, &[first[3]]).err().expect("differing rows accepted");
    assert!(format!("{e}").contains("differ in their columns"), "{e}");
    // A column list holding a node's later components without its first.
    let mut m = split(&a, range, |_, j| j != first[4] as usize);
    let e = FrameIndex::build(&m.csr(), nc, &[first[4]]).err().expect("a segment without its first column accepted");
    assert!(format!("{e}").contains("without the first"), "{e}");
}

#[test]
fn vectors_rotate_to_the_normal_component_and_back() {
    for nc in [2, 3] {
        let u: Vec<f64> = (0..4 * nc).map(|k| (k as f64 * 0.37).sin()).collect();
        let ns = normals();
        let framed = vec![(1, frame(nc, ns[0])), (3, frame(nc, ns[2]))];
        let mut v = u.clone();
        rotate_owned(&mut v, &framed, false);
        for (n, f) in &framed {
            let normal: f64 = (0..nc).map(|i| f.entry(i, nc - 1) * u[nc * n + i]).sum();
            assert!((v[nc * n + nc - 1] - normal).abs() < 1e-15, "nc {nc}, node {n}: not n̂·u");
        }
        assert_eq!(&v[..nc], &u[..nc], "nc {nc}: an unframed node changed");
        rotate_owned(&mut v, &framed, true);
        for (a, b) in v.iter().zip(&u) {
            assert!((a - b).abs() < 4.0 * f64::EPSILON, "nc {nc}: back {a} vs {b}");
        }
    }
}
