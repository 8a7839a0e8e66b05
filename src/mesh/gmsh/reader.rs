//! From a file to a [`Mesh`]: the bytes checked for an ASCII MSH file, the sections read, and
//! the mesh of the cells found built (tetrahedra, or the triangles of a meridian).

use std::path::Path;

use super::meridian;
use super::msh41::{self, Raw};
use super::tet;
use crate::error::{Error, Result};
use crate::mesh::Mesh;

/// Read a Gmsh MSH 4.1 ASCII file into a [`Mesh`].
pub(crate) fn read(path: &Path) -> Result<Mesh> {
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

/// Parse the text of an MSH file (`path` only labels errors).
fn parse(path: &Path, text: &str) -> Result<Mesh> {
    build(path, msh41::read_sections(path, text)?)
}

/// Builds the mesh of the cells found: tetrahedra, or else the triangles of a meridian.
fn build(path: &Path, raw: Raw) -> Result<Mesh> {
    if raw.cells.is_empty() && !raw.tris.is_empty() {
        return meridian::build(path, raw);
    }
    tet::build(path, raw)
}
