//! Fully symmetric Gauss-type quadrature rules with positive weights on the reference tetrahedron and triangle.
//!
//! Reference tetrahedron: vertices (0,0,0), (1,0,0), (0,1,0), (0,0,1), volume 1/6.
//! Reference triangle: vertices (0,0), (1,0), (0,1), area 1/2, its points embedded as `[ξ, η, 0]`.
//!
//! Every rule is given by symmetry orbits in barycentric coordinates (λ0, λ1, λ2, λ3), with
//! the point `x = (λ1, λ2, λ3)`; all weights are positive and all points lie inside the simplex.
//! Coefficients were obtained by solving the moment equations for the given orbit structure
//! to 50 significant digits (Gauss–Newton in arbitrary precision, residual < 1e-50) and then
//! rounded to the nearest `f64`; starting values and orbit structures are those of the cited rules:
//!
//! | element | degree | points | rule |
//! |---|---|---|---|
//! | tet | 1 | 1 | centroid |
//! | tet | 2 | 4 | classical S31 rule, a = (5 − √5)/20 |
//! | tet | 3 | 8 | two S31 orbits with equal weights (solved here; positive, interior) |
//! | tet | 5 | 14 | Walkington / Jaśkowiec–Sukumar 14-point rule (S31, S31, S22) |
//! | tet | 6 | 24 | Keast (1986) rule #7 (3 × S31, S211) |
//! | tet | 7 | 35 | S4, S31, S22, 2 × S211 (same orbit structure and weights as Witherden–Vincent 2015) |
//! | tri | 1 | 1 | centroid |
//! | tri | 2 | 3 | Strang–Fix, a = 1/6 |
//! | tri | 4 | 6 | Strang–Fix / Dunavant degree 4 (2 × S21) |
//! | tri | 5 | 7 | Radon, closed form with √15 |
//! | tri | 6 | 12 | Dunavant degree 6 (2 × S21, S111) |
//! | tri | 8 | 16 | Dunavant degree 8 (S3, 3 × S21, S111) |
//!
//! Asking for a degree with no rule of its own returns the next higher rule (tet 4 → 5, tri 3 → 4,
//! tri 7 → 8); asking beyond the highest degree returns the highest rule (tet 7,
//! tri 8); degree 0 returns the one-point rule.

/// A quadrature rule: points in reference coordinates and their weights.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Quadrature {
    /// Reference coordinates of the points (triangle rules have a zero third component).
    pub(crate) points: Vec<[f64; 3]>,
    /// Weights; they sum to the reference measure (1/6 for the tet, 1/2 for the triangle).
    pub(crate) weights: Vec<f64>,
}

#[cfg(test)]
impl Quadrature {
    /// Number of points.
    pub(crate) fn len(&self) -> usize {
        self.weights.len()
    }
}

/// Highest polynomial degree integrated exactly by a tetrahedron rule of this module.
#[cfg(test)]
pub(crate) const TET_MAX_DEGREE: usize = 7;
/// Highest polynomial degree integrated exactly by a triangle rule of this module.
#[cfg(test)]
pub(crate) const TRI_MAX_DEGREE: usize = 8;

/// Builder that expands barycentric orbits into points.
struct Builder {
    q: Quadrature,
}

impl Builder {
    fn new() -> Self {
        Builder { q: Quadrature { points: Vec::new(), weights: Vec::new() } }
    }

    fn tet_point(&mut self, l: [f64; 4], w: f64) {
        self.q.points.push([l[1], l[2], l[3]]);
        self.q.weights.push(w);
    }

    fn tri_point(&mut self, l: [f64; 3], w: f64) {
        self.q.points.push([l[1], l[2], 0.0]);
        self.q.weights.push(w);
    }

    /// Centroid of the tetrahedron.
    fn s4(mut self, w: f64) -> Self {
        self.tet_point([0.25; 4], w);
        self
    }

    /// The 4 permutations of (a, a, a, 1 − 3a).
    fn s31(mut self, w: f64, a: f64) -> Self {
        let b = 1.0 - 3.0 * a;
        for i in 0..4 {
            let mut l = [a; 4];
            l[i] = b;
            self.tet_point(l, w);
        }
        self
    }

