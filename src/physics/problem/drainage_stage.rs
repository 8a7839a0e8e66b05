//! The surface's drainage in the steps ([`DrainageStage`]): outflow c(g) (p − p_m) through the
//! drained surface (`physics::drainage`) in the residual, its Jacobian and the experiment's
//! outflow, a node's gap the nearer of the plates' and the sealing tools'.

use super::schur::SchurApprox;
use crate::error::Result;
use crate::fem::assembly::Discretization;
use crate::petsc::{Int, Mat};
use crate::physics::contact::Plates;
use crate::physics::drainage::{Drain, SurfaceDrainage};
use crate::physics::medium::Medium;
use crate::physics::tools::ToolSet;

/// What the surface drains against at a stage: the plates and the tools that seal it (either may
/// be absent), the state whose gaps set the conductance when it is not the iterate's (the plates'
/// predictor), and the medium it drains into (None: the bath's gauge 0).
#[derive(Clone, Copy)]
pub(super) struct Seals<'a> {
    pub(super) plates: Option<&'a Plates>,
    pub(super) tools: Option<&'a ToolSet>,
    pub(super) gaps: Option<&'a [f64]>,
    pub(super) medium: Option<&'a Medium>,
}

/// The drained surface.
pub(super) struct DrainageStage {
    surface: SurfaceDrainage,
}

impl DrainageStage {
    pub(super) fn new(surface: SurfaceDrainage) -> DrainageStage {
        DrainageStage { surface }
    }

    /// The drainage terms at the local state `u` at time t: a node's gap is the smaller of the
    /// plates' and the nearest sealing tool's (neither: open), in the seals' gap state, else u's.
    fn drains(&self, disc: &Discretization, u: &[f64], t: f64, seals: Seals) -> Vec<Drain> {
        let state = seals.gaps.unwrap_or(u);
        let (mesh, dofs) = (&disc.mesh, &disc.dofs);
        let plate = seals.plates.map(|p| p.drainage_gap(mesh, dofs, state, t));
        let gap = |n: usize| {
            let by_plates = plate.as_ref().map(|g| g(n));
            let by_tools = seals.tools.and_then(|ts| ts.seal_gap(n, mesh.coords[n], state));
            match (by_plates, by_tools) {
                (Some(a), Some(b)) if b.0 < a.0 => b,
                (Some(a), _) => a,
                (None, Some(b)) => b,
                (None, None) => (f64::INFINITY, [0.0; 3]),
            }
        };
        self.surface.drains(mesh, dofs, gap)
    }

    /// The outflow into the local residual `f`: c(g) (p − p_m) at the local state `u`, p_m the
    /// medium's pressure at the vertex's current position (0 without a medium: the bath's gauge).
    pub(super) fn add_residual(&self, disc: &Discretization, u: &[f64], t: f64, seals: Seals, f: &mut [f64]) {
        for d in self.drains(disc, u, t, seals) {
            match seals.medium {
                None => f[d.p] += d.conductance * u[d.p],
                Some(m) => f[d.p] += d.conductance * (u[d.p] - m.at_node(&disc.mesh, &disc.dofs, d.vertex, u)),
            }
        }
    }

    /// This rank's outflow Σ c(g) (p − p_m) at the local state `u` (the experiment's).
    pub(super) fn outflow(&self, disc: &Discretization, u: &[f64], t: f64, seals: Seals) -> f64 {
        let p_m = |n: usize| seals.medium.map_or(0.0, |m| m.at_node(&disc.mesh, &disc.dofs, n, u));
        self.drains(disc, u, t, seals).iter().map(|d| d.conductance * (u[d.p] - p_m(d.vertex))).sum()
    }

    /// The Jacobian: d(c p)/dp = c on the diagonal, d(c p)/du = c' p on the gap-setting node's
    /// components (not with a fixed gap state); and c in the Schur approximation. With a medium,
    /// c' (p − p_m) instead, and −c ∇p_m on the vertex's u columns (in the pattern: the vertex
    /// couples with its own u, and with the nodes of its faces).
    pub(super) fn add_jacobian(
        &self,
        disc: &Discretization,
        u: &[f64],
        t: f64,
        seals: Seals,
        jac: &mut Mat,
        schur: &mut SchurApprox,
    ) -> Result<()> {
        let (l2g, dofs) = (&disc.dofs.l2g, &disc.dofs);
        let medium = seals.medium;
        for d in self.drains(disc, u, t, seals) {
            if disc.constrained[d.p] {
                continue;
            }
            let p_m = medium.map_or(0.0, |m| m.at_node(&disc.mesh, dofs, d.vertex, u));
            let (mut cols, mut vals) = (vec![l2g[d.p]], vec![d.conductance]);
            if seals.gaps.is_none() {
                // Zero derivatives (the plates' lateral components, a node off the smoothstep's
                // ramp) add nothing.
                for (c, &dc) in d.d_conductance.iter().take(dofs.nc).enumerate().filter(|(_, &dc)| dc != 0.0) {
                    cols.push(l2g[dofs.u_local(d.node, c)]);
                    vals.push(dc * (u[d.p] - p_m));
                }
            }
            jac.add_values(&[l2g[d.p]], &cols, &vals)?;
            if let Some(m) = medium {
                for (c, g) in m.gradient_at(&disc.mesh, dofs, d.vertex, u).iter().take(dofs.nc).enumerate() {
                    let col = dofs.u_local(d.vertex, c);
                    if !disc.constrained[col] {
                        jac.add_values(&[l2g[d.p]], &[l2g[col]], &[-d.conductance * g])?;
                    }
                }
            }
            let gv = disc.mesh.vertex_global[d.p - dofs.n_u_local()] as Int;
            schur.add_diagonal(gv, d.conductance)?;
        }
        Ok(())
    }
}
