//! Reader for Gmsh MSH 4.1 ASCII files: nodes, tetrahedra (linear or quadratic), tagged triangles and points,
//! physical groups; linear meshes are promoted to quadratic with straight mid-edge nodes.
//!
//! Node numbering: only nodes used by tetrahedra are kept, numbered in file order (0-based); nodes added by
//! promotion follow. Triangles and points count only through physical groups (untagged ones are ignored).
//! A tagged triangle on an interior surface is attached to the lower-numbered of its two tets, and its
//! orientation is outward from that tet. Non-manifold meshes (a triangle shared by 3 tets) are not detected
//! here but by the partitioner (`partition::dual_graph`).

use std::collections::{BTreeMap, HashMap};
use std::path::Path;
use std::str::{FromStr, SplitAsciiWhitespace};

use super::{face_key, Mesh};
use crate::error::{Error, Result};
use crate::reference_cell::shape::fold_point;
use crate::reference_cell::{sub, tet_det, Family, TET10_FLIP, TET_FACES};

/// Read a Gmsh MSH 4.1 ASCII file into a [`Mesh`].
pub fn read(path: &Path) -> Result<Mesh> {
    let bytes = std::fs::read(path).map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            Error::mesh(path, "file does not exist")
        } else {
            Error::mesh(path, format!("cannot read file: {e}"))
        }
    })?;
    check_not_binary(path, &bytes)?;
    let text = std::str::from_utf8(&bytes).map_err(|e| {
        let line = 1 + bytes[..e.valid_up_to()].iter().filter(|&&b| b == b'\n').count();
        Error::mesh(path, format!("line {line}: invalid UTF-8 (not an ASCII MSH file?)"))
    })?;
    parse(path, text)
}

/// Binary MSH files are not valid UTF-8, so look at the header before decoding to give a precise message.
fn check_not_binary(path: &Path, bytes: &[u8]) -> Result<()> {
    let mut lines = bytes.split(|&b| b == b'\n').map(|l| l.trim_ascii()).filter(|l| !l.is_empty());
    if lines.next() == Some(b"$MeshFormat".as_slice()) {
        if let Some(fmt) = lines.next() {
            let fmt = String::from_utf8_lossy(fmt);
            if fmt.split_ascii_whitespace().nth(1) == Some("1") {
                return Err(Error::mesh(path, "binary MSH not supported, re-export as ASCII with -format msh41"));
            }
        }
    }
    Ok(())
}

/// Line cursor with 1-based line numbers for error messages.
struct Lines<'a> {
    it: std::str::Split<'a, char>,
    no: usize,
    path: &'a Path,
}

impl<'a> Lines<'a> {
    fn new(path: &'a Path, text: &'a str) -> Self {
        // A final newline ends the last line rather than starting an empty one.
        let text = text.strip_suffix('\n').unwrap_or(text);
        Lines { it: text.split('\n'), no: 0, path }
    }

    /// Next line, trimmed, or `None` at end of file.
    fn next_opt(&mut self) -> Option<&'a str> {
        let l = self.it.next()?;
        self.no += 1;
        Some(l.trim())
    }

    /// Next line; end of file is an error mentioning what was expected.
    fn next(&mut self, what: &str) -> Result<&'a str> {
        self.next_opt()
            .ok_or_else(|| self.err(format!("unexpected end of file while reading {what} (truncated file?)")))
    }

    fn err(&self, msg: impl std::fmt::Display) -> Error {
        Error::mesh(self.path, format!("line {}: {msg}", self.no))
    }

    /// Parse exactly `N` integers from the next line.
    fn ints<T: FromStr + Copy + Default, const N: usize>(&mut self, what: &str) -> Result<[T; N]> {
        let line = self.next(what)?;
        let mut out = [T::default(); N];
        let mut toks = line.split_ascii_whitespace();
        let mut n = 0;
        for tok in toks.by_ref() {
            if n == N {
                n += 1;
                break;
            }
            out[n] = tok.parse().map_err(|_| self.expected(N, "integers", what, line))?;
            n += 1;
        }
        if n != N {
            return Err(self.expected(N, "integers", what, line));
        }
        Ok(out)
    }

    fn expected(&self, n: usize, kind: &str, what: &str, line: &str) -> Error {
        self.err(format!("expected {n} {kind} ({what}), got \"{}\"", shorten(line)))
    }

    /// Consume the `$End...` line closing a section.
    fn end(&mut self, tag: &str) -> Result<()> {
        let l = self.next(tag)?;
        if l != tag {
            return Err(
                self.err(format!("expected {tag}, got \"{}\" (count in the section header too small?)", shorten(l)))
            );
        }
        Ok(())
    }
}

