//! Quadrature on the boundary faces of either cell family: the 6-node triangle of a tetrahedral
//! mesh (dA = |∂x/∂ξ × ∂x/∂η| dξ dη) and the 3-node line of a meridian mesh, which stands for the
//! surface of revolution it sweeps (dA = 2πR |∂x/∂s| ds). Loads, drainage areas, probes and
//! contact measures integrate through [`FaceRule::points`], so they are whole-body values on both.

use super::element::{tabulate_tri6, tri6_surface, Tabulation};
use super::quadrature;
use crate::reference_cell::Family;

/// A quadrature point of a boundary face.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FacePoint {
    /// The point (the tests check the normal's orientation against it).
    #[cfg_attr(not(test), allow(dead_code))]
    pub(crate) x: [f64; 3],
    /// Weight: the rule's weight times the area element (times 2πR on the meridian).
    pub(crate) w: f64,
    /// Unit outward normal (in the x–z plane on the meridian).
    pub(crate) normal: [f64; 3],
    /// P2 face functions at the point (the first `face_nodes` entries).
    pub(crate) n: [f64; 6],
    /// P1 face functions (the first `face_vertices` entries).
    pub(crate) l: [f64; 3],
}

/// Quadrature rules of the faces of a family, tabulated once.
pub(crate) struct FaceRule {
    family: Family,
    tri: Tabulation<6>,
    tri_points: Vec<[f64; 3]>,
    /// Gauss–Legendre points on [0, 1] and weights, for lines.
    line: Vec<(f64, f64)>,
}

impl FaceRule {
    /// A rule exact to degree 5 on flat faces (3-point Gauss on lines; 7 points on triangles).
    pub(crate) fn new(family: Family) -> FaceRule {
        FaceRule::with_degree(family, 5)
    }

    /// A rule of (at least) `degree` on triangles; lines take 3-point Gauss (degree 5) from degree 3
    /// up, 2-point Gauss below.
    pub(crate) fn with_degree(family: Family, degree: usize) -> FaceRule {
        let q = quadrature::tri(degree);
        let line = if degree >= 3 {
            gauss3_line().to_vec()
        } else {
            let a = 0.5 / 3f64.sqrt();
            vec![(0.5 - a, 0.5), (0.5 + a, 0.5)]
        };
        FaceRule { family, tri: tabulate_tri6(&q), tri_points: q.points, line }
    }

    /// The quadrature points of a face with node coordinates `coords` (face node order; the first
    /// `face_nodes` entries are used).
    pub(crate) fn points(&self, coords: &[[f64; 3]]) -> Vec<FacePoint> {
        match self.family {
            Family::Tet10 => {
                let c: [[f64; 3]; 6] = std::array::from_fn(|a| coords[a]);
                (0..self.tri.weights.len())
                    .map(|q| {
                        let s = tri6_surface(&c, &self.tri, q);
                        let xi = self.tri_points[q];
                        FacePoint {
                            x: s.x,
                            w: self.tri.weights[q] * s.da,
                            normal: s.normal,
                            n: self.tri.n[q],
                            l: [1.0 - xi[0] - xi[1], xi[0], xi[1]],
                        }
                    })
                    .collect()
            }
            Family::Tri6 => self.line.iter().map(|&(s, w)| line3_point(coords, s, w)).collect(),
        }
    }
}

/// 3-point Gauss–Legendre on [0, 1]: (point, weight), exact to degree 5.
pub(crate) fn gauss3_line() -> [(f64, f64); 3] {
    let a = 0.5 * (0.6f64).sqrt();
    [(0.5 - a, 5.0 / 18.0), (0.5, 8.0 / 18.0), (0.5 + a, 5.0 / 18.0)]
}

