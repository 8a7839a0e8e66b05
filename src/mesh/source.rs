//! A scene's mesh: the given `.msh`, or one generated from its `.geo` by rank 0 and cached,
//! read and reflected as the scene asks. The scene hands over the values (`MeshSource`,
//! parameters, family, mirror planes): this module does not know the scene's types.

use super::global::Mesh;
use super::gmsh;
use crate::error::{Error, Result};
use crate::mesh::generate::BUILTIN_GEO;
use crate::parallel::path_from_root;
use crate::reference_cell::Family;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// Where generated meshes are cached.
fn cache_dir() -> PathBuf {
    if let Ok(d) = std::env::var("POROPLAST_CACHE") {
        return PathBuf::from(d);
    }
    if let Ok(d) = std::env::var("XDG_CACHE_HOME") {
        return Path::new(&d).join("poroplast");
    }
    if let Ok(h) = std::env::var("HOME") {
        return Path::new(&h).join(".cache/poroplast");
    }
    std::env::temp_dir().join("poroplast-cache")
}

/// Where a scene's mesh comes from, with its paths resolved against the scene file.
#[derive(Debug, Clone)]
pub(crate) enum MeshSource<'a> {
    /// A ready Gmsh `.msh` file.
    Msh(PathBuf),
    /// A `.geo` source: `name` as the scene gives it (also the name of a shipped one), `path`
    /// that name resolved as a file.
    Geo { name: &'a str, path: PathBuf },
}

/// The `.msh` file of a mesh source: given, or generated from its `.geo` by rank 0 (cached), with
/// the `-setnumber` parameters `params`. `scene` names the scene (for the message of an unknown
/// parameter).
pub(crate) fn mesh_file(
    world: &SimpleCommunicator,
    source: MeshSource,
    params: &BTreeMap<String, f64>,
    scene: &str,
) -> Result<PathBuf> {
    let (geo, local) = match source {
        MeshSource::Msh(file) => return Ok(file),
        MeshSource::Geo { name, path } => (name, path),
    };
    let (name, source) = if local.exists() {
        let text = std::fs::read_to_string(&local).map_err(|e| Error::io(&local, e))?;
        (local.file_name().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default(), text)
    } else if let Some((n, text)) = BUILTIN_GEO.iter().find(|(n, _)| *n == geo) {
        (n.to_string(), text.to_string())
    } else {
        return Err(Error::mesh(&local, "geometry source not found (not a file, nor a shipped .geo)"));
    };
    let params: Vec<(String, f64)> = params.iter().map(|(k, v)| (k.clone(), *v)).collect();
    // The scene's own .geo file (not a shipped one): if gmsh cannot read it, its complaint is
    // the error, rather than what follows from it (no parameters found, no mesh).
    let user_geo = local.exists().then_some(local.as_path());
    let unreadable = |e: Error| match user_geo {
        Some(g) => readable_geo(g, &params).err().unwrap_or(e),
        None => e,
    };
    // gmsh ignores a -setnumber it has no DefineConstant for: a typo would go unnoticed.
    let known = define_constants(&source);
    if let Some((k, _)) = params.iter().find(|(k, _)| !known.contains(&k.as_str())) {
        let unknown = Error::Scene {
            path: scene.to_string(),
            msg: format!("mesh.params.{k}: {name} has no parameter `{k}` (it has: {})", known.join(", ")),
        };
        // Every rank stops here; rank 0, which reports, asks gmsh first.
        return Err(if world.rank() == 0 { unreadable(unknown) } else { unknown });
    }
    path_from_root(world, || {
        crate::mesh::generate::cached(&name, &source, &params, 2, &cache_dir()).map_err(unreadable)
    })
}

/// Ok if gmsh reads the `.geo` file `geo` (with the parameters set), else an error naming the
/// file with gmsh's own complaints (file, line, what).
fn readable_geo(geo: &Path, params: &[(String, f64)]) -> Result<()> {
    let errors = crate::mesh::generate::read_errors(geo, params)?;
    if errors.is_empty() {
        Ok(())
    } else {
        Err(Error::mesh(geo, format!("gmsh cannot read it: {}", errors.join("; "))))
    }
}

/// The parameters a `.geo` source declares with `DefineConstant[ name = ... ]`.
fn define_constants(source: &str) -> Vec<&str> {
    source
        .lines()
        .filter_map(|l| l.trim_start().strip_prefix("DefineConstant["))
        .filter_map(|rest| rest.split('=').next())
        .map(str::trim)
        .filter(|n| !n.is_empty())
        .collect()
}

/// Reads the mesh file and reflects it across the symmetry planes `mirror` (in order); the mesh
/// must be of the `family` the scene's geometry needs (tetrahedra for a solid, meridian
/// triangles for an axisymmetric body).
pub(crate) fn read_mesh(path: &Path, family: Family, mirror: &[String]) -> Result<Mesh> {
    let mut mesh = gmsh::read(path)?;
    if mesh.family != family {
        return Err(Error::mesh(
            path,
            format!(
                "mesh.geometry = \"{}\" needs a mesh of {}, but this one has {} (set mesh.geometry, or mesh.meridian \
                 for the meridian of a solid scene)",
                match family {
                    Family::Tet10 => "solid",
                    Family::Tri6 => "axisymmetric",
                },
                match family {
                    Family::Tet10 => "tetrahedra",
                    Family::Tri6 => "meridian triangles",
                },
                match mesh.family {
                    Family::Tet10 => "tetrahedra",
                    Family::Tri6 => "triangles",
                },
            ),
        ));
    }
    for plane in mirror {
        mesh = crate::mesh::mirror::mirror(&mesh, plane)?;
    }
    Ok(mesh)
}

#[cfg(test)]
mod tests {
    #[test]
    fn geo_parameters_are_the_define_constants() {
        let names = super::define_constants(crate::mesh::generate::SPHERE_QUARTER_GEO);
        for p in ["R", "h", "h_pole", "r_pole", "h_edge", "r_edge", "w_edge"] {
            assert!(names.contains(&p), "{p} not in {names:?}");
        }
        assert!(!names.contains(&"h_pol"));
    }
}
