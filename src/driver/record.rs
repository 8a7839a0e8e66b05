//! The run record, `DIR/run.toml`: how a run was started — the scene, its overrides and the
//! PETSc options — which `resume` reads to set the run up again.

use super::run::{Run, RunArgs};
use crate::error::{Error, Result};
use crate::io::rundir;
use crate::scene::LoadedScene;
use std::path::Path;

/// How a run was started (`DIR/run.toml`): what `resume` needs to set it up again.
#[derive(Debug, Clone, serde::Serialize, serde::Deserialize)]
pub(super) struct RunRecord {
    /// The scene argument (a file, made absolute, or a shipped scene's name).
    pub scene: String,
    pub set: Vec<String>,
    pub petsc: Vec<String>,
}

impl RunRecord {
    pub const FILE: &'static str = "run.toml";

    pub fn of(args: &RunArgs) -> RunRecord {
        let p = Path::new(&args.scene);
        let scene = if p.exists() {
            std::fs::canonicalize(p).map(|a| a.display().to_string()).unwrap_or_else(|_| args.scene.clone())
        } else {
            args.scene.clone()
        };
        RunRecord { scene, set: args.set.clone(), petsc: args.petsc.clone() }
    }

    pub fn read(dir: &Path) -> Result<RunRecord> {
        let path = dir.join(Self::FILE);
        let text =
            std::fs::read_to_string(&path).map_err(|e| Error::io(&path, format!("not a run directory ({e})")))?;
        toml::from_str(&text).map_err(|e| Error::io(&path, e.message().to_string()))
    }

    /// The scene, loaded as at the start; it must still resolve to the run's `scene.toml`.
    pub fn scene(&self, dir: &Path) -> Result<LoadedScene> {
        let scene = LoadedScene::load(&self.scene, &self.set)?;
        let path = dir.join("scene.toml");
        let was = std::fs::read_to_string(&path).map_err(|e| Error::io(&path, e))?;
        // The values, not the comments that explain them.
        let values = |text: &str| toml::from_str::<toml::Table>(text).ok();
        let same = matches!((values(&was), values(&scene.to_toml()?)), (Some(a), Some(b)) if a == b);
        if !same {
            return Err(Error::io(
                &path,
                format!("{} no longer resolves to this run's scene (was it edited?): cannot resume", scene.source),
            ));
        }
        Ok(scene)
    }
}

impl<'w> Run<'w> {
    /// `run.toml`: how to set this run up again (rank 0).
    pub(super) fn write_record(&self, dir: &Path) -> Result<()> {
        let record = toml::to_string(&RunRecord::of(&self.args))
            .map_err(|e| Error::io(dir.join(RunRecord::FILE), format!("cannot write the run record: {e}")))?;
        rundir::write_text(
            dir,
            RunRecord::FILE,
            &format!("# how this run was started, for `poroplast resume`\n{record}"),
        )
    }
}
