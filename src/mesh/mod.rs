//! The global mesh as read from a file: quadratic cells of one family (10-node tetrahedra, or
//! 6-node triangles of a meridian), their outward boundary faces and named physical groups
//! ([`Mesh`], in `global`), and the face matching the partitioner and the reader use
//! (`face_match`). The node numbering of a cell and of a face is the reference cell's
//! ([`crate::reference_cell`]).

pub(crate) mod dist;
mod face_match;
pub(crate) mod generate;
mod global;
pub(crate) mod gmsh;
pub(crate) mod mirror;
pub(crate) mod partition;
pub(crate) mod source;

#[cfg(test)]
pub(crate) mod test_util;
#[cfg(test)]
mod tests;

pub(crate) use global::Mesh;
