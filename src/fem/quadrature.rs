//! Quadrature rules with positive weights on the reference tetrahedron
//! (0,0,0),(1,0,0),(0,1,0),(0,0,1) (weights sum to 1/6) and triangle (0,0),(1,0),(0,1)
//! (points [ξ, η, 0], weights sum to 1/2).

/// Points and weights of a rule.
#[derive(Debug, Clone)]
pub struct Quadrature {
    pub points: Vec<[f64; 3]>,
    pub weights: Vec<f64>,
    /// Polynomial degree integrated exactly.
    pub degree: usize,
}

/// The cheapest tetrahedral rule exact to at least `degree` (available: 1, 2, 5; higher
/// requests get degree 5).
pub fn tet(degree: usize) -> Quadrature {
    match degree {
        0 | 1 => Quadrature { points: vec![[0.25; 3]], weights: vec![1.0 / 6.0], degree: 1 },
        2 => {
            let (a, b) = (0.138_196_601_125_010_5, 0.585_410_196_624_968_5);
            Quadrature { points: vec![[a, a, a], [b, a, a], [a, b, a], [a, a, b]], weights: vec![1.0 / 24.0; 4], degree: 2 }
        }
        _ => {
            // 14-point degree-5 rule (Walkington 2000 / Jaśkowiec–Sukumar), all weights positive.
            let mut q = Quadrature { points: vec![], weights: vec![], degree: 5 };
            for (a, w) in [(0.092_735_250_310_891_226_4, 0.012_248_840_519_393_658), (0.310_885_919_263_300_609, 0.018_781_320_953_002_642)] {
                let b = 1.0 - 3.0 * a;
                for p in [[a, a, a], [b, a, a], [a, b, a], [a, a, b]] {
                    q.points.push(p);
                    q.weights.push(w);
                }
            }
            let (a, w) = (0.045_503_704_125_649_649_4, 0.007_091_003_462_846_911);
            let b = 0.5 - a;
            for p in [[a, a, b], [a, b, a], [b, a, a], [a, b, b], [b, a, b], [b, b, a]] {
                q.points.push(p);
                q.weights.push(w);
            }
            q
        }
    }
}

/// The cheapest triangle rule exact to at least `degree` (available: 1, 2, 5).
pub fn tri(degree: usize) -> Quadrature {
    match degree {
        0 | 1 => Quadrature { points: vec![[1.0 / 3.0, 1.0 / 3.0, 0.0]], weights: vec![0.5], degree: 1 },
        2 => {
            let (a, b) = (1.0 / 6.0, 2.0 / 3.0);
            Quadrature { points: vec![[a, a, 0.0], [b, a, 0.0], [a, b, 0.0]], weights: vec![1.0 / 6.0; 3], degree: 2 }
        }
        _ => {
            // Radon's 7-point degree-5 rule.
            let s = 15f64.sqrt();
            let mut q = Quadrature { points: vec![[1.0 / 3.0, 1.0 / 3.0, 0.0]], weights: vec![9.0 / 80.0], degree: 5 };
            for (a, w) in [((6.0 - s) / 21.0, (155.0 - s) / 2400.0), ((6.0 + s) / 21.0, (155.0 + s) / 2400.0)] {
                let b = 1.0 - 2.0 * a;
                for p in [[a, a, 0.0], [b, a, 0.0], [a, b, 0.0]] {
                    q.points.push(p);
                    q.weights.push(w);
                }
            }
            q
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fact(n: usize) -> f64 {
        (1..=n).map(|k| k as f64).product()
    }

    #[test]
    fn tet_rules_integrate_monomials_exactly() {
        for deg in [1, 2, 5] {
            let q = tet(deg);
            assert_eq!(q.degree, deg);
            assert!(q.weights.iter().all(|&w| w > 0.0));
            for a in 0..=deg {
                for b in 0..=deg - a {
                    for c in 0..=deg - a - b {
                        let exact = fact(a) * fact(b) * fact(c) / fact(a + b + c + 3);
                        let num: f64 = q.points.iter().zip(&q.weights).map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32)).sum();
                        assert!((num - exact).abs() < 1e-15, "tet deg {deg}: x^{a} y^{b} z^{c}: {num} vs {exact}");
                    }
                }
            }
        }
    }

    #[test]
    fn tri_rules_integrate_monomials_exactly() {
        for deg in [1, 2, 5] {
            let q = tri(deg);
            assert!(q.weights.iter().all(|&w| w > 0.0));
            for a in 0..=deg {
                for b in 0..=deg - a {
                    let exact = fact(a) * fact(b) / fact(a + b + 2);
                    let num: f64 = q.points.iter().zip(&q.weights).map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32)).sum();
                    assert!((num - exact).abs() < 1e-15, "tri deg {deg}: x^{a} y^{b}: {num} vs {exact}");
                }
            }
        }
    }

    #[test]
    fn degree_requests_round_up() {
        assert_eq!(tet(3).degree, 5);
        assert_eq!(tet(4).degree, 5);
        assert_eq!(tri(3).degree, 5);
    }
}