/// Tokens of one line, parsed on demand with errors pointing at the line.
struct Toks<'a> {
    it: SplitAsciiWhitespace<'a>,
    line: &'a str,
}

impl<'a> Toks<'a> {
    fn new(line: &'a str) -> Self {
        Toks { it: line.split_ascii_whitespace(), line }
    }

    fn get<T: FromStr>(&mut self, lines: &Lines, what: &str) -> Result<T> {
        let tok = self.it.next();
        tok.and_then(|t| t.parse().ok()).ok_or_else(|| {
            lines.err(format!(
                "expected {what}, got {} in \"{}\"",
                tok.map_or("end of line".to_string(), |t| format!("\"{}\"", shorten(t))),
                shorten(self.line)
            ))
        })
    }

    /// Fails if anything is left on the line.
    fn finish(&mut self, lines: &Lines, what: &str) -> Result<()> {
        match self.it.next() {
            None => Ok(()),
            Some(t) => {
                Err(lines.err(format!("unexpected \"{}\" after {what} in \"{}\"", shorten(t), shorten(self.line))))
            }
        }
    }
}

fn shorten(s: &str) -> String {
    const MAX: usize = 80;
    if s.len() <= MAX {
        s.to_string()
    } else {
        let mut end = MAX;
        while !s.is_char_boundary(end) {
            end -= 1;
        }
        format!("{}...", &s[..end])
    }
}

/// Gmsh node tag -> index in file order. Dense when tags are reasonably compact, hashed otherwise.
enum TagMap {
    Dense(Vec<u32>),
    Sparse(HashMap<u64, u32>),
}

impl TagMap {
    fn build(tags: &[u64]) -> std::result::Result<TagMap, u64> {
        let max = tags.iter().copied().max().unwrap_or(0);
        if max <= 4 * tags.len() as u64 + 1024 {
            let mut m = vec![u32::MAX; max as usize + 1];
            for (i, &t) in tags.iter().enumerate() {
                if m[t as usize] != u32::MAX {
                    return Err(t);
                }
                m[t as usize] = i as u32;
            }
            Ok(TagMap::Dense(m))
        } else {
            let mut m = HashMap::with_capacity(tags.len());
            for (i, &t) in tags.iter().enumerate() {
                if m.insert(t, i as u32).is_some() {
                    return Err(t);
                }
            }
            Ok(TagMap::Sparse(m))
        }
    }

    fn get(&self, tag: u64) -> Option<u32> {
        match self {
            TagMap::Dense(m) => m.get(usize::try_from(tag).ok()?).copied().filter(|&i| i != u32::MAX),
            TagMap::Sparse(m) => m.get(&tag).copied(),
        }
    }
}

