//! The run record, `DIR/run.toml`: how a run was started — the scene, its overrides and the
//! PETSc options — which `resume` reads to set the run up again.

use super::args::RunArgs;
use crate::error::{Error, Result};
use crate::io::rundir;
use crate::scene::LoadedScene;
use std::path::Path;

/// How a run was started (`DIR/run.toml`): what `resume` needs to set it up again.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(super) struct RunRecord {
    /// The scene argument (a file, made absolute, or a shipped scene's name).
    pub(crate) scene: String,
    pub(crate) set: Vec<String>,
    pub(crate) petsc: Vec<String>,
}

impl RunRecord {
    pub(crate) const FILE: &'static str = "run.toml";

    pub(crate) fn of(args: &RunArgs) -> RunRecord {
        let p = Path::new(&args.scene);
        let scene = if p.exists() {
            std::fs::canonicalize(p).map(|a| a.display().to_string()).unwrap_or_else(|_| args.scene.clone())
        } else {
            args.scene.clone()
        };
        RunRecord { scene, set: args.set.clone(), petsc: args.petsc.clone() }
    }

    pub(crate) fn read(dir: &Path) -> Result<RunRecord> {
        let path = dir.join(Self::FILE);
        let text =
            std::fs::read_to_string(&path).map_err(|e| Error::io(&path, format!("not a run directory ({e})")))?;
        toml::from_str(&text).map_err(|e| Error::io(&path, e.message().to_string()))
    }

    /// The scene, loaded as at the start; it must still resolve to the run's `scene.toml`, itself
    /// resolved as a scene (so that a run started by a version that wrote fewer defaults, or keys
    /// since moved, resumes: the values compare, not the text).
    pub(crate) fn scene(&self, dir: &Path) -> Result<LoadedScene> {
        let scene = LoadedScene::load(&self.scene, &self.set)?;
        let path = dir.join("scene.toml");
        if !path.is_file() {
            return Err(Error::io(&path, "not found: cannot resume"));
        }
        // What the run computes: the description is words.
        let values = |s: &LoadedScene| -> Result<toml::Value> {
            let mut t: toml::Table = toml::from_str(&s.to_toml()?).map_err(|e| Error::io(&path, e.to_string()))?;
            t.remove("description");
            Ok(toml::Value::Table(t))
        };
        let same = match LoadedScene::load(&path.display().to_string(), &[]) {
            Ok(was) => values(&was)? == values(&scene)?,
            Err(_) => false,
        };
        if !same {
            return Err(Error::io(
                &path,
                format!("{} no longer resolves to this run's scene (was it edited?): cannot resume", scene.source),
            ));
        }
        Ok(scene)
    }

    /// Writes `run.toml` in `dir`: how to set this run up again (rank 0).
    pub(crate) fn write(&self, dir: &Path) -> Result<()> {
        let record = toml::to_string(self)
            .map_err(|e| Error::io(dir.join(RunRecord::FILE), format!("cannot write the run record: {e}")))?;
        rundir::write_text(
            dir,
            RunRecord::FILE,
            &format!("# how this run was started, for `poroplast resume`\n{record}"),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::RunRecord;

    /// A run directory with `scene.toml` holding `text`, started from the shipped `reference`.
    fn resumed(name: &str, text: &str) -> Result<(), String> {
        let dir = std::env::temp_dir().join(format!("poroplast-record-{}-{name}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        std::fs::write(dir.join("scene.toml"), text).unwrap();
        let record = RunRecord { scene: "reference".into(), set: vec![], petsc: vec![] };
        record.scene(&dir).map(|_| ()).map_err(|e| e.to_string())
    }

    #[test]
    fn a_run_resumes_if_its_scene_resolves_alike() {
        // The previous version wrote the scene as given (t_ramp and t_end, no [fem] defaults).
        let old = include_str!("../../tests/data/scenes_v1/reference.toml");
        resumed("old", &format!("# resolved from builtin:reference\n{old}")).unwrap();
        let edited = old.replacen("mu = 20.0", "mu = 21.0", 1);
        let e = resumed("edited", &edited).unwrap_err();
        assert!(
            e.ends_with("builtin:reference no longer resolves to this run's scene (was it edited?): cannot resume"),
            "{e}"
        );
    }
}
