//! Equal-order P1–P1 on the Taylor–Hood element (`[fem] element = "P1-P1"`): the displacement
//! is linear, each mid-edge node tied to its edge's vertices, u_m = ½ (u_a + u_b).
//!
//! Why: it is the classic unstable choice — equal-order u–p fails the inf–sup condition, and in
//! the undrained limit (Δt → 0) its pressure oscillates from element to element — kept as the
//! contrast to P2–P1 (docs/studies.md, stability (a)) and to show that the projection
//! stabilisation (`fem.stabilisation`, Dohrmann & Bochev's, made for P1–P1) cures it.
//!
//! How: the P1 functions are L_a = N_a + ½ Σ_{edges at a} N_m in terms of the P2 ones, so the P1
//! Galerkin rows are the P2 rows combined, r_a + ½ Σ r_m. The element residual and Jacobian are
//! transformed in their rows only: the columns keep the mid-edge unknowns, which the tie rows
//! s (u_m − ½ (u_a + u_b)) fix exactly (s = M h, a stiffness of the size of the other rows).
//! Loads on mid-edge nodes move to the vertices the same way ([`tie_loads`]), and so do the
//! nodal forces of post-processing (`fem::kernel`'s `post`: a contact vertex's reaction
//! includes the halves of its edges' mid-edge rows).
//!
//! Contact: the plates bound the vertices' u_z only (`physics::contact::Plates::new`); a
//! mid-edge node is its edge's slave, so it carries no bound, is never active and is never a
//! contact node, and the drainage's contact state is the vertices' gaps (as for P2–P1). The
//! plates' predictor moves vertices only; [`tie_nodes`] puts the mid-edge nodes back on their
//! edges. Between two contact vertices a face keeps its reference curvature (the geometry is
//! isoparametric P2, the displacement linear), so `max_penetration` reports about the sagitta
//! h²/8R of the contact faces.

use super::element::{ElementMatrix, MAX_DOF as NDOF};
use crate::mesh::dist::LocalMesh;
use crate::reference_cell::TET10_EDGES;

/// The rows of mid-edge node `4 + e`'s three components and of its edge's vertices.
fn edges() -> impl Iterator<Item = (usize, usize, usize)> {
    TET10_EDGES.iter().enumerate().map(|(e, &(a, b))| (4 + e, a, b))
}

/// Moves half of each mid-edge u row of `r` to each of its edge's vertices' rows (the P1
/// combination) and puts `tie(m, a, b, i)` in its place.
fn fold_rows(r: &mut [f64; NDOF], tie: impl Fn(usize, usize, usize, usize) -> f64) {
    for (m, a, b) in edges() {
        for i in 0..3 {
            let rm = r[3 * m + i];
            r[3 * a + i] += 0.5 * rm;
            r[3 * b + i] += 0.5 * rm;
            r[3 * m + i] = tie(m, a, b, i);
        }
    }
}

/// Transforms one element's residual `r` (its contribution only) to P1 rows and tie rows, at
/// nodal displacements `u`, tie stiffness `s`.
pub(crate) fn tie_residual(r: &mut [f64; NDOF], u: &[[f64; 3]; 10], s: f64) {
    fold_rows(r, |m, a, b, i| s * (u[m][i] - 0.5 * (u[a][i] + u[b][i])));
}

/// The P1 rows of a part of the nodal forces (the pressure part of post-processing): the
/// mid-edge rows moved to the vertices, nothing left on the tie rows (whose residual is not a
/// force).
pub(crate) fn fold_forces(r: &mut [f64; NDOF]) {
    fold_rows(r, |_, _, _, _| 0.0);
}

/// The same transformation of one element's Jacobian rows (the derivative of
/// [`tie_residual`]'s result).
pub(crate) fn tie_jacobian(k: &mut ElementMatrix, s: f64) {
    for (m, a, b) in edges() {
        for i in 0..3 {
            let row = k[3 * m + i];
            for c in 0..NDOF {
                k[3 * a + i][c] += 0.5 * row[c];
                k[3 * b + i][c] += 0.5 * row[c];
            }
            k[3 * m + i] = [0.0; NDOF];
            k[3 * m + i][3 * m + i] = s;
            k[3 * m + i][3 * a + i] = -0.5 * s;
            k[3 * m + i][3 * b + i] = -0.5 * s;
        }
    }
}

