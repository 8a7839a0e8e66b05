//! Field output for ParaView: one HDF5 file (`fields.h5`) and one XDMF index (`fields.xdmf`) per run,
//! written collectively by all ranks of a communicator.
//!
//! # Layout of `fields.h5`
//! * `/mesh/coordinates`: `f64`, N×3, global node coordinates (row = global node id).
//! * `/mesh/topology`: `i64`, M×10, global node ids of each quadratic tetrahedron **in VTK/XDMF order**
//!   (see below), row = global cell id; M×6 for the 6-node triangles of a meridian (axisymmetric)
//!   mesh, whose GMSH `Triangle6` order is VTK's `VTK_QUADRATIC_TRIANGLE` order (XDMF `Triangle_6`).
//!   A meridian lies in the x–z plane, and its vector fields are written with a zero y component.
//! * `/time`: `f64`, 1-D, extendible; `time[k]` is the time of step `k`.
//! * `/step_mesh`: `i64`, 1-D, extendible: the mesh group step `k` uses, 0 for `/mesh`, g for
//!   `/mesh_g` — a run resumed on another rank count numbers the nodes differently and writes
//!   its mesh again (`FieldFile::reopen`).
//! * `/fields/<name>/<k as 6 digits>`: `f64`; N (node scalar), N×3 (node vector), M (cell scalar) or
//!   M×3 (cell vector) values of field `<name>` at step `k`. A field may be absent from some steps.
//!
//! # Node order of the 10-node tetrahedron
//! The mesh comes in GMSH `Tetrahedron10` order: vertices 0–3, then mid-edge nodes on edges
//! (0,1),(1,2),(0,2),(0,3),(2,3),(1,3). XDMF's `Tetrahedron_10` is handed by ParaView's XDMF readers
//! unchanged to VTK's `VTK_QUADRATIC_TETRA` (cell type 24), whose order is vertices, then edges
//! (0,1),(1,2),(0,2),(0,3),(1,3),(2,3). So the last two mid-edge nodes are swapped when writing
//! (`layout::GMSH_TO_XDMF_TET10`); `/mesh/topology` is stored in the XDMF/VTK order.
//!
//! The topology name is `Tetrahedron_10`: ParaView 5.11's `Xdmf3ReaderS`/`Xdmf3ReaderT` (XDMF 3) reject
//! `Tet_10` ("Invalid Type selected in XdmfTopologyType::New"), and its legacy `XDMFReader`
//! (XDMF 2) accepts both. Both were checked to produce VTK cell type 24 with the connectivity as written.
//!
//! # The XDMF file
//! A `Temporal` collection with one `Uniform` grid per step. Every grid points at the same
//! `/mesh/coordinates` and `/mesh/topology` datasets (the mesh is stored once) and at that step's
//! `/fields/...` datasets. Before the first step the XDMF holds a single `Uniform` grid with the
//! bare mesh. Rank 0 rewrites it after every step, to a temporary `fields.xdmf.<pid>-<n>.tmp`
//! then renamed over `fields.xdmf`, and only after the step's data were flushed, so a run that is
//! still going or has crashed can be opened and shows every completed step.
//!
//! # Parallel I/O and failures
//! The file is opened once with HDF5's MPI-IO driver and stays open. Metadata operations
//! (creating the file, groups and datasets, extending `/time`, flushing, closing) are collective, as
//! parallel HDF5 requires: every rank makes the same calls with the same arguments. Raw data is
//! written with hyperslab selections by each rank for the rows it owns, using **independent**
//! transfers: hdf5-metno 0.9 always passes `H5P_DEFAULT` as the transfer property list and has no
//! way to request `H5FD_MPIO_COLLECTIVE` (that would need raw `hdf5-sys` calls). A rank that owns
//! no rows simply makes no data call, so zero-size pieces are fine.
//!
//! Error handling: arguments are checked locally and compared across ranks (counts, time, field
//! names and kinds, via a hash) *before* any collective HDF5 call, and after each phase every rank's
//! outcome is combined collectively (same semantics as `crate::parallel::agree`): if any rank
//! failed, every rank returns `Err` (the failing rank its own error, the others
//! `Error::Elsewhere` with the lowest failing rank's message) and no rank goes on to the next
//! collective call, so nobody is left waiting. What this cannot cover is a failure *inside* one of
//! HDF5's own collective calls on only some ranks; there we rely on HDF5's collective semantics (it
//! normally fails on all ranks alike). After an error, drop the `FieldFile` on all ranks; steps
//! completed before remain readable (a failed `write_step` is not listed in the XDMF).
//!
//! Drop (or [`FieldFile::close`]) the `FieldFile` on all ranks, before MPI is finalized (that is,
//! before the `mpi::environment::Universe` is dropped).
//!
//! # Where things are
//! `field_file` holds the [`FieldFile`] API (create, reopen, write a step, close) and the backup
//! and restore of the file; `layout` the names, types and node order of what is written; `h5`
//! the HDF5 calls of the file, its datasets and mesh groups; `xdmf` the index's text (pure);
//! `checks` the checks of a collective call's arguments.

mod checks;
mod field_file;
mod h5;
mod layout;
mod xdmf;

pub(crate) use field_file::restore_backup;
pub use field_file::FieldFile;
pub(crate) use layout::H5_NAME;
pub use layout::{Field, FieldKind, OutputMesh};
