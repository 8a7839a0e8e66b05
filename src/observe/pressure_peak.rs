//! The largest pore pressure of a run: the largest nodal p over the vertices (where the P1
//! pressure lives) of every step, with its time and the node's reference position — the run
//! summary's "largest p and its place". Kept step by step, because the fields are written at a
//! few steps only, and carried by the checkpoints, so that a resumed run's peak is the whole
//! run's.

use crate::fem::dofmap::DofMap;
use crate::mesh::dist::LocalMesh;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// The largest p seen so far (kPa), at time `t` (s), at the node of reference position `at`
/// (µm; on the meridian (r, 0, z)). `p` is −∞ before any state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct PressurePeak {
    pub(crate) p: f64,
    pub(crate) t: f64,
    pub(crate) at: [f64; 3],
}

impl Default for PressurePeak {
    fn default() -> Self {
        PressurePeak { p: f64::NEG_INFINITY, t: f64::NAN, at: [f64::NAN; 3] }
    }
}

impl PressurePeak {
    /// The largest p of the state `local` at time t (collective): of the owned vertices, the
    /// lowest rank's on a tie.
    pub(crate) fn of_state(mesh: &LocalMesh, dofs: &DofMap, local: &[f64], t: f64, world: &SimpleCommunicator) -> Self {
        let mut mine = PressurePeak { t, ..PressurePeak::default() };
        for node in 0..mesh.n_owned_nodes {
            let v = mesh.vertex_of_node[node];
            if v >= 0 {
                let p = local[dofs.p_local(v as usize)];
                if p > mine.p {
                    (mine.p, mine.at) = (p, mesh.coords[node]);
                }
            }
        }
        let p = crate::parallel::max(world, mine.p);
        // The lowest rank that holds it sends its place.
        let holder = if mine.p == p { world.rank() } else { world.size() };
        let mut first = holder;
        world.all_reduce_into(&holder, &mut first, mpi::collective::SystemOperation::min());
        let mut at = mine.at.to_vec();
        crate::parallel::broadcast_vec(world, first.min(world.size() - 1), &mut at);
        PressurePeak { p, t, at: [at[0], at[1], at[2]] }
    }

    /// The larger of two peaks (the earlier on a tie).
    pub(crate) fn max(self, other: PressurePeak) -> PressurePeak {
        if other.p > self.p {
            other
        } else {
            self
        }
    }

    /// As a checkpoint stores it: p, t, x, y, z.
    pub(crate) fn to_array(self) -> [f64; 5] {
        [self.p, self.t, self.at[0], self.at[1], self.at[2]]
    }

    pub(crate) fn from_array(a: [f64; 5]) -> PressurePeak {
        PressurePeak { p: a[0], t: a[1], at: [a[2], a[3], a[4]] }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_larger_and_on_a_tie_the_earlier() {
        let a = PressurePeak { p: 2.0, t: 1.0, at: [1.0, 0.0, 2.0] };
        let b = PressurePeak { p: 3.0, t: 2.0, at: [0.0, 0.0, 5.0] };
        let c = PressurePeak { p: 3.0, t: 4.0, at: [9.0, 0.0, 9.0] };
        assert_eq!(PressurePeak::default().max(a), a);
        assert_eq!(a.max(b), b);
        assert_eq!(b.max(a), b);
        assert_eq!(b.max(c), b);
        assert_eq!(PressurePeak::from_array(c.to_array()), c);
    }
}
