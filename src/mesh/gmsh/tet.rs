//! The tetrahedral mesh from an MSH file's raw contents: linear tets promoted, every tet
//! oriented positively and checked for folds, tagged triangles attached to their tets.

use std::collections::{BTreeMap, HashMap};
use std::path::Path;

use super::build::{finish, promote, used_nodes, Parts};
use super::msh41::Raw;
use crate::error::{Error, Result};
use crate::mesh::face_match::face_key;
use crate::mesh::Mesh;
use crate::reference_cell::shape::fold_point;
use crate::reference_cell::{sub, tet_det, Family, TET10_FLIP, TET_FACES};

/// Compact, promote, orient, match faces and resolve groups.
pub(super) fn build(path: &Path, mut raw: Raw) -> Result<Mesh> {
    let err = |msg: String| Error::mesh(path, msg);
    if raw.cells.is_empty() {
        return Err(err(
            "no tetrahedra (element types 4 or 11) nor triangles (2 or 9) in $Elements: generate with gmsh -3 \
             (or gmsh -2 for a meridian mesh)"
                .into(),
        ));
    }
    let linear = tets_are_linear(&raw).map_err(err)?;
    let nv = if linear { 4 } else { 10 };

    // Keep the nodes used by tets, in file order.
    let (new_id, mut coords) = used_nodes(&raw.coords, &raw.cells, nv);
    let mut tets = std::mem::take(&mut raw.cells);
    for tet in &mut tets {
        for n in &mut tet[..nv] {
            *n = new_id[*n as usize];
        }
    }
    if linear {
        promote(Family::Tet10, &mut tets, &mut coords).map_err(err)?;
    }
    orient_tets(&mut tets, &coords, &raw.tet_tags).map_err(err)?;

    let nt = if linear { 3 } else { 6 };
    let tagged = TaggedTriangles::new(&raw, &new_id, nt).map_err(err)?;
    let (faces, face_cell) = tagged.attach(&raw, &tets, coords.len(), linear).map_err(err)?;

    let parts = Parts { coords, cells: tets, faces, face_cell, face_groups: tagged.groups, new_id };
    finish(path, &raw, Family::Tet10, &raw.tet_entity, parts)
}

/// Whether the tets are linear (tet4, with tri3 faces) rather than quadratic (tet10, tri6); a
/// mix is an error.
fn tets_are_linear(raw: &Raw) -> std::result::Result<bool, String> {
    let linear = raw.n_tet4 > 0;
    if linear && raw.n_tet10 > 0 {
        return Err(format!("mixed linear/quadratic mesh: {} tet4 and {} tet10", raw.n_tet4, raw.n_tet10));
    }
    if (linear && raw.n_tri6 > 0) || (!linear && raw.n_tri3 > 0) {
        return Err(format!(
            "mixed linear/quadratic mesh: {} {} tets with {} tri3 and {} tri6",
            raw.cells.len(),
            if linear { "linear" } else { "quadratic" },
            raw.n_tri3,
            raw.n_tri6
        ));
    }
    Ok(linear)
}

/// Gives every tet a positive orientation; a (near-)zero volume or a curved map that folds over
/// is an error naming the tet's element tag (coordinates are finite, so no NaN here).
fn orient_tets(tets: &mut [[u32; 10]], coords: &[[f64; 3]], tags: &[u64]) -> std::result::Result<(), String> {
    for (t, tet) in tets.iter_mut().enumerate() {
        let x = |k: usize| coords[tet[k] as usize];
        let (u, v, w) = (sub(x(1), x(0)), sub(x(2), x(0)), sub(x(3), x(0)));
        let det = tet_det(x(0), x(1), x(2), x(3));
        let scale = norm(u) * norm(v) * norm(w);
        if det.abs() <= 1e-12 * scale {
            return Err(format!("tetrahedron {} (element tag) is degenerate: volume {:.3e}", tags[t], det / 6.0));
        }
        if det < 0.0 {
            let old = *tet;
            for (k, &src) in TET10_FLIP.iter().enumerate() {
                tet[k] = old[src];
            }
        }
        // The curved (P2) map must not fold over: det of its Jacobian > 0 at the nodes and the
        // centroid (a tangled element passes the vertex test above).
        let xs: [[f64; 3]; 10] = std::array::from_fn(|k| coords[tet[k] as usize]);
        if let Some((at, d)) = fold_point(Family::Tet10, &xs, det.abs()) {
            return Err(format!(
                "tetrahedron {} (element tag) is tangled: det of its curved map is {d:.3e} at ({:.6}, {:.6}, {:.6}) \
                 (its mid-edge nodes fold it over; straight volume {:.3e})",
                tags[t],
                at[0],
                at[1],
                at[2],
                det.abs() / 6.0
            ));
        }
    }
    Ok(())
}

