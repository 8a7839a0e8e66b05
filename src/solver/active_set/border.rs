//! Force-controlled positions in the active-set Newton: the bordered system.
//!
//! A tool pressed with a prescribed force has its position d_k along its axis as an unknown,
//! with the equation G_k = c_k·F − f_k = 0: c_k the tool's reaction functional on the raw
//! residual F (its compressive force, as the problem counts it), f_k the target. The bounds of
//! the tool's dofs move with it, so an active dof's step onto its bound is Δx̃_i = t_i + s_ik Δd_k:
//! for the upper plate the bound vectors' sensitivities ∂l/∂d_k, ∂u/∂d_k (bounds on single
//! unknowns, [`Moves::Bounds`]); for a tool of the curved contact ([`Moves::Tool`]) the active
//! normal dofs of its nodes, in their rotated frames (the normal the last of the node's block),
//! with s = n̂·a_k (φ moves by −∇φ·a_k Δd_k), and c_k the sum of its nodes' residuals along a_k.
//! With B = QᵀJQ the rotated operator whose active rows and columns are replaced (Q = I without
//! curved tools), the step is Sherman–Morrison on the bordered matrix [[B, W], [C̃ᵀ, 0]] with one
//! factorisation of B: y₀ = B⁻¹ rhs (the step at fixed d), y_k = B⁻¹ w_k with w_k = −QᵀJQ s_k
//! (diag·s_k on the active rows), c̃_k = Jᵀ c_k (J before the rotation and the replacement: the
//! reaction's derivative, without the contact's curvature), then the m×m Schur complement
//! S_jk = c̃_j·Qy_k on the d's: Δd = −S⁻¹(G + C̃ᵀQy₀), Δx = Qy₀ + Σ Δd_k Qy_k. W, C̃ and the
//! y_k (rotated back) are kept with the operator: a chord iteration costs its one solve, as
//! without force control. (The residual's own dependence on d — adhesion, a current-gap
//! drainage — is left out of the linearisation: it slows Newton, it does not change the
//! solution.)
//!
//! A tool with no active dof anywhere leaves its d undetermined (S_kk = 0): its step is then
//! the contact search, the advance that brings its first dof onto its bound and
//! [`SEARCH_OVERSHOOT`] beyond. Why beyond: a dof merely at its bound is active only where the
//! residual pushes into it, which a tool that has not yet pressed does not cause; the overshoot
//! (projected away) makes that dof's residual push, and the next step is a bordered one.

use super::contact::{CurvedContact, NodeContact};
use super::frames::{rotate_owned, Frame};
use crate::error::{Error, Result};
use crate::petsc::{Int, Ksp, Mat, Vector};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::cell::RefCell;
use std::rc::Rc;

/// How far (in the unknowns' length unit: 100 times the "at the bound" tolerance) the contact
/// search advances a tool past first touch.
const SEARCH_OVERSHOOT: f64 = 1e-6;

/// The positions of one owner (the plates, the tools), shared by the problem (its bounds, its
/// tools' gaps and its residual read d; it sets d and the targets at each stage time) and the
/// solver (which moves d with the Newton step).
#[derive(Debug, Clone, Default)]
pub(crate) struct Positions {
    /// d_k, in the unknowns' length unit.
    pub(crate) d: Vec<f64>,
    /// f_k in the unit of c_k·F, or None: the position is prescribed now.
    pub(crate) target: Vec<Option<f64>>,
}

pub(crate) type SharedPositions = Rc<RefCell<Positions>>;

/// One position: where it is kept, its name (in messages) and how its bounds move with it.
pub(crate) struct PositionUnknown {
    pub(crate) shared: SharedPositions,
    pub(crate) index: usize,
    pub(crate) name: String,
    pub(crate) moves: Moves,
}

/// How a position's bounds move with it, and its reaction.
pub(crate) enum Moves {
    /// Bounds on single unknowns (the upper plate): ∂l/∂d_k and ∂u/∂d_k (0 on dofs it does not
    /// bound), and c_k.
    Bounds { lower: Vector, upper: Vector, reaction: Vector },
    /// Tool k of the curved contact: its nodes at the iterate (`NodeContact::tool`).
    Tool(usize),
}

