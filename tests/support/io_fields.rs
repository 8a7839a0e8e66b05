//! Test driver for `io::fields` under `mpirun`: writes a small two-cell mesh split across the ranks
//! over three steps (plus `expect.json` with the values the file must hold), or times a large write.
//!
//! Usage: `mpirun -n P io_fields DIR CASE [--abort-after K]`
//! * CASE `split`: two 10-node tetrahedra, nodes and cells spread evenly; `meridian`: the same with
//!   two 6-node triangles in the x–z plane (`Family::Tri6`, an axisymmetric meridian);
//!   `nocells-last`: the last rank owns nodes but no cells; `empty-last`: the last rank owns
//!   nothing; `bad-len` / `bad-names`: at step 1 the last rank passes a wrong data length / a
//!   different field name, every rank must get `Err` (exit 3); `bad-mesh`: the last rank's nodes
//!   overlap the previous rank's, `create` fails everywhere (exit 2).
//! * `--abort-after K`: `MPI_Abort` right after K steps, leaving the file open (a crashed run).
//! * `--pause-after K`: after K steps rank 0 creates `DIR/paused` and all ranks wait (at most 60 s)
//!   for `DIR/resume` to appear, so a test can read the files of a run that is still going.
//! * `mpirun -n P io_fields DIR bench N`: times steps of one node-vector field on N nodes.
//!
//! `expect.json` holds `"family"` (`"Tet10"` or `"Tri6"`), `"coordinates"`, `"topology_gmsh"` (rows
//! of 10 or 6 global node ids in GMSH order), `"time"` and `"steps"`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use mpi::collective::SystemOperation;
use mpi::traits::*;
use poroplast::io::fields::{Field, FieldFile, FieldKind, OutputMesh};
use poroplast::reference_cell::Family;

/// GMSH Tetrahedron10 edges, as local vertex pairs.
const GMSH_EDGES: [(usize, usize); 6] = [(0, 1), (1, 2), (0, 2), (0, 3), (2, 3), (1, 3)];
/// GMSH Triangle6 edges, as local vertex pairs (also the VTK quadratic-triangle order).
const GMSH_TRI6_EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

struct Mesh {
    coords: Vec<[f64; 3]>,
    /// GMSH order; a Tri6 cell uses the first 6 slots, the others are 0.
    cells: Vec<[u32; 10]>,
    family: Family,
}

/// A quadratic mesh of straight-sided cells on `verts`: each cell lists its vertices, its mid-edge
/// nodes on `edges` follow (GMSH order; shared edges share their node). The numbering is shuffled
/// so that vertices are not simply first.
fn quadratic(verts: &[[f64; 3]], cell_verts: &[&[usize]], edges: &[(usize, usize)], family: Family) -> Mesh {
    let (nv, npe) = (family.cell_vertices(), family.cell_nodes());
    assert_eq!(nv + edges.len(), npe);
    let mut coords: Vec<[f64; 3]> = verts.to_vec();
    let mut edge_ids: Vec<((usize, usize), usize)> = Vec::new();
    let mut cells = Vec::new();
    for &t in cell_verts {
        let mut c = [0usize; 10];
        c[..nv].copy_from_slice(t);
        for (e, &(a, b)) in edges.iter().enumerate() {
            let key = (t[a].min(t[b]), t[a].max(t[b]));
            let id = match edge_ids.iter().find(|(k, _)| *k == key) {
                Some(&(_, id)) => id,
                None => {
                    let (p, q) = (verts[key.0], verts[key.1]);
                    coords.push([0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]), 0.5 * (p[2] + q[2])]);
                    edge_ids.push((key, coords.len() - 1));
                    coords.len() - 1
                }
            };
            c[nv + e] = id;
        }
        cells.push(c);
    }
    let n = coords.len();
    let perm = |i: usize| (i * 5 + 3) % n;
    assert_ne!(n % 5, 0, "the shuffle needs gcd(5, n) = 1");
    let mut shuffled = vec![[0.0; 3]; n];
    for (i, x) in coords.iter().enumerate() {
        shuffled[perm(i)] = *x;
    }
    let cells = cells.iter().map(|c| std::array::from_fn(|k| if k < npe { perm(c[k]) as u32 } else { 0 })).collect();
    Mesh { coords: shuffled, cells, family }
}

/// Two positively oriented quadratic tets sharing a face; 14 nodes, numbered in a shuffled order.
fn two_tets() -> Mesh {
    let verts = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]];
    quadratic(&verts, &[&[0, 1, 2, 3], &[1, 4, 2, 3]], &GMSH_EDGES, Family::Tet10)
}

