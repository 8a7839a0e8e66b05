//! The sections of an MSH 4.1 ASCII file read into their raw contents (nodes, elements by type,
//! entities and physical names), with errors naming the line.

use std::collections::HashMap;
use std::path::Path;

use super::lexer::{shorten, Lines, Toks};
use crate::error::{Error, Result};

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

/// Reads the sections of an MSH 4.1 text into its raw contents.
pub(super) fn read_sections(path: &Path, text: &str) -> Result<Raw> {
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
    Ok(raw)
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
