//! The reference cells below meshes and elements (deal.II's `ReferenceCell` layer): the cell
//! families, their node numbering (gmsh's), the P1/P2 shape functions on them (`shape`) and the
//! check that a curved cell's map does not fold. Meshes use it to build and check cells, elements
//! to integrate on them; it depends on neither.
//!
//! Conventions (gmsh's, verified on a straight-sided order-2 mesh, see `mesh::tests::gmsh_tet10_edge_order`):
//! * a tet has 10 nodes: vertices 0..4, then the mid-edge node `4 + k` on edge `TET10_EDGES[k]`;
//! * every tet is positively oriented: det [x1 - x0, x2 - x0, x3 - x0] > 0;
//! * a boundary face has 6 nodes in gmsh Triangle6 order (3 vertices, then the mid-nodes of edges
//!   01, 12, 20), oriented so that the right-hand rule on the 3 vertices gives the outward normal;
//! * a meridian triangle has 6 nodes (3 vertices, then the mid-nodes of edges 01, 12, 20) and is
//!   counter-clockwise in (x, z).

mod family;
mod numbering;
pub(crate) mod shape;
mod simplex;

pub use family::Family;
pub(crate) use numbering::TET10_EDGES;

pub(crate) use numbering::{MAX_CELL_NODES, MAX_FACE_NODES, TET10_FLIP, TET_FACES, TRI6_EDGES, TRI6_FLIP, TRI6_SIDES};
pub(crate) use simplex::{area2, straight_measure, sub, tet_det};
