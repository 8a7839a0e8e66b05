//! Loading a scene: a file or a builtin by name, `--set` overrides applied, `auto` choices
//! resolved, validated; paths resolved against the scene file; the `[petsc]` options; the
//! resolved scene as TOML for the run directory.

use super::diagnose::{from_table, override_message, toml_message};
use super::overrides;
use super::resolve;
use super::sections::Scene;
use crate::error::{Error, Result};
use std::path::{Path, PathBuf};

/// A scene together with where it came from.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    pub(crate) scene: Scene,
    /// The `--set KEY=VALUE` overrides applied to the file (already in `scene`).
    pub(crate) overrides: Vec<String>,
    /// The file, or `builtin:<name>`.
    pub source: String,
    /// Directory relative paths are resolved against (None for builtin scenes).
    pub(crate) dir: Option<PathBuf>,
    /// What the user should know: deprecated keys and what to write instead, values allowed but
    /// likely mistaken (printed by `run` and `check` as notes).
    pub notes: Vec<String>,
}

/// Scenes shipped inside the binary, runnable by name from any directory.
pub const BUILTIN: &[(&str, &str)] = &[
    ("terzaghi", include_str!("../../meshes/scenes/terzaghi.toml")),
    ("cryer", include_str!("../../meshes/scenes/cryer.toml")),
    ("reference", include_str!("../../meshes/scenes/reference.toml")),
    ("reference_405", include_str!("../../meshes/scenes/reference_405.toml")),
    ("reference_full", include_str!("../../meshes/scenes/reference_full.toml")),
    ("relaxation", include_str!("../../meshes/scenes/relaxation.toml")),
    ("remodel_40", include_str!("../../meshes/scenes/remodel_40.toml")),
    ("remodel_155", include_str!("../../meshes/scenes/remodel_155.toml")),
    ("remodel_405", include_str!("../../meshes/scenes/remodel_405.toml")),
    ("remodel_155_c2", include_str!("../../meshes/scenes/remodel_155_c2.toml")),
    ("elastic_155", include_str!("../../meshes/scenes/elastic_155.toml")),
    ("reference_axi", include_str!("../../meshes/scenes/reference_axi.toml")),
    ("tst_hold", include_str!("../../meshes/scenes/tst_hold.toml")),
    ("tst_two_compressions", include_str!("../../meshes/scenes/tst_two_compressions.toml")),
    ("creep_plates", include_str!("../../meshes/scenes/creep_plates.toml")),
    ("indent_sphere", include_str!("../../meshes/scenes/indent_sphere.toml")),
];

impl LoadedScene {
    /// Loads `arg`: a path to a `.toml` file, or the name of a builtin scene, with the
    /// `--set KEY=VALUE` overrides applied in order (see `overrides`).
    pub fn load(arg: &str, overrides: &[String]) -> Result<LoadedScene> {
        let (mut scene, source, dir, stem) = Self::read(arg, overrides)?;
        if scene.name.is_empty() {
            scene.name = stem;
        }
        let scene_err = |msg: String| Error::Scene { path: source.clone(), msg };
        let mut notes = resolve::resolve(&mut scene).map_err(scene_err)?;
        scene.validate(&mut notes).map_err(scene_err)?;
        Ok(LoadedScene { scene, overrides: overrides.to_vec(), source, dir, notes })
    }

    /// That the overrides name keys of the scene `arg`, with values of their types: the scene
    /// read, neither resolved nor validated. A sweep checks this of every case before it runs
    /// any; a value out of range stays the failure of the case that has it.
    pub(crate) fn check_keys(arg: &str, overrides: &[String]) -> Result<()> {
        Self::read(arg, overrides).map(drop)
    }

