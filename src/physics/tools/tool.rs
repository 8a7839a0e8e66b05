//! A tool: a profile placed in space, moving along its axis. Its signed distance in 3-D is the
//! profile's at (ρ, ζ), ζ = (x − c)·a the height along the axis a and ρ the distance from it
//! (`profile`: why the section's distance is the solid's), with c = origin + d a at the tool's
//! position d; on the meridian (tools on the symmetry axis) it is the profile's at (r, ±(z − c_z)).

use super::profile::Profile;
use super::sdf::Sdf2;
use crate::error::{Error, Result};
use crate::scene::tools::{ToolDrainage, ToolKind, ToolSpec};

/// A rigid tool of revolution.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Tool {
    pub(crate) name: String,
    pub(crate) profile: Profile,
    /// The frame's origin c at displacement 0 (the sphere's centre, the punch's face centre, the
    /// pipette's mouth centre, a point of the plane).
    pub(crate) origin: [f64; 3],
    /// The unit axis a, from the tool towards the body (the body lies at ζ > 0).
    pub(crate) axis: [f64; 3],
    /// Whether it seals the surface it touches (impermeable, the default), or lets it drain
    /// (`tools.drainage = "free"`; `physics::drainage`).
    pub(crate) seals: bool,
}

/// The signed distance at a point of space: φ, its gradient ∇φ (the unit normal of the level
/// set, pointing away from the tool), its Hessian ∇²φ and the closest point of the tool's surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Gap {
    pub(crate) phi: f64,
    pub(crate) normal: [f64; 3],
    pub(crate) hess: [[f64; 3]; 3],
    pub(crate) closest: [f64; 3],
}

/// Below this distance from the axis (relative to the tool's and the point's scale), a point is
/// on the axis, where the radial direction is any normal to the axis.
const ON_AXIS: f64 = 1e-12;

impl Tool {
    /// A tool with the axis along `axis` (any non-zero vector: normalised).
    pub(crate) fn new(name: &str, profile: Profile, origin: [f64; 3], axis: [f64; 3]) -> Tool {
        let n = dot(axis, axis).sqrt();
        debug_assert!(n > 0.0, "tool {name}: zero axis");
        Tool { name: name.to_string(), profile, origin, axis: axis.map(|c| c / n), seals: true }
    }

    /// The tool a scene's `[[tools]]` entry describes; a malformed one is an error naming the
    /// key, with `context` (the scene file) as its path.
    pub(crate) fn from_spec(spec: &ToolSpec, context: &str) -> Result<Tool> {
        spec.check_shape().map_err(|msg| Error::Scene { path: context.to_string(), msg })?;
        // Given, as the kind needs them (checked above).
        let dim = |v: Option<f64>| v.unwrap_or(f64::NAN);
        let profile = match spec.kind {
            ToolKind::Plane => Profile::Plane,
            ToolKind::Sphere => Profile::Sphere { radius: dim(spec.radius) },
            ToolKind::Punch => Profile::Punch { radius: dim(spec.radius), edge: dim(spec.edge_radius) },
            ToolKind::Pipette => {
                Profile::Pipette { inner: dim(spec.inner_radius), wall: dim(spec.wall), rim: dim(spec.rim_radius) }
            }
        };
        let tool = Tool::new(&spec.name, profile, spec.origin, spec.axis);
        Ok(Tool { seals: spec.drainage == ToolDrainage::Sealed, ..tool })
    }

    /// The frame's origin at the tool's position `d` along its axis: c = origin + d a.
    pub(crate) fn centre(&self, d: f64) -> [f64; 3] {
        std::array::from_fn(|i| self.origin[i] + d * self.axis[i])
    }

