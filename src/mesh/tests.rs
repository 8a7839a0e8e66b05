//! Tests of the mesh module. Meshes are generated with the gmsh CLI into a cache under the system temp dir.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

use super::dist::{distribute, LocalMesh};
use super::generate::{cached, generate, generate_with, COLUMN_GEO, SPHERE_GEO, SPHERE_QUARTER_GEO};
use super::gmsh::read;
use super::partition::{dual_graph, partition};
use super::Mesh;
use crate::error::Error;
use crate::reference_cell::shape::tet10;
use crate::reference_cell::{sub, tet_det, TET10_EDGES, TET10_FLIP, TET_FACES};

// ---------------------------------------------------------------- helpers

fn cache_dir() -> PathBuf {
    std::env::temp_dir().join("poroplast-mesh-tests")
}

/// A fresh empty directory for files written by one test.
fn scratch_dir() -> PathBuf {
    static N: AtomicUsize = AtomicUsize::new(0);
    let d = std::env::temp_dir().join(format!(
        "poroplast-mesh-scratch-{}-{}",
        std::process::id(),
        N.fetch_add(1, Ordering::Relaxed)
    ));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn params(p: &[(&str, f64)]) -> Vec<(String, f64)> {
    p.iter().map(|(k, v)| (k.to_string(), *v)).collect()
}

fn gen(name: &str, src: &str, p: &[(&str, f64)], order: usize) -> Mesh {
    let path = cached(name, src, &params(p), order, &cache_dir()).unwrap();
    read(&path).unwrap()
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn mid(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [0.5 * (a[0] + b[0]), 0.5 * (a[1] + b[1]), 0.5 * (a[2] + b[2])]
}

fn close(a: [f64; 3], b: [f64; 3], tol: f64) -> bool {
    norm(sub(a, b)) <= tol
}

/// Keast's 11-point rule, exact for degree 4 on the reference tet (weights sum to 1/6).
fn keast4() -> Vec<([f64; 3], f64)> {
    let mut q = vec![([0.25; 3], -74.0 / 5625.0)];
    let (a, b) = (1.0 / 14.0, 11.0 / 14.0);
    for p in [[a, a, a], [b, a, a], [a, b, a], [a, a, b]] {
        q.push((p, 343.0 / 45000.0));
    }
    let s = (5.0f64 / 14.0).sqrt();
    let (c, d) = ((1.0 + s) / 4.0, (1.0 - s) / 4.0);
    for p in [[c, c, d], [c, d, c], [d, c, c], [c, d, d], [d, c, d], [d, d, c]] {
        q.push((p, 56.0 / 2250.0));
    }
    q
}

/// det of the isoparametric Jacobian of tet `t` at `xi`.
fn jac_det(mesh: &Mesh, t: usize, xi: [f64; 3]) -> f64 {
    let (_, g) = tet10(&xi);
    let mut j = [[0.0; 3]; 3];
    for (k, &n) in mesh.cells[t].iter().enumerate() {
        let x = mesh.coords[n as usize];
        for c in 0..3 {
            for d in 0..3 {
                j[c][d] += x[c] * g[k][d];
            }
        }
    }
    let col = |d: usize| [j[0][d], j[1][d], j[2][d]];
    dot(col(0), cross(col(1), col(2)))
}

/// Volume of the curved mesh; also asserts that the Jacobian is positive at every quadrature point.
fn curved_volume(mesh: &Mesh) -> f64 {
    let q = keast4();
    let mut v = 0.0;
    for t in 0..mesh.cells.len() {
        for &(xi, w) in &q {
            let d = jac_det(mesh, t, xi);
            assert!(d > 0.0, "tet {t}: non-positive Jacobian {d}");
            v += w * d;
        }
    }
    v
}

/// Flat normal (right-hand rule on the 3 vertices) of face `f`.
fn face_normal(mesh: &Mesh, f: usize) -> [f64; 3] {
    let x = |k: usize| mesh.coords[mesh.faces[f][k] as usize];
    cross(sub(x(1), x(0)), sub(x(2), x(0)))
}

/// Checks every mesh must pass: positive tets, faces equal to their tet's local face, group ranges,
/// vertex flags, and the faces of a tagged closed boundary = the tet faces without neighbour.
fn check_invariants(mesh: &Mesh) {
    assert_eq!(mesh.is_vertex.len(), mesh.coords.len());
    for (t, tet) in mesh.cells.iter().enumerate() {
        let x = |k: usize| mesh.coords[tet[k] as usize];
        assert!(tet_det(x(0), x(1), x(2), x(3)) > 0.0, "tet {t} negatively oriented");
        for &n in &tet[..4] {
            assert!(mesh.is_vertex[n as usize]);
        }
        for &n in &tet[4..] {
            assert!(!mesh.is_vertex[n as usize]);
        }
    }
    assert_eq!(mesh.faces.len(), mesh.face_cell.len());
    let mut keys = BTreeSet::new();
    for (f, (face, &(t, lf))) in mesh.faces.iter().zip(&mesh.face_cell).enumerate() {
        let tet = mesh.cells[t as usize];
        assert_eq!(*face, TET_FACES[lf as usize].map(|p| tet[p]), "face {f}");
        assert!(keys.insert(super::face_match::face_key(face[0], face[1], face[2])), "face {f} duplicated");
        // The opposite vertex lies behind the face.
        let opp = (0..4).find(|k| !TET_FACES[lf as usize][..3].contains(k)).unwrap();
        let n = face_normal(mesh, f);
        assert!(dot(n, sub(mesh.coords[tet[opp] as usize], mesh.coords[face[0] as usize])) < 0.0);
    }
    for (_, g) in &mesh.face_groups {
        assert!(g.windows(2).all(|w| w[0] < w[1]) && g.iter().all(|&f| (f as usize) < mesh.faces.len()));
    }
    for (_, g) in &mesh.volume_groups {
        assert!(g.windows(2).all(|w| w[0] < w[1]) && g.iter().all(|&t| (t as usize) < mesh.cells.len()));
    }
}

/// Boundary = tet faces without a neighbour, as sorted vertex triples.
fn exterior_faces(mesh: &Mesh) -> BTreeSet<[u32; 3]> {
    let f: Vec<([u32; 3], u32, u8)> = super::face_match::sorted_cell_faces(mesh.family, &mesh.cells)
        .into_iter()
        .map(super::face_match::unpack_face)
        .collect();
    let mut out = BTreeSet::new();
    let mut i = 0;
    while i < f.len() {
        let mut j = i + 1;
        while j < f.len() && f[j].0 == f[i].0 {
            j += 1;
        }
        if j - i == 1 {
            out.insert(f[i].0);
        }
        i = j;
    }
    out
}

fn face_keys(mesh: &Mesh, faces: &[u32]) -> BTreeSet<[u32; 3]> {
    faces
        .iter()
        .map(|&f| {
            super::face_match::face_key(mesh.faces[f as usize][0], mesh.faces[f as usize][1], mesh.faces[f as usize][2])
        })
        .collect()
}

fn group_names(groups: &[(String, Vec<u32>)]) -> Vec<&str> {
    groups.iter().map(|(n, _)| n.as_str()).collect()
}

/// Max | |x - c| - R | over the mid-edge nodes of the faces in `faces`, and the same for the chord midpoints.
fn sphere_deviation(mesh: &Mesh, faces: &[u32], c: [f64; 3], r: f64) -> (f64, f64) {
    let (mut dev, mut chord) = (0.0f64, 0.0f64);
    for &f in faces {
        let face = mesh.faces[f as usize];
        let x = |k: usize| mesh.coords[face[k] as usize];
        for (k, (a, b)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
            dev = dev.max((norm(sub(x(3 + k), c)) - r).abs());
            chord = chord.max((norm(sub(mid(x(a), x(b)), c)) - r).abs());
        }
    }
    (dev, chord)
}

// ---------------------------------------------------------------- conventions

#[test]
fn keast_rule_is_degree_4() {
    let fact = |n: usize| (1..=n).product::<usize>() as f64;
    for a in 0..=4 {
        for b in 0..=4 - a {
            for c in 0..=4 - a - b {
                let exact = fact(a) * fact(b) * fact(c) / fact(a + b + c + 3);
                let q: f64 = keast4()
                    .iter()
                    .map(|(p, w)| w * p[0].powi(a as i32) * p[1].powi(b as i32) * p[2].powi(c as i32))
                    .sum();
                assert!((q - exact).abs() < 1e-14, "x^{a} y^{b} z^{c}: {q} vs {exact}");
            }
        }
    }
}

#[test]
fn tet_faces_point_outward_on_reference_tet() {
    let mut x = [
        [0.0; 3],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.0; 3],
        [0.0; 3],
        [0.0; 3],
        [0.0; 3],
        [0.0; 3],
        [0.0; 3],
    ];
    for (k, &(a, b)) in TET10_EDGES.iter().enumerate() {
        x[4 + k] = mid(x[a], x[b]);
    }
    assert!(tet_det(x[0], x[1], x[2], x[3]) > 0.0);
    let centroid = [0.25; 3];
    let mut opposite = BTreeSet::new();
    for f in TET_FACES {
        let n = cross(sub(x[f[1]], x[f[0]]), sub(x[f[2]], x[f[0]]));
        let fc = [
            (x[f[0]][0] + x[f[1]][0] + x[f[2]][0]) / 3.0,
            (x[f[0]][1] + x[f[1]][1] + x[f[2]][1]) / 3.0,
            (x[f[0]][2] + x[f[1]][2] + x[f[2]][2]) / 3.0,
        ];
        assert!(dot(n, sub(fc, centroid)) > 0.0, "face {f:?} points inward");
        // Triangle6 order: mid-nodes of edges 01, 12, 20.
        assert!(close(x[f[3]], mid(x[f[0]], x[f[1]]), 0.0));
        assert!(close(x[f[4]], mid(x[f[1]], x[f[2]]), 0.0));
        assert!(close(x[f[5]], mid(x[f[2]], x[f[0]]), 0.0));
        opposite.insert((0..4).find(|k| !f[..3].contains(k)).unwrap());
    }
    assert_eq!(opposite.len(), 4);
    // The flip makes a negative tet positive and keeps every mid-node on its edge.
    let y: Vec<[f64; 3]> = TET10_FLIP.iter().map(|&k| x[k]).collect();
    assert!(tet_det(y[0], y[1], y[2], y[3]) < 0.0);
    for (k, &(a, b)) in TET10_EDGES.iter().enumerate() {
        assert!(close(y[4 + k], mid(y[a], y[b]), 0.0));
    }
}

#[test]
fn gmsh_tet10_edge_order() {
    // Straight-sided order-2 box: every mid-node is exactly the midpoint of its edge.
    let geo = "SetFactory(\"OpenCASCADE\");\nBox(1) = {0,0,0, 1,2,3};\nMesh.MeshSizeMax = 0.7;\n\
               Physical Volume(\"box\") = {1};\nPhysical Surface(\"all\") = Surface{:};\n";
    let mesh = gen("box.geo", geo, &[], 2);
    check_invariants(&mesh);
    assert!(mesh.cells.len() > 50);
    for tet in &mesh.cells {
        let x = |k: usize| mesh.coords[tet[k] as usize];
        for (k, &(a, b)) in TET10_EDGES.iter().enumerate() {
            assert!(close(x(4 + k), mid(x(a), x(b)), 1e-12), "mid-node {} not on edge {a}-{b}", 4 + k);
        }
    }
    for face in &mesh.faces {
        let x = |k: usize| mesh.coords[face[k] as usize];
        assert!(close(x(3), mid(x(0), x(1)), 1e-12) && close(x(4), mid(x(1), x(2)), 1e-12));
    }
    let v = curved_volume(&mesh);
    assert!((v - 6.0).abs() < 1e-10, "box volume {v}");
    assert_eq!(face_keys(&mesh, mesh.face_group("all").unwrap()), exterior_faces(&mesh));
}

// ---------------------------------------------------------------- the .geo files

#[test]
fn sphere_default() {
    let r = 100.0;
    let mesh = gen("sphere.geo", SPHERE_GEO, &[], 2);
    check_invariants(&mesh);
    assert_eq!(group_names(&mesh.volume_groups), ["aggregate"]);
    assert_eq!(group_names(&mesh.face_groups), ["surface"]);
    assert_eq!(group_names(&mesh.point_groups), ["pole_bottom", "pole_top", "equator_y"]);
    // The rigid-mode lock of a full sphere: one node at (0, R, R), on the curved surface.
    let eq = mesh.point_group("equator_y").unwrap();
    assert_eq!(eq.len(), 1);
    let x = mesh.coords[eq[0] as usize];
    assert!(x[0].abs() < 1e-9 * r && (x[1] - r).abs() < 1e-9 * r && (x[2] - r).abs() < 1e-9 * r, "{x:?}");
    assert_eq!(mesh.volume_groups[0].1.len(), mesh.cells.len());
    let c = [0.0, 0.0, r];
    let surf = mesh.face_group("surface").unwrap();
    assert_eq!(face_keys(&mesh, surf), exterior_faces(&mesh));
    assert_eq!(surf.len(), mesh.faces.len());

    let v = curved_volume(&mesh);
    let exact = 4.0 / 3.0 * std::f64::consts::PI * r * r * r;
    assert!((v / exact - 1.0).abs() < 1e-3, "sphere volume {v} vs {exact}");

    let (dev, chord) = sphere_deviation(&mesh, surf, c, r);
    assert!(dev < 1e-9 * r, "boundary mid-nodes off the sphere by {dev}");
    assert!(chord > 1e-3 * r, "chord midpoints unexpectedly on the sphere ({chord})");

    for f in 0..mesh.faces.len() {
        let n = face_normal(&mesh, f);
        for k in 0..3 {
            assert!(dot(n, sub(mesh.coords[mesh.faces[f][k] as usize], c)) > 0.0, "face {f} not outward");
        }
    }
    let pb = mesh.point_group("pole_bottom").unwrap();
    let pt = mesh.point_group("pole_top").unwrap();
    assert_eq!((pb.len(), pt.len()), (1, 1));
    assert!(close(mesh.coords[pb[0] as usize], [0.0, 0.0, 0.0], 1e-9 * r));
    assert!(close(mesh.coords[pt[0] as usize], [0.0, 0.0, 2.0 * r], 1e-9 * r));
    assert!(mesh.is_vertex[pb[0] as usize] && mesh.is_vertex[pt[0] as usize]);

    // Refinement: edges at the poles are about h_pole = 25/3, in the bulk about h = 25.
    let edge_len_near = |p: [f64; 3]| {
        let mut sum = 0.0;
        let mut cnt = 0;
        for tet in &mesh.cells {
            let x0 = mesh.coords[tet[0] as usize];
            if norm(sub(x0, p)) < 10.0 {
                sum += norm(sub(mesh.coords[tet[1] as usize], x0));
                cnt += 1;
            }
        }
        sum / cnt as f64
    };
    let near = edge_len_near([0.0, 0.0, 0.0]);
    let near_top = edge_len_near([0.0, 0.0, 2.0 * r]);
    let bulk = edge_len_near(c);
    assert!(near < 0.6 * bulk && near_top < 0.6 * bulk, "edges: poles {near}, {near_top}; bulk {bulk}");
    assert!(bulk > 15.0 && bulk < 45.0, "bulk edge length {bulk} for h = 25");
    let err = mesh.face_group("top").unwrap_err().to_string();
    assert!(err.contains("\"top\"") && err.contains("\"surface\""), "{err}");
    let err = mesh.point_group("centre").unwrap_err().to_string();
    assert!(err.contains("\"centre\"") && err.contains("\"pole_bottom\"") && err.contains("\"pole_top\""), "{err}");
    eprintln!(
        "sphere default: {} tets, {} nodes, {} vertices, {} faces; volume rel. error {:.2e}; mid-node deviation {:.1e} R (chord {:.1e} R); mean edge near poles {near:.1}, {near_top:.1}, bulk {bulk:.1}",
        mesh.cells.len(), mesh.coords.len(), mesh.n_vertices(), mesh.faces.len(), v / exact - 1.0, dev / r, chord / r
    );
}

#[test]
fn sphere_parameters_from_command_line() {
    // Smaller R with proportionally smaller h: same topology scaled; r_pole and h_pole follow.
    let r = 2.0;
    let mesh = gen("sphere.geo", SPHERE_GEO, &[("R", r), ("h", 0.5)], 2);
    check_invariants(&mesh);
    let surf = mesh.face_group("surface").unwrap();
    let (dev, _) = sphere_deviation(&mesh, surf, [0.0, 0.0, r], r);
    assert!(dev < 1e-9 * r);
    let pt = mesh.point_group("pole_top").unwrap();
    assert!(close(mesh.coords[pt[0] as usize], [0.0, 0.0, 2.0 * r], 1e-9 * r));
    let coarse = gen("sphere.geo", SPHERE_GEO, &[("h", 40.0), ("h_pole", 40.0)], 2);
    let default = gen("sphere.geo", SPHERE_GEO, &[], 2);
    assert!(coarse.cells.len() * 2 < default.cells.len(), "{} vs {}", coarse.cells.len(), default.cells.len());
}

#[test]
fn sphere_quarter_default() {
    let r = 100.0;
    let mesh = gen("sphere_quarter.geo", SPHERE_QUARTER_GEO, &[], 2);
    check_invariants(&mesh);
    assert_eq!(group_names(&mesh.volume_groups), ["aggregate"]);
    assert_eq!(group_names(&mesh.face_groups), ["surface", "symmetry_x", "symmetry_y"]);
    assert_eq!(group_names(&mesh.point_groups), ["pole_bottom", "pole_top", "equator_y"]);
    // The rigid-mode lock of a full sphere: one node at (0, R, R), on the curved surface.
    let eq = mesh.point_group("equator_y").unwrap();
    assert_eq!(eq.len(), 1);
    let x = mesh.coords[eq[0] as usize];
    assert!(x[0].abs() < 1e-9 * r && (x[1] - r).abs() < 1e-9 * r && (x[2] - r).abs() < 1e-9 * r, "{x:?}");
    let c = [0.0, 0.0, r];
    let surf = mesh.face_group("surface").unwrap();
    let sx = mesh.face_group("symmetry_x").unwrap();
    let sy = mesh.face_group("symmetry_y").unwrap();
    let mut all = face_keys(&mesh, surf);
    all.extend(face_keys(&mesh, sx));
    all.extend(face_keys(&mesh, sy));
    assert_eq!(surf.len() + sx.len() + sy.len(), mesh.faces.len());
    assert_eq!(all, exterior_faces(&mesh));

    let v = curved_volume(&mesh);
    let exact = std::f64::consts::PI * r * r * r / 3.0;
    assert!((v / exact - 1.0).abs() < 1e-3, "quarter volume {v} vs {exact}");
    let (dev, _) = sphere_deviation(&mesh, surf, c, r);
    assert!(dev < 1e-9 * r, "curved mid-nodes off the sphere by {dev}");
    for &f in surf {
        let n = face_normal(&mesh, f as usize);
        for k in 0..3 {
            assert!(dot(n, sub(mesh.coords[mesh.faces[f as usize][k] as usize], c)) > 0.0);
        }
    }
    for (group, axis) in [(sx, 0), (sy, 1)] {
        for &f in group {
            let n = face_normal(&mesh, f as usize);
            assert!(n[axis] / norm(n) < -1.0 + 1e-12, "symmetry face normal {n:?}");
            for &node in &mesh.faces[f as usize] {
                assert!(mesh.coords[node as usize][axis].abs() < 1e-9 * r);
            }
        }
    }
    for (name, z) in [("pole_bottom", 0.0), ("pole_top", 2.0 * r)] {
        let p = mesh.point_group(name).unwrap();
        assert_eq!(p.len(), 1);
        assert!(close(mesh.coords[p[0] as usize], [0.0, 0.0, z], 1e-9 * r));
    }
    eprintln!(
        "quarter default: {} tets, {} nodes; volume rel. error {:.2e}; mid-node deviation {:.1e} R",
        mesh.cells.len(),
        mesh.coords.len(),
        v / exact - 1.0,
        dev / r
    );
}

#[test]
fn column_default_and_graded() {
    let mesh = gen("column.geo", COLUMN_GEO, &[], 2);
    check_invariants(&mesh);
    let (h, w) = (1.0, 0.1);
    assert_eq!(group_names(&mesh.volume_groups), ["column"]);
    assert_eq!(group_names(&mesh.face_groups), ["top", "bottom", "sides"]);
    assert!((300..5000).contains(&mesh.cells.len()), "{} tets", mesh.cells.len());
    let v = curved_volume(&mesh);
    assert!((v - w * w * h).abs() < 1e-12, "column volume {v}");
    let mut all = BTreeSet::new();
    for (name, expect) in [("top", Some([0.0, 0.0, 1.0])), ("bottom", Some([0.0, 0.0, -1.0])), ("sides", None)] {
        let g = mesh.face_group(name).unwrap();
        assert!(!g.is_empty());
        let mut area = 0.0;
        for &f in g {
            let n = face_normal(&mesh, f as usize);
            area += 0.5 * norm(n);
            let n = n.map(|c| c / norm(n));
            match expect {
                Some(e) => assert!(dot(n, e) > 1.0 - 1e-12, "{name} normal {n:?}"),
                None => {
                    // Lateral faces: horizontal outward normal.
                    let x = mesh.coords[mesh.faces[f as usize][0] as usize];
                    assert!(n[2].abs() < 1e-12);
                    assert!(dot(n, [x[0] - w / 2.0, x[1] - w / 2.0, 0.0]) > 0.0);
                }
            }
        }
        let expect_area = if expect.is_some() { w * w } else { 4.0 * w * h };
        assert!((area - expect_area).abs() < 1e-12, "{name} area {area}");
        all.extend(face_keys(&mesh, g));
    }
    assert_eq!(all, exterior_faces(&mesh));
    eprintln!("column default: {} tets, {} nodes", mesh.cells.len(), mesh.coords.len());

    // Grading: h_top = h/4 gives more, thinner layers at the top.
    let graded = gen("column.geo", COLUMN_GEO, &[("h_top", 0.1 / 12.0)], 2);
    check_invariants(&graded);
    let layers = |m: &Mesh| {
        let mut z: Vec<f64> = (0..m.coords.len()).filter(|&n| m.is_vertex[n]).map(|n| m.coords[n][2]).collect();
        z.sort_by(f64::total_cmp);
        z.dedup_by(|a, b| (*a - *b).abs() < 1e-12);
        z
    };
    let z = layers(&graded);
    let top_gap = z[z.len() - 1] - z[z.len() - 2];
    let bottom_gap = z[1] - z[0];
    assert!((top_gap - 0.1 / 12.0).abs() < 0.2 * 0.1 / 12.0, "top layer {top_gap}");
    assert!((bottom_gap - 0.1 / 3.0).abs() < 0.2 * 0.1 / 3.0, "bottom layer {bottom_gap}");
    assert!((curved_volume(&graded) - w * w * h).abs() < 1e-12);
}

// ---------------------------------------------------------------- linear meshes

#[test]
fn tet4_promotion() {
    let lin = gen("sphere.geo", SPHERE_GEO, &[], 1);
    check_invariants(&lin);
    let quad = gen("sphere.geo", SPHERE_GEO, &[], 2);
    // Same vertices; mid-nodes are straight midpoints, one per distinct edge.
    assert_eq!(lin.n_vertices(), quad.n_vertices());
    assert_eq!(lin.coords.len(), quad.coords.len());
    assert_eq!(lin.cells.len(), quad.cells.len());
    let mut edges = BTreeSet::new();
    for tet in &lin.cells {
        let x = |k: usize| lin.coords[tet[k] as usize];
        for (k, &(a, b)) in TET10_EDGES.iter().enumerate() {
            assert!(close(x(4 + k), mid(x(a), x(b)), 1e-12));
            edges.insert((tet[a].min(tet[b]), tet[a].max(tet[b]), tet[4 + k]));
        }
    }
    assert_eq!(edges.len() + lin.n_vertices(), lin.coords.len());
    // The polyhedral volume is below the sphere's.
    let v = curved_volume(&lin);
    let exact = 4.0 / 3.0 * std::f64::consts::PI * 1e6;
    assert!(v < exact && v > 0.9 * exact, "linear volume {v}");
    let surf = lin.face_group("surface").unwrap();
    assert_eq!(face_keys(&lin, surf), exterior_faces(&lin));
}

/// Two tets sharing face (1,2,3); the second is negatively oriented in the file.
const TWO_TETS: &str = "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n\
$PhysicalNames\n3\n2 10 \"bottom\"\n2 11 \"inner\"\n3 20 \"body\"\n$EndPhysicalNames\n\
$Entities\n0 0 2 1\n1 0 0 0 1 1 0 1 10 0\n2 0 0 0 1 1 1 1 11 0\n1 0 0 0 1 1 1 1 20 0\n$EndEntities\n\
$Nodes\n1 5 10 50\n3 1 0 5\n10\n20\n30\n40\n50\n0 0 0\n1 0 0\n0 1 0\n0 0 1\n1 1 1\n$EndNodes\n\
$Elements\n3 4 1 4\n2 1 2 1\n1 10 30 20\n2 2 2 1\n2 20 30 40\n3 1 4 2\n3 10 20 30 40\n4 50 20 30 40\n$EndElements\n";

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

#[test]
fn handwritten_linear_mesh() {
    let dir = scratch_dir();
    let mesh = read(&write(&dir, "two.msh", TWO_TETS)).unwrap();
    check_invariants(&mesh);
    assert_eq!(mesh.cells.len(), 2);
    assert_eq!(mesh.n_vertices(), 5);
    assert_eq!(mesh.coords.len(), 5 + 9); // 9 distinct edges
                                          // Sparse node tags 10..50 were compacted in file order.
    assert_eq!(mesh.coords[..5], [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]]);
    // The second tet was flipped to a positive orientation.
    assert_eq!(mesh.cells[1][..4], [4, 2, 1, 3]);
    assert_eq!(mesh.volume_group("body").unwrap(), [0, 1]);
    let b = mesh.face_group("bottom").unwrap();
    assert_eq!(b.len(), 1);
    assert_eq!(face_normal(&mesh, b[0] as usize), [0.0, 0.0, -1.0]);
    // The interior face is attached to the lower-numbered tet, outward from it.
    let inner = mesh.face_group("inner").unwrap();
    assert_eq!(mesh.face_cell[inner[0] as usize].0, 0);
    let n = face_normal(&mesh, inner[0] as usize);
    assert!(dot(n, [1.0, 1.0, 1.0]) > 0.0);
    let _ = std::fs::remove_dir_all(dir);
}