    /// The scene `arg` as read, with the overrides applied: (scene, source, directory, stem).
    fn read(arg: &str, overrides: &[String]) -> Result<(Scene, String, Option<PathBuf>, String)> {
        let path = Path::new(arg);
        let (text, source, dir, stem) = if path.exists() {
            let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
            let dir =
                path.parent().map(|p| if p.as_os_str().is_empty() { PathBuf::from(".") } else { p.to_path_buf() });
            let stem = path.file_stem().map(|s| s.to_string_lossy().into_owned()).unwrap_or_default();
            (text, path.display().to_string(), dir, stem)
        } else if let Some((name, text)) = BUILTIN.iter().find(|(n, _)| *n == arg) {
            (text.to_string(), format!("builtin:{name}"), None, name.to_string())
        } else {
            let names: Vec<_> = BUILTIN.iter().map(|(n, _)| *n).collect();
            return Err(Error::Scene {
                path: arg.into(),
                msg: format!("no such file, and not a builtin scene (builtin: {})", names.join(", ")),
            });
        };
        let scene_err = |msg: String| Error::Scene { path: source.clone(), msg };
        let scene: Scene = if overrides.is_empty() {
            toml::from_str(&text).map_err(|e| scene_err(toml_message(&text, &e)))?
        } else {
            // All overrides first, then the scene is read once: one override may need another
            // (a new `remodelling` table needs both its fields), so the scene half-way through
            // them need not be valid. A value the scene rejects is then blamed on its override.
            let file: toml::Table = toml::from_str(&text).map_err(|e| scene_err(toml_message(&text, &e)))?;
            let mut table = file.clone();
            for spec in overrides {
                overrides::apply(&mut table, spec).map_err(scene_err)?;
            }
            from_table(&table).map_err(|e| scene_err(override_message(&text, &file, overrides, &e)))?
        };
        Ok((scene, source, dir, stem))
    }

    fn err(&self, msg: impl Into<String>) -> Error {
        Error::Scene { path: self.source.clone(), msg: msg.into() }
    }

    /// The `[petsc]` table as command-line style options (`-key value`).
    pub(crate) fn petsc_args(&self) -> Vec<String> {
        let mut out = Vec::new();
        for (k, v) in &self.scene.petsc {
            let key = format!("-{}", k.trim_start_matches('-'));
            match v {
                toml::Value::Boolean(true) => out.push(key),
                toml::Value::Boolean(false) => {}
                toml::Value::String(s) => {
                    out.push(key);
                    out.push(s.clone());
                }
                other => {
                    out.push(key);
                    out.push(other.to_string());
                }
            }
        }
        out
    }

    /// Where the scene's mesh comes from (`mesh.file`, or the `.geo` of its geometry), resolved
    /// against the scene file.
    pub(crate) fn mesh_source(&self) -> crate::mesh::source::MeshSource<'_> {
        use crate::mesh::source::MeshSource;
        match self.scene.mesh.source() {
            (_, Some(file)) => MeshSource::Msh(self.resolve(file)),
            (geo, None) => {
                let name = geo.unwrap_or_default();
                MeshSource::Geo { name, path: self.resolve(name) }
            }
        }
    }

    /// Resolves a path given in the scene: relative to the scene file.
    pub(crate) fn resolve(&self, p: &str) -> PathBuf {
        match &self.dir {
            Some(d) if Path::new(p).is_relative() => d.join(p),
            _ => PathBuf::from(p),
        }
    }

    /// The scene as TOML, every value on its key's line (`explain` writes the run directory's
    /// `scene.toml` from it).
    pub(crate) fn to_toml(&self) -> Result<String> {
        toml::to_string(&self.scene).map_err(|e| self.err(format!("cannot write the resolved scene as TOML: {e}")))
    }
}

#[cfg(test)]
mod tests {
    use super::LoadedScene;

    #[test]
    fn an_unknown_choice_in_an_override_is_blamed_on_it() {
        let Err(e) = LoadedScene::load("reference", &["solver.preset=\"amg\"".into()]) else {
            panic!("an unknown preset was accepted");
        };
        let m = e.to_string();
        assert!(
            m.ends_with("--set solver.preset=\"amg\": unknown variant `amg`, expected one of `auto`, `direct`, `fieldsplit`, `lu`"),
            "{m}"
        );
    }

    #[test]
    fn counts_given_negative_are_named_in_words() {
        let Err(e) = LoadedScene::load("reference", &["output.fields_every=-1".into()]) else {
            panic!("a negative count was accepted");
        };
        let m = e.to_string();
        assert!(
            m.ends_with("--set output.fields_every=-1: invalid value: integer `-1`, expected a non-negative integer"),
            "{m}"
        );
    }
}
