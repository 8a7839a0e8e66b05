//! Reflection of a mesh across one of its symmetry planes: a quarter sphere mirrored across
//! x = 0 and y = 0 is a full sphere with exactly the quarter's discretisation, so quarter and full
//! models can be compared without mesh differences (they must agree to solver tolerance).

use super::Mesh;
use crate::error::{Error, Result};
use crate::reference_cell::{Family, TET10_FLIP, TET_FACES};

/// Local face index in the flipped tet (vertices 1 and 2 swapped) of each local face.
const FLIPPED_FACE: [u8; 4] = [0, 3, 2, 1];

/// The mesh and its reflection across the face group `plane`, which must lie in x = 0, y = 0 or
/// z = 0 and becomes interior (it is dropped). Nodes on the plane are shared; all other groups
/// are extended by their reflections (a point group off the plane gains the mirror node).
pub(crate) fn mirror(mesh: &Mesh, plane: &str) -> Result<Mesh> {
    let err = |msg: String| Error::Mesh { path: format!("mirror across \"{plane}\""), msg };
    if mesh.family != Family::Tet10 {
        return Err(err("only a tetrahedral mesh can be mirrored (a meridian mesh is already the whole body)".into()));
    }
    let plane_faces = mesh.face_group(plane)?;
    let n = mesh.coords.len();
    let extent = mesh.coords.iter().flatten().map(|x| x.abs()).fold(0.0, f64::max);
    let flat = |axis: usize| {
        plane_faces
            .iter()
            .flat_map(|&f| mesh.faces[f as usize])
            .all(|v| mesh.coords[v as usize][axis].abs() <= 1e-9 * extent)
    };
    let axis =
        (0..3).find(|&a| flat(a)).ok_or_else(|| err("the group is not in a plane x = 0, y = 0 or z = 0".into()))?;
    let mut on_plane = vec![false; n];
    for &f in plane_faces {
        for &v in &mesh.faces[f as usize] {
            on_plane[v as usize] = true;
        }
    }
    // Mirror image of each node: itself on the plane, else a new node appended after the originals.
    let mut image = vec![0u32; n];
    let mut coords = mesh.coords.clone();
    let mut is_vertex = mesh.is_vertex.clone();
    for i in 0..n {
        if on_plane[i] {
            image[i] = i as u32;
        } else {
            image[i] = coords.len() as u32;
            let mut x = mesh.coords[i];
            x[axis] = -x[axis];
            coords.push(x);
            is_vertex.push(mesh.is_vertex[i]);
        }
    }
    let nt = mesh.cells.len() as u32;
    let mut tets = mesh.cells.clone();
    // A reflection reverses orientation: swap vertices 1 and 2 to make the image positive again.
    tets.extend(mesh.cells.iter().map(|t| TET10_FLIP.map(|p| image[t[p] as usize])));
    // Faces: the originals except the plane's, then their images (outward from the image tets).
    let dropped: std::collections::BTreeSet<u32> = plane_faces.iter().copied().collect();
    let kept: Vec<u32> = (0..mesh.faces.len() as u32).filter(|f| !dropped.contains(f)).collect();
    let mut new_index = vec![u32::MAX; mesh.faces.len()];
    let (mut faces, mut face_cell) = (Vec::new(), Vec::new());
    for &f in &kept {
        new_index[f as usize] = faces.len() as u32;
        faces.push(mesh.faces[f as usize]);
        face_cell.push(mesh.face_cell[f as usize]);
    }
    let nk = kept.len() as u32;
    for &f in &kept {
        let (t, lf) = mesh.face_cell[f as usize];
        let (ti, lfi) = (t + nt, FLIPPED_FACE[lf as usize]);
        faces.push(TET_FACES[lfi as usize].map(|p| tets[ti as usize][p]));
        face_cell.push((ti, lfi));
    }
    let volume_groups = mesh
        .volume_groups
        .iter()
        .map(|(name, ts)| (name.clone(), ts.iter().copied().chain(ts.iter().map(|t| t + nt)).collect()))
        .collect();
    let face_groups = mesh
        .face_groups
        .iter()
        .filter(|(name, _)| name != plane)
        .map(|(name, fs)| {
            let mut g: Vec<u32> = fs.iter().map(|&f| new_index[f as usize]).filter(|&f| f != u32::MAX).collect();
            let images: Vec<u32> = g.iter().map(|f| f + nk).collect();
            g.extend(images);
            (name.clone(), g)
        })
        .collect();
    let point_groups = mesh
        .point_groups
        .iter()
        .map(|(name, ns)| {
            let mut g: Vec<u32> = ns.iter().copied().chain(ns.iter().map(|&v| image[v as usize])).collect();
            g.sort_unstable();
            g.dedup();
            (name.clone(), g)
        })
        .collect();
    Ok(Mesh {
        family: mesh.family,
        coords,
        cells: tets,
        faces,
        face_cell,
        volume_groups,
        face_groups,
        point_groups,
        is_vertex,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One straight tet10 with a face on x = 0, mirrored: volume doubles, orientation stays
    /// positive, the plane face disappears and the boundary stays closed and outward.
    #[test]
    fn mirrored_tet_is_positive_and_closed() {
        let v = [[0.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]];
        let mut coords: Vec<[f64; 3]> = v.to_vec();
        let mut tet = [0u32; 10];
        for (k, &(a, b)) in crate::reference_cell::TET10_EDGES.iter().enumerate() {
            coords.push(std::array::from_fn(|d| 0.5 * (v[a][d] + v[b][d])));
            tet[4 + k] = 4 + k as u32;
        }
        tet[..4].copy_from_slice(&[0, 1, 2, 3]);
        let det = |t: &[u32; 10], c: &[[f64; 3]]| {
            let d = |i: usize| -> [f64; 3] { std::array::from_fn(|k| c[t[i] as usize][k] - c[t[0] as usize][k]) };
            let (a, b, e) = (d(1), d(2), d(3));
            a[0] * (b[1] * e[2] - b[2] * e[1]) - a[1] * (b[0] * e[2] - b[2] * e[0]) + a[2] * (b[0] * e[1] - b[1] * e[0])
        };
        if det(&tet, &coords) < 0.0 {
            tet = TET10_FLIP.map(|p| tet[p]);
        }
        let face_cell: Vec<(u32, u8)> = (0..4).map(|f| (0, f)).collect();
        let faces: Vec<[u32; 6]> = (0..4).map(|f| TET_FACES[f].map(|p| tet[p])).collect();
        // The face with all vertices at x = 0 is the plane.
        let plane = (0..4u32).find(|&f| faces[f as usize][..3].iter().all(|&n| coords[n as usize][0] == 0.0)).unwrap();
        let mesh = Mesh {
            family: Family::Tet10,
            coords: coords.clone(),
            cells: vec![tet],
            faces: faces.clone(),
            face_cell,
            volume_groups: vec![("v".into(), vec![0])],
            face_groups: vec![("plane".into(), vec![plane]), ("all".into(), vec![0, 1, 2, 3])],
            point_groups: vec![("tip".into(), vec![3])],
            is_vertex: (0..10).map(|i| i < 4).collect(),
        };
        let m = mirror(&mesh, "plane").unwrap();
        assert_eq!(m.cells.len(), 2);
        assert_eq!(m.coords.len(), 10 + 4); // the 6 plane nodes are shared
        assert!(det(&m.cells[0], &m.coords) > 0.0 && det(&m.cells[1], &m.coords) > 0.0);
        assert_eq!(m.faces.len(), 6);
        assert_eq!(m.face_groups.len(), 1);
        assert_eq!(m.face_groups[0].1.len(), 6);
        assert_eq!(m.point_groups[0].1.len(), 2);
        // Outward normals: the divergence theorem gives ∑ ∫ x n_x dA = volume (2 × 1/6).
        let mut flux = 0.0;
        for f in &m.faces {
            let p: [[f64; 3]; 3] = std::array::from_fn(|a| m.coords[f[a] as usize]);
            let e1: [f64; 3] = std::array::from_fn(|k| p[1][k] - p[0][k]);
            let e2: [f64; 3] = std::array::from_fn(|k| p[2][k] - p[0][k]);
            let nx = 0.5 * (e1[1] * e2[2] - e1[2] * e2[1]);
            flux += nx * (p[0][0] + p[1][0] + p[2][0]) / 3.0;
        }
        assert!((flux - 2.0 / 6.0).abs() < 1e-12, "{flux}");
        // Mirroring across a group that is not in a coordinate plane is an error.
        assert!(mirror(&mesh, "all").is_err());
    }
}
