//! Scene files: what to simulate (mesh, material, boundary conditions, time stepping, output,
//! solver options), parsed from TOML with unknown keys rejected by name, and validated with
//! physical ranges before anything runs.

pub mod auto;
pub mod overrides;
#[cfg(test)]
mod validation_tests;

use crate::error::{Error, Result};
use crate::material::{FlowForm, Integrator};
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
    /// Rigid plates squeezing the aggregate (contact, drainage, loading).
    #[serde(default)]
    pub plates: Option<PlatesSpec>,
    #[serde(default)]
    pub solver: SolverSpec,
    #[serde(default)]
    pub fem: FemSpec,
    /// The state at t = 0 (default: undeformed, p = 0).
    #[serde(default)]
    pub initial: Option<InitialSpec>,
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
    /// Symmetry planes (face groups) to reflect the mesh across, in order: a quarter sphere
    /// mirrored across `["symmetry_x", "symmetry_y"]` is a full sphere with the same elements.
    #[serde(default)]
    pub mirror: Vec<String>,
    /// The body's geometry: `solid` (3-D, tetrahedra) or `axisymmetric` (a body of revolution
    /// about the z axis, meshed on its meridian in the x–z plane with triangles).
    #[serde(default)]
    pub geometry: Geometry,
    /// The `.geo` of the body's meridian, used instead of `geo` when `geometry = "axisymmetric"`
    /// (with the same `params`): so one override switches a scene to its meridian.
    #[serde(default)]
    pub meridian: Option<String>,
    /// `given` (default: the sizes in `params`) or `auto` (the measured best sizes for plate
    /// experiments, scaled by `params.R`; sizes given in `params` win). See [`auto`].
    #[serde(default)]
    pub grading: auto::Grading,
}

/// The geometry of a scene's body (see [`MeshSpec::geometry`]).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Geometry {
    #[default]
    Solid,
    Axisymmetric,
}

impl Geometry {
    /// The mesh family this geometry is discretised with.
    pub fn family(self) -> crate::reference_cell::Family {
        match self {
            Geometry::Solid => crate::reference_cell::Family::Tet10,
            Geometry::Axisymmetric => crate::reference_cell::Family::Tri6,
        }
    }
}

impl MeshSpec {
    /// The `.geo` source and `.msh` file the geometry uses (one of the two is set).
    pub fn source(&self) -> (Option<&str>, Option<&str>) {
        match (self.geometry, &self.meridian) {
            (Geometry::Axisymmetric, Some(m)) => (Some(m.as_str()), None),
            _ => (self.geo.as_deref(), self.file.as_deref()),
        }
    }
}

/// Constitutive model of the solid skeleton and the fluid flow. (Parsed once per run, so the
/// size difference between the variants does not matter.)
#[allow(clippy::large_enum_variant)]
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
    /// Finite-strain biphasic mixture (model.md §2–§3): Holmes–Mow solid, compaction penalty,
    /// Holmes–Mow permeability, gravity.
    HolmesMow {
        /// Shear modulus µ (kPa) and Poisson ratio ν of Ψ/Φs; the α's follow from eq. (56) ...
        #[serde(default)]
        mu: Option<f64>,
        #[serde(default)]
        nu: Option<f64>,
        /// ... or are given directly: [α0 (kPa), α1, α2] (α3 = 1).
        #[serde(default)]
        alpha: Option<[f64; 3]>,
        /// Referential solid fraction Φs.
        phi_s: f64,
        /// Referential conductivity k0 (µm⁴/(nN s); 1 mm⁴/(N s) = 1000).
        k0: f64,
        /// Permeability exponents: k = k0 [(J − Φs)/(1 − Φs)]^κ exp(m0 (J² − 1)/2).
        kappa: f64,
        m0: f64,
        /// Remodelling-dependent permeability (model.md (45)–(48)) with this c; isotropic if absent.
        #[serde(default)]
        permeability_c: Option<f64>,
        /// Compaction penalty U(J) (model.md (33)); none if absent.
        #[serde(default)]
        penalty: Option<PenaltySpec>,
        /// Visco-plastic remodelling of B_p (model.md §4); none if absent (B_p = I, no qp state).
        #[serde(default)]
        remodelling: Option<RemodellingSpec>,
        /// Densities (kg/m³).
        #[serde(default = "water")]
        rho_s: f64,
        #[serde(default = "water")]
        rho_f: f64,
        /// Gravity acceleration (m/s²).
        #[serde(default)]
        gravity: [f64; 3],
        /// No fluid: p ≡ 0 everywhere, the drained skeleton alone (each step a static solve,
        /// the limit a long hold relaxes to).
        #[serde(default)]
        drained: bool,
    },
}

/// Compaction penalty U(J) = Φs U0 H(J_cr − J) (J − J_cr)^{2q} / (J − Φs)^r.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PenaltySpec {
    pub j_cr: f64,
    /// U0 (kPa).
    pub u0: f64,
    pub q: f64,
    pub r: f64,
}

