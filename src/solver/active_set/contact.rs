//! A node in contact with a curved tool, as the active-set Newton sees it at one iterate
//! (issue 53, design §3.2, §3.5): its frame, the side of the bound, the gap, and what the split
//! and the assembled operator take from them — the active test and the step onto the tool on its
//! rotated normal dof, and the contact's geometric stiffness on its tangential dofs.
//!
//! The constraint φ(x + u) ≥ 0, linearised at the iterate u^k, is a bound on the rotated normal
//! unknown ũ_last = n̂·u (n̂ = σ∇φ): σ = +1, ũ_last ≥ ũ_last^k − φ; σ = −1, ũ_last ≤ ũ_last^k + φ.
//! So the step onto the tool is −σφ, whatever the node's position: the bound is re-linearised
//! at every iterate.

use super::bounds::AT_BOUND;
use super::frames::Frame;
use crate::error::Result;
use crate::petsc::{Int, Vector};

/// What the active-set Newton needs of the curved tools (the problem implements it: the solver
/// knows no geometry). Its values are those of the iterate last evaluated: the problem updates
/// them in every residual evaluation, after the ghost exchange, so that every rank computes a
/// ghost node's frame from the same bits as its owner.
pub(crate) trait CurvedContact {
    /// The displacement components per node (2 on the meridian, 3 in space).
    fn components(&self) -> usize;
    /// The first global u dof of every local candidate node (owned and ghost), fixed for the run.
    fn candidates(&self) -> &[Int];
    /// Per candidate (the order of [`candidates`](Self::candidates)), its frame at the iterate:
    /// None for a node far from every curved tool (not rotated).
    fn frames(&self) -> &[Option<Frame>];
    /// The owned candidates with a frame, as the split takes them.
    fn nodes(&self) -> &[NodeContact];
    /// Moves the owned candidates of `x` that are inside a tool onto its surface (the
    /// projection of an iterate onto the admissible set, as the bounds' clamp for the plates).
    /// Returns the largest depth found relative to half the tool's thickness: beyond 1 a node
    /// may have crossed a thin tool (a pipette's wall), and the step is to be shortened.
    fn project(&self, x: &mut Vector) -> Result<f64>;
}

/// A candidate node's contact with its nearest curved tool at the current iterate.
#[derive(Debug, Clone, Copy)]
pub(crate) struct NodeContact {
    /// Owned local node (its u entries at nc n .. nc n + nc of the owned arrays).
    pub(crate) node: usize,
    /// Columns: the tangents, then n̂ = σ∇φ.
    pub(crate) frame: Frame,
    /// +1: the bound is a lower one on the normal unknown; −1: an upper one.
    pub(crate) sigma: f64,
    /// The gap φ at the iterate.
    pub(crate) phi: f64,
    /// ∇²φ at the iterate, Cartesian (nc × nc used).
    pub(crate) hess: [[f64; 3]; 3],
    /// The nearest tool (its index in the problem's tools) and its axis a in the node's
    /// components (force control: the tool's position moves the bound along a, and its
    /// reaction is the nodes' residual along a).
    pub(crate) tool: usize,
    pub(crate) axis: [f64; 3],
}

impl NodeContact {
    /// s = n̂·a: how the step onto the tool of the normal dof moves with the tool's position.
    pub(crate) fn along(&self) -> f64 {
        let nc = self.frame.components();
        (0..nc).map(|k| self.frame.entry(k, nc - 1) * self.axis[k]).sum()
    }

    /// a·F_n of the owned array `f` (Cartesian): the node's part of the tool's reaction.
    pub(crate) fn along_axis(&self, f: &[f64]) -> f64 {
        let nc = self.frame.components();
        (0..nc).map(|k| self.axis[k] * f[nc * self.node + k]).sum()
    }

    /// The split of the node's nc dofs from their residual `f` (Cartesian): F̃ = QᵀF, the
    /// normal dof active if F̃ pushes into the tool (λ = σF̃_last > 0) and the node is at it
    /// (φ ≤ AT_BOUND) or would reach it (λ > c φ, `c` the scale of a u row: the free step
    /// would close the gap — the primal–dual active-set test, which keeps a node that a
    /// retreating tool leaves behind in contact while it is pushed). Writes the Newton
    /// right-hand side in the frame, −F̃ (0 on the active normal), and the step onto the tool,
    /// −σφ on the active normal (0 elsewhere). Returns whether the normal is active, and λ.
    pub(crate) fn split(&self, f: &[f64], c: f64, rhs: &mut [f64], to_bound: &mut [f64]) -> (bool, f64) {
        let nc = self.frame.components();
        let mut ft = [0.0; 3];
        ft[..nc].copy_from_slice(&f[..nc]);
        self.frame.frame_components(&mut ft);
        let lambda = self.sigma * ft[nc - 1];
        let active = lambda > 0.0 && (self.phi <= AT_BOUND || lambda > c * self.phi);
        for c in 0..nc {
            rhs[c] = -ft[c];
            to_bound[c] = 0.0;
        }
        if active {
            rhs[nc - 1] = 0.0;
            to_bound[nc - 1] = -self.sigma * self.phi;
        }
        (active, lambda)
    }

