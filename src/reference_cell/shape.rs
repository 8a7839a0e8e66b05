//! The P1 and P2 shape functions of the reference cells (gmsh node order) and the check that a
//! curved cell's P2 map does not fold.

use super::{Family, TET10_EDGES, TRI6_EDGES};

/// Largest number of nodes and vertices of a family's cell.
pub(crate) const MAX_NODES: usize = super::MAX_CELL_NODES;
pub(crate) const MAX_VERTICES: usize = 4;

/// Reference gradients of the P1 functions (barycentric coordinates) of the tetrahedron ...
const DL_TET: [[f64; 3]; 4] = [[-1.0, -1.0, -1.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
/// ... and of the triangle.
const DL_TRI: [[f64; 2]; 3] = [[-1.0, -1.0], [1.0, 0.0], [0.0, 1.0]];

/// P1 values (barycentric coordinates) of a family's cell at the reference point ξ (a
/// triangle's in the first 3 slots; its `ξ[2]` is ignored).
#[inline]
pub(crate) fn p1_values(family: Family, xi: &[f64; 3]) -> [f64; MAX_VERTICES] {
    match family {
        Family::Tet10 => [1.0 - xi[0] - xi[1] - xi[2], xi[0], xi[1], xi[2]],
        Family::Tri6 => [1.0 - xi[0] - xi[1], xi[0], xi[1], 0.0],
    }
}

/// P2 on the tetrahedron: N_i = L_i (2 L_i − 1) at vertices, 4 L_a L_b on edges.
pub(crate) fn tet10(xi: &[f64; 3]) -> ([f64; 10], [[f64; 3]; 10]) {
    let (l, dl) = (p1_values(Family::Tet10, xi), DL_TET);
    let mut n = [0.0; 10];
    let mut dn = [[0.0; 3]; 10];
    for i in 0..4 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        for d in 0..3 {
            dn[i][d] = (4.0 * l[i] - 1.0) * dl[i][d];
        }
    }
    for (e, &(a, b)) in TET10_EDGES.iter().enumerate() {
        n[4 + e] = 4.0 * l[a] * l[b];
        for d in 0..3 {
            dn[4 + e][d] = 4.0 * (l[a] * dl[b][d] + l[b] * dl[a][d]);
        }
    }
    (n, dn)
}

/// P2 on the triangle.
pub(crate) fn tri6(xi: &[f64; 2]) -> ([f64; 6], [[f64; 2]; 6]) {
    let (l, dl) = (p1_values(Family::Tri6, &[xi[0], xi[1], 0.0]), DL_TRI);
    let mut n = [0.0; 6];
    let mut dn = [[0.0; 2]; 6];
    for i in 0..3 {
        n[i] = l[i] * (2.0 * l[i] - 1.0);
        for d in 0..2 {
            dn[i][d] = (4.0 * l[i] - 1.0) * dl[i][d];
        }
    }
    for (e, &(a, b)) in TRI6_EDGES.iter().enumerate() {
        n[3 + e] = 4.0 * l[a] * l[b];
        for d in 0..2 {
            dn[3 + e][d] = 4.0 * (l[a] * dl[b][d] + l[b] * dl[a][d]);
        }
    }
    (n, dn)
}

/// P2 values and reference gradients of a family's cell at ξ, in the 10-slot layout (a
/// triangle's 6 functions first, the other slots zero; its gradients (∂/∂ξ, ∂/∂η, 0)).
pub(crate) fn p2_values(family: Family, xi: &[f64; 3]) -> ([f64; MAX_NODES], [[f64; 3]; MAX_NODES]) {
    match family {
        Family::Tet10 => tet10(xi),
        Family::Tri6 => {
            let (n, dn) = tri6(&[xi[0], xi[1]]);
            (
                std::array::from_fn(|a| if a < 6 { n[a] } else { 0.0 }),
                std::array::from_fn(|a| if a < 6 { [dn[a][0], dn[a][1], 0.0] } else { [0.0; 3] }),
            )
        }
    }
}

/// Where the P2 map of a positively oriented cell (nodes `x`; straight measure `det0`: det of the
/// vertex simplex's map) folds: the first of its nodes and its centroid with det J ≤ 1e-8 det0,
/// that point and that det; None if nowhere. J is ∂x/∂ξ in 3-D, ∂(x, z)/∂(ξ, η) on the meridian.
pub(crate) fn fold_point(family: Family, x: &[[f64; 3]], det0: f64) -> Option<([f64; 3], f64)> {
    let vertices = family.cell_vertices();
    let dim = vertices - 1;
    // the reference nodes (vertices, then mid-edges) and the centroid, as ξ
    let vertex = |i: usize| -> [f64; 3] { std::array::from_fn(|k| if i > 0 && k + 1 == i { 1.0 } else { 0.0 }) };
    let mut points: Vec<[f64; 3]> = (0..vertices).map(vertex).collect();
    points.extend(family.edges().iter().map(|&(a, b)| {
        let (p, q) = (vertex(a), vertex(b));
        std::array::from_fn(|k| 0.5 * (p[k] + q[k]))
    }));
    points.push(std::array::from_fn(|k| if k < dim { 1.0 / vertices as f64 } else { 0.0 }));
    let axes = family.axes();
    for xi in points {
        let (n, dn) = p2_values(family, &xi);
        let mut j = [[0.0; 3]; 3];
        let mut at = [0.0; 3];
        for a in 0..family.cell_nodes() {
            for (r, &c) in axes.iter().enumerate() {
                for k in 0..dim {
                    j[r][k] += x[a][c] * dn[a][k];
                }
            }
            for c in 0..3 {
                at[c] += n[a] * x[a][c];
            }
        }
        let d = if dim == 3 {
            j[0][0] * (j[1][1] * j[2][2] - j[1][2] * j[2][1]) - j[0][1] * (j[1][0] * j[2][2] - j[1][2] * j[2][0])
                + j[0][2] * (j[1][0] * j[2][1] - j[1][1] * j[2][0])
        } else {
            j[0][0] * j[1][1] - j[0][1] * j[1][0]
        };
        if d <= 1e-8 * det0 {
            return Some((at, d));
        }
    }
    None
}

#[cfg(test)]
mod fold_tests {
    use super::fold_point;
    use crate::reference_cell::{Family, TET10_EDGES, TRI6_EDGES};

    fn straight() -> [[f64; 3]; 10] {
        let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        std::array::from_fn(|k| {
            if k < 4 {
                v[k]
            } else {
                let (a, b) = TET10_EDGES[k - 4];
                std::array::from_fn(|c| 0.5 * (v[a][c] + v[b][c]))
            }
        })
    }

    #[test]
    fn a_straight_or_gently_curved_tet10_does_not_fold_a_tangled_one_does() {
        let x = straight();
        assert!(fold_point(Family::Tet10, &x, 1.0).is_none());
        let mut bent = x;
        bent[4][1] -= 0.1; // mid-node of edge (0, 1) bowed a little
        assert!(fold_point(Family::Tet10, &bent, 1.0).is_none());
        let mut tangled = x;
        tangled[4] = [0.5, 0.0, 1.2]; // mid-node of edge (0, 1) pulled past the opposite edge
        let (_, d) = fold_point(Family::Tet10, &tangled, 1.0).expect("folds");
        assert!(d <= 0.0);
    }

    #[test]
    fn a_straight_tri6_does_not_fold_a_tangled_one_does() {
        // the meridian triangle lies in the (x, z) plane
        let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]];
        let x: [[f64; 3]; 6] = std::array::from_fn(|k| {
            if k < 3 {
                v[k]
            } else {
                let (a, b) = TRI6_EDGES[k - 3];
                std::array::from_fn(|c| 0.5 * (v[a][c] + v[b][c]))
            }
        });
        assert!(fold_point(Family::Tri6, &x, 1.0).is_none());
        let mut tangled = x;
        tangled[3] = [0.5, 0.0, 1.2]; // mid-node of edge (0, 1) pulled past the opposite vertex
        let (at, d) = fold_point(Family::Tri6, &tangled, 1.0).expect("folds");
        assert!(d <= 0.0 && at[1] == 0.0);
    }

    use super::tet10;

    #[test]
    fn tet10_partition_of_unity_and_kronecker() {
        let v = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
        let ref_nodes: Vec<[f64; 3]> = (0..10)
            .map(|k| {
                if k < 4 {
                    v[k]
                } else {
                    let (a, b) = TET10_EDGES[k - 4];
                    std::array::from_fn(|c| 0.5 * (v[a][c] + v[b][c]))
                }
            })
            .collect();
        for (i, x) in ref_nodes.iter().enumerate() {
            let (n, _) = tet10(x);
            for (a, v) in n.iter().enumerate() {
                assert!((v - if a == i { 1.0 } else { 0.0 }).abs() < 1e-15);
            }
        }
        for p in [[0.25, 0.25, 0.25], [0.1, 0.2, 0.3], [0.6, 0.05, 0.1], [0.0, 0.5, 0.5]] {
            let (n, dn) = tet10(&p);
            assert!((n.iter().sum::<f64>() - 1.0).abs() < 1e-14);
            for d in 0..3 {
                assert!(dn.iter().map(|g| g[d]).sum::<f64>().abs() < 1e-14);
            }
        }
    }

    #[test]
    fn tet10_gradients_match_finite_differences() {
        let p = [0.2, 0.15, 0.3];
        let (_, dn) = tet10(&p);
        let h = 1e-6;
        for k in 0..3 {
            let (mut a, mut b) = (p, p);
            a[k] += h;
            b[k] -= h;
            let (na, nb) = (tet10(&a).0, tet10(&b).0);
            for i in 0..10 {
                assert!(((na[i] - nb[i]) / (2.0 * h) - dn[i][k]).abs() < 1e-9);
            }
        }
    }
}
