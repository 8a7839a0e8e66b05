//! Chord iterations across small active-set changes: the Sherman–Morrison–Woodbury update of a
//! factorised active-set operator.
//!
//! The active-set Newton solves with B = J with the rows and columns of the active set S
//! replaced by d·I. A factorisation P⁻¹ of that operator for an earlier set S₀ (same J) is
//! kept for chord iterations; when k dofs D = S₀ Δ S have changed status, B − P lives in the
//! rows and columns of D only:
//!
//!   B − P = Σ_{i∈D} e_i r_iᵀ + c̃_i e_iᵀ,   r_i = (B − P)ᵀ e_i,   c̃_i = (B − P) e_i with the D
//!   entries zeroed (so that the D×D block is counted once),
//!
//! a rank-2k update B = P + U Vᵀ. Then B⁻¹ b = y − Z K⁻¹ Vᵀ y with y = P⁻¹ b, Z = P⁻¹ U and the
//! 2k×2k capacitance matrix K = I + Vᵀ Z. Setting it up costs 2k solves with P (one block
//! solve: a single pass over the factors) and one product with J and Jᵀ per changed dof; each
//! use one solve and 2k dot products. That is cheaper than assembling and factorising anew
//! while k is small, and it is exact: the chord iteration stays the one with the operator of
//! the current active set.

use crate::error::{Error, Result};
use crate::parallel::{all_gather_vec, sum_slice};
use crate::petsc::{Int, Mat, Pc, Vector};
use mpi::topology::SimpleCommunicator;
use nalgebra::{DMatrix, DVector, Dyn, LU};

/// B⁻¹ for an active set that differs from the factorised operator's in a few dofs.
pub struct ActiveSetUpdate {
    /// The active set (owned dofs, global indices) this update solves for.
    pub(crate) active: Vec<Int>,
    /// Global indices of the changed dofs D (the same list on every rank).
    changed: Vec<Int>,
    /// r_i = (B − P)ᵀ e_i for i ∈ D.
    rows: Vec<Vector>,
    /// Z = P⁻¹ U: the P⁻¹ e_i, then the P⁻¹ c̃_i.
    z: Vec<Vector>,
    /// LU of the capacitance matrix (the same on every rank).
    capacitance: LU<f64, Dyn, Dyn>,
    /// Changed dofs owned here: (local index, position in `changed`).
    owned: Vec<(usize, usize)>,
}

/// Membership of the owned dofs in a sorted list of global indices.
fn mask(active: &[Int], first: usize, n: usize) -> Vec<bool> {
    let mut m = vec![false; n];
    for &g in active {
        m[g as usize - first] = true;
    }
    m
}