    /// The signed distance at `x` with the tool at position `d`: ∇φ = φ_ρ e_ρ + φ_ζ a and
    /// ∇²φ = φ_ρρ e_ρe_ρ + φ_ρζ (e_ρa + ae_ρ) + φ_ζζ aa + (φ_ρ / ρ) e_θe_θ, the last (the hoop
    /// curvature) its limit φ_ρρ on the axis, where the profiles are smooth or, in the
    /// pipette's bore, far from any contact (there only φ means anything).
    pub(crate) fn gap(&self, x: [f64; 3], d: f64) -> Gap {
        let c = self.centre(d);
        let a = self.axis;
        let v: [f64; 3] = std::array::from_fn(|i| x[i] - c[i]);
        let zeta = dot(v, a);
        let radial: [f64; 3] = std::array::from_fn(|i| v[i] - zeta * a[i]);
        let rho = dot(radial, radial).sqrt();
        let on_axis = rho <= ON_AXIS * dot(v, v).sqrt().max(self.profile.size());
        let e = if on_axis { perpendicular(a) } else { radial.map(|r| r / rho) };
        let s = self.profile.sdf(if on_axis { 0.0 } else { rho }, zeta);
        let [[h_rr, h_rz], [_, h_zz]] = s.hess;
        let hoop = if on_axis { h_rr } else { s.grad[0] / rho };
        let hess = std::array::from_fn(|i| {
            std::array::from_fn(|j| {
                let delta = if i == j { 1.0 } else { 0.0 };
                h_rr * e[i] * e[j]
                    + h_rz * (e[i] * a[j] + a[i] * e[j])
                    + h_zz * a[i] * a[j]
                    + hoop * (delta - e[i] * e[j] - a[i] * a[j])
            })
        });
        Gap {
            phi: s.phi,
            normal: std::array::from_fn(|i| s.grad[0] * e[i] + s.grad[1] * a[i]),
            hess,
            closest: std::array::from_fn(|i| c[i] + s.closest[0] * e[i] + s.closest[1] * a[i]),
        }
    }

    /// The distance ρ of `x` from the tool's axis (the tool at `d`).
    pub(crate) fn radial_distance(&self, x: [f64; 3], d: f64) -> f64 {
        let c = self.centre(d);
        let v: [f64; 3] = std::array::from_fn(|i| x[i] - c[i]);
        let zeta = dot(v, self.axis);
        (0..3).map(|i| (v[i] - zeta * self.axis[i]).powi(2)).sum::<f64>().sqrt()
    }

    /// The closest point of the tool's surface to `x` (the tool at `d`): x − φ ∇φ.
    pub(crate) fn project(&self, x: [f64; 3], d: f64) -> [f64; 3] {
        self.gap(x, d).closest
    }

    /// Whether the tool lies on the z axis, as a meridian (r, z) model needs: axis ±e_z, origin
    /// (0, 0, z) (the scene's checks refuse others on a meridian mesh).
    pub(crate) fn on_z_axis(&self) -> bool {
        let [ax, ay, _] = self.axis;
        let [ox, oy, _] = self.origin;
        ax == 0.0 && ay == 0.0 && ox == 0.0 && oy == 0.0
    }

    /// The signed distance at (r, z) of a meridian model, the tool (on the z axis) at `d`:
    /// ρ = r, ζ = σ (z − c_z) with a = σ e_z, so ∇φ = (φ_ρ, σ φ_ζ) and the Hessian's mixed
    /// term has the sign σ; no hoop term (u_θ ≡ 0). At r = 0 every profile gives ∇φ = ±e_z.
    pub(crate) fn meridian(&self, rz: [f64; 2], d: f64) -> Sdf2 {
        debug_assert!(self.on_z_axis(), "tool {} off the axis in a meridian model", self.name);
        let sigma = self.axis[2];
        let cz = self.centre(d)[2];
        let s = self.profile.sdf(rz[0], sigma * (rz[1] - cz));
        let [[h_rr, h_rz], [h_zr, h_zz]] = s.hess;
        Sdf2 {
            phi: s.phi,
            grad: [s.grad[0], sigma * s.grad[1]],
            hess: [[h_rr, sigma * h_rz], [sigma * h_zr, h_zz]],
            closest: [s.closest[0], cz + sigma * s.closest[1]],
        }
    }
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// A unit vector normal to the unit vector `a`: a × (the Cartesian axis least along a), normalised.
fn perpendicular(a: [f64; 3]) -> [f64; 3] {
    let k = (0..3).min_by(|&i, &j| a[i].abs().total_cmp(&a[j].abs())).unwrap_or(0);
    let mut b = [0.0; 3];
    b[k] = 1.0;
    let c = [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]];
    let n = dot(c, c).sqrt();
    c.map(|x| x / n)
}