/// Everything read from the file, before compaction and promotion. Node references are file-order indices.
#[derive(Default)]
pub(super) struct Raw {
    pub(super) phys_names: HashMap<(usize, i32), String>,
    /// Per entity dimension: entity tag -> physical tags.
    pub(super) entity_phys: [HashMap<i32, Vec<i32>>; 4],
    pub(super) node_tags: Vec<u64>,
    pub(super) coords: Vec<[f64; 3]>,
    tag_map: Option<TagMap>,
    /// Tets: 4 or 10 nodes (unused slots u32::MAX), their element tags and entity tags.
    pub(super) cells: Vec<[u32; 10]>,
    pub(super) tet_tags: Vec<u64>,
    pub(super) tet_entity: Vec<i32>,
    pub(super) n_tet4: usize,
    pub(super) n_tet10: usize,
    pub(super) tris: Vec<[u32; 6]>,
    pub(super) tri_tags: Vec<u64>,
    pub(super) tri_entity: Vec<i32>,
    pub(super) n_tri3: usize,
    pub(super) n_tri6: usize,
    /// Lines: 2 or 3 nodes (unused slot u32::MAX), their element tags and entity tags (the
    /// boundary faces of a meridian mesh).
    pub(super) lines: Vec<[u32; 3]>,
    pub(super) line_tags: Vec<u64>,
    pub(super) line_entity: Vec<i32>,
    pub(super) n_line3: usize,
    /// Point elements: (node, entity tag, element tag).
    pub(super) points: Vec<(u32, i32, u64)>,
    pub(super) has_elements: bool,
}

/// Supported element types: gmsh type -> (dimension, nodes per element).
fn supported(ty: i32) -> Option<(usize, usize)> {
    match ty {
        15 => Some((0, 1)),
        1 => Some((1, 2)),
        8 => Some((1, 3)),
        2 => Some((2, 3)),
        9 => Some((2, 6)),
        4 => Some((3, 4)),
        11 => Some((3, 10)),
        _ => None,
    }
}

/// Names of the gmsh element types we reject, for the error message.
fn type_name(ty: i32) -> &'static str {
    match ty {
        3 => "4-node quadrangle",
        5 => "8-node hexahedron",
        6 => "6-node prism",
        7 => "5-node pyramid",
        10 => "9-node quadrangle",
        12 => "27-node hexahedron",
        13 => "18-node prism",
        14 => "14-node pyramid",
        16 => "8-node quadrangle",
        17 => "20-node hexahedron",
        18 => "15-node prism",
        19 => "13-node pyramid",
        20 => "9-node triangle",
        21 => "10-node triangle",
        26 => "4-node line",
        27 => "5-node line",
        28 => "6-node line",
        29 => "20-node tetrahedron",
        30 => "35-node tetrahedron",
        92 => "64-node hexahedron",
        93 => "125-node hexahedron",
        _ => "unknown type",
    }
}

fn is_3d_type(ty: i32) -> bool {
    matches!(ty, 4 | 5 | 6 | 7 | 11 | 12 | 13 | 14 | 17 | 18 | 19 | 29 | 30 | 31 | 92 | 93)
}

/// Parse the text of an MSH file (`path` only labels errors).
pub(crate) fn parse(path: &Path, text: &str) -> Result<Mesh> {
    let mut lines = Lines::new(path, text);
    let mut raw = Raw::default();
    let mut seen_format = false;
    let mut seen_nodes = false;
    while let Some(l) = lines.next_opt() {
        if l.is_empty() {
            continue;
        }
        if !seen_format && l != "$MeshFormat" {
            return Err(lines.err(format!("not a Gmsh MSH file: expected $MeshFormat, got \"{}\"", shorten(l))));
        }
        match l {
            "$MeshFormat" => {
                read_format(&mut lines)?;
                seen_format = true;
            }
            "$PhysicalNames" => read_physical_names(&mut lines, &mut raw)?,
            "$Entities" => read_entities(&mut lines, &mut raw)?,
            "$Nodes" => {
                if seen_nodes {
                    return Err(lines.err("second $Nodes section"));
                }
                read_nodes(&mut lines, &mut raw, text.len())?;
                seen_nodes = true;
            }
            "$Elements" => {
                if !seen_nodes {
                    return Err(lines.err("$Elements before $Nodes (or no $Nodes section)"));
                }
                if raw.has_elements {
                    return Err(lines.err("second $Elements section"));
                }
                read_elements(&mut lines, &mut raw, text.len())?;
                raw.has_elements = true;
            }
            s if s.starts_with("$End") => return Err(lines.err(format!("{s} without matching section start"))),
            s if s.starts_with('$') => skip_section(&mut lines, s)?,
            s => return Err(lines.err(format!("unexpected text outside any section: \"{}\"", shorten(s)))),
        }
    }
    if !seen_format {
        return Err(Error::mesh(path, "empty file (no $MeshFormat)"));
    }
    if !seen_nodes {
        return Err(Error::mesh(path, "no $Nodes section"));
    }
    if !raw.has_elements {
        return Err(Error::mesh(path, "no $Elements section"));
    }
    build(path, raw)
}

