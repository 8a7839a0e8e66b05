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

use crate::error::Result;
use crate::fem::dofmap::DofMap;
use crate::mesh::dist::LocalMesh;
use crate::petsc::{NullSpace, Vector};
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// The candidate modes at reference position x: translation in x, in y, rotation about z.
fn mode(m: usize, x: &[f64; 3]) -> [f64; 3] {
    match m {
        0 => [1.0, 0.0, 0.0],
        1 => [0.0, 1.0, 0.0],
        _ => [-x[1], x[0], 0.0],
    }
}

/// The free rigid modes of a scene (see the module docs).
pub struct FreeRigidModes {
    world: SimpleCommunicator,
    /// Which of (x translation, y translation, z rotation) are free.
    free: [bool; 3],
    /// Reference coordinates of the owned nodes (their u dofs are 3n + c of the owned vector).
    coords: Vec<[f64; 3]>,
}

impl FreeRigidModes {
    /// The modes that none of the constrained local dofs `constrained_u` (u dofs 3n + c of local
    /// nodes n) blocks, on any rank; None if all are blocked.
    pub fn find(
        world: &SimpleCommunicator,
        dofs: &DofMap,
        mesh: &LocalMesh,
        constrained_u: &[usize],
    ) -> Option<FreeRigidModes> {
        let scale = mesh.coords.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-300);
        let blocked_here: Vec<f64> = (0..3)
            .map(|m| {
                let hit = constrained_u.iter().any(|&l| mode(m, &mesh.coords[l / 3])[l % 3].abs() > 1e-9 * scale);
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
    pub fn describe(&self) -> String {
        let names = ["x translation", "y translation", "rotation about z"];
        (0..3).filter(|&m| self.free[m]).map(|m| names[m]).collect::<Vec<_>>().join(", ")
    }

    /// The null space at the state `x` (owned u then p entries; zero on p): the free modes at
    /// the current positions X + u.
    pub fn null_space(&self, x: &Vector) -> Result<NullSpace> {
        let mut modes = Vec::new();
        for m in (0..3).filter(|&m| self.free[m]) {
            let mut v = x.duplicate()?;
            {
                let xv = x.read()?;
                let mut w = v.write()?;
                w.fill(0.0);
                for (n, p) in self.coords.iter().enumerate() {
                    let cur = [p[0] + xv[3 * n], p[1] + xv[3 * n + 1], p[2] + xv[3 * n + 2]];
                    let t = mode(m, &cur);
                    w[3 * n..3 * n + 3].copy_from_slice(&t);
                }
            }
            modes.push(v);
        }
        super::orthonormalise(&mut modes)?;
        NullSpace::from_vectors(self.world.as_raw(), &modes)
    }
}