/// Every local mid-edge node once, with its edge's vertices (local node numbers).
fn local_edges(mesh: &LocalMesh) -> impl Iterator<Item = (usize, usize, usize)> + '_ {
    let mut done = vec![false; mesh.coords.len()];
    mesh.cells
        .iter()
        .flat_map(|t| edges().map(move |(m, a, b)| (t[m] as usize, t[a] as usize, t[b] as usize)))
        .filter(move |&(m, _, _)| !std::mem::replace(&mut done[m], true))
}

/// Moves external loads on mid-edge u dofs (local layout: u of local node n at 3n + c) to the
/// edge's vertices, half to each.
pub(crate) fn tie_loads(ext: &mut [f64], mesh: &LocalMesh) {
    for (m, a, b) in local_edges(mesh) {
        for i in 0..3 {
            let f = std::mem::take(&mut ext[3 * m + i]);
            ext[3 * a + i] += 0.5 * f;
            ext[3 * b + i] += 0.5 * f;
        }
    }
}

/// Puts every local mid-edge node's displacement back on its edge, u_m = ½ (u_a + u_b) (local
/// layout as in [`tie_loads`]): the state the tie rows hold, for a predictor that moved vertices.
pub(crate) fn tie_nodes(u: &mut [f64], mesh: &LocalMesh) {
    for (m, a, b) in local_edges(mesh) {
        for i in 0..3 {
            u[3 * m + i] = 0.5 * (u[3 * a + i] + u[3 * b + i]);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The P1 rows are the P2 rows tested with L_a = N_a + ½ Σ N_m: for r_P2 = K u (a linear
    /// "element"), the transformed rows equal Tᵀ K at every u, and the tie Jacobian matches.
    #[test]
    fn tie_rows_are_the_p1_combination_and_their_derivative() {
        let kmat: [[f64; NDOF]; NDOF] =
            std::array::from_fn(|i| std::array::from_fn(|j| ((i * 7 + j * 3) % 11) as f64 - 5.0));
        let x: [f64; NDOF] = std::array::from_fn(|i| (i as f64 * 0.37).sin());
        let mut r = [0.0; NDOF];
        for i in 0..NDOF {
            r[i] = (0..NDOF).map(|j| kmat[i][j] * x[j]).sum();
        }
        let u: [[f64; 3]; 10] = std::array::from_fn(|n| std::array::from_fn(|c| x[3 * n + c]));
        let s = 2.5;
        let r0 = r;
        tie_residual(&mut r, &u, s);
        let mut k = kmat;
        tie_jacobian(&mut k, s);
        // Linear: the transformed residual is the transformed matrix times x.
        for i in 0..NDOF {
            let kx: f64 = (0..NDOF).map(|j| k[i][j] * x[j]).sum();
            assert!((kx - r[i]).abs() < 1e-12, "row {i}: {kx} vs {}", r[i]);
        }
        // Vertex 0 collects half of the rows of the mid-edge nodes on its edges (4, 6, 7).
        for c in 0..3 {
            let want = r0[c] + 0.5 * (r0[3 * 4 + c] + r0[3 * 6 + c] + r0[3 * 7 + c]);
            assert!((r[c] - want).abs() < 1e-12);
        }
        // p rows untouched.
        assert_eq!(r[30..], r0[30..]);
    }

    /// Folded forces keep each component's total (a reaction sum over vertices is the whole
    /// element's force) and leave nothing on the mid-edge rows.
    #[test]
    fn folded_forces_keep_the_total_on_the_vertices() {
        let r0: [f64; NDOF] = std::array::from_fn(|i| (i as f64 * 0.61).cos());
        let mut r = r0;
        fold_forces(&mut r);
        for c in 0..3 {
            let total = |r: &[f64; NDOF], nodes: std::ops::Range<usize>| nodes.map(|n| r[3 * n + c]).sum::<f64>();
            assert!((total(&r, 0..4) - total(&r0, 0..10)).abs() < 1e-12);
            assert_eq!(total(&r, 4..10), 0.0);
        }
    }
}
