//! A cell's straight (vertex) simplex: signed areas, volumes and measures.

use super::Family;

/// Twice the signed area of the straight triangle in the (x, z) plane.
pub(crate) fn area2(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    (b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0])
}

/// The measure of a cell's straight (vertex) simplex, vertex i at `x(i)`: the volume of a
/// tetrahedron, the area of a meridian triangle.
pub(crate) fn straight_measure(family: Family, x: impl Fn(usize) -> [f64; 3]) -> f64 {
    match family {
        Family::Tet10 => tet_det(x(0), x(1), x(2), x(3)).abs() / 6.0,
        Family::Tri6 => area2(x(0), x(1), x(2)).abs() / 2.0,
    }
}

/// Determinant of [b - a, c - a, d - a] (6 x signed volume of the straight tet).
pub(crate) fn tet_det(a: [f64; 3], b: [f64; 3], c: [f64; 3], d: [f64; 3]) -> f64 {
    let u = sub(b, a);
    let v = sub(c, a);
    let w = sub(d, a);
    u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0]) + u[2] * (v[0] * w[1] - v[1] * w[0])
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
