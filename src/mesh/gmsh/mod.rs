//! Reader for Gmsh MSH 4.1 ASCII files ([`read`], in `reader`): the text's sections read into raw
//! contents (`lexer`, `msh41`), then the mesh built from them (`tet`, or `meridian` for a 2-D file
//! of triangles, on the steps both share in `build`). Tetrahedra or triangles may be linear or
//! quadratic; linear ones are promoted to quadratic with straight mid-edge nodes. Tagged faces and
//! points count only through physical groups (untagged ones are ignored).
//!
//! Node numbering: only nodes used by cells are kept, numbered in file order (0-based); nodes
//! added by promotion follow. A tagged face on an interior surface is attached to the
//! lower-numbered of its two cells, and its orientation is outward from that cell. Non-manifold
//! meshes (a triangle shared by 3 tets) are not detected here but by the partitioner
//! (`partition::dual_graph`).

mod build;
mod lexer;
mod meridian;
mod msh41;
mod reader;
mod tet;

pub(crate) use reader::read;
