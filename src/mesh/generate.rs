//! Mesh generation by running the `gmsh` command-line tool on a `.geo` file, with a content-addressed cache.
//!
//! The executable is `gmsh` from `PATH`, or the one named by the environment variable `GMSH`.
//! Output is always written to a temporary name in the target directory and renamed on success, so an
//! interrupted or failed run never leaves a partial `.msh` behind (gmsh itself writes a file even on error).

use std::ffi::{OsStr, OsString};
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::OnceLock;

use crate::error::{Error, Result};
use crate::files::write_text_atomically;
use crate::hash::Fnv;

/// Full sphere (radius `R`, centre (0,0,R)): volume "aggregate", surface "surface", points "pole_bottom", "pole_top".
pub(crate) const SPHERE_GEO: &str = include_str!("../../meshes/sphere.geo");
/// Quarter sphere x, y >= 0: adds surfaces "symmetry_x", "symmetry_y".
pub(crate) const SPHERE_QUARTER_GEO: &str = include_str!("../../meshes/sphere_quarter.geo");
/// Terzaghi column `[0,W]^2 x [0,H]`: volume "column", surfaces "top", "bottom", "sides".
pub(crate) const COLUMN_GEO: &str = include_str!("../../meshes/column.geo");
/// The block [0, L]³ with its six faces as groups (0-D verification).
pub(crate) const BLOCK_GEO: &str = include_str!("../../meshes/block.geo");
/// The meridian half-disc of the sphere (axisymmetric scenes).
pub(crate) const SPHERE_MERIDIAN_GEO: &str = include_str!("../../meshes/sphere_meridian.geo");
/// The meridian rectangle of a cylinder column (axisymmetric Terzaghi).
pub(crate) const COLUMN_MERIDIAN_GEO: &str = include_str!("../../meshes/column_meridian.geo");

/// The meridian rectangle of a block graded towards the top of its axis (indentation).
pub(crate) const BLOCK_MERIDIAN_GEO: &str = include_str!("../../meshes/block_meridian.geo");

/// The `.geo` sources shipped inside the binary, by file name.
pub(crate) const BUILTIN_GEO: &[(&str, &str)] = &[
    ("sphere.geo", SPHERE_GEO),
    ("sphere_quarter.geo", SPHERE_QUARTER_GEO),
    ("column.geo", COLUMN_GEO),
    ("block.geo", BLOCK_GEO),
    ("sphere_meridian.geo", SPHERE_MERIDIAN_GEO),
    ("column_meridian.geo", COLUMN_MERIDIAN_GEO),
    ("block_meridian.geo", BLOCK_MERIDIAN_GEO),
];

fn gmsh_exe() -> OsString {
    std::env::var_os("GMSH").unwrap_or_else(|| "gmsh".into())
}

/// Run the gmsh executable `exe` with `args`; a missing executable is reported as such.
fn run_gmsh(exe: &OsStr, args: &[OsString], label: &Path) -> Result<Output> {
    Command::new(exe).args(args).output().map_err(|e| {
        if e.kind() == std::io::ErrorKind::NotFound {
            Error::mesh(label, format!("cannot run gmsh: {exe:?} not found (install gmsh or set GMSH)"))
        } else {
            Error::mesh(label, format!("cannot run gmsh {exe:?}: {e}"))
        }
    })
}

/// The last `n` non-empty lines of gmsh's stderr (where its errors go), or of stdout if stderr is empty.
fn tail(out: &Output, n: usize) -> String {
    let pick = |b: &[u8]| {
        let s = String::from_utf8_lossy(b).into_owned();
        let lines: Vec<&str> = s.lines().filter(|l| !l.trim().is_empty()).collect();
        lines[lines.len().saturating_sub(n)..].join("\n")
    };
    let err = pick(&out.stderr);
    if err.is_empty() {
        pick(&out.stdout)
    } else {
        err
    }
}