fn read_format(lines: &mut Lines) -> Result<()> {
    let l = lines.next("$MeshFormat")?;
    let mut t = Toks::new(l);
    let version: String = t.get(lines, "the format version")?;
    if version.starts_with('2') || version.starts_with("3") {
        return Err(lines.err(format!("MSH {version} not supported, re-export with -format msh41")));
    }
    if version != "4.1" {
        return Err(lines.err(format!("MSH {version} not supported (only 4.1), re-export with -format msh41")));
    }
    let file_type: i32 = t.get(lines, "the file type (0 = ASCII)")?;
    if file_type != 0 {
        return Err(lines.err("binary MSH not supported, re-export as ASCII with -format msh41"));
    }
    lines.end("$EndMeshFormat")
}

fn read_physical_names(lines: &mut Lines, raw: &mut Raw) -> Result<()> {
    let [n]: [usize; 1] = lines.ints("number of physical names")?;
    for _ in 0..n {
        let l = lines.next("$PhysicalNames")?;
        let mut t = Toks::new(l);
        let dim: usize = t.get(lines, "a physical dimension")?;
        let tag: i32 = t.get(lines, "a physical tag")?;
        let rest = t.it.collect::<Vec<_>>().join(" ");
        let name = rest.trim().trim_matches('"').to_string();
        if dim > 3 || name.is_empty() {
            return Err(lines.err(format!("bad physical name line \"{}\"", shorten(l))));
        }
        raw.phys_names.insert((dim, tag), name);
    }
    lines.end("$EndPhysicalNames")
}

fn read_entities(lines: &mut Lines, raw: &mut Raw) -> Result<()> {
    let counts: [usize; 4] = lines.ints("numPoints numCurves numSurfaces numVolumes")?;
    for (dim, &count) in counts.iter().enumerate() {
        for _ in 0..count {
            let l = lines.next("$Entities")?;
            let mut t = Toks::new(l);
            let tag: i32 = t.get(lines, "an entity tag")?;
            // A point has x y z, higher entities a bounding box.
            for _ in 0..if dim == 0 { 3 } else { 6 } {
                t.get::<f64>(lines, "a coordinate")?;
            }
            let nphys: usize = t.get(lines, "the number of physical tags")?;
            let mut phys = Vec::with_capacity(nphys.min(16));
            for _ in 0..nphys {
                phys.push(t.get::<i32>(lines, "a physical tag")?);
            }
            if !phys.is_empty() {
                raw.entity_phys[dim].insert(tag, phys);
            }
        }
    }
    lines.end("$EndEntities")
}