/// Perzyna remodelling dB_p/dt = −2 γp B_p dev Σ, γp = λp [‖dev σ‖ − √(2/3) σy]₊ / ‖dev σ‖.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct RemodellingSpec {
    /// λp in (kPa s)⁻¹ (Table 1: 0.001 = 1 (MPa s)⁻¹).
    pub lambda_p: f64,
    /// Yield stress σy (kPa).
    pub sigma_y: f64,
    /// Which form of the paper's flow rule (40): "40b" (default, dB_p/dt = −2 γp B_p dev Σ,
    /// what the paper says it solved) or "40a" (L b_e = −2 γp b_e dev σ: a rate 1/J faster).
    #[serde(default)]
    pub form: FlowForm,
    /// Step integrator: "implicit" (default: the exponential map, unconditionally stable),
    /// "trapezoidal" (half the step explicit, half implicit: second order, A-stable) or
    /// "explicit" (forward Euler in B_p, conditionally stable: for stability studies).
    #[serde(default)]
    pub integrator: Integrator,
}

fn water() -> f64 {
    1000.0
}

/// A boundary condition on a named physical surface group. Exactly one kind per entry.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct BoundaryCondition {
    pub group: String,
    /// Prescribed displacement components, e.g. `{ z = 0.0 }` or `{ x = 0, y = 0, z = 0 }`.
    #[serde(default)]
    pub displacement: Option<BTreeMap<Axis, f64>>,
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
    /// Only in this geometry (e.g. the quarter's symmetry rollers: `geometry = "solid"`); both if
    /// absent.
    #[serde(default)]
    pub geometry: Option<Geometry>,
}

/// A Cartesian axis: a displacement component's name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Axis {
    X,
    Y,
    Z,
}

impl Axis {
    /// 0, 1, 2.
    pub fn index(self) -> usize {
        self as usize
    }
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
    /// Largest step during the plates' loading ramp (0 to `plates.t_ramp`): backward Euler
    /// over-integrates a flow that rises through the ramp (the remodelling) by a share of
    /// Δt / t, which geometric growth keeps constant; a cap makes it shrink.
    #[serde(default)]
    pub dt_max_ramp: Option<f64>,
    /// dt_{n+1} = min(growth · dt_n, dt_max); 1 = constant steps. With `error_tolerance`, only
    /// where there is no error estimate (the first step after a kink of the loading).
    #[serde(default = "one")]
    pub growth: f64,
    /// Choose the steps by a local error estimate (see `driver::rate::StepRate::error`): the
    /// tolerance relative to each field's magnitude. Absent: geometric growth.
    #[serde(default)]
    pub error_tolerance: Option<f64>,
    #[serde(default)]
    pub land_on: Vec<f64>,
    /// Retries (each cutting the step, by 0.25 by default) allowed when a solve fails.
    #[serde(default = "default_retries")]
    pub max_retries: usize,
    /// A step cut below this (s) by failed solves ends the run with an error: the solve is not
    /// converging there, and ever shorter steps would only make the run crawl (default 1e-6 dt).
    #[serde(default)]
    pub dt_min: Option<f64>,
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
    /// Also write fields at these times (the time steps land on them).
    #[serde(default)]
    pub fields_at: Vec<f64>,
    /// Write a checkpoint every N steps (0: not by steps).
    #[serde(default = "default_checkpoint_every")]
    pub checkpoint_every: usize,
    /// Write a checkpoint when this much wall time (minutes) has passed since the last (0: not
    /// by time).
    #[serde(default = "default_checkpoint_minutes")]
    pub checkpoint_minutes: f64,
}
fn default_checkpoint_every() -> usize {
    25
}
fn default_checkpoint_minutes() -> f64 {
    10.0
}
impl Default for OutputSpec {
    fn default() -> Self {
        OutputSpec {
            fields_every: 1,
            fields: true,
            fields_at: vec![],
            checkpoint_every: default_checkpoint_every(),
            checkpoint_minutes: default_checkpoint_minutes(),
        }
    }
}
fn default_every() -> usize {
    1
}
fn yes() -> bool {
    true
}

/// An affine initial displacement u(X, 0) = G X (a homogeneous deformation F = I + G), e.g. a
/// stretch applied at t = 0 and then held by the boundary conditions.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct InitialSpec {
    /// G = Grad u, rows i: `G[i][j]` = ∂u_i/∂X_j.
    pub displacement_gradient: [[f64; 3]; 3],
}

/// A scalar observable written to `history.csv` each step.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct Probe {
    /// Column name.
    pub name: String,
    /// `p`, `ux`, `uy` or `uz`.
    pub field: ProbeField,
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

/// What a probe reads: the pore pressure or a displacement component.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ProbeField {
    P,
    Ux,
    Uy,
    Uz,
}

impl std::fmt::Display for ProbeField {
    /// The scene's spelling.
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        f.write_str(match self {
            ProbeField::P => "p",
            ProbeField::Ux => "ux",
            ProbeField::Uy => "uy",
            ProbeField::Uz => "uz",
        })
    }
}