/// gmsh's own error lines ("Error   : 'f.geo', line 2: syntax error (;)"), without the prefix.
fn error_lines(out: &Output) -> Vec<String> {
    [&out.stderr, &out.stdout]
        .iter()
        .flat_map(|b| String::from_utf8_lossy(b).lines().map(str::to_string).collect::<Vec<_>>())
        .filter_map(|l| l.strip_prefix("Error").map(|r| r.trim_start_matches([' ', ':']).trim().to_string()))
        .filter(|l| !l.is_empty())
        .collect()
}

/// gmsh's complaints when it only reads `geo` (`gmsh -0`, nothing meshed) with the parameters
/// set: empty if it reads the file without error.
pub(crate) fn read_errors(geo: &Path, params: &[(String, f64)]) -> Result<Vec<String>> {
    let tmp = temp_path(&std::env::temp_dir().join("poroplast-read-check"), "geo_unrolled");
    let mut args: Vec<OsString> = vec!["-0".into()];
    for (name, value) in params {
        args.extend(["-setnumber".into(), name.into(), value.to_string().into()]);
    }
    args.extend([geo.as_os_str().to_owned(), "-o".into(), tmp.as_os_str().to_owned()]);
    let out = run_gmsh(&gmsh_exe(), &args, geo);
    let _ = std::fs::remove_file(&tmp);
    Ok(error_lines(&out?))
}

/// A unique temporary file name next to `target` (same directory, so the final rename is atomic).
fn temp_path(target: &Path, ext: &str) -> PathBuf {
    static COUNTER: AtomicUsize = AtomicUsize::new(0);
    let n = COUNTER.fetch_add(1, Ordering::Relaxed);
    let stem = target.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
    target.with_file_name(format!(".{stem}.{}-{n}.tmp.{ext}", std::process::id()))
}

/// Mesh `geo` in 3-D at the given element `order`, with `-setnumber name value` for each parameter,
/// into `out` (MSH 4.1 ASCII).
pub(crate) fn generate(geo: &Path, params: &[(String, f64)], order: usize, out: &Path) -> Result<()> {
    generate_with(&gmsh_exe(), geo, params, order, out)
}

/// [`generate`] with an explicit gmsh executable.
pub(crate) fn generate_with(exe: &OsStr, geo: &Path, params: &[(String, f64)], order: usize, out: &Path) -> Result<()> {
    if !geo.exists() {
        return Err(Error::mesh(geo, "geometry file does not exist"));
    }
    if !(1..=4).contains(&order) {
        return Err(Error::mesh(geo, format!("element order {order} out of range 1..=4")));
    }
    let mut args: Vec<OsString> =
        vec!["-3".into(), "-order".into(), order.to_string().into(), "-format".into(), "msh41".into()];
    for (name, value) in params {
        if name.is_empty() || name.chars().any(|c| c.is_whitespace()) || !value.is_finite() {
            return Err(Error::mesh(geo, format!("bad gmsh parameter {name:?} = {value}")));
        }
        args.extend(["-setnumber".into(), name.into(), value.to_string().into()]);
    }
    let tmp = temp_path(out, "msh");
    args.extend([geo.as_os_str().to_owned(), "-o".into(), tmp.as_os_str().to_owned()]);
    let res = run_gmsh(exe, &args, geo);
    let output = match res {
        Ok(o) => o,
        Err(e) => {
            let _ = std::fs::remove_file(&tmp);
            return Err(e);
        }
    };
    if !output.status.success() || !tmp.exists() {
        let _ = std::fs::remove_file(&tmp);
        // gmsh's own error lines first (on the message's first line), else the end of its output.
        let errors = error_lines(&output);
        let msg = if errors.is_empty() {
            format!("gmsh failed ({}):\n{}", output.status, tail(&output, 10))
        } else {
            format!("gmsh failed: {}", errors.join("; "))
        };
        return Err(Error::mesh(geo, msg));
    }
    std::fs::rename(&tmp, out).map_err(|e| {
        let _ = std::fs::remove_file(&tmp);
        Error::mesh(out, format!("cannot rename {} to it: {e}", tmp.display()))
    })
}

