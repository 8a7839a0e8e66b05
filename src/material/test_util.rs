//! Test helpers: reproducible random states and central finite differences with respect to F.

use super::tensor::{idx, Tangent};
use nalgebra::{Matrix3, Rotation3, Vector3};

/// Small xorshift generator: reproducible states without a rand dependency.
pub(crate) struct Rng(u64);

impl Rng {
    pub(crate) fn new(seed: u64) -> Self {
        Rng(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// Uniform in [lo, hi).
    pub(crate) fn uniform(&mut self, lo: f64, hi: f64) -> f64 {
        self.0 ^= self.0 << 13;
        self.0 ^= self.0 >> 7;
        self.0 ^= self.0 << 17;
        lo + (hi - lo) * ((self.0 >> 11) as f64 / (1u64 << 53) as f64)
    }
    pub(crate) fn matrix(&mut self, amp: f64) -> Matrix3<f64> {
        Matrix3::from_fn(|_, _| self.uniform(-amp, amp))
    }
    /// Entries uniform in [−amp, amp).
    pub(crate) fn vector(&mut self, amp: f64) -> Vector3<f64> {
        Vector3::from_fn(|_, _| self.uniform(-amp, amp))
    }
    /// A rotation by a random angle about a random axis.
    pub(crate) fn rotation(&mut self) -> Matrix3<f64> {
        let axis = Vector3::new(self.uniform(-1.0, 1.0), self.uniform(-1.0, 1.0), 1.0);
        Rotation3::from_scaled_axis(axis.normalize() * self.uniform(-3.0, 3.0)).into_inner()
    }
    /// A general (rotated, sheared) F with det F = j.
    pub(crate) fn deformation(&mut self, j: f64) -> Matrix3<f64> {
        let f = self.rotation() * (Matrix3::identity() + self.matrix(0.3));
        let det = f.determinant();
        assert!(det > 0.0);
        f * (j / det).cbrt()
    }
    /// A symmetric positive definite B_p with det 1, far from the identity.
    pub(crate) fn remodelling_metric(&mut self) -> Matrix3<f64> {
        let m = Matrix3::identity() + self.matrix(0.4);
        let b = m * m.transpose();
        b / b.determinant().cbrt()
    }
}

/// |x − y| ≤ tol |y|, naming both when not.
#[track_caller]
pub(crate) fn assert_close(x: f64, y: f64, tol: f64) {
    assert!((x - y).abs() <= tol * y.abs().max(1e-300), "{x} vs {y}");
}

/// The kinematics of F (which must be admissible).
pub(crate) fn kin(f: &Matrix3<f64>) -> super::law::Kinematics {
    super::law::Kinematics::new(f).unwrap()
}

/// Relative step for central differences: truncation O(h²) ≈ 1e-12, round-off O(ε/h) ≈ 1e-10.
pub(crate) const H: f64 = 1e-6;

/// Central difference of a scalar function of F: the gradient ∂ψ/∂F.
pub(crate) fn fd_gradient(psi: impl Fn(&Matrix3<f64>) -> f64, f: &Matrix3<f64>) -> Matrix3<f64> {
    let h = H * f.norm();
    Matrix3::from_fn(|k, l| {
        let (mut fp, mut fm) = (*f, *f);
        fp[(k, l)] += h;
        fm[(k, l)] -= h;
        (psi(&fp) - psi(&fm)) / (2.0 * h)
    })
}

/// Central difference of a matrix function of F: column idx(k, l) holds ∂P/∂F_kl.
pub(crate) fn fd_tangent(p: impl Fn(&Matrix3<f64>) -> Matrix3<f64>, f: &Matrix3<f64>) -> Tangent {
    let h = H * f.norm();
    let mut a = Tangent::zeros();
    for k in 0..3 {
        for l in 0..3 {
            let (mut fp, mut fm) = (*f, *f);
            fp[(k, l)] += h;
            fm[(k, l)] -= h;
            let d = (p(&fp) - p(&fm)) / (2.0 * h);
            for i in 0..3 {
                for j in 0..3 {
                    a[(idx(i, j), idx(k, l))] = d[(i, j)];
                }
            }
        }
    }
    a
}

/// ‖x − y‖ / ‖y‖ (Frobenius): scale-aware, so tiny entries do not dominate.
pub(crate) fn rel_err<const R: usize, const C: usize>(
    x: &nalgebra::SMatrix<f64, R, C>,
    y: &nalgebra::SMatrix<f64, R, C>,
) -> f64 {
    (x - y).norm() / y.norm()
}
