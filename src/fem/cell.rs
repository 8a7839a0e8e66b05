//! The two cell families of the generic element kernel, as types: what a quadrature point of a
//! cell hands the pointwise laws.
//!
//! * [`Tet10`]: the curved 10-node tetrahedron, dV = det J dξ, ∇_X N_a = J⁻ᵀ ∇_ξ N_a.
//! * [`Tri6Axi`]: the curved 6-node triangle of the meridian plane (x = R, z = Z), for a body of
//!   revolution without twist. A point sees the full 3-D tensors of the body (model: §9): Grad u
//!   gains the hoop entry u_r / R in the θθ slot, Grad w the entry w_r / R, Grad p has no θ
//!   component, and dV = 2πR dR dZ. The laws below the kernel are the 3-D ones, unchanged.
//!
//! Arrays are sized for the largest family (10 nodes, 4 vertices, 3 components); a family uses the
//! first [`CellShape::NN`], [`CellShape::NV`], [`CellShape::NC`] entries. The kernel is generic
//! over the family, so these are constants of the compiled loops.

use super::element::{tet10_geometry, Tabulation};
use crate::error::{Error, Result};
use crate::reference_cell::shape::{p1_values, MAX_NODES, MAX_VERTICES};
use crate::reference_cell::{Family, TET10_EDGES, TRI6_EDGES};

/// The map of a cell at one quadrature point.
#[derive(Debug, Clone, Copy)]
pub(crate) struct CellPoint {
    /// Reference position of the point (the manufactured solutions of the tests).
    #[cfg(test)]
    pub(crate) x: [f64; 3],
    /// Integration weight of the point: det J times the rule's weight (times 2πR on the meridian).
    pub(crate) w: f64,
    /// The same without the 2πR factor: the point's share of the cell's own measure (volume or area).
    pub(crate) w_cell: f64,
    /// ∂N_a/∂X of the P2 functions (3-D; (∂/∂R, 0, ∂/∂Z) on the meridian).
    pub(crate) dn: [[f64; 3]; MAX_NODES],
    /// 1/R on the meridian (the hoop entries N_a / R), 0 in 3-D.
    pub(crate) inv_r: f64,
}

/// A cell family of the kernel.
pub(crate) trait CellShape: Copy + Default + 'static {
    const FAMILY: Family;
    /// P2 nodes, P1 vertices, displacement components per node.
    const NN: usize = Self::FAMILY.cell_nodes();
    const NV: usize = Self::FAMILY.cell_vertices();
    const NC: usize = Self::FAMILY.components();
    /// u dofs and all dofs of a cell (the layout of `element`: u of node a, component c at
    /// NC a + c, then p of vertex m).
    const NU: usize = Self::NC * Self::NN;
    /// Whether points carry the hoop entries.
    const AXI: bool = Self::FAMILY.axisymmetric();
    /// The Cartesian axis of each displacement component (the meridian's (u_r, u_z) are x and z).
    const AXES: [usize; 3];

    /// The map at point q of a tabulation (`Tabulation::cell`); an error for an inverted or
    /// degenerate cell.
    fn point(coords: &[[f64; 3]; MAX_NODES], tab: &Tabulation<MAX_NODES>, q: usize) -> Result<CellPoint>;

    /// P1 values (barycentric coordinates) at a reference point.
    fn p1_values(xi: &[f64; 3]) -> [f64; MAX_VERTICES];

    /// h² of a cell of measure `m` (volume or area): the squared edge of the regular cell.
    fn h2(m: f64) -> f64;
}

/// The 10-node tetrahedron.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Tet10;

/// The 6-node triangle of the meridian plane.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Tri6Axi;

impl CellShape for Tet10 {
    const FAMILY: Family = Family::Tet10;
    const AXES: [usize; 3] = [0, 1, 2];

    #[inline]
    fn point(coords: &[[f64; 3]; MAX_NODES], tab: &Tabulation<MAX_NODES>, q: usize) -> Result<CellPoint> {
        let g = tet10_geometry(coords, tab, q)?;
        let w = tab.weights[q] * g.jac_det;
        Ok(CellPoint {
            #[cfg(test)]
            x: g.x,
            w,
            w_cell: w,
            dn: g.dn_dx,
            inv_r: 0.0,
        })
    }

    #[inline]
    fn p1_values(xi: &[f64; 3]) -> [f64; MAX_VERTICES] {
        p1_values(Family::Tet10, xi)
    }

    fn h2(vol: f64) -> f64 {
        (6.0 * std::f64::consts::SQRT_2 * vol).powf(2.0 / 3.0)
    }
}

impl CellShape for Tri6Axi {
    const FAMILY: Family = Family::Tri6;
    const AXES: [usize; 3] = [0, 2, usize::MAX];