// ---------------------------------------------------------------- malformed input

fn read_err(dir: &Path, name: &str, text: &str) -> String {
    match read(&write(dir, name, text)) {
        Ok(_) => panic!("{name}: accepted"),
        Err(e @ Error::Mesh { .. }) => e.to_string(),
        Err(e) => panic!("{name}: wrong error kind {e}"),
    }
}

#[test]
fn malformed_inputs_are_errors() {
    let dir = scratch_dir();
    let missing = read(&dir.join("nope.msh")).unwrap_err().to_string();
    assert!(missing.contains("nope.msh") && missing.contains("does not exist"), "{missing}");

    let e = read_err(&dir, "v2.msh", "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n");
    assert!(e.contains("MSH 2.2 not supported, re-export with -format msh41"), "{e}");
    let e = read_err(&dir, "bin.msh", "$MeshFormat\n4.1 1 8\n\u{1}\0\0\0\n$EndMeshFormat\n");
    assert!(e.contains("binary"), "{e}");
    let e = read_err(&dir, "empty.msh", "");
    assert!(e.contains("empty"), "{e}");
    let e = read_err(&dir, "text.msh", "hello\n");
    assert!(e.contains("line 1") && e.contains("$MeshFormat"), "{e}");

    // Truncated at every line: always an error, never a panic.
    let lines: Vec<&str> = TWO_TETS.lines().collect();
    for cut in 1..lines.len() {
        let text = lines[..cut].join("\n");
        let r = read(&write(&dir, "cut.msh", &text));
        assert!(r.is_err(), "truncated after {cut} lines accepted");
    }
    let e = read_err(&dir, "trunc.msh", &TWO_TETS[..TWO_TETS.find("40\n50\n0 0 0").unwrap()]);
    assert!(e.contains("end of file"), "{e}");

    // Garbage in place of numbers, with the line number.
    let e = read_err(&dir, "garbage.msh", &TWO_TETS.replace("0 0 1\n1 1 1", "0 0 x1\n1 1 1"));
    assert!(e.contains("line 27") && e.contains("x1"), "{e}");
    let e = read_err(&dir, "garbage2.msh", &TWO_TETS.replace("1 5 10 50", "1 5 ten 50"));
    assert!(e.contains("line 17") && e.contains("expected 4 integers"), "{e}");
    let e = read_err(&dir, "huge.msh", &TWO_TETS.replace("1 5 10 50", "1 99999999999999 10 50"));
    assert!(e.contains("line"), "{e}");
    let e = read_err(&dir, "nan.msh", &TWO_TETS.replace("0 0 1\n1 1 1", "0 0 NaN\n1 1 1"));
    assert!(e.contains("non-finite"), "{e}");

    // Missing sections.
    let start = TWO_TETS.find("$Nodes").unwrap();
    let end = TWO_TETS.find("$Elements").unwrap();
    let no_nodes = format!("{}{}", &TWO_TETS[..start], &TWO_TETS[end..]);
    let e = read_err(&dir, "nonodes.msh", &no_nodes);
    assert!(e.contains("$Nodes"), "{e}");
    let e = read_err(&dir, "noelems.msh", &TWO_TETS[..end]);
    assert!(e.contains("no $Elements"), "{e}");
    let e = read_err(&dir, "notets.msh", &TWO_TETS.replace("3 1 4 2\n3 10 20 30 40\n4 50 20 30 40\n", "3 1 4 0\n"));
    assert!(e.contains("no tetrahedra"), "{e}");

    // Unsupported element types.
    let e = read_err(&dir, "hex.msh", &TWO_TETS.replace("3 1 4 2\n", "3 1 5 2\n"));
    assert!(e.contains("hexahedron") && e.contains("type 5"), "{e}");
    let e = read_err(&dir, "quad.msh", &TWO_TETS.replace("2 1 2 1\n", "2 1 3 1\n"));
    assert!(e.contains("quadrangle"), "{e}");
    let e = read_err(&dir, "weird.msh", &TWO_TETS.replace("2 1 2 1\n", "2 1 77 1\n"));
    assert!(e.contains("77"), "{e}");

    // References to undefined nodes; wrong node counts.
    let e = read_err(&dir, "undef.msh", &TWO_TETS.replace("4 50 20 30 40", "4 50 20 30 41"));
    assert!(e.contains("node tag 41") && e.contains("line 38"), "{e}");
    let e = read_err(&dir, "short.msh", &TWO_TETS.replace("4 50 20 30 40", "4 50 20 30"));
    assert!(e.contains("line 38"), "{e}");
    let e = read_err(&dir, "long.msh", &TWO_TETS.replace("4 50 20 30 40", "4 50 20 30 40 10"));
    assert!(e.contains("line 38"), "{e}");
    let e = read_err(&dir, "dup.msh", &TWO_TETS.replace("40\n50\n", "40\n40\n"));
    assert!(e.contains("defined twice"), "{e}");

    // A tagged triangle that is not a tet face; a degenerate tet.
    let e = read_err(&dir, "orphan.msh", &TWO_TETS.replace("1 10 30 20", "1 10 30 50"));
    assert!(e.contains("boundary triangle 1") && e.contains("not a face"), "{e}");
    let e = read_err(&dir, "flat.msh", &TWO_TETS.replace("1 1 1\n$EndNodes", "1 1 -1\n$EndNodes"));
    assert!(e.contains("degenerate"), "{e}");

    // Mixed orders.
    let mixed = TWO_TETS.replace("2 1 2 1\n1 10 30 20\n", "2 1 9 1\n1 10 30 20 10 30 20\n");
    let e = read_err(&dir, "mixed.msh", &mixed);
    assert!(e.contains("mixed linear/quadratic"), "{e}");

    // Unknown sections are skipped; an unterminated one is an error.
    let extra = TWO_TETS.replace("$Nodes", "$Periodic\n0\n$EndPeriodic\n$NodeData\n1\n\"p\"\n$EndNodeData\n$Nodes");
    assert_eq!(read(&write(&dir, "extra.msh", &extra)).unwrap().cells.len(), 2);
    let e = read_err(&dir, "open.msh", &TWO_TETS.replace("$Nodes", "$Periodic\n0\n$Nodes"));
    assert!(e.contains("$Periodic") && e.contains("never closed"), "{e}");

    // Line-level damage to a real gmsh file (deleted, duplicated or garbled lines) never panics.
    let geo = "SetFactory(\"OpenCASCADE\");\nSphere(1) = {0,0,0, 1};\nMesh.MeshSizeMax = 0.6;\n\
               Physical Volume(\"v\") = {1};\nPhysical Surface(\"s\") = Surface{:};\n\
               Physical Point(\"p\") = Point{:};\n";
    let real = std::fs::read_to_string(cached("fuzz.geo", geo, &[], 2, &cache_dir()).unwrap()).unwrap();
    let real: Vec<&str> = real.lines().collect();
    let mut seed = 987654321u64;
    let mut rand = |n: usize| {
        seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (seed >> 33) as usize % n
    };
    let (mut ok, mut failed) = (0, 0);
    for _ in 0..150 {
        let mut l: Vec<String> = real.iter().map(|s| s.to_string()).collect();
        for _ in 0..1 + rand(3) {
            let i = rand(l.len());
            match rand(4) {
                0 => {
                    l.remove(i);
                }
                1 => l.insert(i, l[i].clone()),
                2 => l[i] = l[i].replace('1', "-7"),
                _ => l[i] = l[i].split(' ').rev().collect::<Vec<_>>().join(" "),
            }
        }
        match read(&write(&dir, "fuzz.msh", &l.join("\n"))) {
            Ok(m) => {
                ok += 1;
                assert!(m.cells.iter().flatten().all(|&n| (n as usize) < m.coords.len()));
            }
            Err(Error::Mesh { msg, .. }) => {
                failed += 1;
                assert!(!msg.is_empty());
                if failed % 10 == 0 {
                    eprintln!("  {msg}");
                }
            }
            Err(e) => panic!("wrong error kind {e}"),
        }
    }
    eprintln!("fuzz: {ok} damaged files accepted, {failed} rejected");
    assert!(failed > 50, "{ok} damaged files accepted, {failed} rejected");

    // Random byte noise never panics.
    let mut seed = 12345u64;
    for _ in 0..200 {
        let mut bytes = TWO_TETS.as_bytes().to_vec();
        for _ in 0..3 {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            let pos = (seed >> 33) as usize % bytes.len();
            bytes[pos] = b"0123456789 -.\n$x"[(seed >> 20) as usize % 16];
        }
        let p = dir.join("noise.msh");
        std::fs::write(&p, &bytes).unwrap();
        let _ = read(&p);
    }
    let _ = std::fs::remove_dir_all(dir);
}