/// Faces in their tets' node order, and (tet, local face) of each.
type AttachedFaces = (Vec<[u32; 6]>, Vec<(u32, u8)>);

/// The tagged triangles of a tet mesh, deduplicated by vertex triple in file order.
struct TaggedTriangles {
    /// Nodes per triangle (3 or 6).
    nt: usize,
    /// Sorted vertex triple -> face index.
    face_of_key: HashMap<[u32; 3], u32>,
    /// Per face: (its first triangle, compact node ids).
    unique: Vec<(usize, [u32; 6])>,
    /// Physical tag -> face indices.
    groups: BTreeMap<i32, Vec<u32>>,
}

impl TaggedTriangles {
    fn new(raw: &Raw, new_id: &[u32], nt: usize) -> std::result::Result<TaggedTriangles, String> {
        let mut t = TaggedTriangles { nt, face_of_key: HashMap::new(), unique: Vec::new(), groups: BTreeMap::new() };
        for (i, tri) in raw.tris.iter().enumerate() {
            let Some(phys) = raw.entity_phys[2].get(&raw.tri_entity[i]) else {
                continue; // untagged triangle
            };
            let mut ids = [u32::MAX; 6];
            for k in 0..nt {
                ids[k] = new_id[tri[k] as usize];
            }
            if ids[..nt].contains(&u32::MAX) {
                return Err(format!("{} uses a node of no tetrahedron", describe_tri(raw, i, nt)));
            }
            let key = face_key(ids[0], ids[1], ids[2]);
            let fi = *t.face_of_key.entry(key).or_insert_with(|| {
                t.unique.push((i, ids));
                t.unique.len() as u32 - 1
            });
            for &p in phys {
                t.groups.entry(p).or_default().push(fi);
            }
        }
        Ok(t)
    }

    /// Attaches each face to a tet in one pass over the tet faces, looking up only faces whose
    /// vertices all lie on tagged triangles; the first (lowest-numbered) tet wins. Returns the
    /// faces in the tets' node order and (tet, local face) of each; a face of no tet, or one
    /// whose mid-edge nodes differ from its tet's, is an error.
    fn attach(
        &self,
        raw: &Raw,
        tets: &[[u32; 10]],
        n_nodes: usize,
        linear: bool,
    ) -> std::result::Result<AttachedFaces, String> {
        let nt = self.nt;
        let mut on_face = vec![false; n_nodes];
        for (_, ids) in &self.unique {
            for &n in &ids[..3] {
                on_face[n as usize] = true;
            }
        }
        let mut face_cell = vec![(u32::MAX, 0u8); self.unique.len()];
        for (t, tet) in tets.iter().enumerate() {
            for (f, lf) in TET_FACES.iter().enumerate() {
                let (a, b, c) = (tet[lf[0]], tet[lf[1]], tet[lf[2]]);
                if on_face[a as usize] && on_face[b as usize] && on_face[c as usize] {
                    if let Some(&fi) = self.face_of_key.get(&face_key(a, b, c)) {
                        if face_cell[fi as usize].0 == u32::MAX {
                            face_cell[fi as usize] = (t as u32, f as u8);
                        }
                    }
                }
            }
        }
        let mut faces: Vec<[u32; 6]> = Vec::with_capacity(self.unique.len());
        for (&(i, ids), &(t, lf)) in self.unique.iter().zip(&face_cell) {
            if t == u32::MAX {
                return Err(format!("{} is not a face of any tetrahedron", describe_tri(raw, i, nt)));
            }
            let face = TET_FACES[lf as usize].map(|p| tets[t as usize][p]);
            if !linear {
                let (mut a, mut b) = (face, ids);
                a.sort_unstable();
                b.sort_unstable();
                if a != b {
                    return Err(format!(
                        "{}: its mid-edge nodes differ from those of tetrahedron {} (non-conforming mesh)",
                        describe_tri(raw, i, nt),
                        raw.tet_tags[t as usize]
                    ));
                }
            }
            faces.push(face);
        }
        Ok((faces, face_cell))
    }
}

/// "boundary triangle <element tag> (node tags ...)" for error messages.
fn describe_tri(raw: &Raw, i: usize, nt: usize) -> String {
    let tags: Vec<String> = raw.tris[i][..nt].iter().map(|&n| raw.node_tags[n as usize].to_string()).collect();
    format!("boundary triangle {} (element tag; node tags {})", raw.tri_tags[i], tags.join(" "))
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}
