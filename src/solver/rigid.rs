//! The rigid motions frictionless plates cannot stop: translation in x and y and rotation about
//! the (vertical) z axis. Those that no displacement constraint blocks (on the full sphere with
//! the poles held in x and y: the rotation about z) are free, and they span the null space of
//! the Jacobian at every state: the residual
//! is invariant under them (objective material, plates and gravity along z), so J t = 0 for
//! the two translations and for the rotation generator e_z × x at the current positions
//! x = X + u. The right-hand side is consistent: the x and y forces and the z moment of the
//! residual vanish by equilibrium (the contact reactions act along z).
//!
//! Attached as the operator's null space (`MatSetNullSpace`), the Krylov method removes these
//! components from its iterates, so each Newton step is the one orthogonal to them and the
//! aggregate does not drift. Why not lock the rotation at a point: a single dof holding a global
//! rotation leaves the operator so ill-conditioned that AMG stalls (FGMRES at 400 iterations)
//! and only LU worked. Why the poles are still held in x and y: a sphere touching a plate at a
//! point (before and while it settles under gravity) can also rotate about horizontal axes
//! through its centre at almost no cost, and those modes are not exact null vectors (they stop
//! being soft once the contact patch grows), so they cannot be projected out.
//!
//! With a direct factorisation the null space is not needed: the free modes are locked instead
//! at as many dofs ([`FreeRigidModes::pins`]), held like active contact dofs (a zero step), so
//! the factorised operator is nonsingular — MUMPS then needs no null-pivot detection, and a kept
//! factorisation can be updated to a new active set (`solver::woodbury`). No reaction arises at
//! a pin: the residual's x, y forces and z moment vanish by equilibrium, so the pinned rows are
//! satisfied once the others are. The solution differs from the null-space one by a rigid
//! motion, which no observable sees.

use crate::error::Result;
use crate::fem::dofmap::DofMap;
use crate::mesh::dist::LocalMesh;
use crate::petsc::{Int, NullSpace, Vector};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// Rigid-body mode m of 3-D displacements at (reference, or centred) position x: the
/// translations e_m (m < 3), then the rotations e_k × x about x, y, z (m = 3 + k).
pub(crate) fn rigid_mode(m: usize, x: &[f64; 3]) -> [f64; 3] {
    match m {
        0..=2 => std::array::from_fn(|c| f64::from(u8::from(c == m))),
        3 => [0.0, -x[2], x[1]],
        4 => [x[2], 0.0, -x[0]],
        _ => [-x[1], x[0], 0.0],
    }
}

/// The candidate modes at reference position x (of the six of [`rigid_mode`]): translation in
/// x, in y, rotation about z.
fn candidate_mode(m: usize, x: &[f64; 3]) -> [f64; 3] {
    rigid_mode([0, 1, 5][m.min(2)], x)
}

/// The free rigid modes of a scene (see the module docs).
pub(crate) struct FreeRigidModes {
    world: SimpleCommunicator,
    /// Which of (x translation, y translation, z rotation) are free.
    free: [bool; 3],
    /// Reference coordinates of the owned nodes (their u dofs are 3n + c of the owned vector).
    coords: Vec<[f64; 3]>,
}

impl FreeRigidModes {
    /// The modes that none of the constrained local dofs `constrained_u` (u dofs 3n + c of local
    /// nodes n) blocks, on any rank; None if all are blocked.
    pub(crate) fn find(
        world: &SimpleCommunicator,
        dofs: &DofMap,
        mesh: &LocalMesh,
        constrained_u: &[usize],
    ) -> Option<FreeRigidModes> {
        // The meridian has none of these motions (its only rigid motion, along z, the plates block).
        if mesh.family.axisymmetric() {
            return None;
        }
        let scale = mesh.coords.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
        let blocked_here: Vec<f64> = (0..3)
            .map(|m| {
                let hit =
                    constrained_u.iter().any(|&l| candidate_mode(m, &mesh.coords[l / 3])[l % 3].abs() > 1e-9 * scale);
                f64::from(u8::from(hit))
            })
            .collect();
        let free: [bool; 3] = std::array::from_fn(|m| crate::parallel::max(world, blocked_here[m]) == 0.0);
        free.iter().any(|&f| f).then(|| FreeRigidModes {
            world: world.duplicate(),
            free,
            coords: mesh.coords[..dofs.n_owned_nodes].to_vec(),
        })
    }

    /// Names of the free modes, for the log.
    pub(crate) fn describe(&self) -> String {
        let names = ["x translation", "y translation", "rotation about z"];
        (0..3).filter(|&m| self.free[m]).map(|m| names[m]).collect::<Vec<_>>().join(", ")
    }