/// What is kept with an assembled operator.
struct Kept {
    /// The controlled positions it was set up for (their indices).
    on: Vec<usize>,
    /// Q y_k and c̃_k (Cartesian).
    y: Vec<Vector>,
    ct: Vec<Vector>,
    /// Whether position k has an active dof on some rank.
    touching: Vec<bool>,
    /// The owned framed nodes the operator was rotated with.
    framed: Vec<(usize, Frame)>,
}

/// The bordered part of the Newton system (module docs).
pub(crate) struct Border {
    world: SimpleCommunicator,
    unknowns: Vec<PositionUnknown>,
    /// The curved contact, for the tools' positions.
    contact: Option<Rc<RefCell<dyn CurvedContact>>>,
    /// d at the accepted iterate.
    accepted: Vec<f64>,
    /// G_k at the last residual (0 for a prescribed position), and the last step's Δd.
    g: Vec<f64>,
    step: Vec<f64>,
    kept: Option<Kept>,
}

impl Border {
    pub(crate) fn new(world: &SimpleCommunicator, unknowns: Vec<PositionUnknown>) -> Border {
        let m = unknowns.len();
        Border {
            world: world.duplicate(),
            unknowns,
            contact: None,
            accepted: vec![0.0; m],
            g: vec![0.0; m],
            step: vec![0.0; m],
            kept: None,
        }
    }

    /// The curved contact whose tools some positions are (their nodes and frames).
    pub(crate) fn set_contact(&mut self, contact: Rc<RefCell<dyn CurvedContact>>) {
        self.contact = Some(contact);
    }

    fn d(&self, k: usize) -> f64 {
        let u = &self.unknowns[k];
        u.shared.borrow().d[u.index]
    }

    fn target(&self, k: usize) -> Option<f64> {
        let u = &self.unknowns[k];
        u.shared.borrow().target[u.index]
    }

    /// The force-controlled positions now.
    fn on(&self) -> Vec<usize> {
        (0..self.unknowns.len()).filter(|&k| self.target(k).is_some()).collect()
    }

    /// Whether any position is force-controlled now.
    pub(super) fn active(&self) -> bool {
        (0..self.unknowns.len()).any(|k| self.target(k).is_some())
    }

    /// Whether a chord iteration may use what is kept (set up for the positions controlled now).
    pub(super) fn ready(&self) -> bool {
        self.kept.as_ref().is_some_and(|k| k.on == self.on())
    }

    /// At a solve's start: the positions of the initial iterate are the accepted ones.
    pub(super) fn begin(&mut self) {
        self.accepted = (0..self.unknowns.len()).map(|k| self.d(k)).collect();
        self.step.iter_mut().for_each(|s| *s = 0.0);
    }

    /// Forgets the kept columns (a new operator, a failed attempt, a restart).
    pub(super) fn forget(&mut self) {
        self.kept = None;
    }

    /// The nodes of the curved contact at the iterate last evaluated that belong to tool `tool`.
    fn tool_nodes(&self, tool: usize) -> Vec<NodeContact> {
        self.contact
            .as_ref()
            .map_or_else(Vec::new, |c| c.borrow().nodes().iter().filter(|n| n.tool == tool).copied().collect())
    }

    /// c_k·f: the tool's reaction in the residual `f` (collective).
    fn reaction(&self, k: usize, f: &Vector) -> Result<f64> {
        match &self.unknowns[k].moves {
            Moves::Bounds { reaction, .. } => reaction.dot(f),
            Moves::Tool(tool) => {
                let fv = f.read()?;
                let here: f64 = self.tool_nodes(*tool).iter().map(|n| n.along_axis(&fv)).sum();
                Ok(crate::parallel::sum(&self.world, here))
            }
        }
    }