/// The compression–release experiment (model.md §1, §5): rigid, flat, impermeable,
/// frictionless plates; the reference sphere (radius R, centre (0, 0, R)) touches the lower plate
/// (top face z = 0, moving up by u(t), eq. (53)) and the fixed upper plate (bottom face z = 2R).
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PlatesSpec {
    /// Radius R of the reference sphere (must match the mesh).
    pub radius: f64,
    /// Surface group that can touch the plates (and drains where it does not).
    #[serde(default = "default_surface")]
    pub group: String,
    /// ũ_max = u_max / (2R): the lower plate rises by u_max.
    pub compression: f64,
    /// Duration of each ramp (s).
    pub t_ramp: f64,
    /// End of the release ramp (s); the rest lasts until time.t_end.
    pub t_end: f64,
    /// p = 0 on the surface out of contact (false: sealed aggregate).
    #[serde(default = "yes")]
    pub drainage: bool,
    /// Point group of the bottom pole, kept on the lower plate (bilateral contact).
    #[serde(default = "default_anchor")]
    pub anchor: String,
    /// γ of the free-surface drainage conductance β_max = γ k0 / h (stiff Robin, p ≈ 0).
    #[serde(default = "default_penalty")]
    pub drainage_penalty: f64,
    /// Gap (µm) over which drainage opens as a contact separates (default 0.01 R).
    #[serde(default)]
    pub seal_gap: Option<f64>,
    /// Which gap opens the drainage within a step: the step predictor's (default) or the
    /// Newton iterate's (fully implicit; numerics.md, "Drainage that follows contact").
    #[serde(default)]
    pub drainage_gap: DrainageGap,
    /// The plates' permeability k_β (µm⁴/(nN s); the paper's Table 1: 3.7729e-4): fluid leaves
    /// through the contact area with the conductance k_β / `thickness` (a Robin outflow; the
    /// plates are impermeable when it is omitted).
    #[serde(default)]
    pub permeability: Option<f64>,
    /// The plates' thickness L (µm) that the outflow through them crosses (with `permeability`).
    #[serde(default)]
    pub thickness: Option<f64>,
    /// The material point X_U of the `probe_p` and `probe_porosity` columns (reference
    /// coordinates, µm; default the paper's (0.4 R, 0, 1.9 R), 1.5 µm under the surface).
    #[serde(default)]
    pub probe_point: Option<[f64; 3]>,
}

/// The gap that sets a surface vertex's drainage conductance during a step.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum DrainageGap {
    /// The step predictor's gap (semi-implicit: fixed during the Newton iteration).
    #[default]
    Predicted,
    /// The current iterate's gap (fully implicit, differentiated exactly).
    Current,
}

fn default_penalty() -> f64 {
    100.0
}

fn default_anchor() -> String {
    "pole_bottom".into()
}

fn default_surface() -> String {
    "surface".into()
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
    /// `auto` (default: `direct` for small systems, `fieldsplit` for large ones), `direct`
    /// (Krylov with a reused MUMPS factorisation), `fieldsplit` (Schur fieldsplit, AMG on u with
    /// rigid-body modes, fixed-stress Schur approximation) or `lu` (MUMPS for every Newton
    /// system, the reference). See `solver`.
    #[serde(default)]
    pub preset: Option<crate::solver::Preset>,
}

#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct FemSpec {
    /// Degree of the quadrature rule (default 2 for the linear model, exact on straight
    /// elements; 3 for the finite-strain models). On a meridian mesh the triangle rule is one
    /// degree higher (dV = 2πR dA).
    #[serde(default)]
    pub quadrature_degree: Option<usize>,
    /// c of the pressure stabilisation (c / (λ + 2µ)) ∫ (ṗ − Πṗ)(q − Πq) that keeps the
    /// undrained limit monotone next to drained boundaries (default 4: exact lumping; 0 off).
    #[serde(default)]
    pub stabilisation: Option<f64>,
    /// τ₀: the stabilisation fades as a step resolves the drainage, weight c (1 − (τ/τ₀)²)₊ with
    /// τ = c_v Δt / h² (`fem::kernel::Stabilisation`; default: constant). Taylor–Hood only:
    /// P1–P1 keeps the constant weight, which its inf–sup stability needs.
    #[serde(default)]
    pub stabilisation_fade: Option<f64>,
    /// The element: "P2-P1" (Taylor–Hood, default), "auto" (the measured best: P2–P1; see
    /// [`auto`]) or "P1-P1" (equal order, unstable without
    /// the stabilisation; `fem::equal_order`). With plates, P1–P1's contact bounds and contact
    /// state are on the vertices (its mid-edge nodes follow their edges); its stabilisation
    /// keeps the constant weight (`stabilisation_fade` is for Taylor–Hood only).
    #[serde(default)]
    pub element: Option<Element>,
}