impl ActiveSetUpdate {
    /// The update from the factorised operator P (active set `old`, preconditioner `pc` an exact
    /// factorisation of it, `jac` the Jacobian before the active rows were replaced) to the
    /// active set `new`. `diag` is the identity rows' scale. None if B is singular (K is).
    /// Collective.
    pub fn new(
        world: &SimpleCommunicator,
        jac: &Mat,
        pc: Pc,
        old: &[Int],
        new: &[Int],
        diag: f64,
    ) -> Result<Option<ActiveSetUpdate>> {
        let (mut e, mut jcol) = jac.create_vecs()?;
        let mut jrow = jcol.duplicate()?;
        let (first, n) = (e.ownership_start(), e.local_size());
        let (was, is) = (mask(old, first, n), mask(new, first, n));
        // D, gathered: +(i+1) for a dof that left the active set, −(i+1) for one that entered.
        let local: Vec<i64> =
            (0..n).filter(|&i| was[i] != is[i]).map(|i| if was[i] { 1 } else { -1 } * (first + i + 1) as i64).collect();
        let signed = all_gather_vec(world, &local);
        let changed: Vec<Int> = signed.iter().map(|s| (s.unsigned_abs() - 1) as Int).collect();
        let owned: Vec<(usize, usize)> = changed
            .iter()
            .enumerate()
            .filter(|(_, &g)| (first..first + n).contains(&(g as usize)))
            .map(|(m, &g)| (g as usize - first, m))
            .collect();
        let k = changed.len();

        // The changed rows r_i and columns c̃_i of B − P, from J e_i and Jᵀ e_i: for a dof that
        // left S the row (column) of J restricted to the new free set, minus d e_i; for one
        // that entered, d e_i minus the row (column) of J restricted to the old free set.
        // U = [e_D, C̃], and Z = P⁻¹ U after the loop.
        let mut rows = Vec::with_capacity(k);
        let mut u = Vec::with_capacity(2 * k);
        let mut cols = Vec::with_capacity(k);
        for (m, &s) in signed.iter().enumerate() {
            let here = owned.iter().find(|o| o.1 == m).map(|o| o.0);
            e.zero()?;
            if let Some(i) = here {
                e.write()?[i] = 1.0;
            }
            u.push(e.copy()?);
            jac.mult(&e, &mut jcol)?;
            jac.mult_transpose(&e, &mut jrow)?;
            // The row and column of J that one of B and P has, on that one's free set.
            let (sign, active) = if s > 0 { (1.0, &is) } else { (-1.0, &was) };
            let mut r = jrow.duplicate()?;
            let mut c = jcol.duplicate()?;
            {
                let (jr, jc) = (jrow.read()?, jcol.read()?);
                let (mut rw, mut cw) = (r.write()?, c.write()?);
                for i in 0..n {
                    let free = if active[i] { 0.0 } else { sign };
                    rw[i] = free * jr[i];
                    cw[i] = free * jc[i];
                }
                if let Some(i) = here {
                    rw[i] -= sign * diag;
                    cw[i] -= sign * diag;
                }
                for &(i, _) in &owned {
                    cw[i] = 0.0;
                }
            }
            rows.push(r);
            cols.push(c);
        }

        u.append(&mut cols);
        let mut z = u.iter().map(|v| v.duplicate()).collect::<Result<Vec<_>>>()?;
        pc.apply_columns(&u, &mut z)?;

        // K = I + Vᵀ Z, Vᵀ = [R; E_Dᵀ]: partial sums here, one reduction.
        let mut part = vec![0.0; 4 * k * k];
        for (b, zb) in z.iter().enumerate() {
            let zv = zb.read()?;
            for (a, r) in rows.iter().enumerate() {
                part[a * 2 * k + b] = r.read()?.iter().zip(zv.iter()).map(|(x, y)| x * y).sum();
            }
            for &(i, m) in &owned {
                part[(k + m) * 2 * k + b] = zv[i];
            }
        }
        let mut kmat = DMatrix::from_row_slice(2 * k, 2 * k, &sum_slice(world, &part));
        kmat += DMatrix::identity(2 * k, 2 * k);
        let capacitance = kmat.lu();
        if !capacitance.is_invertible() {
            return Ok(None);
        }
        Ok(Some(ActiveSetUpdate { active: new.to_vec(), changed, rows, z, capacitance, owned }))
    }

    /// Number of changed dofs.
    pub fn n_changed(&self) -> usize {
        self.changed.len()
    }

    /// x = B⁻¹ b (collective).
    pub fn solve(&self, world: &SimpleCommunicator, pc: Pc, b: &Vector, x: &mut Vector) -> Result<()> {
        let k = self.changed.len();
        pc.apply(b, x)?;
        let mut part = vec![0.0; 2 * k];
        {
            let y = x.read()?;
            for (a, r) in self.rows.iter().enumerate() {
                part[a] = r.read()?.iter().zip(y.iter()).map(|(p, q)| p * q).sum();
            }
            for &(i, m) in &self.owned {
                part[k + m] = y[i];
            }
        }
        let alpha = self
            .capacitance
            .solve(&DVector::from_vec(sum_slice(world, &part)))
            .ok_or_else(|| Error::Diverged("active-set update: singular capacitance matrix".into()))?;
        for (zm, a) in self.z.iter().zip(alpha.iter()) {
            x.axpy(-a, zm)?;
        }
        Ok(())
    }
}