    /// The dofs that lock the free modes (global indices of this rank's, ascending), one per
    /// mode, among the x and y dofs of two nodes: A farthest from the z axis and B farthest from
    /// A in the xy-plane, chosen so that the modes' values there form the best-conditioned
    /// square matrix (largest |det|). `first` is the global index of the first owned dof.
    /// Collective.
    pub(crate) fn pins(&self, first: usize) -> Vec<Int> {
        let free: Vec<usize> = (0..3).filter(|&m| self.free[m]).collect();
        let a = self.farthest(|p| p[0] * p[0] + p[1] * p[1]);
        let b = self.farthest(|p| (p[0] - a.1[0]).powi(2) + (p[1] - a.1[1]).powi(2));
        let candidates = [(a, 0), (a, 1), (b, 0), (b, 1)];
        let value = |i: usize, m: usize| {
            let ((_, x, _), c) = candidates[i];
            candidate_mode(m, &x)[c]
        };
        let mut best = (0.0, Vec::new());
        for set in (0..1usize << 4).filter(|s| s.count_ones() as usize == free.len()) {
            let rows: Vec<usize> = (0..4).filter(|i| set >> i & 1 == 1).collect();
            let m = nalgebra::DMatrix::from_fn(rows.len(), free.len(), |r, c| value(rows[r], free[c]));
            let det = m.determinant().abs();
            if det > best.0 {
                best = (det, rows);
            }
        }
        let me = self.world.rank();
        let mut pins: Vec<Int> = best
            .1
            .iter()
            .filter_map(|&i| {
                let ((owner, _, node), c) = candidates[i];
                (owner == me).then(|| (first + 3 * node + c) as Int)
            })
            .collect();
        pins.sort_unstable();
        pins.dedup();
        pins
    }

    /// The owned node maximising `score` over all ranks (ties: the lowest rank): its rank, its
    /// reference coordinates, and its local index (meaningful on that rank only). Collective.
    fn farthest(&self, score: impl Fn(&[f64; 3]) -> f64) -> (i32, [f64; 3], usize) {
        let (node, s) = self
            .coords
            .iter()
            .enumerate()
            .map(|(n, p)| (n, score(p)))
            .fold((0, f64::NEG_INFINITY), |b, c| if c.1 > b.1 { c } else { b });
        let x = self.coords.get(node).copied().unwrap_or_default();
        let mine = [s, x[0], x[1], x[2]];
        let mut all = vec![0.0; 4 * self.world.size() as usize];
        self.world.all_gather_into(&mine[..], &mut all[..]);
        let owner = (0..self.world.size() as usize).fold(0, |b, r| if all[4 * r] > all[4 * b] { r } else { b });
        let at = [all[4 * owner + 1], all[4 * owner + 2], all[4 * owner + 3]];
        (owner as i32, at, node)
    }

    /// The null space at the state `x` (owned u then p entries; zero on p): the free modes at
    /// the current positions X + u.
    pub(crate) fn null_space(&self, x: &Vector) -> Result<NullSpace> {
        let mut modes = Vec::new();
        for m in (0..3).filter(|&m| self.free[m]) {
            let mut v = x.duplicate()?;
            {
                let xv = x.read()?;
                let mut w = v.write()?;
                w.fill(0.0);
                for (n, p) in self.coords.iter().enumerate() {
                    let cur = [p[0] + xv[3 * n], p[1] + xv[3 * n + 1], p[2] + xv[3 * n + 2]];
                    let t = candidate_mode(m, &cur);
                    w[3 * n..3 * n + 3].copy_from_slice(&t);
                }
            }
            modes.push(v);
        }
        super::gram_schmidt::orthonormalise(&mut modes)?;
        NullSpace::from_vectors(self.world.as_raw(), &modes)
    }
}

#[cfg(test)]
mod tests {
    use super::{candidate_mode, rigid_mode};

    #[test]
    fn rigid_modes_are_translations_and_rotations() {
        let x = [0.3, -1.2, 2.5];
        for m in 0..3 {
            let e: [f64; 3] = std::array::from_fn(|c| f64::from(u8::from(c == m)));
            assert_eq!(rigid_mode(m, &x), e);
            // A rotation e_k × x: orthogonal to its axis and to x, of length |e_k × x|.
            let r = rigid_mode(3 + m, &x);
            assert_eq!(r[m], 0.0);
            assert!((r[0] * x[0] + r[1] * x[1] + r[2] * x[2]).abs() < 1e-15);
        }
        assert_eq!(rigid_mode(5, &x), [1.2, 0.3, 0.0]);
        // The plates' candidates: x and y translation, rotation about z.
        assert_eq!(candidate_mode(0, &x), [1.0, 0.0, 0.0]);
        assert_eq!(candidate_mode(1, &x), [0.0, 1.0, 0.0]);
        assert_eq!(candidate_mode(2, &x), [1.2, 0.3, 0.0]);
    }
}