/// The element pair of the u–p discretisation.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
pub enum Element {
    /// Taylor–Hood P2–P1.
    #[serde(rename = "P2-P1")]
    P2P1,
    /// Equal-order P1–P1 (`fem::equal_order`).
    #[serde(rename = "P1-P1")]
    P1P1,
    /// The measured best for the scene; resolved when the scene is loaded ([`auto::resolve`]).
    #[serde(rename = "auto")]
    Auto,
}

impl FemSpec {
    /// Equal-order P1–P1 instead of Taylor–Hood.
    pub fn equal_order(&self) -> bool {
        self.element == Some(Element::P1P1)
    }
}

/// A scene together with where it came from.
#[derive(Debug, Clone)]
pub struct LoadedScene {
    pub scene: Scene,
    /// The `--set KEY=VALUE` overrides applied to the file (already in `scene`).
    pub overrides: Vec<String>,
    /// The file, or `builtin:<name>`.
    pub source: String,
    /// Directory relative paths are resolved against (None for builtin scenes).
    pub dir: Option<PathBuf>,
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
];

impl LoadedScene {
    /// Loads `arg`: a path to a `.toml` file, or the name of a builtin scene, with the
    /// `--set KEY=VALUE` overrides applied in order (see [`overrides`]).
    pub fn load(arg: &str, overrides: &[String]) -> Result<LoadedScene> {
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
        let mut scene: Scene = if overrides.is_empty() {
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
        if scene.name.is_empty() {
            scene.name = stem;
        }
        auto::resolve(&mut scene).map_err(scene_err)?;
        let loaded = LoadedScene { scene, overrides: overrides.to_vec(), source, dir };
        loaded.validate()?;
        Ok(loaded)
    }

    fn err(&self, msg: impl Into<String>) -> Error {
        Error::Scene { path: self.source.clone(), msg: msg.into() }
    }

    /// Checks ranges and consistency; every message names the offending key and value.
    pub fn validate(&self) -> Result<()> {
        self.validate_mesh()?;
        self.validate_material()?;
        self.validate_bcs()?;
        self.validate_initial()?;
        self.validate_output()?;
        self.validate_time()?;
        self.validate_probes()?;
        self.validate_plates()?;
        self.validate_verification()?;
        self.validate_fem()?;
        self.validate_petsc()?;
        Ok(())
    }

    /// [mesh]: one source, mirror only for solids, finite positive lengths.
    fn validate_mesh(&self) -> Result<()> {
        let s = &self.scene;
        match (&s.mesh.geo, &s.mesh.file) {
            (Some(_), Some(_)) => return Err(self.err("[mesh]: give either `geo` or `file`, not both")),
            (None, None) => return Err(self.err("[mesh]: give `geo` (a .geo source) or `file` (a .msh mesh)")),
            _ => {}
        }
        if s.mesh.geometry == Geometry::Axisymmetric && !s.mesh.mirror.is_empty() {
            return Err(self
                .err("[mesh]: mirror is for solid (3-D) meshes; an axisymmetric meridian is already the whole body"));
        }
        for (k, v) in &s.mesh.params {
            if !v.is_finite() {
                return Err(self.err(format!("[mesh.params] {k} = {v} is not a finite number")));
            }
            if ["R", "h", "h_pole", "H", "W"].contains(&k.as_str()) && *v <= 0.0 {
                return Err(self.err(format!("[mesh.params] {k} = {v}: a length must be positive")));
            }
        }
        Ok(())
    }

    /// [material]: the parameters of the model in their physical ranges.
    fn validate_material(&self) -> Result<()> {
        let s = &self.scene;
        match &s.material {
            Material::Linear { mu, nu, permeability } => {
                positive(self, "material.mu", *mu)?;
                poisson(self, *nu)?;
                positive(self, "material.permeability", *permeability)?;
            }
            Material::HolmesMow {
                mu,
                nu,
                alpha,
                phi_s,
                k0,
                kappa,
                m0,
                permeability_c,
                rho_s,
                rho_f,
                gravity,
                remodelling,
                ..
            } => {
                match (mu, nu, alpha) {
                    (Some(mu), Some(nu), None) => {
                        positive(self, "material.mu", *mu)?;
                        poisson(self, *nu)?;
                    }
                    (None, None, Some(a)) => positive(self, "material.alpha[0]", a[0])?,
                    _ => return Err(self.err("[material] holmes_mow: give `mu` and `nu`, or `alpha` (not both)")),
                }
                if !(*phi_s > 0.0 && *phi_s < 1.0) {
                    return Err(self.err(format!("material.phi_s = {phi_s}: solid fraction must lie in (0, 1)")));
                }
                positive(self, "material.k0", *k0)?;
                finite(self, "material.kappa", *kappa)?;
                finite(self, "material.m0", *m0)?;
                if let Some(c) = permeability_c {
                    positive(self, "material.permeability_c", *c)?;
                }
                if let Some(r) = remodelling {
                    non_negative(self, "material.remodelling.lambda_p", r.lambda_p)?;
                    non_negative(self, "material.remodelling.sigma_y", r.sigma_y)?;
                }
                for (key, rho) in [("material.rho_s", *rho_s), ("material.rho_f", *rho_f)] {
                    if !(rho.is_finite() && rho >= 0.0) {
                        return Err(self.err(format!("{key} = {rho}: must be >= 0 (kg/m^3)")));
                    }
                }
                for g in gravity {
                    finite(self, "material.gravity", *g)?;
                }
            }
        }
        Ok(())
    }

    /// [[bc]]: one kind per entry, known displacement components, one traction form.
    fn validate_bcs(&self) -> Result<()> {
        let s = &self.scene;
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
            for v in bc.displacement.iter().flat_map(|d| d.values()) {
                finite(self, "displacement", *v)?;
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
        Ok(())
    }

    /// [initial]: a finite displacement gradient with det(I + G) > 0.
    fn validate_initial(&self) -> Result<()> {
        let s = &self.scene;
        if let Some(init) = &s.initial {
            for g in init.displacement_gradient.iter().flatten() {
                finite(self, "initial.displacement_gradient", *g)?;
            }
            let f =
                nalgebra::Matrix3::from_fn(|i, j| init.displacement_gradient[i][j] + if i == j { 1.0 } else { 0.0 });
            if f.determinant() <= 0.0 {
                return Err(
                    self.err(format!("initial.displacement_gradient: det(I + G) = {} must be > 0", f.determinant()))
                );
            }
        }
        Ok(())
    }

    /// [output]: the checkpoint interval.
    fn validate_output(&self) -> Result<()> {
        let s = &self.scene;
        let m = s.output.checkpoint_minutes;
        if !(m.is_finite() && m >= 0.0) {
            return Err(self.err(format!("output.checkpoint_minutes = {m}: must be >= 0 (0: not by time)")));
        }
        Ok(())
    }

    /// [time]: positive steps and end time, growth >= 1, landing times inside the run.
    fn validate_time(&self) -> Result<()> {
        let s = &self.scene;
        let t = &s.time;
        for &a in t.land_on.iter().chain(&s.output.fields_at) {
            if !(a > 0.0 && a <= t.t_end) {
                return Err(
                    self.err(format!("time.land_on / output.fields_at: {a} must lie in (0, time.t_end = {}]", t.t_end))
                );
            }
        }
        positive(self, "time.t_end", t.t_end)?;
        positive(self, "time.dt", t.dt)?;
        if let Some(m) = t.dt_max_ramp {
            positive(self, "time.dt_max_ramp", m)?;
            if s.plates.is_none() {
                return Err(
                    self.err("time.dt_max_ramp caps the steps of the plates' loading ramp: the scene has no [plates]")
                );
            }
            if t.dt > m {
                return Err(self
                    .err(format!("time.dt = {} exceeds time.dt_max_ramp = {m}: the first step must be <= it", t.dt)));
            }
        }
        if let Some(m) = t.dt_max {
            positive(self, "time.dt_max", m)?;
            if t.dt > m {
                return Err(
                    self.err(format!("time.dt = {} exceeds time.dt_max = {m}: the first step must be <= dt_max", t.dt))
                );
            }
        }
        if let Some(e) = t.error_tolerance {
            positive(self, "time.error_tolerance", e)?;
        }
        if let Some(m) = t.dt_min {
            positive(self, "time.dt_min", m)?;
            if m >= t.dt {
                return Err(self.err(format!("time.dt_min = {m}: must be below the first step time.dt = {}", t.dt)));
            }
        }
        if !(t.growth >= 1.0 && t.growth.is_finite()) {
            return Err(self.err(format!("time.growth = {}: must be >= 1", t.growth)));
        }
        Ok(())
    }

    /// [[probe]]: a known field, one location, a finite non-zero scale.
    fn validate_probes(&self) -> Result<()> {
        let s = &self.scene;
        for p in &s.probe {
            if p.point.is_some() == p.group.is_some() {
                return Err(self.err(format!("probe \"{}\": give exactly one of `point` or `group`", p.name)));
            }
            if p.scale == 0.0 || !p.scale.is_finite() {
                return Err(self.err(format!("probe \"{}\": scale must be finite and non-zero", p.name)));
            }
        }
        Ok(())
    }

    /// [plates]: geometry, loading, drainage and the plates' permeability.
    fn validate_plates(&self) -> Result<()> {
        let s = &self.scene;
        if let Some(p) = &s.plates {
            positive(self, "plates.radius", p.radius)?;
            if !(p.compression.is_finite() && p.compression >= 0.0 && p.compression < 1.0) {
                return Err(self.err(format!("plates.compression = {}: must lie in [0, 1)", p.compression)));
            }
            positive(self, "plates.t_ramp", p.t_ramp)?;
            if !(p.t_end.is_finite() && p.t_end >= 2.0 * p.t_ramp) {
                return Err(self.err(format!(
                    "plates.t_end = {}: must be at least 2 t_ramp = {}",
                    p.t_end,
                    2.0 * p.t_ramp
                )));
            }
            positive(self, "plates.drainage_penalty", p.drainage_penalty)?;
            if let Some(g) = p.seal_gap {
                positive(self, "plates.seal_gap", g)?;
            }
            match (p.permeability, p.thickness) {
                (Some(k), Some(l)) => {
                    if !(k.is_finite() && k >= 0.0) {
                        return Err(self.err(format!("plates.permeability = {k}: must be >= 0")));
                    }
                    positive(self, "plates.thickness", l)?;
                    if !p.drainage && k > 0.0 {
                        return Err(self.err(
                            "plates.permeability: the plates drain the contact area, but plates.drainage = false seals the \
                             aggregate (drop one of them)"
                                .to_string(),
                        ));
                    }
                }
                (Some(_), None) => {
                    return Err(
                        self.err("plates.permeability needs plates.thickness (µm), the plates' thickness".to_string())
                    )
                }
                (None, Some(_)) => {
                    return Err(self.err("plates.thickness is only used with plates.permeability: set both".to_string()))
                }
                (None, None) => {}
            }
            for x in p.probe_point.iter().flatten() {
                finite(self, "plates.probe_point", *x)?;
            }
        }
        Ok(())
    }

    /// [verification]: a positive length and a finite load.
    fn validate_verification(&self) -> Result<()> {
        let s = &self.scene;
        if let Some(v) = &s.verification {
            let (a, b) = match v {
                Verification::Terzaghi { height, load } => (height, load),
                Verification::Cryer { radius, load } => (radius, load),
            };
            positive(self, "verification length", *a)?;
            finite(self, "verification load", *b)?;
        }
        Ok(())
    }

    /// [fem]: stabilisation, element and quadrature degree.
    fn validate_fem(&self) -> Result<()> {
        let s = &self.scene;
        if let Some(a) = s.fem.stabilisation {
            if !(a.is_finite() && a >= 0.0) {
                return Err(self.err(format!("fem.stabilisation = {a}: must be >= 0")));
            }
        }
        if let Some(t) = s.fem.stabilisation_fade {
            if !(t.is_finite() && t > 0.0) {
                return Err(self.err(format!("fem.stabilisation_fade = {t}: must be positive (omit it for none)")));
            }
        }
        if let Some(q) = s.fem.quadrature_degree {
            if !(1..=8).contains(&q) {
                return Err(self.err(format!("fem.quadrature_degree = {q}: use 1..8")));
            }
        }
        Ok(())
    }

    /// [petsc]: scalar values only.
    fn validate_petsc(&self) -> Result<()> {
        let s = &self.scene;
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

    /// Where the scene's mesh comes from (`mesh.file`, or the `.geo` of its geometry), resolved
    /// against the scene file.
    pub fn mesh_source(&self) -> crate::mesh::source::MeshSource<'_> {
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
    pub fn resolve(&self, p: &str) -> PathBuf {
        match &self.dir {
            Some(d) if Path::new(p).is_relative() => d.join(p),
            _ => PathBuf::from(p),
        }
    }

    /// The scene as TOML (for the run directory).
    pub fn to_toml(&self) -> Result<String> {
        toml::to_string_pretty(&self.scene)
            .map_err(|e| self.err(format!("cannot write the resolved scene as TOML: {e}")))
    }
}

/// The scene of a TOML table (the file with `--set` overrides applied).
fn from_table(table: &toml::Table) -> std::result::Result<Scene, toml::de::Error> {
    toml::Value::Table(table.clone()).try_into()
}

/// The message of a scene that cannot be read once its overrides are applied: "--set SPEC:
/// message" for the override without which the error goes away or changes (the last such), else
/// the scene file's own error (`toml_message`).
fn override_message(text: &str, file: &toml::Table, specs: &[String], e: &toml::de::Error) -> String {
    let msg = plain(e.message().trim());
    for skip in (0..specs.len()).rev() {
        let mut t = file.clone();
        for (_, spec) in specs.iter().enumerate().filter(|(i, _)| *i != skip) {
            // An override that no longer applies without the skipped one changes the error too.
            if overrides::apply(&mut t, spec).is_err() {
                return format!("--set {}: {msg}", specs[skip]);
            }
        }
        let same = matches!(from_table(&t), Err(e2) if plain(e2.message().trim()) == msg);
        if !same {
            return format!("--set {}: {msg}", specs[skip]);
        }
    }
    match toml::from_str::<Scene>(text) {
        Err(fe) => toml_message(text, &fe),
        Ok(_) => format!("with the overrides --set {}: {msg}", specs.join(" --set ")),
    }
}

/// The dotted key of the value a serde type error ("invalid type: sequence, expected a number")
/// or unknown choice ("unknown variant `40c`, expected `40b` or `40a`") is about — serde loses
/// it inside tagged enums such as `[material]`: of the values of that kind (or that string),
/// the one whose removal changes the error (the innermost, if a table and its value both do).
/// None unless exactly one.
fn culprit_key(table: &toml::Table, msg: &str) -> Option<String> {
    // The values the error can be about: of the kind it names, or the string it names.
    let suspect: Box<dyn Fn(&toml::Value) -> bool> = if let Some(kind) = msg.strip_prefix("invalid type: ") {
        Box::new(move |v| kind.starts_with(serde_kind(v)))
    } else {
        let variant = unknown_variant(msg)?;
        Box::new(move |v| v.as_str() == Some(variant))
    };
    let base = plain(from_table(table).err()?.message().trim());
    fn collect(
        v: &toml::Value,
        path: &mut Vec<String>,
        suspect: &dyn Fn(&toml::Value) -> bool,
        out: &mut Vec<Vec<String>>,
    ) {
        let children: Vec<(String, &toml::Value)> = match v {
            toml::Value::Table(t) => t.iter().map(|(k, v)| (k.clone(), v)).collect(),
            toml::Value::Array(a) => a.iter().enumerate().map(|(i, v)| (i.to_string(), v)).collect(),
            _ => return,
        };
        for (k, child) in children {
            path.push(k);
            if suspect(child) {
                out.push(path.clone());
            }
            collect(child, path, suspect, out);
            path.pop();
        }
    }
    fn remove(v: &mut toml::Value, path: &[String]) {
        let Some((first, rest)) = path.split_first() else { return };
        let child = match v {
            toml::Value::Table(t) if rest.is_empty() => {
                t.remove(first);
                return;
            }
            toml::Value::Array(a) if rest.is_empty() => {
                if let Ok(i) = first.parse::<usize>() {
                    if i < a.len() {
                        a.remove(i);
                    }
                }
                return;
            }
            toml::Value::Table(t) => t.get_mut(first),
            toml::Value::Array(a) => first.parse::<usize>().ok().and_then(|i| a.get_mut(i)),
            _ => None,
        };
        if let Some(c) = child {
            remove(c, rest);
        }
    }
    let mut candidates = Vec::new();
    collect(&toml::Value::Table(table.clone()), &mut Vec::new(), suspect.as_ref(), &mut candidates);
    let culprits: Vec<Vec<String>> = candidates
        .into_iter()
        .filter(|p| {
            let mut v = toml::Value::Table(table.clone());
            remove(&mut v, p);
            let toml::Value::Table(t) = v else { return false };
            !matches!(from_table(&t), Err(e) if plain(e.message().trim()) == base)
        })
        .collect();
    let innermost: Vec<&Vec<String>> =
        culprits.iter().filter(|p| !culprits.iter().any(|q| q.len() > p.len() && q.starts_with(p))).collect();
    match innermost[..] {
        [p] => Some(p.join(".")),
        _ => None,
    }
}

/// The choice an "unknown variant `X`, expected ..." error names.
fn unknown_variant(msg: &str) -> Option<&str> {
    msg.strip_prefix("unknown variant `")?.split_once('`').map(|(v, _)| v)
}

/// serde's name of the kind of a TOML value (as in "invalid type: <kind>").
fn serde_kind(v: &toml::Value) -> &'static str {
    match v {
        toml::Value::String(_) => "string",
        toml::Value::Integer(_) => "integer",
        toml::Value::Float(_) => "floating point",
        toml::Value::Boolean(_) => "boolean",
        toml::Value::Datetime(_) => "datetime",
        toml::Value::Array(_) => "sequence",
        toml::Value::Table(_) => "map",
    }
}

/// A TOML error on one line: "line N (`text`): message" (the parser's own text spans lines).
/// A type error or an unknown choice names its key: "line N (`text`): material.phi_s: message"
/// — serde loses the key inside tagged enums such as `[material]`, and reports the whole table;
/// then the key is found by [`culprit_key`] and the line is its `key = value` line in the table
/// (or, failing that, the one line of the table whose value has that type, or holds that
/// choice as a string).
fn toml_message(text: &str, e: &toml::de::Error) -> String {
    let msg = plain(&e.message().replace('\n', " "));
    match e.span() {
        Some(span) => {
            let start = span.start.min(text.len());
            let mut line = text[..start].matches('\n').count() + 1;
            let region = &text[start..span.end.clamp(start, text.len())];
            let key = toml::from_str::<toml::Table>(text).ok().and_then(|t| culprit_key(&t, &msg));
            let name = key.as_deref().map(|k| k.rsplit('.').next().unwrap_or(k));
            let at = name.and_then(|n| {
                region.lines().position(|l| l.split_once('=').is_some_and(|(k, _)| k.trim().trim_matches('"') == n))
            });
            if let Some(i) = at {
                line += i;
            } else if let Some(kind) = msg.strip_prefix("invalid type: ") {
                let hits: Vec<usize> = region
                    .lines()
                    .enumerate()
                    .filter(|(_, l)| value_kind(l).is_some_and(|k| kind.starts_with(k)))
                    .map(|(i, _)| i)
                    .collect();
                if let [i] = hits[..] {
                    line += i;
                }
            } else if let Some(v) = unknown_variant(&msg) {
                let quoted = [format!("\"{v}\""), format!("'{v}'")];
                let hits: Vec<usize> = region
                    .lines()
                    .enumerate()
                    .filter(|(_, l)| quoted.iter().any(|q| l.contains(q.as_str())))
                    .map(|(i, _)| i)
                    .collect();
                if let [i] = hits[..] {
                    line += i;
                }
            }
            let what = text.lines().nth(line - 1).unwrap_or("").trim();
            match key {
                Some(k) => format!("line {line} (`{what}`): {k}: {msg}"),
                None => format!("line {line} (`{what}`): {msg}"),
            }
        }
        None => msg,
    }
}

/// serde's Rust type names in words: "expected usize" → "expected a non-negative integer".
fn plain(msg: &str) -> String {
    let mut m = msg.to_string();
    for (rust, words) in [
        ("expected usize", "expected a non-negative integer"),
        ("expected u64", "expected a non-negative integer"),
        ("expected u32", "expected a non-negative integer"),
        ("expected i64", "expected an integer"),
        ("expected i32", "expected an integer"),
        ("expected f64", "expected a number"),
    ] {
        if let Some(rest) = m.strip_suffix(rust) {
            m = format!("{rest}{words}");
        }
    }
    m
}

/// The serde name of the kind of value on a `key = value` line (None for other lines).
fn value_kind(line: &str) -> Option<&'static str> {
    let (key, value) = line.split_once('=')?;
    let (key, v) = (key.trim(), value.trim());
    if key.is_empty() || key.starts_with(['#', '[']) {
        return None;
    }
    Some(match v.chars().next()? {
        '[' => "sequence",
        '{' => "map",
        '"' | '\'' => "string",
        't' | 'f' if v.starts_with("true") || v.starts_with("false") => "boolean",
        _ if v.split(['#', ' ']).next().is_some_and(|n| n.parse::<i64>().is_ok()) => "integer",
        _ => "floating point",
    })
}

fn poisson(s: &LoadedScene, nu: f64) -> Result<()> {
    if nu.is_finite() && nu > -1.0 && nu < 0.5 {
        Ok(())
    } else {
        Err(s.err(format!("material.nu = {nu}: Poisson ratio must lie in (-1, 0.5)")))
    }
}

fn positive(s: &LoadedScene, key: &str, v: f64) -> Result<()> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(s.err(format!("{key} = {v}: must be positive")))
    }
}