/// Two 6-node triangles of a meridian (x = r ≥ 0, y = 0, z) sharing the edge between vertices 1
/// and 2, both counter-clockwise in (x, z); 9 nodes, numbered in a shuffled order.
fn two_triangles() -> Mesh {
    let verts = [[0.25, 0.0, 0.0], [1.0, 0.0, 0.0], [0.25, 0.0, 1.0], [1.0, 0.0, 1.5]];
    let tris: [&[usize]; 2] = [&[0, 1, 2], &[1, 3, 2]];
    for t in tris {
        let (a, b, c) = (verts[t[0]], verts[t[1]], verts[t[2]]);
        let det = (b[0] - a[0]) * (c[2] - a[2]) - (b[2] - a[2]) * (c[0] - a[0]);
        assert!(det > 0.0, "triangle {t:?} is not counter-clockwise in (x, z)");
    }
    quadratic(&verts, &tris, &GMSH_TRI6_EDGES, Family::Tri6)
}

/// `[lo, hi)` of part `i` of `n` items split into `parts`.
fn chunk(n: usize, parts: usize, i: usize) -> (usize, usize) {
    if i >= parts {
        return (n, n);
    }
    (i * n / parts, (i + 1) * n / parts)
}

fn times() -> [f64; 3] {
    [0.0, 0.1, 0.30000000000000004]
}

/// The fields of step k, as global arrays: (name, kind, values).
fn global_fields(m: &Mesh, k: usize) -> Vec<(&'static str, FieldKind, Vec<f64>)> {
    let kf = k as f64;
    let n = m.coords.len();
    let nc = m.cells.len();
    let mut v = vec![
        ("p", FieldKind::NodeScalar, (0..n).map(|i| 100.0 * kf + i as f64 + 0.25).collect()),
        (
            "u",
            FieldKind::NodeVector,
            m.coords.iter().flat_map(|x| [x[0] * (kf + 1.0), x[1] * (kf + 1.0) + 0.5, x[2] - kf]).collect(),
        ),
        ("damage", FieldKind::CellScalar, (0..nc).map(|c| 10.0 * kf + c as f64 + 0.5).collect()),
        ("flux", FieldKind::CellVector, (0..nc).flat_map(|c| [c as f64, kf, c as f64 * kf + 0.125]).collect()),
    ];
    if k >= 1 {
        v.push(("late", FieldKind::NodeScalar, (0..n).map(|i| -(i as f64) - kf / 3.0).collect()));
    }
    v
}

fn json_list(v: impl IntoIterator<Item = String>) -> String {
    format!("[{}]", v.into_iter().collect::<Vec<_>>().join(","))
}

fn f(x: f64) -> String {
    format!("{x:?}")
}

fn write_expect(dir: &Path, m: &Mesh, steps: usize) {
    let mut s = String::from("{\n");
    let _ = writeln!(s, "\"family\": \"{:?}\",", m.family);
    let _ = writeln!(s, "\"coordinates\": {},", json_list(m.coords.iter().map(|x| json_list(x.iter().map(|&v| f(v))))));
    let _ = writeln!(
        s,
        "\"topology_gmsh\": {},",
        json_list(m.cells.iter().map(|c| json_list(c[..m.family.cell_nodes()].iter().map(|v| v.to_string()))))
    );
    let _ = writeln!(s, "\"time\": {},", json_list(times()[..steps].iter().map(|&t| f(t))));
    let mut steps_json = Vec::new();
    for k in 0..steps {
        let fields = global_fields(m, k).into_iter().map(|(name, kind, vals)| {
            let shaped = match kind {
                FieldKind::NodeScalar | FieldKind::CellScalar => json_list(vals.iter().map(|&v| f(v))),
                _ => json_list(vals.chunks(3).map(|r| json_list(r.iter().map(|&v| f(v))))),
            };
            format!("\"{name}\": {{\"kind\": \"{kind:?}\", \"values\": {shaped}}}")
        });
        steps_json.push(format!("{{{}}}", fields.collect::<Vec<_>>().join(", ")));
    }
    let _ = writeln!(s, "\"steps\": [\n{}\n]\n}}", steps_json.join(",\n"));
    std::fs::write(dir.join("expect.json"), s).expect("write expect.json");
}

