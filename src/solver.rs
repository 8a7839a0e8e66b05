//! Solver policy: default PETSc options per preset, the u/p field decomposition handed to
//! PCFIELDSPLIT through a DMShell (with the rigid-body near-null space on u), and the
//! fixed-stress Schur approximation as the user Schur preconditioner.
//!
//! Default ("fieldsplit"): FGMRES on the full u–p system, preconditioned by an upper Schur
//! factorisation; the u block by one GAMG V-cycle (block size 3, six rigid-body modes), the
//! Schur complement by one BoomerAMG V-cycle on Ŝ = K_darcy + (shift/K_dr) M_p, which stays
//! spectrally equivalent to the true Schur complement as Δt → 0 and as k → 0.
//! Reference ("lu"): MUMPS direct solve. Every default is overridable from the command line
//! (`-- -pc_type ...`) or the scene's `[petsc]` table.

use crate::error::Result;
use crate::fem::dofmap::DofMap;
use crate::mesh::dist::LocalMesh;
use crate::petsc::{check, ffi, options, FieldDecomposition, IndexSet, Mat, NullSpace, Snes, Vector};

/// Sets the defaults of a preset (only options the user has not set).
pub fn set_default_options(preset: &str) -> Result<()> {
    let d = |k: &str, v: &str| options::set_default(k, Some(v));
    match preset {
        "lu" => {
            d("ksp_type", "preonly")?;
            d("pc_type", "lu")?;
            d("pc_factor_mat_solver_type", "mumps")?;
        }
        _ => {
            d("ksp_type", "fgmres")?;
            d("ksp_rtol", "1e-8")?;
            d("ksp_max_it", "400")?;
            d("ksp_gmres_restart", "100")?;
            d("pc_type", "fieldsplit")?;
            d("pc_fieldsplit_type", "schur")?;
            d("pc_fieldsplit_schur_fact_type", "upper")?;
            d("fieldsplit_u_ksp_type", "preonly")?;
            // Set explicitly: PETSc 3.18's SNESVI replaces a first-split PCBJACOBI by fixed
            // 101×101 blocks, which fails in parallel.
            d("fieldsplit_u_pc_type", "gamg")?;
            d("fieldsplit_p_ksp_type", "preonly")?;
            d("fieldsplit_p_pc_type", "hypre")?;
        }
    }
    d("snes_rtol", "1e-8")?;
    d("snes_atol", "1e-10")?;
    d("snes_max_it", "25")?;
    Ok(())
}

/// The u and p fields of the full system, for PCFIELDSPLIT via a DMShell.
pub struct Fields {
    u: IndexSet,
    p: IndexSet,
    near_null: NullSpace,
}

impl Fields {
    pub fn new(comm: ffi::MPI_Comm, dofs: &DofMap, mesh: &LocalMesh) -> Result<Fields> {
        let (u0, u1) = dofs.u_range();
        let (p0, p1) = dofs.p_range();
        let mut u = IndexSet::stride(comm, u1 - u0, u0, 1)?;
        u.set_block_size(3)?;
        let p = IndexSet::stride(comm, p1 - p0, p0, 1)?;
        // Rigid-body modes of the u block from the owned nodes' coordinates.
        let mut coords = Vector::mpi(comm, 3 * dofs.n_owned_nodes)?;
        coords.set_block_size(3)?;
        {
            let mut w = coords.write()?;
            for n in 0..dofs.n_owned_nodes {
                w[3 * n..3 * n + 3].copy_from_slice(&mesh.coords[n]);
            }
        }
        let near_null = NullSpace::rigid_body(&coords)?;
        Ok(Fields { u, p, near_null })
    }
}

impl FieldDecomposition for Fields {
    fn fields(&mut self, _snes: Option<Snes>) -> Result<Vec<(String, IndexSet)>> {
        let mut u = IndexSet::stride_like(&self.u)?;
        u.set_block_size(3)?;
        u.compose("nearnullspace", &self.near_null)?;
        let p = IndexSet::stride_like(&self.p)?;
        Ok(vec![("u".into(), u), ("p".into(), p)])
    }
}

/// Uses `schur` as the Schur-complement preconditioner if the PC is a Schur fieldsplit and the
/// user did not choose another (`-pc_fieldsplit_schur_precondition`).
pub fn use_schur_matrix(snes: &Snes, schur: &Mat) -> Result<()> {
    let pc = snes.ksp()?.pc()?;
    if pc.type_name()? == "fieldsplit" && !options::has("pc_fieldsplit_schur_precondition")? {
        check(unsafe {
            ffi::PCFieldSplitSetSchurPre(
                pc.raw_handle(),
                ffi::PCFieldSplitSchurPreType::PC_FIELDSPLIT_SCHUR_PRE_USER,
                schur.as_raw(),
            )
        })?;
    }
    Ok(())
}
