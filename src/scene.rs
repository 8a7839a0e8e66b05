//! Scene files: what to simulate (mesh, material, boundary conditions, time stepping, output,
//! solver options), parsed from TOML with unknown keys rejected by name, and validated with
//! physical ranges before anything runs.

use crate::error::{Error, Result};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// A whole scene. Sections are grouped by concern.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Scene {
    /// Short name (default: the file stem); names the run directory.
    #[serde(default)]
    pub name: String,
    #[serde(default)]
    pub description: String,
    pub mesh: MeshSpec,
    pub material: Material,
    #[serde(default)]
    pub bc: Vec<BoundaryCondition>,
    pub time: TimeSpec,
    #[serde(default)]
    pub output: OutputSpec,
    #[serde(default)]
    pub probe: Vec<Probe>,
    #[serde(default)]
    pub verification: Option<Verification>,
    #[serde(default)]
    pub solver: SolverSpec,
    #[serde(default)]
    pub fem: FemSpec,
    /// PETSc options without the leading dash: `ksp_rtol = 1e-10`, `ksp_monitor = true`.
    #[serde(default)]
    pub petsc: BTreeMap<String, toml::Value>,
}

/// Where the mesh comes from: a Gmsh `.geo` source meshed on the fly (cached), or a `.msh` file.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MeshSpec {
    /// A `.geo` file (relative to the scene file, or the name of one shipped in `meshes/`).
    #[serde(default)]
    pub geo: Option<String>,
    /// A ready Gmsh 4.1 `.msh` file (relative to the scene file).
    #[serde(default)]
    pub file: Option<String>,
    /// `-setnumber` parameters for the `.geo` (R, h, h_pole, ...).
    #[serde(default)]
    pub params: BTreeMap<String, f64>,
}

/// Constitutive model of the solid skeleton and the fluid flow.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields, tag = "model", rename_all = "snake_case")]
pub enum Material {
    /// Small-strain linear poroelasticity, incompressible constituents (Biot α = 1, M = ∞).
    Linear {
        /// Drained shear modulus µ (kPa).
        mu: f64,
        /// Drained Poisson ratio ν, in (-1, 0.5).
        nu: f64,
        /// Darcy conductivity k (µm⁴/(nN s)): Q = −k ∇p.
        permeability: f64,
    },
}

/// A boundary condition on a named physical surface group. Exactly one kind per entry.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryCondition {
    pub group: String,
    /// Prescribed displacement components, e.g. `{ z = 0.0 }` or `{ x = 0, y = 0, z = 0 }`.
    #[serde(default)]
    pub displacement: Option<BTreeMap<String, f64>>,
    /// Zero normal displacement on an axis-aligned plane (symmetry planes, confined sides).
    #[serde(default)]
    pub roller: Option<bool>,
    /// Reference-configuration traction: `{ normal = -1.0 }` (t = value·N) or `{ vector = [..] }`.
    #[serde(default)]
    pub traction: Option<Traction>,
    /// Prescribed pore pressure (kPa), e.g. 0 on a drained surface.
    #[serde(default)]
    pub pressure: Option<f64>,
    /// Prescribed outward fluid flux Q·N (µm/s); zero flux is the default and needs no entry.
    #[serde(default)]
    pub flux: Option<f64>,
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Traction {
    #[serde(default)]
    pub normal: Option<f64>,
    #[serde(default)]
    pub vector: Option<[f64; 3]>,
}

/// Time stepping: geometric growth from `dt` to `dt_max`, landing exactly on `t_end` and on
/// every time in `land_on`.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct TimeSpec {
    pub t_end: f64,
    /// First step (s).
    pub dt: f64,
    #[serde(default)]
    pub dt_max: Option<f64>,
    /// dt_{n+1} = min(growth · dt_n, dt_max); 1 = constant steps.
    #[serde(default = "one")]
    pub growth: f64,
    #[serde(default)]
    pub land_on: Vec<f64>,
    /// Retries (each cutting the step, by 0.25 by default) allowed when a solve fails.
    #[serde(default = "default_retries")]
    pub max_retries: usize,
}

fn one() -> f64 {
    1.0
}
fn default_retries() -> usize {
    8
}

#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct OutputSpec {
    /// Write fields every N steps (and always the last); 0 = last step only.
    #[serde(default = "default_every")]
    pub fields_every: usize,
    /// Write fields at all (large runs in studies may only want history.csv).
    #[serde(default = "yes")]
    pub fields: bool,
}
impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec { fields_every: 1, fields: true }
    }
}
fn default_every() -> usize {
    1
}
fn yes() -> bool {
    true
}