    /// The contact's geometric stiffness on the tangential dofs of an active node with contact
    /// force λ: −λ τ_iᵀ ∇²φ τ_j ((nc − 1)² entries of its own diagonal block, always in the
    /// pattern). It makes Newton quadratic on a curved tool: the reaction λ∇φ turns with the
    /// normal as the node slides.
    pub(crate) fn curvature(&self, lambda: f64) -> [[f64; 2]; 2] {
        let nc = self.frame.components();
        let tangent =
            |i: usize| -> [f64; 3] { std::array::from_fn(|k| if k < nc { self.frame.entry(k, i) } else { 0.0 }) };
        let mut block = [[0.0; 2]; 2];
        for (i, row) in block.iter_mut().enumerate().take(nc - 1) {
            for (j, b) in row.iter_mut().enumerate().take(nc - 1) {
                let (ti, tj) = (tangent(i), tangent(j));
                let h: f64 = (0..nc).map(|k| (0..nc).map(|l| ti[k] * self.hess[k][l] * tj[l]).sum::<f64>()).sum();
                *b = -lambda * h;
            }
        }
        block
    }
}

/// The curved-tool nodes' part of the split, after the plane split of every dof (`Bounds::split`,
/// which leaves their dofs free: no bound is finite there): each node's nc entries of `rhs` and
/// `to_bound` (owned arrays; `first` the global index of the first owned dof) rewritten in its
/// frame by [`NodeContact::split`], its normal dof added to `active` (kept ascending) when
/// active. `lambda` gets each node's contact force (0 when free), in the order of `nodes`. A node with a dof
/// the plane split made active (a pin) is an error: its frame would mix the pin's row with
/// its others.
#[allow(clippy::too_many_arguments)]
pub(super) fn split_curved(
    nodes: &[NodeContact],
    c: f64,
    first: usize,
    f: &[f64],
    rhs: &mut [f64],
    to_bound: &mut [f64],
    active: &mut Vec<Int>,
    lambda: &mut Vec<f64>,
) -> Result<()> {
    lambda.clear();
    let mut added = Vec::new();
    for node in nodes {
        let nc = node.frame.components();
        let i = nc * node.node;
        let dofs = (first + i) as Int..(first + i + nc) as Int;
        let k = active.partition_point(|&a| a < dofs.start);
        if k < active.len() && active[k] < dofs.end {
            return Err(crate::error::Error::Diverged(format!(
                "global dofs {}..{} are held (a pinned rigid mode) and touch a curved tool: hold the body elsewhere",
                dofs.start, dofs.end
            )));
        }
        let (on, l) = node.split(&f[i..i + nc], c, &mut rhs[i..i + nc], &mut to_bound[i..i + nc]);
        lambda.push(if on { l } else { 0.0 });
        if on {
            added.push(dofs.end - 1);
        }
    }
    if !added.is_empty() {
        active.extend(added);
        active.sort_unstable();
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A node on a sphere of radius `r` about the origin at the point of outward unit normal n
    /// (the tool below the body: σ = +1), gap `phi`: ∇²φ = (I − nnᵀ)/(r + φ).
    fn on_sphere(n: [f64; 3], r: f64, phi: f64) -> NodeContact {
        let d = r + phi;
        let hess = std::array::from_fn(|i| std::array::from_fn(|j| ((i == j) as u8 as f64 - n[i] * n[j]) / d));
        NodeContact { node: 0, frame: Frame::spatial(n), sigma: 1.0, phi, hess, tool: 0, axis: [0.0, 0.0, 1.0] }
    }

    fn unit(v: [f64; 3]) -> [f64; 3] {
        let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        v.map(|x| x / n)
    }

    #[test]
    fn the_normal_dof_is_active_at_the_tool_when_pushed_into_it() {
        let n = unit([0.3, -0.4, 0.8]);
        // A residual pushing into the tool (F along +n̂: the Newton step −F goes into it), plus a
        // tangential part.
        let f = [2.0 * n[0] + 0.5, 2.0 * n[1] - 0.1, 2.0 * n[2] - 0.125];
        let at = on_sphere(n, 10.0, 1e-12);
        let (mut rhs, mut d) = ([9.0; 3], [9.0; 3]);
        let (active, lambda) = at.split(&f, 0.0, &mut rhs, &mut d);
        let along: f64 = (0..3).map(|i| f[i] * n[i]).sum();
        assert!(active && (lambda - along).abs() < 1e-15, "λ = {lambda}, F·n̂ = {along}");
        assert_eq!((rhs[2], d[2]), (0.0, -1e-12), "active normal: no rhs, the step onto the tool −φ");
        // The tangential rhs is −F̃ in the frame: together with λ it is F, rotated.
        let mut back = [-rhs[0], -rhs[1], lambda];
        at.frame.cartesian_components(&mut back);
        for i in 0..3 {
            assert!((back[i] - f[i]).abs() < 1e-15, "component {i}: {back:?} vs {f:?}");
        }
        assert_eq!((d[0], d[1]), (0.0, 0.0), "tangents: no step onto the tool");
        // Away from the tool (λ = 2 below c φ = 10), or pulled off it: free, the whole −F̃.
        for (node, f) in [(on_sphere(n, 10.0, 1e-2), f), (at, f.map(|x| -x))] {
            let (active, _) = node.split(&f, 1e3, &mut rhs, &mut d);
            assert!(!active && rhs[2] != 0.0 && d == [0.0; 3], "φ {}: active {active}, rhs {rhs:?}", node.phi);
        }
        // Off the tool but pushed harder than the stiffness c holds over the gap (λ = 2 > c φ =
        // 1e-3): active, stepped onto the tool (the primal–dual test).
        let (active, _) = on_sphere(n, 10.0, 1e-6).split(&f, 1e3, &mut rhs, &mut d);
        assert!(active && rhs[2] == 0.0 && d[2] == -1e-6, "PDAS: active {active}, step {}", d[2]);
        // An upper bound (the tool above, σ = −1): pushed into it is F̃_last < 0; the step +φ.
        let above = NodeContact { sigma: -1.0, phi: -2e-13, ..at };
        let (active, lambda) = above.split(&f.map(|x| -x), 0.0, &mut rhs, &mut d);
        assert!(active && lambda > 0.0 && d[2] == -2e-13, "upper: active {active}, λ {lambda}, step {}", d[2]);
    }

    /// Force control: the normal's step moves with the tool by n̂·a, and the node's reaction
    /// along the axis is a·F.
    #[test]
    fn a_tools_axis_enters_the_normal_and_the_reaction() {
        let n = unit([0.3, -0.4, 0.8]);
        let a = unit([0.0, 0.6, -0.8]);
        let node = NodeContact { node: 1, axis: a, ..on_sphere(n, 10.0, 0.0) };
        let along = n[0] * a[0] + n[1] * a[1] + n[2] * a[2];
        assert!((node.along() - along).abs() < 1e-15, "{} vs {along}", node.along());
        let f = [9.0, 9.0, 9.0, 1.0, 2.0, 3.0];
        assert!((node.along_axis(&f) - (a[0] + 2.0 * a[1] + 3.0 * a[2])).abs() < 1e-15);
    }

    #[test]
    fn a_spheres_curvature_softens_both_tangents_by_lambda_over_its_radius() {
        let (r, lambda) = (7.0, 3.0);
        for n in [unit([0.3, -0.4, 0.8]), unit([-0.9, 0.1, 0.2]), [0.0, 0.0, 1.0]] {
            let block = on_sphere(n, r, 0.0).curvature(lambda);
            let want = [[-lambda / r, 0.0], [0.0, -lambda / r]];
            for i in 0..2 {
                for j in 0..2 {
                    assert!((block[i][j] - want[i][j]).abs() < 1e-15, "n̂ {n:?}: {block:?}");
                }
            }
        }
        // On the meridian (no hoop term): one tangent, the same −λ/r.
        let m = [0.6, 0.8];
        let hess = [
            [(1.0 - m[0] * m[0]) / r, -m[0] * m[1] / r, 0.0],
            [-m[0] * m[1] / r, (1.0 - m[1] * m[1]) / r, 0.0],
            [0.0; 3],
        ];
        let node = NodeContact {
            node: 0,
            frame: Frame::meridian(m),
            sigma: 1.0,
            phi: 0.0,
            hess,
            tool: 0,
            axis: [0.0, 1.0, 0.0],
        };
        let block = node.curvature(lambda);
        assert!((block[0][0] + lambda / r).abs() < 1e-15 && block[0][1] == 0.0 && block[1] == [0.0; 2], "{block:?}");
        // A plane: nothing.
        let flat = NodeContact { hess: [[0.0; 3]; 3], ..node };
        assert_eq!(flat.curvature(lambda), [[0.0; 2]; 2]);
    }
}