// ---------------------------------------------------------------- generation

#[test]
fn cache_and_generation_errors() {
    let dir = scratch_dir();
    let geo = "SetFactory(\"OpenCASCADE\");\nDefineConstant[ a = 1 ];\nBox(1) = {0,0,0, a,a,a};\n\
               Mesh.MeshSizeMax = a / 2;\nPhysical Volume(\"v\") = {1};\n";
    let p1 = cached("cube.geo", geo, &params(&[("a", 1.0)]), 2, &dir).unwrap();
    let name = p1.file_name().unwrap().to_string_lossy().into_owned();
    assert!(name.starts_with("cube-") && name.ends_with(".msh") && name.len() == "cube-".len() + 16 + 4, "{name}");
    let t1 = std::fs::metadata(&p1).unwrap().modified().unwrap();
    let p2 = cached("cube.geo", geo, &params(&[("a", 1.0)]), 2, &dir).unwrap();
    assert_eq!(p1, p2);
    assert_eq!(std::fs::metadata(&p2).unwrap().modified().unwrap(), t1, "regenerated");
    let p3 = cached("cube.geo", geo, &params(&[("a", 2.0)]), 2, &dir).unwrap();
    let p4 = cached("cube.geo", geo, &params(&[("a", 1.0)]), 1, &dir).unwrap();
    assert!(p3 != p1 && p4 != p1 && p3 != p4);
    let big = read(&p3).unwrap();
    assert!((curved_volume(&big) - 8.0).abs() < 1e-10);

    // gmsh errors carry gmsh's message; nothing is left behind.
    let bad = "SetFactory(\"OpenCASCADE\");\nBox(1) = {0,0,0, 1,1,1;\n";
    let e = cached("bad.geo", bad, &[], 2, &dir).unwrap_err().to_string();
    assert!(e.contains("gmsh failed") && e.contains("syntax error"), "{e}");
    let e = generate(&dir.join("missing.geo"), &[], 2, &dir.join("x.msh")).unwrap_err().to_string();
    assert!(e.contains("does not exist"), "{e}");
    let geo_path = write(&dir, "ok.geo", geo);
    let e = generate_with("/nonexistent/gmsh".as_ref(), &geo_path, &[], 2, &dir.join("x.msh")).unwrap_err();
    assert!(e.to_string().contains("not found"), "{e}");
    let e = generate(&geo_path, &params(&[("a b", 1.0)]), 2, &dir.join("x.msh")).unwrap_err();
    assert!(e.to_string().contains("bad gmsh parameter"), "{e}");
    generate(&geo_path, &params(&[("a", 0.5)]), 1, &dir.join("direct.msh")).unwrap();
    assert!((curved_volume(&read(&dir.join("direct.msh")).unwrap()) - 0.125).abs() < 1e-12);
    let leftovers: Vec<String> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.contains("tmp") || (n.starts_with("bad") && n.ends_with(".msh")) || n == "x.msh")
        .collect();
    assert!(leftovers.is_empty(), "{leftovers:?}");
    let _ = std::fs::remove_dir_all(dir);
}

