//! The value of a signed distance in a profile's (ρ, ζ) plane, and how flat faces, circular
//! arcs and the mirror about the axis make it.

/// The signed distance at a point of the (ρ, ζ) plane: φ, ∇φ = (φ_ρ, φ_ζ), the Hessian
/// [[φ_ρρ, φ_ρζ], [φ_ζρ, φ_ζζ]] (the curvature of the level set: 0 on flat faces), and the
/// closest point of the section's boundary.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Sdf2 {
    pub(crate) phi: f64,
    pub(crate) grad: [f64; 2],
    pub(crate) hess: [[f64; 2]; 2],
    pub(crate) closest: [f64; 2],
}

impl Sdf2 {
    /// Beside a flat face: no curvature.
    pub(super) fn flat(phi: f64, grad: [f64; 2], closest: [f64; 2]) -> Sdf2 {
        Sdf2 { phi, grad, hess: [[0.0; 2]; 2], closest }
    }

    /// Beside a circular arc: the Hessian of a distance to a point, (I − ∇φ∇φᵀ) / (distance to
    /// the arc's centre), `kappa` its inverse.
    pub(super) fn curved(phi: f64, grad: [f64; 2], kappa: f64, closest: [f64; 2]) -> Sdf2 {
        let [a, b] = grad;
        let hess = [[kappa * (1.0 - a * a), -kappa * a * b], [-kappa * a * b, kappa * (1.0 - b * b)]];
        Sdf2 { phi, grad, hess, closest }
    }

    /// The same distance seen at −ρ (the mirrored section): the odd parts change sign.
    pub(super) fn mirrored(self) -> Sdf2 {
        let Sdf2 { phi, grad, hess, closest } = self;
        Sdf2 {
            phi,
            grad: [-grad[0], grad[1]],
            hess: [[hess[0][0], -hess[0][1]], [-hess[1][0], hess[1][1]]],
            closest: [-closest[0], closest[1]],
        }
    }
}