fn non_negative(s: &LoadedScene, key: &str, v: f64) -> Result<()> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(s.err(format!("{key} = {v}: must be finite and >= 0")))
    }
}

fn finite(s: &LoadedScene, key: &str, v: f64) -> Result<()> {
    if v.is_finite() {
        Ok(())
    } else {
        Err(s.err(format!("{key} = {v}: must be finite")))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_type_error_in_a_tagged_table_names_its_line() {
        let text = "name = \"x\"\n[mesh]\ngeo = \"column.geo\"\n[material]\nmodel = \"linear\"\nmu = [1]\nnu = 0.2\n";
        let e = toml::from_str::<Scene>(text).expect_err("mu is not a number");
        let m = toml_message(text, &e);
        assert_eq!(m, "line 6 (`mu = [1]`): material.mu: invalid type: sequence, expected a number");
        // Two values of that kind in the table: the key is the one whose removal changes the error.
        let text = "[mesh]\ngeo = \"g\"\n[material]\nmodel = \"holmes_mow\"\nmu = 20.0\nnu = 0.2\n\
                    phi_s = [0.6]\nk0 = 1.0\nkappa = 1.0\nm0 = 0.1\ngravity = [0.0, 0.0, -9.81]\n";
        let e = toml::from_str::<Scene>(text).expect_err("phi_s is not a number");
        let m = toml_message(text, &e);
        assert_eq!(m, "line 7 (`phi_s = [0.6]`): material.phi_s: invalid type: sequence, expected a number");
        assert_eq!(value_kind("nu = 0.2  # comment"), Some("floating point"));
        assert_eq!(value_kind("n = 3"), Some("integer"));
        assert_eq!(value_kind("drained = true"), Some("boolean"));
        assert_eq!(value_kind("[material]"), None);
    }

    #[test]
    fn an_unknown_choice_names_its_key_line_and_the_choices() {
        let text = "[mesh]\ngeo = \"g\"\n[material]\nmodel = \"holmes_mow\"\nmu = 20.0\nnu = 0.2\nphi_s = 0.6\n\
                    k0 = 1.0\nkappa = 1.0\nm0 = 0.1\nremodelling = { lambda_p = 0.001, sigma_y = 2.0, form = \"40c\" }\n";
        let e = toml::from_str::<Scene>(text).expect_err("40c is no flow rule");
        assert_eq!(
            toml_message(text, &e),
            "line 11 (`remodelling = { lambda_p = 0.001, sigma_y = 2.0, form = \"40c\" }`): material.remodelling.form: \
             unknown variant `40c`, expected `40b` or `40a`"
        );
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