// ---------------------------------------------------------------- partition and distribution

#[test]
fn dual_graph_is_face_adjacency() {
    let mesh = gen("sphere_quarter.geo", SPHERE_QUARTER_GEO, &[], 2);
    let (xadj, adj) = dual_graph(&mesh).unwrap();
    assert_eq!(xadj.len(), mesh.cells.len() + 1);
    // Each interior face is one undirected edge: 4 nt = 2 edges + exterior faces.
    assert_eq!(4 * mesh.cells.len(), adj.len() + exterior_faces(&mesh).len());
    for t in 0..mesh.cells.len() {
        let row = &adj[xadj[t] as usize..xadj[t + 1] as usize];
        assert!(row.len() <= 4);
        for &u in row {
            let back = &adj[xadj[u as usize] as usize..xadj[u as usize + 1] as usize];
            assert!(back.contains(&(t as i32)));
            let a: BTreeSet<u32> = mesh.cells[t][..4].iter().copied().collect();
            assert_eq!(mesh.cells[u as usize][..4].iter().filter(|n| a.contains(n)).count(), 3);
        }
    }
}

#[test]
fn partition_parts_nonempty_and_deterministic() {
    let mesh = gen("sphere.geo", SPHERE_GEO, &[], 2);
    assert_eq!(partition(&mesh, 1).unwrap(), vec![0; mesh.cells.len()]);
    for np in [2usize, 3] {
        let p = partition(&mesh, np).unwrap();
        assert_eq!(p.len(), mesh.cells.len());
        let mut count = vec![0usize; np];
        for &q in &p {
            count[q as usize] += 1;
        }
        let ideal = mesh.cells.len() / np;
        for &c in &count {
            assert!(c > 0 && c < ideal * 13 / 10, "unbalanced {count:?}");
        }
        assert_eq!(partition(&mesh, np).unwrap(), p, "not deterministic");
    }
    assert!(partition(&mesh, 0).is_err());
    let dir = scratch_dir();
    let tiny = read(&write(&dir, "two.msh", TWO_TETS)).unwrap();
    assert!(partition(&tiny, 3).unwrap_err().to_string().contains("non-empty"));
    let _ = std::fs::remove_dir_all(dir);
}

