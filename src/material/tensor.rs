//! Small tensors of the constitutive laws and the point models.
//!
//! * Fourth-order tangents are `SMatrix<f64, 9, 9>` with the row-major index map
//!   (i, j) → 3 i + j on both sides: `A[(idx(i, j), idx(k, l))] = ∂P_ij/∂F_kl` (see [`idx`]).
//!   This is an index convention on (row, column), independent of nalgebra's column-major
//!   storage. The `add_*` functions add the three index patterns of products of 3 × 3 matrices.
//! * The cofactor cof A = det(A) A⁻ᵀ, its bilinear part and its derivative, from the entries
//!   (polynomial, so exact near det A = 0).
//! * Symmetric second-order tensors as six components (00, 11, 22, 01, 02, 12): the form in
//!   which the remodelling metric B_p is stored per quadrature point and differentiated.

use nalgebra::{Matrix3, SMatrix};

/// A fourth-order tensor ∂P_ij/∂F_kl stored at `[(idx(i, j), idx(k, l))]`.
pub(crate) type Tangent = SMatrix<f64, 9, 9>;

/// Row-major position of the pair (i, j) in a 9-vector: 3 i + j.
#[inline(always)]
pub(crate) const fn idx(i: usize, j: usize) -> usize {
    3 * i + j
}

/// Cofactor matrix cof A = det(A) A⁻ᵀ from the entries: cof_ij = A_{i1 j1} A_{i2 j2} − A_{i1 j2} A_{i2 j1},
/// with i1 = i + 1, i2 = i + 2 (mod 3), likewise for j.
pub(crate) fn cof(a: &Matrix3<f64>) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| {
        let (i1, i2, j1, j2) = ((i + 1) % 3, (i + 2) % 3, (j + 1) % 3, (j + 2) % 3);
        a[(i1, j1)] * a[(i2, j2)] - a[(i1, j2)] * a[(i2, j1)]
    })
}

/// The bilinear part X(A, B) of the cofactor, cof(A + B) = cof A + X(A, B) + cof B; X(A, ·) is
/// the derivative of cof at A, and X(A, L)_kl = ∂(cof A : L)/∂A_kl.
pub(crate) fn cof_cross(a: &Matrix3<f64>, b: &Matrix3<f64>) -> Matrix3<f64> {
    Matrix3::from_fn(|i, j| {
        let (i1, i2, j1, j2) = ((i + 1) % 3, (i + 2) % 3, (j + 1) % 3, (j + 2) % 3);
        a[(i1, j1)] * b[(i2, j2)] + b[(i1, j1)] * a[(i2, j2)] - a[(i1, j2)] * b[(i2, j1)] - b[(i1, j2)] * a[(i2, j1)]
    })
}

/// Levi-Civita symbol ε_ijk for indices in 0..3.
fn levi(i: usize, j: usize, k: usize) -> f64 {
    let (i, j, k) = (i as i32, j as i32, k as i32);
    ((i - j) * (j - k) * (k - i) / 2) as f64
}

/// ∂(cof F)_ij/∂F_kl = ε_ikm ε_jln F_mn (= J (F⁻ᵀ_ij F⁻ᵀ_kl − F⁻ᵀ_il F⁻ᵀ_kj)), polynomial in F.
pub(crate) fn dcof(f: &Matrix3<f64>) -> Tangent {
    let mut a = Tangent::zeros();
    for i in 0..3 {
        for j in 0..3 {
            for k in (0..3).filter(|&k| k != i) {
                for l in (0..3).filter(|&l| l != j) {
                    let (m, n) = (3 - i - k, 3 - j - l);
                    a[(idx(i, j), idx(k, l))] = levi(i, k, m) * levi(j, l, n) * f[(m, n)];
                }
            }
        }
    }
    a
}

/// A[ij, kl] += s X_ij Y_kl.
#[inline]
pub(crate) fn add_outer(a: &mut Tangent, s: f64, x: &Matrix3<f64>, y: &Matrix3<f64>) {
    for i in 0..3 {
        for j in 0..3 {
            let sx = s * x[(i, j)];
            for k in 0..3 {
                for l in 0..3 {
                    a[(idx(i, j), idx(k, l))] += sx * y[(k, l)];
                }
            }
        }
    }
}

/// A[ij, kl] += s X_ik Y_lj (the pattern of dF ↦ X dF Y).
#[inline]
pub(crate) fn add_ik_lj(a: &mut Tangent, s: f64, x: &Matrix3<f64>, y: &Matrix3<f64>) {
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                let sx = s * x[(i, k)];
                for l in 0..3 {
                    a[(idx(i, j), idx(k, l))] += sx * y[(l, j)];
                }
            }
        }
    }
}

/// A[ij, kl] += s X_il Y_kj (the pattern of dF ↦ X dFᵀ Y).
#[inline]
pub(crate) fn add_il_kj(a: &mut Tangent, s: f64, x: &Matrix3<f64>, y: &Matrix3<f64>) {
    for i in 0..3 {
        for j in 0..3 {
            for k in 0..3 {
                let sy = s * y[(k, j)];
                for l in 0..3 {
                    a[(idx(i, j), idx(k, l))] += sy * x[(i, l)];
                }
            }
        }
    }
}

// Six-component symmetric tensors.

/// The symmetric unit directions of the six components (00, 11, 22, 01, 02, 12): a symmetric
/// matrix is Σ_s x_s `sym_basis()[s]`.
pub(crate) fn sym_basis() -> [Matrix3<f64>; 6] {
    std::array::from_fn(|s| {
        let mut x = [0.0; 6];
        x[s] = 1.0;
        from_sym6(&x)
    })
}

/// (row, column) of the six symmetric components.
pub(crate) const SYM_PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];

/// The six components of a symmetric matrix (upper triangle).
pub(crate) fn to_sym6(m: &Matrix3<f64>) -> [f64; 6] {
    SYM_PAIRS.map(|(a, b)| 0.5 * (m[(a, b)] + m[(b, a)]))
}

/// The symmetric matrix of six components.
pub(crate) fn from_sym6(x: &[f64]) -> Matrix3<f64> {
    Matrix3::new(x[0], x[3], x[4], x[3], x[1], x[5], x[4], x[5], x[2])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn index_map_is_row_major() {
        assert_eq!((idx(0, 0), idx(0, 2), idx(1, 0), idx(2, 1), idx(2, 2)), (0, 2, 3, 7, 8));
    }
}