/// gmsh's version string (`gmsh --version` prints it on stderr), queried once per process and
/// remembered in `cache_dir` under the executable's identity (path, size, modification time):
/// running gmsh costs 0.1 s, a third of the start of a run that finds its mesh in the cache.
pub(crate) fn gmsh_version(cache_dir: &Path) -> Result<String> {
    static VERSION: OnceLock<String> = OnceLock::new();
    if let Some(v) = VERSION.get() {
        return Ok(v.clone());
    }
    let remembered = executable_identity(&gmsh_exe()).map(|id| cache_dir.join(format!("gmsh-version-{id}.txt")));
    if let Some(v) = remembered.as_ref().and_then(|f| std::fs::read_to_string(f).ok()).filter(|v| !v.is_empty()) {
        return Ok(VERSION.get_or_init(|| v).clone());
    }
    let out = run_gmsh(&gmsh_exe(), &["--version".into()], Path::new("gmsh"))?;
    let text = format!("{}{}", String::from_utf8_lossy(&out.stdout), String::from_utf8_lossy(&out.stderr));
    let v = text.trim().to_string();
    if !out.status.success() || v.is_empty() {
        return Err(Error::mesh("gmsh", format!("`gmsh --version` failed: {}", tail(&out, 5))));
    }
    if let Some(file) = remembered {
        // Only a shortcut: a cache that cannot be written costs the 0.1 s next time.
        let _ = write_text_atomically(&file, &v);
    }
    Ok(VERSION.get_or_init(|| v).clone())
}

/// A hash of the executable `exe` (a path, or a name looked up in `PATH`) as installed: its
/// resolved path, size and modification time; `None` if it cannot be found.
fn executable_identity(exe: &OsStr) -> Option<String> {
    let candidates: Vec<PathBuf> = if Path::new(exe).components().count() > 1 {
        vec![PathBuf::from(exe)]
    } else {
        std::env::split_paths(&std::env::var_os("PATH")?).map(|d| d.join(exe)).collect()
    };
    let path = candidates.into_iter().find(|p| p.is_file())?.canonicalize().ok()?;
    let meta = path.metadata().ok()?;
    let mtime = meta.modified().ok()?.duration_since(std::time::UNIX_EPOCH).ok()?;
    let mut h = Fnv::new();
    h.field(path.as_os_str().as_encoded_bytes());
    h.field(&meta.len().to_le_bytes());
    h.field(&mtime.as_nanos().to_le_bytes());
    Some(h.hex())
}

/// Hash of everything that determines the generated mesh.
fn cache_key(geo_source: &str, params: &[(String, f64)], order: usize, version: &str) -> String {
    let mut h = Fnv::new();
    h.field(geo_source.as_bytes());
    // Parameter order does not change the mesh (later duplicates win in gmsh, so keep their relative order).
    let mut sorted: Vec<&(String, f64)> = params.iter().collect();
    sorted.sort_by(|a, b| a.0.cmp(&b.0));
    for (name, value) in sorted {
        h.field(name.as_bytes());
        h.field(&value.to_bits().to_le_bytes());
    }
    h.field(&(order as u64).to_le_bytes());
    h.field(version.as_bytes());
    h.hex()
}

/// Path of `<stem>-<hash>.msh` in `cache_dir`, generating it from `geo_source` (saved as `<stem>-<hash>.geo`)
/// only if it does not exist yet. The hash covers the source, the parameters, the order and gmsh's version.
pub(crate) fn cached(
    geo_name: &str,
    geo_source: &str,
    params: &[(String, f64)],
    order: usize,
    cache_dir: &Path,
) -> Result<PathBuf> {
    let stem = Path::new(geo_name)
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .filter(|s| !s.is_empty())
        .ok_or_else(|| Error::mesh(geo_name, "empty geometry name"))?;
    let key = cache_key(geo_source, params, order, &gmsh_version(cache_dir)?);
    let msh = cache_dir.join(format!("{stem}-{key}.msh"));
    if msh.exists() {
        return Ok(msh);
    }
    std::fs::create_dir_all(cache_dir).map_err(|e| Error::io(cache_dir, e))?;
    let geo = cache_dir.join(format!("{stem}-{key}.geo"));
    write_text_atomically(&geo, geo_source)?;
    generate(&geo, params, order, &msh)?;
    Ok(msh)
}
