//! What a run observes of a converged state, as the recorder's records (`io::recorder`): the
//! `history.csv` columns of the experiment, the remodelling summary, the probes and the exact
//! solutions (declared by [`Observers::columns`]), and the fields. Observing is two phases, so
//! that the state at t = 0 can be sampled before the first step (with the qp state it had) and
//! observed after it: [`Observers::sample`] post-processes the state, [`Observers::observe`]
//! turns a sample into the step's [`Observed`] values.

use super::aspiration;
use super::experiment::{self, Experiment};
use super::force_control;
use super::pressure_peak::PressurePeak;
use super::probe::Probe;
use super::remodelling_summary;
use super::tools;
use super::verification::{exact_columns, Exact};
use crate::error::Result;
use crate::io::recorder::{Column, ColumnKind, Declared, Observed, StepFields};
use crate::mesh::dist::LocalMesh;
use crate::petsc::Vector;
use crate::physics::problem::{backward_euler_rate, PoroProblem, Post};
use crate::scene::LoadedScene;
use mpi::topology::SimpleCommunicator;

/// What is observed besides the state itself; built (and validated) before the run directory
/// is touched.
pub(crate) struct Observers {
    pub(crate) probes: Vec<Probe>,
    /// The plates experiment's observables, if the scene has plates.
    pub(crate) experiment: Option<Experiment>,
    /// The names of the scene's tools (their columns: `observe::tools`).
    pub(crate) tools: Vec<String>,
    /// Whether the upper plate has force rows: its position and target are recorded.
    pub(crate) force_control: bool,
    /// Whether the medium's aspirated length and drag are recorded (`aspiration::columns`).
    pub(crate) medium: (bool, bool),
    /// Exact-solution columns of a verification scene.
    pub(crate) exact: Vec<Exact>,
    /// Whether the model keeps qp state (remodelling): its summary is recorded.
    pub(crate) remodelling: bool,
    /// Write fields at all.
    pub(crate) fields: bool,
    /// The largest nodal p of the steps observed so far (with a checkpoint's, after a resume).
    pub(crate) pressure_peak: PressurePeak,
    /// The owned mid-edge nodes and their edges' ends ([`mid_edge_nodes`]): where the fields show
    /// the P1 pressure interpolated (empty without fields).
    pub(crate) mid_edges: Vec<(usize, usize, usize)>,
}

/// A converged state sampled for output: its local (owned + ghost) values, post-processed when
/// something reads more than the values.
pub(crate) enum Sample {
    State(Vec<f64>),
    Post(Box<Post>),
}

impl Sample {
    fn local(&self) -> &[f64] {
        match self {
            Sample::State(l) => l,
            Sample::Post(p) => &p.local,
        }
    }
}

impl Observers {
    /// The `history.csv` columns these observers fill, in the order of [`Observed::values`]
    /// (the recorder adds the step's own around them).
    pub(crate) fn columns(&self) -> Vec<Column> {
        observed_columns(
            self.experiment.is_some(),
            self.force_control,
            self.tools.iter().map(String::as_str),
            self.medium,
            self.remodelling,
            self.probes.iter().map(|p| p.name.as_str()).chain(self.exact.iter().map(|e| e.doc.name)),
        )
    }

    /// The experiment's time-integrated outflow so far (0 without plates).
    pub(crate) fn outflow(&self) -> f64 {
        self.experiment.as_ref().map_or(0.0, |e| e.outflow())
    }

    /// Restores the experiment's outflow of a checkpoint.
    pub(crate) fn set_outflow(&mut self, outflow: f64) {
        if let Some(ex) = self.experiment.as_mut() {
            ex.set_outflow(outflow);
        }
    }