fn run(
    world: &mpi::topology::SimpleCommunicator,
    dir: &Path,
    case: &str,
    abort_after: Option<usize>,
    pause_after: Option<usize>,
) -> i32 {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let m = if case == "meridian" { two_triangles() } else { two_tets() };
    let (n, nc) = (m.coords.len(), m.cells.len());
    let (node_parts, cell_parts) = match case {
        "nocells-last" if size > 1 => (size, size - 1),
        "empty-last" if size > 1 => (size - 1, size - 1),
        _ => (size, size),
    };
    let (mut n0, n1) = chunk(n, node_parts, rank);
    if case == "bad-mesh" && rank == size - 1 && n0 > 0 {
        n0 -= 1; // overlaps the previous rank's nodes
    }
    let (c0, c1) = chunk(nc, cell_parts, rank);
    let mesh = OutputMesh {
        n_global_nodes: n,
        node_offset: n0,
        coords: &m.coords[n0..n1],
        n_global_cells: nc,
        cell_offset: c0,
        cells: &m.cells[c0..c1],
        family: m.family,
    };
    println!("rank {rank}: nodes [{n0},{n1}) cells [{c0},{c1})");
    let mut ff = match FieldFile::create(dir, world, &mesh) {
        Ok(ff) => ff,
        Err(e) => {
            println!("ERROR rank {rank}: {e}");
            return 2;
        }
    };
    if rank == 0 {
        write_expect(dir, &m, 0);
    }
    let last = rank == size - 1;
    for (k, &t) in times().iter().enumerate() {
        if abort_after == Some(k) {
            world.barrier();
            if rank == 0 {
                println!("aborting after {k} steps");
                world.abort(17);
            }
            world.barrier();
        }
        if pause_after == Some(k) {
            if rank == 0 {
                std::fs::write(dir.join("paused"), "").expect("write paused");
                let t0 = Instant::now();
                while !dir.join("resume").exists() && t0.elapsed().as_secs() < 60 {
                    std::thread::sleep(std::time::Duration::from_millis(10));
                }
            }
            world.barrier();
        }
        let gf = global_fields(&m, k);
        let mut local: Vec<(String, FieldKind, Vec<f64>)> = gf
            .iter()
            .map(|(name, kind, vals)| {
                let (lo, hi, c) = match kind {
                    FieldKind::NodeScalar => (n0, n1, 1),
                    FieldKind::NodeVector => (n0, n1, 3),
                    FieldKind::CellScalar => (c0, c1, 1),
                    FieldKind::CellVector => (c0, c1, 3),
                };
                (name.to_string(), *kind, vals[lo * c..hi * c].to_vec())
            })
            .collect();
        if k == 1 && last && case == "bad-len" {
            local[0].2.push(1.0);
        }
        if k == 1 && last && case == "bad-names" {
            local[0].0 = "q".into();
        }
        let fields: Vec<Field> =
            local.iter().map(|(name, kind, data)| Field { name: name.as_str(), kind: *kind, data }).collect();
        if let Err(e) = ff.write_step(t, &fields) {
            println!("EXPECTED_ERROR rank {rank}: {e}");
            return 3;
        }
        if rank == 0 {
            write_expect(dir, &m, k + 1);
        }
    }
    match ff.close() {
        Ok(()) => 0,
        Err(e) => {
            println!("ERROR rank {rank}: close: {e}");
            2
        }
    }
}

fn bench(world: &mpi::topology::SimpleCommunicator, dir: &Path, n: usize) -> i32 {
    let (rank, size) = (world.rank() as usize, world.size() as usize);
    let nc = n / 10;
    let (n0, n1) = chunk(n, size, rank);
    let (c0, c1) = chunk(nc, size, rank);
    let coords: Vec<[f64; 3]> = (n0..n1).map(|i| [i as f64, 0.5 * i as f64, 1.0]).collect();
    let cells: Vec<[u32; 10]> = (c0..c1).map(|c| std::array::from_fn(|k| (10 * c + k) as u32)).collect();
    let mesh = OutputMesh {
        n_global_nodes: n,
        node_offset: n0,
        coords: &coords,
        n_global_cells: nc,
        cell_offset: c0,
        cells: &cells,
        family: Family::Tet10,
    };
    world.barrier();
    let t0 = Instant::now();
    let mut ff = FieldFile::create(dir, world, &mesh).expect("create");
    let t_create = t0.elapsed().as_secs_f64();
    let u: Vec<f64> = (n0 * 3..n1 * 3).map(|i| i as f64 * 1e-3).collect();
    let mut worst = Vec::new();
    for k in 0..5 {
        world.barrier();
        let t0 = Instant::now();
        ff.write_step(k as f64, &[Field { name: "u", kind: FieldKind::NodeVector, data: &u }]).expect("write_step");
        let mine = t0.elapsed().as_secs_f64();
        let mut max = 0.0;
        world.all_reduce_into(&mine, &mut max, SystemOperation::max());
        worst.push(max);
    }
    drop(ff);
    if rank == 0 {
        let ms: Vec<String> = worst.iter().map(|s| format!("{:.1}", s * 1e3)).collect();
        println!(
            "BENCH {n} nodes, {size} ranks: create+mesh {:.1} ms; write_step (1 node vector) ms: {}",
            t_create * 1e3,
            ms.join(" ")
        );
    }
    0
}

fn main() {
    let args: Vec<String> = std::env::args().collect();
    if args.len() < 3 {
        eprintln!("usage: io_fields DIR CASE [--abort-after K] | io_fields DIR bench N");
        std::process::exit(1);
    }
    let dir = PathBuf::from(&args[1]);
    let case = args[2].as_str();
    let flag = |name: &str| args.iter().position(|a| a == name).map(|i| args[i + 1].parse::<usize>().expect("K"));
    let (abort_after, pause_after) = (flag("--abort-after"), flag("--pause-after"));
    let universe = mpi::initialize().expect("MPI init");
    let world = universe.world();
    if world.rank() == 0 {
        std::fs::create_dir_all(&dir).expect("create dir");
    }
    world.barrier();
    let code = if case == "bench" {
        bench(&world, &dir, args[3].parse().expect("N"))
    } else {
        run(&world, &dir, case, abort_after, pause_after)
    };
    drop(world);
    drop(universe);
    std::process::exit(code);
}
