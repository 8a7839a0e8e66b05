//! gmsh's node numbering of the cells and their faces (the conventions: module docs of
//! `reference_cell`), and the largest node counts.

/// Mid-edge node `4 + k` of a Tetrahedron10 sits on the edge between vertices `TET10_EDGES[k]` (gmsh order).
pub(crate) const TET10_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)];

/// Local faces of a Tetrahedron10: 3 vertex positions then the 3 mid-edge positions (Triangle6 order),
/// ordered so that the right-hand-rule normal points OUT of a positively oriented tet.
/// Face 0 is opposite vertex 3, face 1 opposite vertex 2, face 2 opposite vertex 0, face 3 opposite vertex 1.
pub(crate) const TET_FACES: [[usize; 6]; 4] =
    [[0, 2, 1, 6, 5, 4], [0, 1, 3, 4, 9, 7], [1, 2, 3, 5, 8, 9], [0, 3, 2, 7, 8, 6]];

/// Node permutation that turns a negatively oriented Tetrahedron10 into a positive one
/// (swap vertices 1 and 2; the mid-edge nodes follow their edges).
pub(crate) const TET10_FLIP: [usize; 10] = [0, 2, 1, 3, 6, 5, 4, 7, 9, 8];

/// Nodes of a Triangle6 cell's sides as Line3 faces (vertex, vertex, mid-edge node), each ordered
/// so that the outward normal of a positively oriented triangle is the tangent turned clockwise
/// in the (x, z) plane (see [`Family::Tri6`](super::Family::Tri6)).
pub(crate) const TRI6_SIDES: [[usize; 3]; 3] = [[0, 1, 3], [1, 2, 4], [2, 0, 5]];

/// Mid-edge node `3 + k` of a Triangle6 sits on the edge between vertices `TRI6_EDGES[k]` (gmsh order).
pub(crate) const TRI6_EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

pub(crate) const MAX_CELL_NODES: usize = 10;
pub(crate) const MAX_FACE_NODES: usize = 6;

/// Node permutation that turns a clockwise Triangle6 counter-clockwise (swap vertices 1 and 2; the
/// mid-edge nodes follow their edges).
pub(crate) const TRI6_FLIP: [usize; 6] = [0, 2, 1, 5, 4, 3];