    /// Samples the state `u` at time t reached from `prev` in a step of size dt (0: the initial
    /// state):
    /// the post-processing element loop (reactions, cell fields) only when something reads it;
    /// probes and history alone need just the local state.
    pub(crate) fn sample(
        &self,
        problem: &mut PoroProblem,
        u: &Vector,
        prev: &Vector,
        t: f64,
        dt: f64,
        fields: bool,
    ) -> Result<Sample> {
        let drag = self.medium.1;
        if self.experiment.is_some() || !self.tools.is_empty() || (fields && self.fields) || self.remodelling || drag {
            let dt_eff = if dt > 0.0 { dt } else { 1.0 };
            let udot = backward_euler_rate(u, prev, dt_eff)?;
            Ok(Sample::Post(Box::new(problem.post_process(t, dt_eff, u, &udot)?)))
        } else {
            Ok(Sample::State(problem.localize(u)?))
        }
    }

    /// The observed values of a sample at time t after a step of size dt, with the fields if
    /// `fields` (collective). The experiment's outflow takes the drainage gaps of the problem's
    /// last step.
    pub(crate) fn observe(
        &mut self,
        world: &SimpleCommunicator,
        problem: &PoroProblem,
        sample: Sample,
        t: f64,
        dt: f64,
        fields: bool,
    ) -> Observed {
        let (mesh, dofs) = (problem.mesh(), problem.dofs());
        let local = sample.local();
        let post = match &sample {
            Sample::Post(p) => Some(p.as_ref()),
            Sample::State(_) => None,
        };
        let mut values = Vec::new();
        let obs = match (&mut self.experiment, problem.plates(), post) {
            (Some(ex), Some(pl), Some(post)) => {
                Some(ex.observe(t, dt, pl, mesh, dofs, post, problem.drainage_outflow(&post.local, t), world))
            }
            _ => None,
        };
        if let Some(o) = &obs {
            values.extend(o.values());
        }
        if let (true, Some(pl), Some(post)) = (self.force_control, problem.plates(), post) {
            values.extend(Declared::row(&force_control::COLUMNS, &force_control::observe(pl, t, post.upper_d)));
        }
        if let (Some(post), Some(set)) = (post, problem.tools()) {
            values.extend(tools::read(&set, &post.tool_d, dofs, local, &post.reaction, world));
        }
        if let (true, Some(m)) = (self.medium.0, problem.medium()) {
            values.extend(Declared::row(&aspiration::LENGTH, &aspiration::aspiration(m, mesh, dofs, local, world)));
        }
        if let (true, Some(m), Some(post)) = (self.medium.1, problem.medium(), post) {
            values.extend(Declared::row(&aspiration::DRAG, &aspiration::drag(post.drag, m.meridian(), world)));
        }
        if let (Some(post), true) = (post, self.remodelling) {
            let summary = remodelling_summary::observe(post, world);
            values.extend(Declared::row(&remodelling_summary::COLUMNS, &summary));
        }
        self.pressure_peak = self.pressure_peak.max(PressurePeak::of_state(mesh, dofs, local, t, world));
        values.extend(self.probes.iter().map(|p| p.value(mesh, dofs, local, world)));
        values.extend(self.exact.iter().map(|e| (e.value)(t)));
        let fields = match (sample, fields && self.fields) {
            (Sample::Post(post), true) => {
                let post = *post;
                let (u, p) = node_fields(problem, &post.local, &self.mid_edges);
                Some(StepFields {
                    u,
                    p,
                    j: post.cell_j,
                    von_mises: post.cell_von_mises,
                    darcy_flux: post.cell_darcy,
                    porosity: problem.model().solid_fraction().map(|_| post.cell_porosity),
                    contact: obs.map(|o| o.node_contact),
                    norm_ep: self.remodelling.then_some(post.cell_norm_ep),
                })
            }
            _ => None,
        };
        Observed { values, fields }
    }
}