    #[inline]
    fn point(coords: &[[f64; 3]; MAX_NODES], tab: &Tabulation<MAX_NODES>, q: usize) -> Result<CellPoint> {
        let dn = &tab.dn[q];
        // j = [[∂R/∂ξ, ∂R/∂η], [∂Z/∂ξ, ∂Z/∂η]]
        let (mut j, mut x) = ([[0.0; 2]; 2], [0.0; 3]);
        for a in 0..6 {
            for d in 0..3 {
                x[d] += tab.n[q][a] * coords[a][d];
            }
            for k in 0..2 {
                j[0][k] += coords[a][0] * dn[a][k];
                j[1][k] += coords[a][2] * dn[a][k];
            }
        }
        let det = j[0][0] * j[1][1] - j[0][1] * j[1][0];
        if det.is_nan() || det <= 0.0 || x[0].is_nan() || x[0] <= 0.0 {
            return Err(Error::Mesh {
                path: "element geometry".into(),
                msg: format!(
                    "inverted or degenerate meridian triangle near (r, z) = ({:.4e}, {:.4e}): Jacobian \
                     determinant {det:.3e}",
                    x[0], x[2]
                ),
            });
        }
        let mut dn_dx = [[0.0; 3]; MAX_NODES];
        for a in 0..6 {
            // ∂N/∂R = (∂N/∂ξ ∂Z/∂η − ∂N/∂η ∂Z/∂ξ) / det, ∂N/∂Z = (∂N/∂η ∂R/∂ξ − ∂N/∂ξ ∂R/∂η) / det
            dn_dx[a][0] = (dn[a][0] * j[1][1] - dn[a][1] * j[1][0]) / det;
            dn_dx[a][2] = (dn[a][1] * j[0][0] - dn[a][0] * j[0][1]) / det;
        }
        let w_cell = tab.weights[q] * det;
        Ok(CellPoint {
            #[cfg(test)]
            x,
            w: 2.0 * std::f64::consts::PI * x[0] * w_cell,
            w_cell,
            dn: dn_dx,
            inv_r: 1.0 / x[0],
        })
    }

    #[inline]
    fn p1_values(xi: &[f64; 3]) -> [f64; MAX_VERTICES] {
        p1_values(Family::Tri6, xi)
    }

    fn h2(area: f64) -> f64 {
        4.0 * area / 3f64.sqrt()
    }
}

/// Physical gradients of the P1 (vertex) functions, exact on curved cells: the vertex function
/// L_m equals N_m + ½ Σ N_mid over the mid-edge nodes of the edges at m, in reference coordinates,
/// so its gradient follows from the P2 gradients.
#[inline]
pub(crate) fn p1_gradients<C: CellShape>(dn: &[[f64; 3]; MAX_NODES]) -> [[f64; 3]; MAX_VERTICES] {
    let mut g = [[0.0; 3]; MAX_VERTICES];
    g[..C::NV].copy_from_slice(&dn[..C::NV]);
    let edges: &[(usize, usize)] = if C::AXI { &TRI6_EDGES } else { &TET10_EDGES };
    for (e, &(a, b)) in edges.iter().enumerate() {
        for d in 0..3 {
            g[a][d] += 0.5 * dn[C::NV + e][d];
            g[b][d] += 0.5 * dn[C::NV + e][d];
        }
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fem::element::tabulate_cell;
    use crate::fem::quadrature;

    /// On a distorted straight tet, the P1 gradients derived from the P2 ones are the exact
    /// gradients of the barycentric coordinates: L_m is linear with L_m(v_n) = δ_mn.
    #[test]
    fn p1_gradients_are_the_barycentric_gradients_on_a_distorted_tet() {
        let v = [[0.1, -0.2, 0.05], [1.3, 0.1, -0.1], [0.2, 0.9, 0.3], [-0.1, 0.3, 1.2]];
        let mut c = [[0.0; 3]; MAX_NODES];
        c[..4].copy_from_slice(&v);
        for (e, &(a, b)) in TET10_EDGES.iter().enumerate() {
            c[4 + e] = std::array::from_fn(|d| 0.5 * (v[a][d] + v[b][d]));
        }
        let q = quadrature::tet(5);
        let tab = tabulate_cell(Family::Tet10, &q);
        for k in 0..q.weights.len() {
            let g1 = p1_gradients::<Tet10>(&Tet10::point(&c, &tab, k).unwrap().dn);
            for m in 0..4 {
                for n in 0..4 {
                    let dot: f64 = (0..3).map(|d| g1[m][d] * (v[n][d] - v[0][d])).sum();
                    let expect = if m == n { 1.0 } else { 0.0 } - if m == 0 { 1.0 } else { 0.0 };
                    assert!((dot - expect).abs() < 1e-12);
                }
            }
        }
    }
}