fn check_distribution(mesh: &Mesh, part: &[u32], nranks: usize) -> Vec<LocalMesh> {
    let locals: Vec<LocalMesh> = (0..nranks).map(|r| distribute(mesh, part, nranks, r).unwrap()).collect();
    let nn = mesh.coords.len();
    let mut global_of = vec![u32::MAX; nn];
    let mut vglobal_of = vec![u32::MAX; nn];
    let mut owned_count = vec![0; nn];
    let mut owned_globals = BTreeSet::new();
    let mut n_elems = 0;
    for (r, l) in locals.iter().enumerate() {
        assert_eq!((l.rank, l.nranks, l.n_global_nodes, l.n_global_elems), (r, nranks, nn, mesh.cells.len()));
        assert_eq!(l.n_global_vertices, mesh.n_vertices());
        assert_eq!(l.node_ranges, locals[0].node_ranges);
        assert_eq!(l.vertex_ranges, locals[0].vertex_ranges);
        assert_eq!((l.node_offset, l.node_offset + l.n_owned_nodes), (l.node_ranges[r], l.node_ranges[r + 1]));
        assert_eq!(
            (l.vertex_offset, l.vertex_offset + l.n_owned_vertices),
            (l.vertex_ranges[r], l.vertex_ranges[r + 1])
        );
        assert_eq!(l.elem_offset, n_elems);
        n_elems += l.cells.len();
        for i in 0..l.coords.len() {
            let o = l.node_original[i] as usize;
            assert_eq!(l.coords[i], mesh.coords[o]);
            // Same original node -> same global id on every rank.
            assert!(global_of[o] == u32::MAX || global_of[o] == l.node_global[i]);
            global_of[o] = l.node_global[i];
            assert_eq!(l.owner_of_global_node(l.node_global[i] as usize), l.node_owner[i] as usize);
            if l.is_owned_node(i) {
                owned_count[o] += 1;
                assert_eq!(l.node_owner[i] as usize, r);
                assert_eq!(l.node_global[i] as usize, l.node_offset + i);
                owned_globals.insert(l.node_global[i]);
            } else {
                assert_ne!(l.node_owner[i] as usize, r);
            }
            let v = l.vertex_of_node[i];
            assert_eq!(v >= 0, mesh.is_vertex[o]);
            if v >= 0 {
                let v = v as usize;
                assert_eq!(l.vertex_node[v] as usize, i);
                assert_eq!(l.is_owned_vertex(v), l.is_owned_node(i));
                assert!(vglobal_of[o] == u32::MAX || vglobal_of[o] == l.vertex_global[v]);
                vglobal_of[o] = l.vertex_global[v];
                assert_eq!(l.owner_of_global_vertex(l.vertex_global[v] as usize), l.node_owner[i] as usize);
                if l.is_owned_vertex(v) {
                    assert_eq!(l.vertex_global[v] as usize, l.vertex_offset + v);
                }
            }
        }
        // Ghosts sorted by global id; owned nodes in original order.
        assert!(l.node_global[l.n_owned_nodes..].windows(2).all(|w| w[0] < w[1]));
        assert!(l.node_original[..l.n_owned_nodes].windows(2).all(|w| w[0] < w[1]));
        assert!(l.vertex_global[l.n_owned_vertices..].windows(2).all(|w| w[0] < w[1]));
        // Local tets reproduce the original ones.
        assert!(l.cell_original.windows(2).all(|w| w[0] < w[1]));
        for (lt, &t) in l.cell_original.iter().enumerate() {
            assert_eq!(part[t as usize] as usize, r);
            for k in 0..10 {
                assert_eq!(l.coords[l.cells[lt][k] as usize], mesh.coords[mesh.cells[t as usize][k] as usize]);
            }
        }
        // Faces: outward, same nodes as globally.
        for (lf, face) in l.faces.iter().enumerate() {
            let (lt, f) = l.face_cell[lf];
            assert_eq!(*face, TET_FACES[f as usize].map(|p| l.cells[lt as usize][p]));
        }
        assert_eq!(group_names(&l.face_groups), group_names(&mesh.face_groups));
        assert_eq!(group_names(&l.volume_groups), group_names(&mesh.volume_groups));
        assert_eq!(group_names(&l.point_groups), group_names(&mesh.point_groups));
    }
    assert_eq!(n_elems, mesh.cells.len());
    assert!(owned_count.iter().all(|&c| c == 1), "a node is not owned exactly once");
    assert_eq!(owned_globals.len(), nn);
    assert_eq!(*owned_globals.iter().next_back().unwrap() as usize, nn - 1);
    // Groups: local pieces add up to the global groups.
    for (gi, (name, g)) in mesh.face_groups.iter().enumerate() {
        let total: usize = locals.iter().map(|l| l.face_groups[gi].1.len()).sum();
        assert_eq!(total, g.len(), "face group {name}");
    }
    for (gi, (name, g)) in mesh.point_groups.iter().enumerate() {
        let mut seen = BTreeSet::new();
        for l in &locals {
            seen.extend(l.point_groups[gi].1.iter().map(|&i| l.node_original[i as usize]));
        }
        assert_eq!(seen, g.iter().copied().collect(), "point group {name}");
    }

    // Neighbour CSR = union over the whole mesh, by brute force.
    let mut nbr: Vec<BTreeSet<u32>> = vec![BTreeSet::new(); nn];
    for tet in &mesh.cells {
        for &a in tet {
            for &b in tet {
                nbr[a as usize].insert(global_of[b as usize]);
            }
        }
    }
    let mut orig_of_global = vec![0usize; nn];
    for (o, &g) in global_of.iter().enumerate() {
        orig_of_global[g as usize] = o;
    }
    for l in &locals {
        assert_eq!(l.node_nbr_offsets.len(), l.n_owned_nodes + 1);
        assert_eq!(l.node_nbr.len(), l.node_nbr_vertex_global.len());
        for i in 0..l.n_owned_nodes {
            let row = &l.node_nbr[l.node_nbr_offsets[i]..l.node_nbr_offsets[i + 1]];
            let expect: Vec<u32> = nbr[l.node_original[i] as usize].iter().copied().collect();
            assert_eq!(row, expect.as_slice());
            for k in l.node_nbr_offsets[i]..l.node_nbr_offsets[i + 1] {
                let o = orig_of_global[l.node_nbr[k] as usize];
                let vg = if mesh.is_vertex[o] { vglobal_of[o] as i32 } else { -1 };
                assert_eq!(l.node_nbr_vertex_global[k], vg);
            }
        }
    }
    locals
}

