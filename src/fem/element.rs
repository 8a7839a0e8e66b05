//! The isoparametric maps of curved 10-node tetrahedra and 6-node triangles, x(ξ) = Σ N_a(ξ) x_a,
//! ∇_X N_a = J⁻ᵀ ∇_ξ N_a, dV = det J dξ, on the reference shape functions of
//! [`crate::reference_cell::shape`] tabulated at quadrature points; and the element's dof layout.
//!
//! Element dof layout: u of node a, component c at NC a + c (NC = 3 in 3-D, 2 on the meridian),
//! then p of vertex m at NU + m (NU = NC × nodes); see `cell::CellShape`. Arrays are sized for the
//! largest family (10 nodes, 4 vertices, 34 dofs); a family uses the leading entries.

use super::quadrature::Quadrature;
use crate::error::{Error, Result};
use crate::reference_cell::shape::{p2_values, tri6};
use crate::reference_cell::Family;

/// Largest number of element dofs of a family.
pub(crate) const MAX_DOF: usize = 34;

/// Local dofs of an element (the first `NDOF` of its family).
pub(crate) type ElementDofs = [usize; MAX_DOF];
/// An element matrix (the leading NDOF × NDOF block of its family).
pub(crate) type ElementMatrix = [[f64; MAX_DOF]; MAX_DOF];

/// Shape values and reference gradients at every point of a rule, computed once.
#[derive(Debug, Clone)]
pub(crate) struct Tabulation<const N: usize> {
    pub(crate) n: Vec<[f64; N]>,
    /// Reference gradients (third component 0 for triangles).
    pub(crate) dn: Vec<[[f64; 3]; N]>,
    pub(crate) weights: Vec<f64>,
}

#[cfg(test)]
pub(crate) fn tabulate_tet10(q: &Quadrature) -> Tabulation<10> {
    let (n, dn) = q.points.iter().map(crate::reference_cell::shape::tet10).unzip();
    Tabulation { n, dn, weights: q.weights.clone() }
}

pub(crate) fn tabulate_tri6(q: &Quadrature) -> Tabulation<6> {
    let mut t = Tabulation { n: vec![], dn: vec![], weights: q.weights.clone() };
    for p in &q.points {
        let (n, d) = tri6(&[p[0], p[1]]);
        t.n.push(n);
        t.dn.push(std::array::from_fn(|a| [d[a][0], d[a][1], 0.0]));
    }
    t
}

/// The cell functions of a family at every point of a rule, in the kernel's 10-slot layout
/// ([`p2_values`]).
pub(crate) fn tabulate_cell(family: Family, q: &Quadrature) -> Tabulation<10> {
    let (n, dn) = q.points.iter().map(|p| p2_values(family, p)).unzip();
    Tabulation { n, dn, weights: q.weights.clone() }
}

/// The isoparametric map of a 10-node tet at one quadrature point.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Geometry {
    #[cfg(test)]
    pub(crate) x: [f64; 3],
    pub(crate) jac_det: f64,
    /// Physical gradients ∂N_a/∂X of the 10 P2 functions.
    pub(crate) dn_dx: [[f64; 3]; 10],
}

/// Geometry at point `q` of a tabulation; an error for an inverted or degenerate element.
#[inline]
pub(crate) fn tet10_geometry(coords: &[[f64; 3]; 10], tab: &Tabulation<10>, q: usize) -> Result<Geometry> {
    let dn = &tab.dn[q];
    let mut j = [[0.0; 3]; 3]; // j[d][k] = ∂x_d/∂ξ_k
    let mut x = [0.0; 3];
    for a in 0..10 {
        for d in 0..3 {
            x[d] += tab.n[q][a] * coords[a][d];
            for k in 0..3 {
                j[d][k] += coords[a][d] * dn[a][k];
            }
        }
    }
    let c00 = j[1][1] * j[2][2] - j[1][2] * j[2][1];
    let c01 = j[1][2] * j[2][0] - j[1][0] * j[2][2];
    let c02 = j[1][0] * j[2][1] - j[1][1] * j[2][0];
    let det = j[0][0] * c00 + j[0][1] * c01 + j[0][2] * c02;
    // Also catches NaN.
    if det.is_nan() || det <= 0.0 {
        return Err(Error::Mesh {
            path: "element geometry".into(),
            msg: format!(
                "inverted or degenerate element near ({:.4e}, {:.4e}, {:.4e}): Jacobian determinant {det:.3e}",
                x[0], x[1], x[2]
            ),
        });
    }
    // inv[k][d] = ∂ξ_k/∂x_d (adjugate / det).
    let inv = [
        [c00 / det, (j[0][2] * j[2][1] - j[0][1] * j[2][2]) / det, (j[0][1] * j[1][2] - j[0][2] * j[1][1]) / det],
        [c01 / det, (j[0][0] * j[2][2] - j[0][2] * j[2][0]) / det, (j[0][2] * j[1][0] - j[0][0] * j[1][2]) / det],
        [c02 / det, (j[0][1] * j[2][0] - j[0][0] * j[2][1]) / det, (j[0][0] * j[1][1] - j[0][1] * j[1][0]) / det],
    ];
    let mut dn_dx = [[0.0; 3]; 10];
    for a in 0..10 {
        for d in 0..3 {
            dn_dx[a][d] = dn[a][0] * inv[0][d] + dn[a][1] * inv[1][d] + dn[a][2] * inv[2][d];
        }
    }
    Ok(Geometry {
        #[cfg(test)]
        x,
        jac_det: det,
        dn_dx,
    })
}