/// A scalar observable written to `history.csv` each step.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Probe {
    /// Column name.
    pub name: String,
    /// `p`, `ux`, `uy` or `uz`.
    pub field: String,
    /// Value at this reference point ...
    #[serde(default)]
    pub point: Option<[f64; 3]>,
    /// ... or the mean over this surface group.
    #[serde(default)]
    pub group: Option<String>,
    /// The column holds value / scale (e.g. the applied load, to normalise).
    #[serde(default = "one")]
    pub scale: f64,
}

/// Adds exact-solution columns next to the probes, for verification scenes.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields, tag = "kind", rename_all = "snake_case")]
pub enum Verification {
    /// Columns `<probe>_exact` for probes named `p_bottom` (pressure at z = 0, normalised by the
    /// load) and `settlement` (top displacement, downward positive).
    Terzaghi { height: f64, load: f64 },
    /// Column `p_center_exact` (centre pressure normalised by the load).
    Cryer { radius: f64, load: f64 },
}

#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// `fieldsplit` (default: Schur fieldsplit, AMG on u with rigid-body modes, fixed-stress
    /// Schur approximation) or `lu` (MUMPS direct solve, the reference).
    #[serde(default)]
    pub preset: Option<String>,
}

#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FemSpec {
    /// Degree of the tetrahedral quadrature rule (default 2 for the linear model: exact on
    /// straight elements).
    #[serde(default)]
    pub quadrature_degree: Option<usize>,
    /// c of the pressure stabilisation (c / (λ + 2µ)) ∫ (ṗ − Πṗ)(q − Πq) that keeps the
    /// undrained limit monotone next to drained boundaries (default 4: exact lumping; 0 off).
    #[serde(default)]
    pub stabilisation: Option<f64>,
}

/// A scene together with where it came from.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    pub scene: Scene,
    /// The file, or `builtin:<name>`.
    pub source: String,
    /// Directory relative paths are resolved against (None for builtin scenes).
    pub dir: Option<PathBuf>,
}

/// Scenes shipped inside the binary, runnable by name from any directory.
pub const BUILTIN: &[(&str, &str)] = &[
    ("terzaghi", include_str!("../meshes/scenes/terzaghi.toml")),
    ("cryer", include_str!("../meshes/scenes/cryer.toml")),
];

/// The `.geo` sources shipped inside the binary.
pub const BUILTIN_GEO: &[(&str, &str)] = &[
    ("sphere.geo", crate::mesh::generate::SPHERE_GEO),
    ("sphere_quarter.geo", crate::mesh::generate::SPHERE_QUARTER_GEO),
    ("column.geo", crate::mesh::generate::COLUMN_GEO),
];

impl LoadedScene {
    /// Loads `arg`: a path to a `.toml` file, or the name of a builtin scene.
    pub fn load(arg: &str) -> Result<LoadedScene> {
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
        let mut scene: Scene =
            toml::from_str(&text).map_err(|e| Error::Scene { path: source.clone(), msg: toml_message(&text, &e) })?;
        if scene.name.is_empty() {
            scene.name = stem;
        }
        let loaded = LoadedScene { scene, source, dir };
        loaded.validate()?;
        Ok(loaded)
    }

    fn err(&self, msg: impl Into<String>) -> Error {
        Error::Scene { path: self.source.clone(), msg: msg.into() }
    }