    /// ‖G‖ at the residual `f` (collective).
    pub(super) fn residual(&mut self, f: &Vector) -> Result<f64> {
        let mut sum = 0.0;
        for k in 0..self.unknowns.len() {
            self.g[k] = match self.target(k) {
                Some(t) => self.reaction(k, f)? - t,
                None => 0.0,
            };
            sum += self.g[k] * self.g[k];
        }
        Ok(sum.sqrt())
    }

    /// The owned framed nodes of the curved contact at the iterate last evaluated (the frames
    /// the operator is rotated with).
    fn framed(&self) -> Vec<(usize, Frame)> {
        self.contact.as_ref().map_or_else(Vec::new, |c| c.borrow().nodes().iter().map(|n| (n.node, n.frame)).collect())
    }

    /// Before the Jacobian `a` is rotated and its active rows replaced: c̃_k = aᵀc_k and the
    /// columns w_k (in the frames) for the active set `active` at x (a plate's active dof takes
    /// the sensitivity of its nearer bound). Returns the w_k, to solve for once the operator is
    /// set up ([`Border::solve`]).
    pub(super) fn prepare(
        &mut self,
        a: &Mat,
        x: &Vector,
        bounds: (&Vector, &Vector),
        active: &[Int],
        diag: f64,
    ) -> Result<Vec<Vector>> {
        let on = self.on();
        let framed = self.framed();
        let first = x.ownership_start();
        let (mut ws, mut ct, mut touching) = (Vec::new(), Vec::new(), Vec::new());
        for &k in &on {
            let mut s = x.duplicate()?;
            s.zero()?;
            let mut c = x.duplicate()?;
            let mut here = false;
            match &self.unknowns[k].moves {
                Moves::Bounds { lower, upper, reaction } => {
                    let (xv, lo, hi, sl, su) =
                        (x.read()?, bounds.0.read()?, bounds.1.read()?, lower.read()?, upper.read()?);
                    let mut sv = s.write()?;
                    for &g in active {
                        let i = g as usize - first;
                        sv[i] = if (xv[i] - lo[i]).abs() <= (hi[i] - xv[i]).abs() { sl[i] } else { su[i] };
                        here |= sv[i] != 0.0;
                    }
                    c.copy_from(reaction)?;
                }
                Moves::Tool(tool) => {
                    c.zero()?;
                    let (mut sv, mut cv) = (s.write()?, c.write()?);
                    for n in self.tool_nodes(*tool) {
                        let nc = n.frame.components();
                        let normal = nc * n.node + nc - 1;
                        if active.binary_search(&((first + normal) as Int)).is_ok() {
                            sv[normal] = n.along();
                            here |= sv[normal] != 0.0;
                        }
                        cv[nc * n.node..nc * n.node + nc].copy_from_slice(&n.axis[..nc]);
                    }
                }
            }
            // w = −QᵀJQ s, diag·s on the active rows.
            let mut q_s = s.copy()?;
            rotate_owned(&mut q_s.write()?, &framed, true);
            let mut w = x.duplicate()?;
            a.mult(&q_s, &mut w)?;
            w.scale(-1.0)?;
            {
                let (sv, mut wv) = (s.read()?, w.write()?);
                rotate_owned(&mut wv, &framed, false);
                for &g in active {
                    let i = g as usize - first;
                    wv[i] = diag * sv[i];
                }
            }
            let mut cj = x.duplicate()?;
            a.mult_transpose(&c, &mut cj)?;
            ws.push(w);
            ct.push(cj);
            touching.push(crate::parallel::any(&self.world, here));
        }
        self.kept = Some(Kept { on, y: Vec::new(), ct, touching, framed });
        Ok(ws)
    }

    /// y_k = B⁻¹ w_k with the set-up operator of `ksp`, kept rotated back (Q y_k).
    pub(super) fn solve(&mut self, ksp: &Ksp, ws: Vec<Vector>) -> Result<()> {
        let Some(kept) = &mut self.kept else { return Ok(()) };
        for w in ws {
            let mut y = w.duplicate()?;
            ksp.solve(&w, &mut y)?;
            rotate_owned(&mut y.write()?, &kept.framed, true);
            kept.y.push(y);
        }
        Ok(())
    }