fn read_nodes(lines: &mut Lines, raw: &mut Raw, text_len: usize) -> Result<()> {
    let [nblocks, nnodes, _min, _max]: [u64; 4] = lines.ints("numEntityBlocks numNodes minNodeTag maxNodeTag")?;
    // Never trust a count for preallocation beyond what the file could hold.
    let cap = (nnodes as usize).min(text_len / 8);
    raw.node_tags.reserve(cap);
    raw.coords.reserve(cap);
    for _ in 0..nblocks {
        let [_dim, _entity, _parametric, n]: [u64; 4] = lines.ints("entityDim entityTag parametric numNodesInBlock")?;
        let start = raw.node_tags.len();
        for _ in 0..n {
            let l = lines.next("node tags")?;
            let mut t = Toks::new(l);
            raw.node_tags.push(t.get(lines, "a node tag")?);
            t.finish(lines, "the node tag")?;
        }
        for _ in 0..n {
            let l = lines.next("node coordinates")?;
            let mut t = Toks::new(l);
            let mut x = [0.0f64; 3];
            for c in &mut x {
                *c = t.get(lines, "3 node coordinates")?;
                if !c.is_finite() {
                    return Err(lines.err(format!("non-finite coordinate in \"{}\"", shorten(l))));
                }
            }
            // Parametric coordinates may follow; they are not needed.
            raw.coords.push(x);
        }
        debug_assert_eq!(raw.coords.len() - start, n as usize);
    }
    if raw.node_tags.len() as u64 != nnodes {
        return Err(lines.err(format!("$Nodes header announces {nnodes} nodes, blocks hold {}", raw.node_tags.len())));
    }
    if raw.node_tags.len() >= u32::MAX as usize {
        return Err(lines.err("too many nodes"));
    }
    lines.end("$EndNodes")?;
    let map = TagMap::build(&raw.node_tags).map_err(|t| lines.err(format!("node tag {t} defined twice in $Nodes")))?;
    raw.tag_map = Some(map);
    Ok(())
}

fn read_elements(lines: &mut Lines, raw: &mut Raw, text_len: usize) -> Result<()> {
    let [nblocks, _nelems, _min, _max]: [u64; 4] =
        lines.ints("numEntityBlocks numElements minElementTag maxElementTag")?;
    let map = match raw.tag_map.take() {
        Some(m) => m,
        None => return Err(lines.err("$Elements before $Nodes")),
    };
    let mut nodes = [0u32; 10];
    for _ in 0..nblocks {
        let [dim, entity, ty, n]: [i64; 4] = lines.ints("entityDim entityTag elementType numElementsInBlock")?;
        let (tdim, nn) = match supported(ty as i32) {
            Some(s) => s,
            None if is_3d_type(ty as i32) => {
                return Err(lines.err(format!(
                    "3-D element type {ty} ({}) not supported: only tetrahedra (types 4, 11)",
                    type_name(ty as i32)
                )))
            }
            None => {
                return Err(lines.err(format!(
                    "element type {ty} ({}) not supported: only points, lines, triangles (2, 9) and tetrahedra (4, 11)",
                    type_name(ty as i32)
                )))
            }
        };
        if dim != tdim as i64 {
            return Err(lines.err(format!("element type {ty} in a block of dimension {dim}")));
        }
        if n < 0 || n as u64 > text_len as u64 {
            return Err(lines.err(format!("bad element count {n}")));
        }
        let entity = entity as i32;
        for _ in 0..n {
            let l = lines.next("elements")?;
            let mut t = Toks::new(l);
            let etag: u64 = t.get(lines, "an element tag")?;
            for slot in nodes.iter_mut().take(nn) {
                let tag: u64 = t.get(lines, "a node tag")?;
                *slot = map.get(tag).ok_or_else(|| {
                    lines.err(format!("node tag {tag} used by element {etag} is not defined in $Nodes"))
                })?;
            }
            t.finish(lines, "the element's node tags")?;
            match tdim {
                0 => raw.points.push((nodes[0], entity, etag)),
                1 => {
                    let mut line = [u32::MAX; 3];
                    line[..nn].copy_from_slice(&nodes[..nn]);
                    raw.lines.push(line);
                    raw.line_tags.push(etag);
                    raw.line_entity.push(entity);
                    raw.n_line3 += usize::from(nn == 3);
                }
                2 => {
                    let mut tri = [u32::MAX; 6];
                    tri[..nn].copy_from_slice(&nodes[..nn]);
                    raw.tris.push(tri);
                    raw.tri_tags.push(etag);
                    raw.tri_entity.push(entity);
                    if nn == 3 {
                        raw.n_tri3 += 1
                    } else {
                        raw.n_tri6 += 1
                    }
                }
                _ => {
                    let mut tet = [u32::MAX; 10];
                    tet[..nn].copy_from_slice(&nodes[..nn]);
                    raw.cells.push(tet);
                    raw.tet_tags.push(etag);
                    raw.tet_entity.push(entity);
                    if nn == 4 {
                        raw.n_tet4 += 1
                    } else {
                        raw.n_tet10 += 1
                    }
                }
            }
        }
    }
    lines.end("$EndElements")?;
    raw.tag_map = Some(map);
    Ok(())
}

