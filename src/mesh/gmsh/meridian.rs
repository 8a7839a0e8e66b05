//! The meridian (axisymmetric) mesh from a 2-D Gmsh file: 6-node triangles in the x–z plane
//! (x = r ≥ 0, y = 0) with 3-node line faces; linear meshes are promoted with straight mid-edge
//! nodes. The same rules as the tetrahedral build (`gmsh::build`): only nodes used by cells are
//! kept, in file order; cells are oriented positively (counter-clockwise in (x, z)); a tagged line is
//! attached to the lowest-numbered cell having it as a side, outward from it; physical surfaces
//! name cell groups, physical curves face groups.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use super::build::{finish, promote, used_nodes, Parts};
use super::msh41::Raw;
use crate::error::{Error, Result};
use crate::mesh::face_match::face_key;
use crate::mesh::Mesh;
use crate::reference_cell::shape::fold_point;
use crate::reference_cell::{area2, Family, TRI6_FLIP, TRI6_SIDES};

/// Compact, promote, orient, match faces and resolve groups of a triangle mesh.
pub(super) fn build(path: &Path, raw: Raw) -> Result<Mesh> {
    let err = |msg: String| Error::mesh(path, msg);
    let linear = raw.n_tri3 > 0;
    if linear && raw.n_tri6 > 0 {
        return Err(err(format!("mixed linear/quadratic mesh: {} tri3 and {} tri6", raw.n_tri3, raw.n_tri6)));
    }
    if (linear && raw.n_line3 > 0) || (!linear && raw.n_line3 < raw.lines.len()) {
        return Err(err(format!(
            "mixed linear/quadratic mesh: {} triangles with {} line3 of {} lines",
            if linear { "linear" } else { "quadratic" },
            raw.n_line3,
            raw.lines.len()
        )));
    }
    let (nn, nl) = if linear { (3, 2) } else { (6, 3) };

    // Keep the nodes used by triangles, in file order.
    let (new_id, mut coords) = used_nodes(&raw.coords, &raw.tris, nn);
    // The meridian lies in the x–z plane with x = r ≥ 0.
    let scale = coords.iter().flat_map(|x| x.iter()).fold(0.0f64, |m, v| m.max(v.abs())).max(f64::MIN_POSITIVE);
    if let Some(x) = coords.iter().find(|x| x[1].abs() > 1e-9 * scale || x[0] < -1e-9 * scale) {
        return Err(err(format!(
            "no tetrahedra, so the triangles are read as the meridian of an axisymmetric body: it must lie in the x–z plane \
             (y = 0) with x = r ≥ 0, but has a node at ({:.6e}, {:.6e}, {:.6e})",
            x[0], x[1], x[2]
        )));
    }
    let mut cells: Vec<[u32; 10]> = raw
        .tris
        .iter()
        .map(|tri| {
            let mut c = [u32::MAX; 10];
            for k in 0..nn {
                c[k] = new_id[tri[k] as usize];
            }
            c
        })
        .collect();
    if linear {
        promote(Family::Tri6, &mut cells, &mut coords).map_err(err)?;
    }

    for (t, cell) in cells.iter_mut().enumerate() {
        let x = |k: usize| coords[cell[k] as usize];
        let det = area2(x(0), x(1), x(2));
        let len = |a: [f64; 3], b: [f64; 3]| ((a[0] - b[0]).powi(2) + (a[2] - b[2]).powi(2)).sqrt();
        if det.abs() <= 1e-12 * len(x(0), x(1)) * len(x(0), x(2)) {
            return Err(err(format!(
                "triangle {} (element tag) is degenerate: area {:.3e}",
                raw.tri_tags[t],
                det / 2.0
            )));
        }
        if det < 0.0 {
            let old = *cell;
            for (k, &src) in TRI6_FLIP.iter().enumerate() {
                cell[k] = old[src];
            }
        }
        let xs: [[f64; 3]; 6] = std::array::from_fn(|k| coords[cell[k] as usize]);
        if let Some((at, d)) = fold_point(Family::Tri6, &xs, det.abs()) {
            return Err(err(format!(
                "triangle {} (element tag) is tangled: det of its curved map is {d:.3e} at ({:.6}, {:.6}) \
                 (its mid-edge nodes fold it over)",
                raw.tri_tags[t], at[0], at[2]
            )));
        }
    }

    // Tagged lines, deduplicated by vertex pair in file order, attached to the first cell side.
    let mut face_of_key: HashMap<[u32; 3], u32> = HashMap::new();
    let mut unique: Vec<(usize, [u32; 3])> = Vec::new();
    let mut face_groups: BTreeMap<i32, Vec<u32>> = BTreeMap::new();
    let describe = |i: usize| {
        let tags: Vec<String> = raw.lines[i][..nl].iter().map(|&n| raw.node_tags[n as usize].to_string()).collect();
        format!("boundary line {} (element tag; node tags {})", raw.line_tags[i], tags.join(" "))
    };
    for (i, line) in raw.lines.iter().enumerate() {
        let Some(phys) = raw.entity_phys[1].get(&raw.line_entity[i]) else { continue };
        let mut ids = [u32::MAX; 3];
        for k in 0..nl {
            ids[k] = new_id[line[k] as usize];
        }
        if ids[..nl].contains(&u32::MAX) {
            return Err(err(format!("{} uses a node of no triangle", describe(i))));
        }
        let key = face_key(ids[0], ids[1], u32::MAX);
        let fi = *face_of_key.entry(key).or_insert_with(|| {
            unique.push((i, ids));
            unique.len() as u32 - 1
        });
        for &p in phys {
            face_groups.entry(p).or_default().push(fi);
        }
    }
    let mut face_cell = vec![(u32::MAX, 0u8); unique.len()];
    for (t, cell) in cells.iter().enumerate() {
        for (f, side) in TRI6_SIDES.iter().enumerate() {
            if let Some(&fi) = face_of_key.get(&face_key(cell[side[0]], cell[side[1]], u32::MAX)) {
                if face_cell[fi as usize].0 == u32::MAX {
                    face_cell[fi as usize] = (t as u32, f as u8);
                }
            }
        }
    }
    let mut faces: Vec<[u32; 6]> = Vec::with_capacity(unique.len());
    for (&(i, ids), &(t, lf)) in unique.iter().zip(&face_cell) {
        if t == u32::MAX {
            return Err(err(format!("{} is not a side of any triangle", describe(i))));
        }
        let side = TRI6_SIDES[lf as usize].map(|p| cells[t as usize][p]);
        if !linear && ids[2] != side[2] {
            return Err(err(format!(
                "{}: its mid-edge node differs from that of triangle {} (non-conforming mesh)",
                describe(i),
                raw.tri_tags[t as usize]
            )));
        }
        faces.push([side[0], side[1], side[2], u32::MAX, u32::MAX, u32::MAX]);
    }

    let parts = Parts { coords, cells, faces, face_cell, face_groups, new_id };
    finish(path, &raw, Family::Tri6, &raw.tri_entity, parts)
}