    /// The 6 permutations of (a, a, b, b), b = 1/2 − a.
    fn s22(mut self, w: f64, a: f64) -> Self {
        let b = 0.5 - a;
        for i in 0..4 {
            for j in (i + 1)..4 {
                let mut l = [b; 4];
                l[i] = a;
                l[j] = a;
                self.tet_point(l, w);
            }
        }
        self
    }

    /// The 12 permutations of (a, a, b, c), c = 1 − 2a − b.
    fn s211(mut self, w: f64, a: f64, b: f64) -> Self {
        let c = 1.0 - 2.0 * a - b;
        for i in 0..4 {
            for j in (i + 1)..4 {
                let rest: Vec<usize> = (0..4).filter(|&m| m != i && m != j).collect();
                for (kb, kc) in [(rest[0], rest[1]), (rest[1], rest[0])] {
                    let mut l = [0.0; 4];
                    l[i] = a;
                    l[j] = a;
                    l[kb] = b;
                    l[kc] = c;
                    self.tet_point(l, w);
                }
            }
        }
        self
    }

    /// Centroid of the triangle.
    fn s3(mut self, w: f64) -> Self {
        self.tri_point([1.0 / 3.0; 3], w);
        self
    }

    /// The 3 permutations of (a, a, 1 − 2a).
    fn s21(mut self, w: f64, a: f64) -> Self {
        let b = 1.0 - 2.0 * a;
        for i in 0..3 {
            let mut l = [a; 3];
            l[i] = b;
            self.tri_point(l, w);
        }
        self
    }

    /// The 6 permutations of (a, b, 1 − a − b).
    fn s111(mut self, w: f64, a: f64, b: f64) -> Self {
        let c = 1.0 - a - b;
        for l in [[a, b, c], [a, c, b], [b, a, c], [b, c, a], [c, a, b], [c, b, a]] {
            self.tri_point(l, w);
        }
        self
    }

    fn done(self) -> Quadrature {
        self.q
    }
}

/// Quadrature rule on the reference tetrahedron exact for polynomials of total degree `degree`
/// (see the module table; 4 gives the degree-5 rule, anything above 7 the degree-7 rule).
pub(crate) fn tet(degree: usize) -> Quadrature {
    let b = Builder::new();
    match degree {
        0 | 1 => b.s4(1.0 / 6.0),
        2 => b.s31(1.0 / 24.0, 0.1381966011250105),
        3 => b.s31(1.0 / 48.0, 0.11295679451251103).s31(1.0 / 48.0, 0.3288616499302029),
        4 | 5 => b
            .s31(0.012248840519393659, 0.09273525031089122)
            .s31(0.018781320953002643, 0.3108859192633006)
            .s22(0.007091003462846911, 0.04550370412564965),
        6 => b
            .s31(0.006653791709694582, 0.21460287125915203)
            .s31(0.001679535175886774, 0.04067395853461135)
            .s31(0.009226196923942455, 0.3223378901422755)
            .s211(27.0 / 3360.0, 0.06366100187501753, 0.2696723314583158),
        _ => b
            .s4(0.015914214910688475)
            .s31(0.007054930201661171, 0.3157011497782028)
            .s22(0.005316154638809596, 0.05048982259839637)
            .s211(0.0013517951383172236, 0.021265472541483248, 0.14663881381848495)
            .s211(0.006201188454722437, 0.18883383102600104, 0.047160700360997884),
    }
    .done()
}

