//! Faces matched by their vertices, whatever their orientation: the key of a face, and every cell
//! face sorted by it so that the faces two cells share are adjacent (the partitioner's dual graph
//! and the reader's tagged faces).

use crate::reference_cell::{Family, MAX_CELL_NODES};

/// Sorted vertex triple identifying a triangle independently of orientation.
pub(super) fn face_key(a: u32, b: u32, c: u32) -> [u32; 3] {
    let mut k = [a, b, c];
    k.sort_unstable();
    k
}

/// All cell faces, sorted, each packed in a `u128` as (sorted vertex key, 4 * cell + local face) so
/// that faces shared by two cells are adjacent entries (see [`unpack_face`]). A line face's key is its
/// vertex pair followed by `u32::MAX`. Sorting packed integers (not hashing) keeps it deterministic,
/// compact and fast. Needs fewer than 2^30 cells.
pub(super) fn sorted_cell_faces(family: Family, cells: &[[u32; MAX_CELL_NODES]]) -> Vec<u128> {
    let sides = family.cell_faces();
    let mut v = Vec::with_capacity(cells.len() * sides.len());
    for (t, cell) in cells.iter().enumerate() {
        for (f, lf) in sides.iter().enumerate() {
            let [a, b, c] = side_key(family, cell, lf);
            let id = (4 * t + f) as u128;
            v.push(((a as u128) << 96) | ((b as u128) << 64) | ((c as u128) << 32) | id);
        }
    }
    v.sort_unstable();
    v
}

/// The orientation-free key of the side `lf` (local node positions) of a cell.
fn side_key(family: Family, cell: &[u32], lf: &[usize]) -> [u32; 3] {
    match family {
        Family::Tet10 => face_key(cell[lf[0]], cell[lf[1]], cell[lf[2]]),
        Family::Tri6 => face_key(cell[lf[0]], cell[lf[1]], u32::MAX),
    }
}

/// (sorted vertex triple, tet, local face) of an entry of [`sorted_cell_faces`].
pub(super) fn unpack_face(k: u128) -> ([u32; 3], u32, u8) {
    let id = k as u32;
    ([(k >> 96) as u32, (k >> 64) as u32, (k >> 32) as u32], id / 4, (id % 4) as u8)
}
