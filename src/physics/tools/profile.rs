//! The profile of a tool: the section of a solid of revolution in the tool's frame (ρ, ζ), ρ
//! the distance from the axis and ζ the height along it, the body on the ζ > 0 side; and its
//! signed distance φ, positive outside the tool.
//!
//! Sections are mirrored about the axis, φ(−ρ, ζ) = φ(ρ, ζ): for ρ ≥ 0 the nearest point of a
//! solid of revolution lies in the point's own meridian half-plane (|x − y|² = ρ² + ρ'² −
//! 2ρρ' cos Δθ + Δζ² is least at Δθ = 0), so the 2-D distance to the section *is* the 3-D
//! distance (the pipette's mirrored wall, at distance ≥ ρ + R_p, is never nearer than its own).

use super::rounded_strip::RoundedStrip;
use super::sdf::Sdf2;

/// A tool's section (lengths in µm). The scene checks the dimensions (`scene::tools`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Profile {
    /// The half-space ζ ≤ 0 (a plate).
    Plane,
    /// A sphere of this radius, centred at the frame's origin (an indenter, a bead).
    Sphere { radius: f64 },
    /// A flat punch: the cylinder ρ ≤ `radius`, ζ ≤ 0, its face ζ = 0 and its edge rounded with
    /// radius `edge` (≤ `radius`).
    Punch { radius: f64, edge: f64 },
    /// A micropipette: the wall `inner` ≤ ρ ≤ `inner` + `wall`, ζ ≤ 0, the mouth at ζ = 0, both
    /// corners of the rim rounded with radius `rim` (≤ `wall` / 2). Inside the bore φ = `inner` − ρ.
    Pipette { inner: f64, wall: f64, rim: f64 },
}

impl Profile {
    /// φ, ∇φ, the Hessian and the closest point at (ρ, ζ); ρ may be negative (the mirrored
    /// section). Exact (a Euclidean distance) everywhere; the gradient and the closest point are
    /// those of one nearest point where there are several (the medial axis: the sphere's centre,
    /// the pipette's bore axis, deep inside a wall).
    pub(crate) fn sdf(&self, rho: f64, zeta: f64) -> Sdf2 {
        let half = self.half_sdf(rho.abs(), zeta);
        if rho < 0.0 {
            half.mirrored()
        } else {
            half
        }
    }

    /// The largest dimension of the section (0 for the plane): a length scale for tolerances.
    pub(crate) fn size(&self) -> f64 {
        match *self {
            Profile::Plane => 0.0,
            Profile::Sphere { radius } => radius,
            Profile::Punch { radius, .. } => radius,
            Profile::Pipette { inner, wall, .. } => inner + wall,
        }
    }

    /// How deep a point can go into the tool before it is nearer another of its faces (its medial
    /// axis): the sphere's and the punch's radius, half the pipette's wall, ∞ for the plane. A
    /// node projected from deeper would come out on the wrong side of the tool.
    pub(crate) fn thickness(&self) -> f64 {
        match *self {
            Profile::Plane => f64::INFINITY,
            Profile::Sphere { radius } => radius,
            Profile::Punch { radius, .. } => radius,
            Profile::Pipette { wall, .. } => 0.5 * wall,
        }
    }

    /// The distance for ρ ≥ 0.
    fn half_sdf(&self, rho: f64, zeta: f64) -> Sdf2 {
        match *self {
            Profile::Plane => Sdf2::flat(zeta, [0.0, 1.0], [rho, 0.0]),
            Profile::Sphere { radius } => {
                let n = rho.hypot(zeta);
                if n == 0.0 {
                    // The centre: every surface point is nearest; take the pole facing the body.
                    return Sdf2::flat(-radius, [0.0, 1.0], [0.0, radius]);
                }
                let g = [rho / n, zeta / n];
                Sdf2::curved(n - radius, g, 1.0 / n, [radius * g[0], radius * g[1]])
            }
            Profile::Punch { radius, edge } => RoundedStrip { rc: 0.0, h: radius, r: edge }.sdf(rho, zeta),
            Profile::Pipette { inner, wall, rim } => {
                RoundedStrip { rc: inner + 0.5 * wall, h: 0.5 * wall, r: rim }.sdf(rho, zeta)
            }
        }
    }
}