/// 4-point Gauss–Legendre on [0, 1]: (point, weight), exact to degree 7.
pub(crate) fn gauss4_line() -> [(f64, f64); 4] {
    let (a, b) = ((3.0 / 7.0 - 2.0 / 7.0 * (1.2f64).sqrt()).sqrt(), (3.0 / 7.0 + 2.0 / 7.0 * (1.2f64).sqrt()).sqrt());
    let (wa, wb) = ((18.0 + 30f64.sqrt()) / 36.0, (18.0 - 30f64.sqrt()) / 36.0);
    [(0.5 - 0.5 * b, 0.5 * wb), (0.5 - 0.5 * a, 0.5 * wa), (0.5 + 0.5 * a, 0.5 * wa), (0.5 + 0.5 * b, 0.5 * wb)]
}

/// The Line3 functions (vertices a, b, then the mid-node) and their s-derivatives at s ∈ [0, 1].
pub(crate) fn line3(s: f64) -> ([f64; 3], [f64; 3]) {
    (
        [(1.0 - s) * (1.0 - 2.0 * s), s * (2.0 * s - 1.0), 4.0 * s * (1.0 - s)],
        [4.0 * s - 3.0, 4.0 * s - 1.0, 4.0 - 8.0 * s],
    )
}

/// A point of a Line3 face (vertices a, b, then the mid-node) at s ∈ [0, 1] with rule weight w.
fn line3_point(c: &[[f64; 3]], s: f64, w: f64) -> FacePoint {
    let (n, dn) = line3(s);
    let (mut x, mut t) = ([0.0; 3], [0.0; 3]);
    for a in 0..3 {
        for d in 0..3 {
            x[d] += n[a] * c[a][d];
            t[d] += dn[a] * c[a][d];
        }
    }
    let len = (t[0] * t[0] + t[2] * t[2]).sqrt();
    // Outward: the tangent turned clockwise in (x, z) (cells are counter-clockwise).
    let normal = [t[2] / len, 0.0, -t[0] / len];
    FacePoint {
        x,
        w: w * len * 2.0 * std::f64::consts::PI * x[0],
        normal,
        n: [n[0], n[1], n[2], 0.0, 0.0, 0.0],
        l: [1.0 - s, s, 0.0],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The arc of the unit half-circle as Line3 faces with mid-nodes on it: the swept area
    /// converges to the sphere's 4π, and normals point away from the centre.
    #[test]
    fn meridian_arc_sweeps_the_sphere() {
        let rule = FaceRule::new(Family::Tri6);
        let n = 16;
        let at = |t: f64| [t.sin(), 0.0, -t.cos()];
        let mut area = 0.0;
        for k in 0..n {
            let (t0, t1) =
                (std::f64::consts::PI * k as f64 / n as f64, std::f64::consts::PI * (k + 1) as f64 / n as f64);
            let face = [at(t0), at(t1), at(0.5 * (t0 + t1))];
            for p in rule.points(&face) {
                area += p.w;
                let r = (p.x[0] * p.x[0] + p.x[2] * p.x[2]).sqrt();
                assert!((p.normal[0] * p.x[0] + p.normal[2] * p.x[2]) / r > 0.999);
            }
        }
        assert!((area / (4.0 * std::f64::consts::PI) - 1.0).abs() < 1e-5, "{area}");
    }

    /// A straight Line3 from (1, 0, 0) to (2, 0, 0) sweeps the annulus π (2² − 1²), normal −z
    /// for this direction (its cell lies above).
    #[test]
    fn straight_line_sweeps_an_annulus() {
        let rule = FaceRule::new(Family::Tri6);
        let face = [[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [1.5, 0.0, 0.0]];
        let pts = rule.points(&face);
        let area: f64 = pts.iter().map(|p| p.w).sum();
        assert!((area - 3.0 * std::f64::consts::PI).abs() < 1e-13);
        assert!(pts.iter().all(|p| (p.normal[2] + 1.0).abs() < 1e-15));
        // ∫ L_0 dA = 2π ∫ (1 − s)(1 + s) ds = 2π · 2/3
        let l0: f64 = pts.iter().map(|p| p.w * p.l[0]).sum();
        assert!((l0 - 4.0 * std::f64::consts::PI / 3.0).abs() < 1e-13);
    }
}
