//! The u/p field decomposition handed to PCFIELDSPLIT through a DMShell, with the rigid-body
//! near-null space on u.

use super::rigid::rigid_mode;
use crate::error::Result;
use crate::fem::dofmap::DofMap;
use crate::mesh::dist::LocalMesh;
use crate::parallel::sum_slice;
use crate::petsc::{FieldDecomposition, IndexSet, Int, NullSpace, Snes, Vector};
use mpi::collective::SystemOperation;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;

/// The u and p fields for PCFIELDSPLIT via a DMShell: the full u/p sets, or — once SNESVI
/// (vinewtonrsls) has an inactive set — the sets of the reduced system it actually solves.
///
/// Why: rsls solves for the inactive (free) dofs only, with the submatrix A(I, I) numbered
/// 0..|I| across ranks. PETSc 3.18 frees index sets given with `PCFieldSplitSetIS` when the
/// active set changes, but asks the DM for a new decomposition after every reset; so here the
/// full sets are restricted to I (a rank's reduced indices start at the prefix sum of the
/// inactive sizes of lower ranks). The reduced u set is no longer a multiple of 3 (contact u_z
/// dofs are removed), so instead of `MatNullSpaceCreateRigidBody` the six rigid-body modes are
/// restricted to the free u dofs, orthonormalised, and attached as "nearnullspace".
///
/// On the meridian (u_r, u_z per node) the only rigid motion is the translation along the axis:
/// the near-null space is that one vector, and the u block has block size 2.
pub(crate) struct Fields {
    world: SimpleCommunicator,
    /// Displacement components per node (3, or 2 on the meridian).
    nc: usize,
    u_range: (usize, usize),
    p_range: (usize, usize),
    /// Owned node coordinates, centred on the global centroid (better conditioned modes).
    coords: Vec<[f64; 3]>,
    u: IndexSet,
    p: IndexSet,
    near_null: NullSpace,
}

impl Fields {
    pub(crate) fn new(world: &SimpleCommunicator, dofs: &DofMap, mesh: &LocalMesh) -> Result<Fields> {
        let comm = world.as_raw();
        let (u0, u1) = dofs.u_range();
        let (p0, p1) = dofs.p_range();
        let nc = dofs.nc;
        let mut u = IndexSet::stride(comm, u1 - u0, u0, 1)?;
        u.set_block_size(nc)?;
        let p = IndexSet::stride(comm, p1 - p0, p0, 1)?;
        let n = dofs.n_owned_nodes;
        let mut sum = [0.0f64; 4];
        for x in &mesh.coords[..n] {
            sum[0] += x[0];
            sum[1] += x[1];
            sum[2] += x[2];
        }
        sum[3] = n as f64;
        let tot = sum_slice(world, &sum);
        let c: [f64; 3] = std::array::from_fn(|d| tot[d] / tot[3].max(1.0));
        let coords: Vec<[f64; 3]> = mesh.coords[..n].iter().map(|x| [x[0] - c[0], x[1] - c[1], x[2] - c[2]]).collect();
        // Rigid-body modes of the full u block.
        let near_null = if nc == 3 {
            let mut cv = Vector::mpi(comm, 3 * n)?;
            cv.set_block_size(3)?;
            cv.write()?.copy_from_slice(coords.as_flattened());
            NullSpace::rigid_body(&cv)?
        } else {
            let mut v = Vector::mpi(comm, nc * n)?;
            v.write()?.iter_mut().enumerate().for_each(|(i, x)| *x = mode(nc, 0, i % nc, coords[i / nc]));
            let mut modes = vec![v];
            super::gram_schmidt::orthonormalise(&mut modes)?;
            NullSpace::from_vectors(comm, &modes)?
        };
        Ok(Fields { world: world.duplicate(), nc, u_range: (u0, u1), p_range: (p0, p1), coords, u, p, near_null })
    }

    /// The fields of the reduced system solving for the dofs in `inactive`.
    fn restricted(&self, inactive: &IndexSet) -> Result<Vec<(String, IndexSet)>> {
        let comm = self.world.as_raw();
        let idx = inactive.indices()?;
        let n = idx.len() as i64;
        let mut offset = 0i64;
        self.world.exclusive_scan_into(&n, &mut offset, SystemOperation::sum());
        if self.world.rank() == 0 {
            offset = 0; // MPI_Exscan leaves rank 0's result undefined.
        }
        let (mut u_red, mut p_red, mut u_full) = (Vec::new(), Vec::new(), Vec::new());
        for (k, &g) in idx.iter().enumerate() {
            let g = g as usize;
            let r = (offset + k as i64) as Int;
            if (self.u_range.0..self.u_range.1).contains(&g) {
                u_red.push(r);
                u_full.push(g - self.u_range.0);
            } else if (self.p_range.0..self.p_range.1).contains(&g) {
                p_red.push(r);
            }
        }
        // Six rigid-body modes on the free u dofs: translations e_c, rotations e_k × x (on the
        // meridian: the translation along z alone).
        let nc = self.nc;
        let n_modes = if nc == 3 { 6 } else { 1 };
        let mut modes = Vec::with_capacity(n_modes);
        for m in 0..n_modes {
            let mut v = Vector::mpi(comm, u_full.len())?;
            {
                let mut w = v.write()?;
                for (i, &l) in u_full.iter().enumerate() {
                    w[i] = mode(nc, m, l % nc, self.coords[l / nc]);
                }
            }
            modes.push(v);
        }
        super::gram_schmidt::orthonormalise(&mut modes)?;
        let mut u = IndexSet::general(comm, &u_red)?;
        u.compose("nearnullspace", &NullSpace::from_vectors(comm, &modes)?)?;
        let p = IndexSet::general(comm, &p_red)?;
        Ok(vec![("u".into(), u), ("p".into(), p)])
    }
}

/// Rigid-body mode m at displacement component c of a node at (centred) x: in 3-D (nc = 3) the
/// six of [`rigid_mode`]; on the meridian (nc = 2, components u_r, u_z) the translation along z,
/// its one mode.
fn mode(nc: usize, m: usize, c: usize, x: [f64; 3]) -> f64 {
    if nc != 3 {
        return f64::from(u8::from(c == nc - 1));
    }
    rigid_mode(m, &x)[c]
}

impl FieldDecomposition for Fields {
    fn fields(&mut self, snes: Option<Snes>) -> Result<Vec<(String, IndexSet)>> {
        // Before the first VI iteration there is no inactive set: the full sets.
        let inactive = match snes {
            Some(s) if s.is_vi()? => s.vi_inactive_set()?,
            _ => None,
        };
        if let Some(is) = inactive {
            return self.restricted(&is);
        }
        let mut u = IndexSet::stride_like(&self.u)?;
        u.set_block_size(self.nc)?;
        u.compose("nearnullspace", &self.near_null)?;
        let p = IndexSet::stride_like(&self.p)?;
        Ok(vec![("u".into(), u), ("p".into(), p)])
    }
}