#[test]
fn distribute_two_and_three_ranks() {
    let mesh = gen("sphere_quarter.geo", SPHERE_QUARTER_GEO, &[], 2);
    for nranks in [1usize, 2, 3] {
        let part = partition(&mesh, nranks).unwrap();
        let locals = check_distribution(&mesh, &part, nranks);
        if nranks > 1 {
            // Rank 0 owns every node of its tets (smallest part wins); the others see ghosts.
            assert_eq!(locals[0].coords.len(), locals[0].n_owned_nodes);
            assert!(locals[1..].iter().any(|l| l.coords.len() > l.n_owned_nodes), "no ghosts");
        } else {
            assert_eq!(locals[0].n_owned_nodes, mesh.coords.len());
        }
    }
    // An arbitrary (non-METIS) partition, with rank 1 empty, also works.
    let part: Vec<u32> = (0..mesh.cells.len()).map(|t| if t % 3 == 0 { 0 } else { 2 }).collect();
    let locals = check_distribution(&mesh, &part, 3);
    assert_eq!((locals[1].cells.len(), locals[1].n_owned_nodes), (0, 0));
    assert!(distribute(&mesh, &part, 2, 0).is_err());
    assert!(distribute(&mesh, &part, 3, 3).is_err());
    assert!(distribute(&mesh, &part[1..], 3, 0).is_err());
}
