//! The bounds of the contact problem and the active-set split of an iterate (the module docs
//! of `active_set` give the test).

use crate::error::Result;
use crate::petsc::{Int, Vector};

/// PETSc's vinewtonrsls tolerance for "at the bound" (absolute, in the unknowns' units).
pub(super) const AT_BOUND: f64 = 1e-8;

/// Size of the symmetric difference of two ascending index lists.
pub(super) fn symmetric_difference(a: &[Int], b: &[Int]) -> usize {
    let (mut i, mut j, mut n) = (0, 0, 0);
    while i < a.len() && j < b.len() {
        match a[i].cmp(&b[j]) {
            std::cmp::Ordering::Less => (i, n) = (i + 1, n + 1),
            std::cmp::Ordering::Greater => (j, n) = (j + 1, n + 1),
            std::cmp::Ordering::Equal => (i, j) = (i + 1, j + 1),
        }
    }
    n + (a.len() - i) + (b.len() - j)
}

/// The bounds l ≤ x ≤ u (shared with the problem, which moves them with the plate), and the
/// dofs held where they are (the free rigid modes' pins).
pub(super) struct Bounds {
    pub(super) lower: Vector,
    pub(super) upper: Vector,
    pub(super) pinned: Vec<Int>,
}

impl Bounds {
    /// Clamps x into [l, u].
    pub(super) fn project(&self, x: &mut Vector) -> Result<()> {
        let (lo, hi) = (self.lower.read()?, self.upper.read()?);
        for ((xi, &l), &h) in x.write()?.iter_mut().zip(lo.iter()).zip(hi.iter()) {
            *xi = xi.max(l).min(h);
        }
        Ok(())
    }

    /// From x and f = F(x): the active set, the Newton right-hand side −F on the free dofs and
    /// 0 on the active ones, the step onto the bound on the active ones (0 elsewhere) in `to_bound`;
    /// returns the free residual norm. The pinned dofs (ascending) are always active, with a
    /// zero step.
    pub(super) fn split(
        &self,
        x: &Vector,
        f: &Vector,
        rhs: &mut Vector,
        to_bound: &mut Vector,
        active: &mut Vec<Int>,
    ) -> Result<f64> {
        self.split_dofs(x, f, rhs, to_bound, active)?;
        rhs.norm2()
    }

    /// [`split`](Self::split) without the norm (the curved tools' split rewrites some entries
    /// before it is taken).
    pub(super) fn split_dofs(
        &self,
        x: &Vector,
        f: &Vector,
        rhs: &mut Vector,
        to_bound: &mut Vector,
        active: &mut Vec<Int>,
    ) -> Result<()> {
        let first = x.ownership_start();
        active.clear();
        {
            let (xv, fv, lo, hi) = (x.read()?, f.read()?, self.lower.read()?, self.upper.read()?);
            let (mut r, mut d) = (rhs.write()?, to_bound.write()?);
            let mut pins = self.pinned.iter().peekable();
            for i in 0..xv.len() {
                if pins.next_if_eq(&&((first + i) as Int)).is_some() {
                    active.push((first + i) as Int);
                    r[i] = 0.0;
                    d[i] = 0.0;
                    continue;
                }
                let at_lower = xv[i] <= lo[i] + AT_BOUND && fv[i] > 0.0;
                let at_upper = xv[i] >= hi[i] - AT_BOUND && fv[i] < 0.0;
                if at_lower || at_upper {
                    active.push((first + i) as Int);
                    r[i] = 0.0;
                    d[i] = if at_lower { lo[i] } else { hi[i] } - xv[i];
                } else {
                    r[i] = -fv[i];
                    d[i] = 0.0;
                }
            }
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::symmetric_difference;

    #[test]
    fn active_set_changes_count_both_ways() {
        assert_eq!(symmetric_difference(&[1, 3, 5], &[1, 3, 5]), 0);
        assert_eq!(symmetric_difference(&[1, 3, 5], &[1, 4, 5, 9]), 3);
        assert_eq!(symmetric_difference(&[], &[2, 7]), 2);
        assert_eq!(symmetric_difference(&[2, 7], &[]), 2);
    }
}
