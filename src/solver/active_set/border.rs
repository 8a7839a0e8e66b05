//! Force-controlled positions in the active-set Newton: the bordered system.
//!
//! A tool pressed with a prescribed force has its position d_k along its axis as an unknown,
//! with the equation G_k = c_k·F − f_k = 0: c_k the tool's reaction functional on the raw
//! residual F (its compressive force, as the problem counts it), f_k the target. The bounds of
//! the tool's dofs move with it, ∂l/∂d_k and ∂u/∂d_k, so an active dof's step onto its bound is
//! Δx_i = t_i + s_ik Δd_k. With B the operator whose active rows and columns are replaced, the
//! step is Sherman–Morrison on the bordered matrix [[B, W], [C̃ᵀ, 0]] with one factorisation
//! of B: y₀ = B⁻¹ rhs (the step at fixed d), y_k = B⁻¹ w_k with w_k = −J s_k (diag·s_k on the
//! active rows), c̃_k = Jᵀ c_k (J before the replacement), then the m×m Schur complement
//! S_jk = c̃_j·y_k on the d's: Δd = −S⁻¹(G + C̃ᵀy₀), Δx = y₀ + Σ Δd_k y_k. W, C̃ and the y_k
//! are kept with the operator: a chord iteration costs its one solve, as without force control.
//! (The residual's own dependence on d — adhesion, a current-gap drainage — is left out of the
//! linearisation: it slows Newton, it does not change the solution.)
//!
//! A tool with no active dof anywhere leaves its d undetermined (S_kk = 0): its step is then
//! the contact search, the advance that brings its first dof onto its bound and
//! [`SEARCH_OVERSHOOT`] beyond. Why beyond: a dof merely at its bound is active only where the
//! residual pushes into it, which a tool that has not yet pressed does not cause; the overshoot
//! (projected away) makes that dof's residual push, and the next step is a bordered one.

use crate::error::{Error, Result};
use crate::petsc::{Int, Ksp, Mat, Vector};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::cell::RefCell;
use std::rc::Rc;

/// How far (in the unknowns' length unit: 100 times the "at the bound" tolerance) the contact
/// search advances a tool past first touch.
const SEARCH_OVERSHOOT: f64 = 1e-6;

/// The positions, shared by the problem (its bounds and residual read d; it sets d and the
/// targets at each stage time) and the solver (which moves d with the Newton step).
#[derive(Debug, Clone, Default)]
pub(crate) struct Positions {
    /// d_k, in the unknowns' length unit.
    pub(crate) d: Vec<f64>,
    /// f_k in the unit of c_k·F, or None: the position is prescribed now.
    pub(crate) target: Vec<Option<f64>>,
}

pub(crate) type SharedPositions = Rc<RefCell<Positions>>;

/// One position's vectors (layout of the unknowns).
pub(crate) struct PositionUnknown {
    /// ∂l/∂d_k and ∂u/∂d_k of the bounds (0 on dofs the tool does not bound).
    pub(crate) lower: Vector,
    pub(crate) upper: Vector,
    /// c_k: the tool's reaction c_k·F.
    pub(crate) reaction: Vector,
}

/// What is kept with an assembled operator.
struct Kept {
    /// The controlled positions it was set up for (their indices).
    on: Vec<usize>,
    y: Vec<Vector>,
    ct: Vec<Vector>,
    /// Whether position k has an active dof on some rank.
    touching: Vec<bool>,
}

/// The bordered part of the Newton system (module docs).
pub(crate) struct Border {
    world: SimpleCommunicator,
    shared: SharedPositions,
    unknowns: Vec<PositionUnknown>,
    /// d at the accepted iterate.
    accepted: Vec<f64>,
    /// G_k at the last residual (0 for a prescribed position), and the last step's Δd.
    g: Vec<f64>,
    step: Vec<f64>,
    kept: Option<Kept>,
}

impl Border {
    pub(crate) fn new(world: &SimpleCommunicator, shared: SharedPositions, unknowns: Vec<PositionUnknown>) -> Border {
        let m = unknowns.len();
        Border {
            world: world.duplicate(),
            shared,
            unknowns,
            accepted: vec![0.0; m],
            g: vec![0.0; m],
            step: vec![0.0; m],
            kept: None,
        }
    }

    /// The force-controlled positions now.
    fn on(&self) -> Vec<usize> {
        self.shared.borrow().target.iter().enumerate().filter(|t| t.1.is_some()).map(|t| t.0).collect()
    }

    /// Whether any position is force-controlled now.
    pub(super) fn active(&self) -> bool {
        self.shared.borrow().target.iter().any(Option::is_some)
    }

    /// Whether a chord iteration may use what is kept (set up for the positions controlled now).
    pub(super) fn ready(&self) -> bool {
        self.kept.as_ref().is_some_and(|k| k.on == self.on())
    }

