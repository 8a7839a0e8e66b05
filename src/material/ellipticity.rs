//! Strong ellipticity of a solid law: the acoustic tensor Q_ik(N) = A_iJkL N_J N_L (A = ∂P/∂F)
//! is positive definite for every unit direction N.
//!
//! Where it is not, the equilibrium equations lose ellipticity: a deformation can localise in
//! a band normal to N at no cost, discrete solutions then depend on the mesh (the finer, the
//! earlier they localise), and Newton stops converging whatever the time step. The pore
//! pressure adds nothing to Q (its term −pJF⁻ᵀ contributes n̂ ⊗ n̂ − n̂ ⊗ n̂ = 0), so the
//! solid's law alone decides, drained or undrained.
//!
//! Holmes–Mow with α's from (µ, ν) by (56) has α1 = (1 − 3ν)/(1 − ν) < 0 for ν > 1/3, and then
//! loses strong ellipticity under moderate strain: in isochoric uniaxial compression
//! F = diag(λ^−½, λ^−½, λ) at λ² = 7/9 for ν = 0.45 (11.8% compression), 1/2 for ν = 0.4,
//! 1/7 for ν = 0.35 (measured independently by finite differences of the energy over 2000
//! directions; `tests` below). With ν ≤ 0.3 it stays elliptic there down to λ = 0.2.

use super::{idx, HolmesMow, Tangent};
use crate::error::Result;
use nalgebra::{Matrix3, Vector3};

/// Directions on the unit sphere (a Fibonacci lattice; N and −N give the same Q, so the upper
/// half suffices).
fn directions(n: usize) -> impl Iterator<Item = Vector3<f64>> {
    let golden = std::f64::consts::PI * (1.0 + 5f64.sqrt());
    (0..n).map(move |i| {
        let z = 1.0 - (i as f64 + 0.5) / n as f64; // (0, 1]
        let r = (1.0 - z * z).sqrt();
        let th = golden * i as f64;
        Vector3::new(r * th.cos(), r * th.sin(), z)
    })
}

/// Q_ik(N) = A_iJkL N_J N_L.
fn acoustic_tensor(a: &Tangent, n: &Vector3<f64>) -> Matrix3<f64> {
    Matrix3::from_fn(|i, k| {
        let mut q = 0.0;
        for j in 0..3 {
            for l in 0..3 {
                q += a[(idx(i, j), idx(k, l))] * n[j] * n[l];
            }
        }
        q
    })
}

/// The smallest eigenvalue of Q(N) over 1000 directions N: negative where the law has lost
/// strong ellipticity.
pub fn min_acoustic_eigenvalue(a: &Tangent) -> f64 {
    directions(1000).map(|n| acoustic_tensor(a, &n).symmetric_eigenvalues().min()).fold(f64::INFINITY, f64::min)
}

/// The stretch λ of isochoric uniaxial compression F = diag(λ^−½, λ^−½, λ), B_p = I, at which
/// the law loses strong ellipticity, if that happens for some λ in [`lambda_min`, 1]
/// (bisection to 1e-6).
pub fn isochoric_compression_limit(law: &HolmesMow, lambda_min: f64) -> Result<Option<f64>> {
    let elliptic = |lam: f64| -> Result<bool> {
        let f = Matrix3::from_diagonal(&Vector3::new(lam.powf(-0.5), lam.powf(-0.5), lam));
        Ok(min_acoustic_eigenvalue(&law.first_pk_and_tangent(&f, &Matrix3::identity())?.1) > 0.0)
    };
    if elliptic(lambda_min)? {
        return Ok(None);
    }
    // Elliptic at λ = 1 (positive-definite linearisation, checked by `HolmesMow::new`).
    let (mut lo, mut hi) = (lambda_min, 1.0);
    while hi - lo > 1e-6 {
        let mid = 0.5 * (lo + hi);
        if elliptic(mid)? {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(Some(hi))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn holmes_mow_loses_ellipticity_only_for_nu_above_one_third() {
        // References: finite differences of the energy, 2000 directions (module docs).
        for (nu, lam_c) in [(0.45, (7.0f64 / 9.0).sqrt()), (0.4, 0.5f64.sqrt()), (0.35, (1.0f64 / 7.0).sqrt())] {
            let law = HolmesMow::from_mu_nu(3.0, nu, 0.6).unwrap();
            let got = isochoric_compression_limit(&law, 0.2).unwrap().expect("loses ellipticity");
            assert!((got - lam_c).abs() < 2e-3, "nu = {nu}: limit {got}, reference {lam_c}");
        }
        for nu in [0.0, 0.2, 0.3] {
            let law = HolmesMow::from_mu_nu(3.0, nu, 0.6).unwrap();
            assert_eq!(isochoric_compression_limit(&law, 0.2).unwrap(), None, "nu = {nu}");
        }
    }

    #[test]
    fn acoustic_eigenvalue_at_the_reference_is_the_shear_modulus() {
        // Linear elasticity: Q(N) = µ I + (λ + µ) N ⊗ N, smallest eigenvalue µ = Φs µ_solid.
        let law = HolmesMow::from_mu_nu(3.0, 0.45, 0.6).unwrap();
        let a = law.first_pk_and_tangent(&Matrix3::identity(), &Matrix3::identity()).unwrap().1;
        assert!((min_acoustic_eigenvalue(&a) - 0.6 * 3.0).abs() < 1e-9);
    }
}