/// A 6-node triangle at one quadrature point.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Surface {
    pub(crate) x: [f64; 3],
    /// Area element |∂x/∂ξ × ∂x/∂η|.
    pub(crate) da: f64,
    /// Unit normal, oriented by the node order (right-hand rule).
    pub(crate) normal: [f64; 3],
}

pub(crate) fn tri6_surface(coords: &[[f64; 3]; 6], tab: &Tabulation<6>, q: usize) -> Surface {
    let (mut x, mut t1, mut t2) = ([0.0; 3], [0.0; 3], [0.0; 3]);
    for a in 0..6 {
        for d in 0..3 {
            x[d] += tab.n[q][a] * coords[a][d];
            t1[d] += tab.dn[q][a][0] * coords[a][d];
            t2[d] += tab.dn[q][a][1] * coords[a][d];
        }
    }
    let m = [t1[1] * t2[2] - t1[2] * t2[1], t1[2] * t2[0] - t1[0] * t2[2], t1[0] * t2[1] - t1[1] * t2[0]];
    let da = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
    Surface { x, da, normal: [m[0] / da, m[1] / da, m[2] / da] }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::quadrature;
    use crate::reference_cell::TET10_EDGES;

    const REF: [[f64; 3]; 4] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

    fn nodes_of(v: [[f64; 3]; 4]) -> [[f64; 3]; 10] {
        let mut c = [[0.0; 3]; 10];
        c[..4].copy_from_slice(&v);
        for (e, &(a, b)) in TET10_EDGES.iter().enumerate() {
            c[4 + e] = std::array::from_fn(|d| 0.5 * (v[a][d] + v[b][d]));
        }
        c
    }

    /// On a distorted straight tet, P2 reproduces any quadratic and its gradient (the P1
    /// gradients derived from these are checked in `cell`'s tests).
    #[test]
    fn p2_reproduces_quadratics_on_distorted_tet() {
        let v = [[0.1, -0.2, 0.05], [1.3, 0.1, -0.1], [0.2, 0.9, 0.3], [-0.1, 0.3, 1.2]];
        let c = nodes_of(v);
        let f = |x: [f64; 3]| {
            1.0 + 2.0 * x[0] - x[1] + 0.5 * x[2] + x[0] * x[0] - 3.0 * x[0] * x[1]
                + 0.7 * x[1] * x[2]
                + 1.1 * x[2] * x[2]
        };
        let g = |x: [f64; 3]| {
            [2.0 + 2.0 * x[0] - 3.0 * x[1], -1.0 - 3.0 * x[0] + 0.7 * x[2], 0.5 + 0.7 * x[1] + 2.2 * x[2]]
        };
        let q = quadrature::tet(5);
        let tab = tabulate_tet10(&q);
        let mut vol = 0.0;
        for k in 0..q.weights.len() {
            let geo = tet10_geometry(&c, &tab, k).unwrap();
            vol += geo.jac_det * q.weights[k];
            let val: f64 = (0..10).map(|a| tab.n[k][a] * f(c[a])).sum();
            assert!((val - f(geo.x)).abs() < 1e-12);
            let ge = g(geo.x);
            for d in 0..3 {
                let gd: f64 = (0..10).map(|a| geo.dn_dx[a][d] * f(c[a])).sum();
                assert!((gd - ge[d]).abs() < 1e-11, "{gd} vs {}", ge[d]);
            }
        }
        let e1: [f64; 3] = std::array::from_fn(|d| v[1][d] - v[0][d]);
        let e2: [f64; 3] = std::array::from_fn(|d| v[2][d] - v[0][d]);
        let e3: [f64; 3] = std::array::from_fn(|d| v[3][d] - v[0][d]);
        let det = e1[0] * (e2[1] * e3[2] - e2[2] * e3[1]) - e1[1] * (e2[0] * e3[2] - e2[2] * e3[0])
            + e1[2] * (e2[0] * e3[1] - e2[1] * e3[0]);
        assert!((vol - det / 6.0).abs() < 1e-14);
    }

    #[test]
    fn inverted_element_is_an_error() {
        // Mirror image of the reference element: negative orientation everywhere.
        let mut c = nodes_of(REF);
        for x in c.iter_mut() {
            x[0] = -x[0];
        }
        let tab = tabulate_tet10(&quadrature::tet(1));
        let e = tet10_geometry(&c, &tab, 0).unwrap_err().to_string();
        assert!(e.contains("inverted"), "{e}");
    }

    #[test]
    fn curved_triangle_area_and_normal() {
        // Quarter of the unit sphere's octant face approximated by a tri6 with mid-nodes on it:
        // the area converges to π/2 for the octant; here check a flat triangle exactly.
        let c = [[0.0, 0.0, 0.0], [2.0, 0.0, 0.0], [0.0, 1.0, 0.0], [1.0, 0.0, 0.0], [1.0, 0.5, 0.0], [0.0, 0.5, 0.0]];
        let q = quadrature::tri(5);
        let tab = tabulate_tri6(&q);
        let mut area = 0.0;
        for k in 0..q.weights.len() {
            let s = tri6_surface(&c, &tab, k);
            area += s.da * q.weights[k];
            assert!((s.normal[2] - 1.0).abs() < 1e-14);
        }
        assert!((area - 1.0).abs() < 1e-14);
    }
}
