//! The committed quadrature-point (qp) state of a model (e.g. the remodelling metric B_p^n),
//! as one flat array: `len` values per point, `n_points` points per element, elements in local
//! order. The element loops hand each element its read-only slice; the end-of-step state is
//! computed from it inside every evaluation and written back only when a step is accepted.
//!
//! A model without qp state has `len = 0`: the store then allocates nothing and every slice is
//! empty. For restarts the store is read and written by original element number
//! ([`QpStore::export`], [`QpStore::import`]), so it does not depend on the partition.

use crate::error::{Error, Result};

#[derive(Debug, Clone, Default)]
pub(crate) struct QpStore {
    /// Values per point.
    len: usize,
    /// Quadrature points per element.
    n_points: usize,
    /// Committed values, element-major, then point, then value.
    committed: Vec<f64>,
}

impl QpStore {
    /// A store for `n_elems` elements of `n_points` points, each initialised by `init`
    /// (which fills `len` values). Nothing is allocated when `len = 0`.
    pub(crate) fn new(n_elems: usize, n_points: usize, len: usize, init: impl Fn(&mut [f64])) -> QpStore {
        let mut committed = vec![0.0; n_elems * n_points * len];
        if len > 0 {
            committed.chunks_exact_mut(len).for_each(init);
        }
        QpStore { len, n_points, committed }
    }

    /// True when the model keeps no qp state.
    pub(crate) fn is_empty(&self) -> bool {
        self.len == 0
    }

    /// The committed values of element `e` (all its points; empty without qp state).
    #[inline]
    pub(crate) fn element(&self, e: usize) -> &[f64] {
        let n = self.len * self.n_points;
        &self.committed[e * n..(e + 1) * n]
    }

    /// Mutable values of element `e`, for committing an accepted step.
    pub(crate) fn element_mut(&mut self, e: usize) -> &mut [f64] {
        let n = self.len * self.n_points;
        &mut self.committed[e * n..(e + 1) * n]
    }

    /// (original element number, its values) for every local element, e.g. for a checkpoint:
    /// `original[e]` is the original number of local element e.
    pub(crate) fn export<'a>(&'a self, original: &'a [u32]) -> impl Iterator<Item = (u32, &'a [f64])> + 'a {
        original.iter().enumerate().map(move |(e, &o)| (o, self.element(e)))
    }

    /// Loads values by original element number (the inverse of [`export`](Self::export) on any
    /// partition); every local element must be found.
    pub(crate) fn import(&mut self, original: &[u32], lookup: impl Fn(u32) -> Option<Vec<f64>>) -> Result<()> {
        for (e, &o) in original.iter().enumerate() {
            let v = lookup(o).ok_or_else(|| Error::Checkpoint(format!("qp state of element {o} missing")))?;
            let dst = self.element_mut(e);
            if v.len() != dst.len() {
                return Err(Error::Checkpoint(format!(
                    "qp state of element {o}: {} values, expected {}",
                    v.len(),
                    dst.len()
                )));
            }
            dst.copy_from_slice(&v);
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn empty_store_allocates_nothing() {
        let s = QpStore::new(1000, 8, 0, |_| unreachable!());
        assert!(s.is_empty() && s.committed.capacity() == 0);
        assert!(s.element(999).is_empty());
    }

    #[test]
    fn slices_and_round_trip_by_original_number() {
        let mut s = QpStore::new(3, 2, 6, |v| v.copy_from_slice(&[1.0, 1.0, 1.0, 0.0, 0.0, 0.0]));
        assert_eq!(s.element(1).len(), 12);
        s.element_mut(2)[7] = 5.0;
        assert_eq!(s.element(2)[6 + 1], 5.0);
        // Export with one numbering, import into a store whose local order is reversed.
        let orig = [10u32, 20, 30];
        let saved: Vec<(u32, Vec<f64>)> = s.export(&orig).map(|(o, v)| (o, v.to_vec())).collect();
        let mut t = QpStore::new(3, 2, 6, |v| v.fill(0.0));
        let rev = [30u32, 20, 10];
        t.import(&rev, |o| saved.iter().find(|(k, _)| *k == o).map(|(_, v)| v.clone())).unwrap();
        assert_eq!(t.element(0), s.element(2));
        assert!(t.import(&[99], |_| None).is_err());
    }
}