/// The observed columns, in order: the experiment's (with plates), the upper plate's (with
/// force rows), the tools' (five per tool), the medium's (aspirated length, drag: as `medium`
/// says), the remodelling summary's (with qp state), then `named` (the probes', then the exact
/// solutions').
fn observed_columns<'a>(
    plates: bool,
    force: bool,
    tool_names: impl Iterator<Item = &'a str>,
    medium: (bool, bool),
    remodelling: bool,
    named: impl Iterator<Item = &'a str>,
) -> Vec<Column> {
    let mut cols = Vec::new();
    if plates {
        cols.extend(experiment::columns().map(|(doc, kind)| Column::of(doc, kind)));
    }
    if force {
        cols.extend(Declared::header(&force_control::COLUMNS));
    }
    cols.extend(tools::column_names(tool_names).into_iter().map(|name| {
        let kind = if name.ends_with("_contact_nodes") { ColumnKind::Integer } else { ColumnKind::Real };
        Column { name, kind }
    }));
    if medium.0 {
        cols.extend(Declared::header(&aspiration::LENGTH));
    }
    if medium.1 {
        cols.extend(Declared::header(&aspiration::DRAG));
    }
    if remodelling {
        cols.extend(Declared::header(&remodelling_summary::COLUMNS));
    }
    cols.extend(named.map(Column::real));
    cols
}

/// The names of the `history.csv` columns a run of `scene` writes, in order, from the scene alone
/// (no mesh, no PETSc): what `poroplast columns` prints, and what a sweep's observables and a
/// fit's column are checked against before anything runs.
pub fn history_column_names(scene: &LoadedScene) -> Result<Vec<String>> {
    let s = &scene.scene;
    let remodelling = s.material.mixture().is_some_and(|m| m.remodelling.is_some());
    let exact = exact_columns(scene)?;
    let named = s.probe.iter().map(|p| p.name.as_str()).chain(exact.iter().map(|e| e.doc.name));
    let force = s.plates.as_ref().is_some_and(|p| p.upper.iter().flatten().any(|r| r.force.is_some()));
    let medium = aspiration::columns(s.medium.as_ref());
    let observed = observed_columns(s.plates.is_some(), force, s.tool_names(), medium, remodelling, named);
    Ok(crate::io::recorder::history_columns(&observed).into_iter().map(|c| c.name).collect())
}

/// u (three components) and p at the owned nodes from the local state: p of a mid-edge node is
/// the mean of its edge's ends.
fn node_fields(problem: &PoroProblem, local: &[f64], mid_edges: &[(usize, usize, usize)]) -> (Vec<f64>, Vec<f64>) {
    let (mesh, dofs) = (problem.mesh(), problem.dofs());
    let n = mesh.n_owned_nodes;
    let nc = dofs.nc;
    let mut u = vec![0.0; 3 * n];
    for node in 0..n {
        for (c, &a) in mesh.family.axes().iter().enumerate() {
            u[3 * node + a] = local[nc * node + c];
        }
    }
    let mut p = vec![0.0; n];
    for (node, pv) in p.iter_mut().enumerate() {
        let v = mesh.vertex_of_node[node];
        if v >= 0 {
            *pv = local[dofs.p_local(v as usize)];
        }
    }
    for &(m, a, b) in mid_edges {
        let pa = local[dofs.p_local(mesh.vertex_of_node[a] as usize)];
        let pb = local[dofs.p_local(mesh.vertex_of_node[b] as usize)];
        p[m] = 0.5 * (pa + pb);
    }
    (u, p)
}

/// (mid-edge node, end a, end b) for owned mid-edge nodes, to show P1 pressure on P2 nodes.
pub(crate) fn mid_edge_nodes(mesh: &LocalMesh) -> Vec<(usize, usize, usize)> {
    let mut seen = vec![false; mesh.n_owned_nodes];
    let mut out = Vec::new();
    let nv = mesh.family.cell_vertices();
    for t in &mesh.cells {
        for (e, &(a, b)) in mesh.family.edges().iter().enumerate() {
            let m = t[nv + e] as usize;
            if m < mesh.n_owned_nodes && !seen[m] {
                seen[m] = true;
                out.push((m, t[a] as usize, t[b] as usize));
            }
        }
    }
    out
}