fn skip_section(lines: &mut Lines, start: &str) -> Result<()> {
    let end = format!("$End{}", &start[1..]);
    let first = lines.no;
    loop {
        match lines.next_opt() {
            Some(l) if l == end => return Ok(()),
            Some(_) => {}
            None => {
                return Err(Error::mesh(
                    lines.path,
                    format!("line {first}: section {start} is never closed by {end} (truncated file?)"),
                ))
            }
        }
    }
}

/// Compact, promote, orient, match faces and resolve groups.
fn build(path: &Path, mut raw: Raw) -> Result<Mesh> {
    let err = |msg: String| Error::mesh(path, msg);
    if raw.cells.is_empty() {
        if !raw.tris.is_empty() {
            return super::meridian::build(path, raw);
        }
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

/// The nodes used by the first `n` slots of `cells`, in file order: (file node -> compact id,
/// u32::MAX if unused; the compact nodes' coordinates).
pub(super) fn used_nodes<const N: usize>(
    coords: &[[f64; 3]],
    cells: &[[u32; N]],
    n: usize,
) -> (Vec<u32>, Vec<[f64; 3]>) {
    let mut new_id = vec![u32::MAX; coords.len()];
    for cell in cells {
        for &k in &cell[..n] {
            new_id[k as usize] = 0;
        }
    }
    let mut used = Vec::with_capacity(coords.len());
    for (i, id) in new_id.iter_mut().enumerate() {
        if *id == 0 {
            *id = used.len() as u32;
            used.push(coords[i]);
        }
    }
    (new_id, used)
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

/// A mesh's compacted nodes, oriented cells, attached faces and face groups, before the rest.
pub(super) struct Parts {
    pub(super) coords: Vec<[f64; 3]>,
    pub(super) cells: Vec<[u32; 10]>,
    pub(super) faces: Vec<[u32; 6]>,
    pub(super) face_cell: Vec<(u32, u8)>,
    /// Physical tag -> face indices.
    pub(super) face_groups: BTreeMap<i32, Vec<u32>>,
    /// File-order node -> compact node id (u32::MAX: not a node of any cell).
    pub(super) new_id: Vec<u32>,
}

/// The mesh from its parts: cell groups (from the cells' entities `cell_entity`), point groups,
/// named face groups and the vertex flags, for a mesh of `family`.
pub(super) fn finish(path: &Path, raw: &Raw, family: Family, cell_entity: &[i32], p: Parts) -> Result<Mesh> {
    let dim = match family {
        Family::Tet10 => 3,
        Family::Tri6 => 2,
    };
    let mut volume_groups: BTreeMap<i32, Vec<u32>> = BTreeMap::new();
    for (t, e) in cell_entity.iter().enumerate() {
        for &g in raw.entity_phys[dim].get(e).map_or(&[][..], |v| v) {
            volume_groups.entry(g).or_default().push(t as u32);
        }
    }
    let mut point_groups: BTreeMap<i32, Vec<u32>> = BTreeMap::new();
    for &(n, e, etag) in &raw.points {
        let Some(phys) = raw.entity_phys[0].get(&e) else { continue };
        let id = p.new_id[n as usize];
        if id == u32::MAX {
            return Err(Error::mesh(
                path,
                format!(
                    "physical point element {etag} (node tag {}) is not a node of any {}",
                    raw.node_tags[n as usize],
                    family.cell_name()
                ),
            ));
        }
        for &g in phys {
            point_groups.entry(g).or_default().push(id);
        }
    }
    let mut is_vertex = vec![false; p.coords.len()];
    for cell in &p.cells {
        for &n in &cell[..family.cell_vertices()] {
            is_vertex[n as usize] = true;
        }
    }
    Ok(Mesh {
        family,
        coords: p.coords,
        cells: p.cells,
        faces: p.faces,
        face_cell: p.face_cell,
        volume_groups: named_groups(&raw.phys_names, dim, volume_groups),
        face_groups: named_groups(&raw.phys_names, dim - 1, p.face_groups),
        point_groups: named_groups(&raw.phys_names, 0, point_groups),
        is_vertex,
    })
}

/// "boundary triangle <element tag> (node tags ...)" for error messages.
fn describe_tri(raw: &Raw, i: usize, nt: usize) -> String {
    let tags: Vec<String> = raw.tris[i][..nt].iter().map(|&n| raw.node_tags[n as usize].to_string()).collect();
    format!("boundary triangle {} (element tag; node tags {})", raw.tri_tags[i], tags.join(" "))
}

fn norm(a: [f64; 3]) -> f64 {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// Insert one straight mid-edge node per distinct edge of a linear mesh (shared between cells): the
/// mid-node of edge k of a cell goes to slot `family.cell_vertices() + k`.
/// Edges are numbered in sorted (vertex, vertex) order so the result is deterministic.
pub(super) fn promote(
    family: Family,
    cells: &mut [[u32; 10]],
    coords: &mut Vec<[f64; 3]>,
) -> std::result::Result<(), String> {
    let (edges_of, nv) = (family.edges(), family.cell_vertices());
    let ne = edges_of.len();
    let mut edges: Vec<(u64, u32)> = Vec::with_capacity(cells.len() * ne);
    for (t, tet) in cells.iter().enumerate() {
        for (k, &(a, b)) in edges_of.iter().enumerate() {
            let (a, b) = (tet[a].min(tet[b]) as u64, tet[a].max(tet[b]) as u64);
            edges.push(((a << 32) | b, (t * ne + k) as u32));
        }
    }
    edges.sort_unstable();
    let mut last = u64::MAX;
    for &(key, slot) in &edges {
        if key != last {
            if coords.len() >= u32::MAX as usize {
                return Err("too many nodes after promotion to quadratic".into());
            }
            let (a, b) = ((key >> 32) as usize, (key & 0xffff_ffff) as usize);
            let (xa, xb) = (coords[a], coords[b]);
            coords.push([0.5 * (xa[0] + xb[0]), 0.5 * (xa[1] + xb[1]), 0.5 * (xa[2] + xb[2])]);
            last = key;
        }
        let (t, k) = (slot as usize / ne, slot as usize % ne);
        cells[t][nv + k] = (coords.len() - 1) as u32;
    }
    Ok(())
}

/// Turn physical tag -> members into (name, sorted members), including named groups that are empty;
/// unnamed groups are called by their tag; groups sharing a name are merged.
pub(super) fn named_groups(
    names: &HashMap<(usize, i32), String>,
    dim: usize,
    mut groups: BTreeMap<i32, Vec<u32>>,
) -> Vec<(String, Vec<u32>)> {
    for (&(d, tag), _) in names.iter() {
        if d == dim {
            groups.entry(tag).or_default();
        }
    }
    let mut out: Vec<(String, Vec<u32>)> = Vec::new();
    for (tag, members) in groups {
        let name = names.get(&(dim, tag)).cloned().unwrap_or_else(|| tag.to_string());
        match out.iter_mut().find(|(n, _)| *n == name) {
            Some((_, m)) => m.extend(members),
            None => out.push((name, members)),
        }
    }
    for (_, m) in &mut out {
        m.sort_unstable();
        m.dedup();
    }
    out
}
