//! The medium both problems are solved for: a drained skeleton and its permeability, with the
//! moduli the solutions need (the model and conventions are those of [`super`]).

use crate::error::{Error, Result};

/// Drained skeleton and permeability of a linear poroelastic medium with incompressible constituents.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Drained {
    /// Drained shear modulus µ (> 0).
    pub(crate) mu: f64,
    /// Drained Poisson ratio ν, −1 < ν < 1/2.
    pub(crate) nu: f64,
    /// Permeability / hydraulic conductivity k in Darcy's law q = −k ∇p (> 0).
    pub(crate) k: f64,
}

impl Drained {
    /// Validated parameters: µ > 0, −1 < ν < 1/2, k > 0, all finite.
    pub(crate) fn new(mu: f64, nu: f64, k: f64) -> Result<Self> {
        let m = Drained { mu, nu, k };
        if m.is_valid() {
            Ok(m)
        } else {
            Err(Error::Material(format!(
                "poroelastic reference solution needs mu > 0, -1 < nu < 0.5, k > 0 \
                 (got mu = {mu}, nu = {nu}, k = {k})"
            )))
        }
    }

    /// True when the parameters are admissible (see [`Drained::new`]).
    pub(super) fn is_valid(&self) -> bool {
        self.mu.is_finite()
            && self.mu > 0.0
            && self.nu.is_finite()
            && self.nu > -1.0
            && self.nu < 0.5
            && self.k.is_finite()
            && self.k > 0.0
    }

    /// Lamé λ = 2µν/(1 − 2ν).
    fn lambda(&self) -> f64 {
        2.0 * self.mu * self.nu / (1.0 - 2.0 * self.nu)
    }

    /// Oedometric modulus λ + 2µ.
    pub(super) fn oedometric_modulus(&self) -> f64 {
        self.lambda() + 2.0 * self.mu
    }

    /// Drained bulk modulus K = λ + 2µ/3.
    #[cfg(test)]
    pub(super) fn bulk_modulus(&self) -> f64 {
        self.lambda() + 2.0 * self.mu / 3.0
    }

    /// Consolidation coefficient c = k (λ + 2µ).
    pub(crate) fn consolidation_coefficient(&self) -> f64 {
        self.k * self.oedometric_modulus()
    }
}
