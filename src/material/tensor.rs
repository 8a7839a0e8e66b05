//! Symmetric second-order tensors as six components (00, 11, 22, 01, 02, 12): the form in
//! which the remodelling metric B_p is stored per quadrature point and differentiated.

use nalgebra::Matrix3;

/// The symmetric unit directions of the six components (00, 11, 22, 01, 02, 12): a symmetric
/// matrix is Σ_s x_s `sym_basis()[s]`.
pub fn sym_basis() -> [Matrix3<f64>; 6] {
    std::array::from_fn(|s| {
        let mut x = [0.0; 6];
        x[s] = 1.0;
        from_sym6(&x)
    })
}

/// (row, column) of the six symmetric components.
pub const SYM_PAIRS: [(usize, usize); 6] = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)];

/// The six components of a symmetric matrix (upper triangle).
pub fn to_sym6(m: &Matrix3<f64>) -> [f64; 6] {
    SYM_PAIRS.map(|(a, b)| 0.5 * (m[(a, b)] + m[(b, a)]))
}

/// The symmetric matrix of six components.
pub fn from_sym6(x: &[f64]) -> Matrix3<f64> {
    Matrix3::new(x[0], x[3], x[4], x[3], x[1], x[5], x[4], x[5], x[2])
}