    /// Completes the step at fixed d in `step` (Cartesian) with Δd (module docs); a position
    /// that touches nothing takes the contact search step (the bounds at x), or fails the solve
    /// if none of its dofs can be reached.
    pub(super) fn correct(&mut self, step: &mut Vector, x: &Vector, bounds: (&Vector, &Vector)) -> Result<()> {
        let Some(kept) = &self.kept else { return Ok(()) };
        let on: Vec<(usize, usize)> =
            kept.on.iter().enumerate().filter(|(j, _)| kept.touching[*j]).map(|(j, &k)| (j, k)).collect();
        let n = on.len();
        let mut s = nalgebra::DMatrix::zeros(n, n);
        let mut r = nalgebra::DVector::zeros(n);
        for (a, &(j, k)) in on.iter().enumerate() {
            r[a] = -(self.g[k] + kept.ct[j].dot(step)?);
            for (b, &(i, _)) in on.iter().enumerate() {
                s[(a, b)] = kept.ct[j].dot(&kept.y[i])?;
            }
        }
        let dd = if n == 0 { Some(r.clone()) } else { s.lu().solve(&r) }
            .ok_or_else(|| Error::Diverged("the force-controlled positions' Schur complement is singular".into()))?;
        self.step.iter_mut().for_each(|v| *v = 0.0);
        for (a, &(j, k)) in on.iter().enumerate() {
            self.step[k] = dd[a];
            step.axpy(dd[a], &kept.y[j])?;
        }
        for (j, &k) in kept.on.iter().enumerate() {
            if !kept.touching[j] {
                self.step[k] = self.search(k, x, bounds)?;
            }
        }
        Ok(())
    }

    /// The advance of position k that brings its nearest dof onto its bound (collective).
    fn search(&self, k: usize, x: &Vector, bounds: (&Vector, &Vector)) -> Result<f64> {
        let u = &self.unknowns[k];
        let mut best = f64::INFINITY;
        match &u.moves {
            Moves::Bounds { lower, upper, .. } => {
                let (xv, lo, hi, sl, su) =
                    (x.read()?, bounds.0.read()?, bounds.1.read()?, lower.read()?, upper.read()?);
                for i in 0..xv.len() {
                    for (b, s) in [(lo[i], sl[i]), (hi[i], su[i])] {
                        let d = if s != 0.0 { (xv[i] - b) / s } else { f64::NAN };
                        if d >= 0.0 {
                            best = best.min(d);
                        }
                    }
                }
            }
            // φ − (ν·a) Δd = 0 at first touch: the nodes the advance approaches (ν·a > 0).
            Moves::Tool(tool) => {
                for n in self.tool_nodes(*tool) {
                    let approach = n.sigma * n.along();
                    if approach > 0.0 {
                        best = best.min(n.phi.max(0.0) / approach);
                    }
                }
            }
        }
        let best = -crate::parallel::max(&self.world, -best);
        if best.is_finite() {
            Ok(best + SEARCH_OVERSHOOT)
        } else {
            Err(Error::Diverged(format!(
                "force control: {} touches nothing and no advance along its axis brings it onto the body",
                u.name
            )))
        }
    }

    /// Moves the positions to the accepted ones plus λΔd, and the plates' bounds with them.
    pub(super) fn move_to(&mut self, lambda: f64, bounds: (&mut Vector, &mut Vector)) -> Result<()> {
        for k in 0..self.unknowns.len() {
            let new = self.accepted[k] + lambda * self.step[k];
            let delta = new - self.d(k);
            if delta != 0.0 {
                let u = &self.unknowns[k];
                if let Moves::Bounds { lower, upper, .. } = &u.moves {
                    bounds.0.axpy(delta, lower)?;
                    bounds.1.axpy(delta, upper)?;
                }
                u.shared.borrow_mut().d[u.index] = new;
            }
        }
        Ok(())
    }

    /// The positions of the trial iterate are accepted.
    pub(super) fn accept(&mut self) {
        self.accepted = (0..self.unknowns.len()).map(|k| self.d(k)).collect();
    }
}