    /// Checks ranges and consistency; every message names the offending key and value.
    pub fn validate(&self) -> Result<()> {
        let s = &self.scene;
        match (&s.mesh.geo, &s.mesh.file) {
            (Some(_), Some(_)) => return Err(self.err("[mesh]: give either `geo` or `file`, not both")),
            (None, None) => return Err(self.err("[mesh]: give `geo` (a .geo source) or `file` (a .msh mesh)")),
            _ => {}
        }
        for (k, v) in &s.mesh.params {
            if !v.is_finite() {
                return Err(self.err(format!("[mesh.params] {k} = {v} is not a finite number")));
            }
            if ["R", "h", "h_pole", "H", "W"].contains(&k.as_str()) && *v <= 0.0 {
                return Err(self.err(format!("[mesh.params] {k} = {v}: a length must be positive")));
            }
        }
        match &s.material {
            Material::Linear { mu, nu, permeability } => {
                positive(self, "material.mu", *mu)?;
                if !(nu.is_finite() && *nu > -1.0 && *nu < 0.5) {
                    return Err(self.err(format!("material.nu = {nu}: Poisson ratio must lie in (-1, 0.5)")));
                }
                positive(self, "material.permeability", *permeability)?;
            }
        }
        for (i, bc) in s.bc.iter().enumerate() {
            let kinds = [
                bc.displacement.is_some(),
                bc.roller.is_some(),
                bc.traction.is_some(),
                bc.pressure.is_some(),
                bc.flux.is_some(),
            ];
            if kinds.iter().filter(|k| **k).count() != 1 {
                return Err(self.err(format!(
                    "bc #{} (group \"{}\"): give exactly one of displacement, roller, traction, pressure, flux",
                    i + 1,
                    bc.group
                )));
            }
            if let Some(d) = &bc.displacement {
                for (k, v) in d {
                    if !["x", "y", "z"].contains(&k.as_str()) {
                        return Err(self.err(format!(
                            "bc #{} (group \"{}\"): displacement component `{k}` (use x, y, z)",
                            i + 1,
                            bc.group
                        )));
                    }
                    finite(self, "displacement", *v)?;
                }
            }
            if let Some(t) = &bc.traction {
                if t.normal.is_some() == t.vector.is_some() {
                    return Err(self.err(format!(
                        "bc #{} (group \"{}\"): traction needs exactly one of `normal` or `vector`",
                        i + 1,
                        bc.group
                    )));
                }
            }
        }
        let t = &s.time;
        positive(self, "time.t_end", t.t_end)?;
        positive(self, "time.dt", t.dt)?;
        if let Some(m) = t.dt_max {
            positive(self, "time.dt_max", m)?;
        }
        if !(t.growth >= 1.0 && t.growth.is_finite()) {
            return Err(self.err(format!("time.growth = {}: must be >= 1", t.growth)));
        }
        for p in &s.probe {
            if !["p", "ux", "uy", "uz"].contains(&p.field.as_str()) {
                return Err(self.err(format!("probe \"{}\": field `{}` (use p, ux, uy, uz)", p.name, p.field)));
            }
            if p.point.is_some() == p.group.is_some() {
                return Err(self.err(format!("probe \"{}\": give exactly one of `point` or `group`", p.name)));
            }
            if p.scale == 0.0 || !p.scale.is_finite() {
                return Err(self.err(format!("probe \"{}\": scale must be finite and non-zero", p.name)));
            }
        }
        if let Some(v) = &s.verification {
            let (a, b) = match v {
                Verification::Terzaghi { height, load } => (height, load),
                Verification::Cryer { radius, load } => (radius, load),
            };
            positive(self, "verification length", *a)?;
            finite(self, "verification load", *b)?;
        }
        if let Some(p) = &s.solver.preset {
            if !["fieldsplit", "lu"].contains(&p.as_str()) {
                return Err(self.err(format!("solver.preset = \"{p}\" (use \"fieldsplit\" or \"lu\")")));
            }
        }
        if let Some(a) = s.fem.stabilisation {
            if !(a.is_finite() && a >= 0.0) {
                return Err(self.err(format!("fem.stabilisation = {a}: must be >= 0")));
            }
        }
        if let Some(q) = s.fem.quadrature_degree {
            if !(1..=8).contains(&q) {
                return Err(self.err(format!("fem.quadrature_degree = {q}: use 1..8")));
            }
        }
        for (k, v) in &s.petsc {
            if matches!(v, toml::Value::Array(_) | toml::Value::Table(_)) {
                return Err(self.err(format!("[petsc] {k}: values must be strings, numbers or booleans")));
            }
        }
        Ok(())
    }

    /// The `[petsc]` table as command-line style options (`-key value`).
    pub fn petsc_args(&self) -> Vec<String> {
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

    /// Resolves a path given in the scene: relative to the scene file.
    pub fn resolve(&self, p: &str) -> PathBuf {
        match &self.dir {
            Some(d) if Path::new(p).is_relative() => d.join(p),
            _ => PathBuf::from(p),
        }
    }

    /// The scene as TOML (for the run directory).
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(&self.scene).unwrap_or_default()
    }
}

/// A TOML error on one line: "line N (`text`): message" (the parser's own text spans lines).
fn toml_message(text: &str, e: &toml::de::Error) -> String {
    let msg = e.message().replace('\n', " ");
    match e.span() {
        Some(span) => {
            let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
            let what = text.lines().nth(line - 1).unwrap_or("").trim();
            format!("line {line} (`{what}`): {msg}")
        }
        None => msg,
    }
}

fn positive(s: &LoadedScene, key: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(s.err(format!("{key} = {v}: must be positive")))
    }
}

fn finite(s: &LoadedScene, key: &str, v: f64) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(s.err(format!("{key} = {v}: must be finite")))
    }
}