    /// At a solve's start: the positions of the initial iterate are the accepted ones.
    pub(super) fn begin(&mut self) {
        self.accepted.clone_from(&self.shared.borrow().d);
        self.step.iter_mut().for_each(|s| *s = 0.0);
    }

    /// Forgets the kept columns (a new operator, a failed attempt, a restart).
    pub(super) fn forget(&mut self) {
        self.kept = None;
    }

    /// ‖G‖ at the residual `f` (collective).
    pub(super) fn residual(&mut self, f: &Vector) -> Result<f64> {
        let targets = self.shared.borrow().target.clone();
        let mut sum = 0.0;
        for (k, t) in targets.iter().enumerate() {
            self.g[k] = match t {
                Some(t) => self.unknowns[k].reaction.dot(f)? - t,
                None => 0.0,
            };
            sum += self.g[k] * self.g[k];
        }
        Ok(sum.sqrt())
    }

    /// Before the active rows of `a` (the Jacobian) are replaced: c̃_k = aᵀc_k and the columns
    /// w_k for the active set `active` at x (an active dof takes the sensitivity of its nearer
    /// bound). Returns the w_k, to solve for once the operator is set up ([`Border::solve`]).
    pub(super) fn prepare(
        &mut self,
        a: &Mat,
        x: &Vector,
        bounds: (&Vector, &Vector),
        active: &[Int],
        diag: f64,
    ) -> Result<Vec<Vector>> {
        let on = self.on();
        let first = x.ownership_start();
        let (mut ws, mut ct, mut touching) = (Vec::new(), Vec::new(), Vec::new());
        for &k in &on {
            let u = &self.unknowns[k];
            let mut s = x.duplicate()?;
            s.zero()?;
            let mut here = false;
            {
                let (xv, lo, hi, sl, su) =
                    (x.read()?, bounds.0.read()?, bounds.1.read()?, u.lower.read()?, u.upper.read()?);
                let mut sv = s.write()?;
                for &g in active {
                    let i = g as usize - first;
                    sv[i] = if (xv[i] - lo[i]).abs() <= (hi[i] - xv[i]).abs() { sl[i] } else { su[i] };
                    here |= sv[i] != 0.0;
                }
            }
            let mut w = x.duplicate()?;
            a.mult(&s, &mut w)?;
            w.scale(-1.0)?;
            {
                let (sv, mut wv) = (s.read()?, w.write()?);
                for &g in active {
                    let i = g as usize - first;
                    wv[i] = diag * sv[i];
                }
            }
            let mut c = x.duplicate()?;
            a.mult_transpose(&u.reaction, &mut c)?;
            ws.push(w);
            ct.push(c);
            touching.push(crate::parallel::any(&self.world, here));
        }
        self.kept = Some(Kept { on, y: Vec::new(), ct, touching });
        Ok(ws)
    }

    /// y_k = B⁻¹ w_k with the set-up operator of `ksp`.
    pub(super) fn solve(&mut self, ksp: &Ksp, ws: Vec<Vector>) -> Result<()> {
        let Some(kept) = &mut self.kept else { return Ok(()) };
        for w in ws {
            let mut y = w.duplicate()?;
            ksp.solve(&w, &mut y)?;
            kept.y.push(y);
        }
        Ok(())
    }

    /// Completes the step at fixed d in `step` with Δd (module docs); a position that touches
    /// nothing takes the contact search step (the bounds at x), or fails the solve if none of
    /// its dofs can be reached.
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
        let (xv, lo, hi, sl, su) = (x.read()?, bounds.0.read()?, bounds.1.read()?, u.lower.read()?, u.upper.read()?);
        let mut best = f64::INFINITY;
        for i in 0..xv.len() {
            for (b, s) in [(lo[i], sl[i]), (hi[i], su[i])] {
                let d = if s != 0.0 { (xv[i] - b) / s } else { f64::NAN };
                if d >= 0.0 {
                    best = best.min(d);
                }
            }
        }
        let best = -crate::parallel::max(&self.world, -best);
        if best.is_finite() {
            Ok(best + SEARCH_OVERSHOOT)
        } else {
            Err(Error::Diverged(format!(
                "force control: tool {} touches nothing and no advance brings it onto the body",
                k + 1
            )))
        }
    }

    /// Moves the positions to the accepted ones plus λΔd, and the bounds with them.
    pub(super) fn move_to(&mut self, lambda: f64, bounds: (&mut Vector, &mut Vector)) -> Result<()> {
        let mut shared = self.shared.borrow_mut();
        for k in 0..self.unknowns.len() {
            let new = self.accepted[k] + lambda * self.step[k];
            let delta = new - shared.d[k];
            if delta != 0.0 {
                bounds.0.axpy(delta, &self.unknowns[k].lower)?;
                bounds.1.axpy(delta, &self.unknowns[k].upper)?;
                shared.d[k] = new;
            }
        }
        Ok(())
    }

    /// The positions of the trial iterate are accepted.
    pub(super) fn accept(&mut self) {
        self.accepted.clone_from(&self.shared.borrow().d);
    }
}
