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
//! Loads on mid-edge nodes move to the vertices the same way ([`tie_loads`]). Contact acts on
//! mid-edge nodes, so the plates refuse this element.

use super::element::{ElementMatrix, MAX_DOF as NDOF};
use crate::mesh::dist::LocalMesh;
use crate::mesh::TET10_EDGES;

/// The rows of mid-edge node `4 + e`'s three components and of its edge's vertices.
fn edges() -> impl Iterator<Item = (usize, usize, usize)> {
    TET10_EDGES.iter().enumerate().map(|(e, &(a, b))| (4 + e, a, b))
}

/// Transforms one element's residual `r` (its contribution only) to P1 rows and tie rows, at
/// nodal displacements `u`, tie stiffness `s`.
pub fn tie_residual(r: &mut [f64; NDOF], u: &[[f64; 3]; 10], s: f64) {
    for (m, a, b) in edges() {
        for i in 0..3 {
            let rm = r[3 * m + i];
            r[3 * a + i] += 0.5 * rm;
            r[3 * b + i] += 0.5 * rm;
            r[3 * m + i] = s * (u[m][i] - 0.5 * (u[a][i] + u[b][i]));
        }
    }
}

/// The same transformation of one element's Jacobian rows (the derivative of
/// [`tie_residual`]'s result).
pub fn tie_jacobian(k: &mut ElementMatrix, s: f64) {
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

/// Moves external loads on mid-edge u dofs (local layout: u of local node n at 3n + c) to the
/// edge's vertices, half to each.
pub fn tie_loads(ext: &mut [f64], mesh: &LocalMesh) {
    let mut done = vec![false; mesh.coords.len()];
    for t in &mesh.cells {
        for (m, a, b) in edges() {
            let (m, a, b) = (t[m] as usize, t[a] as usize, t[b] as usize);
            if std::mem::replace(&mut done[m], true) {
                continue;
            }
            for i in 0..3 {
                let f = std::mem::take(&mut ext[3 * m + i]);
                ext[3 * a + i] += 0.5 * f;
                ext[3 * b + i] += 0.5 * f;
            }
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
}
