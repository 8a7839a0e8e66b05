//! Test fixture of the layers above the mesh: a structured mesh of either family, the unit cube
//! in Kuhn tetrahedra or the meridian square in triangles, with straight quadratic nodes.

use super::Mesh;
use crate::reference_cell::{area2, tet_det, Family, TET10_EDGES, TRI6_EDGES};

/// The unit cube in n³ cubes of 6 Kuhn tetrahedra, or the meridian square [0, 1]² (x = r, z) in
/// n² squares of 2 triangles; quadratic nodes on the half grid.
pub(crate) fn structured(family: Family, n: usize) -> Mesh {
    let m = 2 * n + 1;
    let (dims, nv) = match family {
        Family::Tet10 => (3, 4),
        Family::Tri6 => (2, 3),
    };
    let id = |g: [usize; 3]| -> u32 { (g[0] + m * (g[1] + m * g[2])) as u32 };
    let total = m.pow(dims as u32);
    let coords: Vec<[f64; 3]> = (0..total)
        .map(|i| {
            let g = [i % m, (i / m) % m, i / (m * m)];
            let h = |k: usize| g[k] as f64 / (2 * n) as f64;
            match family {
                Family::Tet10 => [h(0), h(1), h(2)],
                Family::Tri6 => [h(0), 0.0, h(1)],
            }
        })
        .collect();
    let mut cells = Vec::new();
    let edges = family.edges();
    let mut push = |verts: &[[usize; 3]]| {
        let mut c = [u32::MAX; 10];
        for (k, v) in verts.iter().enumerate() {
            c[k] = id(*v);
        }
        for (e, &(a, b)) in edges.iter().enumerate() {
            c[nv + e] = id(std::array::from_fn(|d| (verts[a][d] + verts[b][d]) / 2));
        }
        cells.push(c);
    };
    for k in 0..if dims == 3 { n } else { 1 } {
        for j in 0..n {
            for i in 0..n {
                let o = [2 * i, 2 * j, 2 * k];
                if dims == 2 {
                    let v = |a: usize, b: usize| [o[0] + 2 * a, o[1] + 2 * b, 0];
                    push(&[v(0, 0), v(1, 0), v(1, 1)]);
                    push(&[v(0, 0), v(1, 1), v(0, 1)]);
                    continue;
                }
                for perm in [[0, 1, 2], [0, 2, 1], [1, 0, 2], [1, 2, 0], [2, 0, 1], [2, 1, 0]] {
                    let mut v = [o; 4];
                    for s in 0..3 {
                        v[s + 1] = v[s];
                        v[s + 1][perm[s]] += 2;
                    }
                    // Positive orientation: swap vertices 1 and 2 of the odd permutations.
                    let odd = matches!(perm, [0, 2, 1] | [1, 0, 2] | [2, 1, 0]);
                    if odd {
                        v.swap(1, 2);
                    }
                    push(&v);
                }
            }
        }
    }
    let mut is_vertex = vec![false; coords.len()];
    for c in &cells {
        for &v in &c[..nv] {
            is_vertex[v as usize] = true;
        }
    }
    Mesh { family, coords, cells, is_vertex, ..Mesh::default() }
}

/// `mesh` with its whole boundary as the face group "surface": every cell face that no other
/// cell shares, outward (the cells' own face order).
pub(crate) fn with_boundary(mut mesh: Mesh) -> Mesh {
    let family = mesh.family;
    let nv = family.face_vertices();
    let mut seen: std::collections::HashMap<Vec<u32>, Vec<(u32, u8)>> = Default::default();
    for (c, cell) in mesh.cells.iter().enumerate() {
        for (lf, nodes) in family.cell_faces().iter().enumerate() {
            let mut key: Vec<u32> = nodes[..nv].iter().map(|&k| cell[k]).collect();
            key.sort_unstable();
            seen.entry(key).or_default().push((c as u32, lf as u8));
        }
    }
    let mut once: Vec<(u32, u8)> = seen.into_values().filter(|v| v.len() == 1).map(|v| v[0]).collect();
    once.sort_unstable();
    for &(c, lf) in &once {
        let mut face = [u32::MAX; crate::reference_cell::MAX_FACE_NODES];
        for (k, &n) in family.cell_faces()[lf as usize].iter().enumerate() {
            face[k] = mesh.cells[c as usize][n];
        }
        mesh.faces.push(face);
        mesh.face_cell.push((c, lf));
    }
    mesh.face_groups = vec![("surface".into(), (0..once.len() as u32).collect())];
    mesh
}

#[test]
fn kuhn_tetrahedra_are_positive_and_fill_the_cube() {
    let m = structured(Family::Tet10, 2);
    let mut vol = 0.0;
    for c in &m.cells {
        let x = |i: usize| m.coords[c[i] as usize];
        let d = tet_det(x(0), x(1), x(2), x(3));
        assert!(d > 0.0, "negative tet");
        vol += d / 6.0;
        for (e, &(a, b)) in TET10_EDGES.iter().enumerate() {
            let mid = x(4 + e);
            assert!((0..3).all(|k| (mid[k] - 0.5 * (x(a)[k] + x(b)[k])).abs() < 1e-15));
        }
    }
    assert!((vol - 1.0).abs() < 1e-14);
    let t = structured(Family::Tri6, 2);
    for c in &t.cells {
        let x = |i: usize| t.coords[c[i] as usize];
        assert!(area2(x(0), x(1), x(2)) > 0.0);
        for (e, &(a, b)) in TRI6_EDGES.iter().enumerate() {
            assert!((0..3).all(|k| (x(3 + e)[k] - 0.5 * (x(a)[k] + x(b)[k])).abs() < 1e-15));
        }
    }
}