/// Quadrature rule on the reference triangle, points `[ξ, η, 0]`, exact for polynomials of total
/// degree `degree` (see the module table; 3 gives the degree-4 rule, 7 and above the degree-8 rule).
pub(crate) fn tri(degree: usize) -> Quadrature {
    let b = Builder::new();
    match degree {
        0 | 1 => b.s3(0.5),
        2 => b.s21(1.0 / 6.0, 1.0 / 6.0),
        3 | 4 => b.s21(0.11169079483900574, 0.4459484909159649).s21(0.054975871827660935, 0.09157621350977074),
        5 => b.s3(9.0 / 80.0).s21(0.06296959027241357, 0.10128650732345634).s21(0.0661970763942531, 0.4701420641051151),
        6 => b.s21(0.058393137863189684, 0.24928674517091043).s21(0.02542245318510341, 0.06308901449150223).s111(
            0.041425537809186785,
            0.053145049844816945,
            0.3103524510337844,
        ),
        _ => b
            .s3(0.07215780383889359)
            .s21(0.04754581713364231, 0.4592925882927232)
            .s21(0.05160868526735912, 0.1705693077517602)
            .s21(0.01622924881159904, 0.05054722831703098)
            .s111(0.013615157087217496, 0.008394777409957605, 0.2631128296346381),
    }
    .done()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fact(n: u32) -> f64 {
        (1..=n).map(f64::from).product()
    }

    fn check_tet(degree: usize) -> f64 {
        let q = tet(degree);
        let mut worst: f64 = 0.0;
        for a in 0..=degree as u32 {
            for b in 0..=(degree as u32 - a) {
                for c in 0..=(degree as u32 - a - b) {
                    let exact = fact(a) * fact(b) * fact(c) / fact(a + b + c + 3);
                    let num: f64 = q
                        .points
                        .iter()
                        .zip(&q.weights)
                        .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32))
                        .sum();
                    worst = worst.max((num - exact).abs());
                }
            }
        }
        worst
    }

    fn check_tri(degree: usize) -> f64 {
        let q = tri(degree);
        let mut worst: f64 = 0.0;
        for a in 0..=degree as u32 {
            for b in 0..=(degree as u32 - a) {
                let exact = fact(a) * fact(b) / fact(a + b + 2);
                let num: f64 =
                    q.points.iter().zip(&q.weights).map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32)).sum();
                worst = worst.max((num - exact).abs());
            }
        }
        worst
    }

    #[test]
    fn tet_rules_exact_positive_inside() {
        let expected_points = [1, 1, 4, 8, 14, 14, 24, 35, 35];
        for (degree, &npts) in expected_points.iter().enumerate() {
            let q = tet(degree);
            assert_eq!(q.len(), npts, "degree {degree}");
            assert!(q.weights.iter().all(|&w| w > 0.0));
            let sum: f64 = q.weights.iter().sum();
            assert!((sum - 1.0 / 6.0).abs() < 1e-15);
            for p in &q.points {
                assert!(p.iter().all(|&x| x > 0.0) && p[0] + p[1] + p[2] < 1.0);
            }
            let err = check_tet(degree.clamp(1, TET_MAX_DEGREE));
            assert!(err < 1e-13, "tet degree {degree}: error {err:e}");
        }
        // No rule is accidentally of higher degree than advertised for degree 1..7 requests.
        assert!(check_tet(TET_MAX_DEGREE) < 1e-13);
        assert!(tet(TET_MAX_DEGREE + 5).len() == 35);
    }

    #[test]
    fn tri_rules_exact_positive_inside() {
        let expected_points = [1, 1, 3, 6, 6, 7, 12, 16, 16];
        for (degree, &npts) in expected_points.iter().enumerate() {
            let q = tri(degree);
            assert_eq!(q.len(), npts, "degree {degree}");
            assert!(q.weights.iter().all(|&w| w > 0.0));
            let sum: f64 = q.weights.iter().sum();
            assert!((sum - 0.5).abs() < 1e-15);
            for p in &q.points {
                assert!(p[0] > 0.0 && p[1] > 0.0 && p[0] + p[1] < 1.0 && p[2] == 0.0);
            }
            let err = check_tri(degree.clamp(1, TRI_MAX_DEGREE));
            assert!(err < 1e-13, "tri degree {degree}: error {err:e}");
        }
        assert!(tri(TRI_MAX_DEGREE + 3).len() == 16);
    }

    #[test]
    fn rules_are_not_overclaimed() {
        // Sanity check of the test itself: each rule fails one degree above its exactness.
        assert!(check_tet_with(&tet(2), 3) > 1e-6);
        assert!(check_tet_with(&tet(5), 6) > 1e-8);
        assert!(check_tet_with(&tet(7), 8) > 1e-10);
    }

    fn check_tet_with(q: &Quadrature, degree: u32) -> f64 {
        let mut worst: f64 = 0.0;
        for a in 0..=degree {
            for b in 0..=(degree - a) {
                let c = degree - a - b;
                let exact = fact(a) * fact(b) * fact(c) / fact(a + b + c + 3);
                let num: f64 = q
                    .points
                    .iter()
                    .zip(&q.weights)
                    .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32))
                    .sum();
                worst = worst.max((num - exact).abs());
            }
        }
        worst
    }
}
