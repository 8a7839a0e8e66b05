//! What a run writes per step: one `history.csv` row (the experiment's observables, the
//! remodelling summary, probes, exact columns, iteration counts) and, when asked, the fields.

use crate::error::Result;
use crate::io::fields::{restore_backup, Field, FieldFile, FieldKind, OutputMesh};
use crate::io::history::History;
use crate::mesh::dist::LocalMesh;
use crate::petsc::Vector;
use crate::physics::experiment::{self, Experiment};
use crate::physics::observables;
use crate::physics::probe::Probe;
use crate::physics::problem::{rate, PoroProblem};
use crate::physics::verification::ExactFn;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::{Path, PathBuf};

/// What is observed besides the state itself; built (and validated) before the run directory
/// is touched.
pub struct Observers {
    pub probes: Vec<Probe>,
    /// The plates experiment's observables, if the scene has plates.
    pub experiment: Option<Experiment>,
    /// Exact-solution columns of a verification scene.
    pub exact: Vec<(String, ExactFn)>,
    /// Whether the model keeps qp state (remodelling): its summary is recorded.
    pub remodelling: bool,
    /// Write fields at all.
    pub fields: bool,
}

/// One step's row, besides the observed values.
pub struct StepRow {
    pub step: usize,
    pub t: f64,
    pub dt: f64,
    /// Newton and Krylov iterations of the step.
    pub its: (usize, usize),
    /// Wall time since the start of the run.
    pub wall: f64,
}

/// The open outputs of a run directory.
pub struct Recorder {
    pub dir: PathBuf,
    fields: Option<FieldFile>,
    history: History,
    obs: Observers,
    /// (mid-edge node, end a, end b) of the owned mid-edge nodes: P1 pressure shown on P2 nodes.
    mid_edges: Vec<(usize, usize, usize)>,
}

impl Recorder {
    /// The `history.csv` columns of these observers.
    pub fn columns(obs: &Observers) -> Vec<String> {
        let mut cols: Vec<String> = vec!["step".into(), "time".into(), "dt".into()];
        if obs.experiment.is_some() {
            cols.extend(experiment::COLUMNS.iter().map(|c| c.to_string()));
        }
        if obs.remodelling {
            cols.extend(observables::COLUMNS.iter().map(|c| c.to_string()));
        }
        cols.extend(obs.probes.iter().map(|p| p.name.clone()));
        cols.extend(obs.exact.iter().map(|(n, _)| n.clone()));
        cols.extend(["newton_its", "ksp_its", "wall_s"].map(String::from));
        cols
    }

    /// Creates `fields.h5/.xdmf` (if fields are written) and `history.csv` in `dir` (collective).
    pub fn create(world: &SimpleCommunicator, dir: &Path, mesh: &LocalMesh, obs: Observers) -> Result<Recorder> {
        let (cells, coords) = output_mesh(mesh);
        let fields =
            if obs.fields { Some(FieldFile::create(dir, world, &omesh(mesh, &coords, &cells))?) } else { None };
        let cols = Self::columns(&obs);
        let colrefs: Vec<&str> = cols.iter().map(|c| c.as_str()).collect();
        let history =
            History::create(&dir.join("history.csv"), &colrefs, &integer_columns(&colrefs), world.rank() == 0)?;
        Ok(Recorder { dir: dir.to_path_buf(), fields, history, obs, mid_edges: mid_edge_nodes(mesh) })
    }

    /// Reopens the outputs of `dir` to continue a run: `history.csv` after its first `rows`
    /// rows, the fields after their first `fields` steps (collective). A fields file that cannot
    /// be continued (damaged by a kill while it was written) is set aside and replaced by
    /// `backup`, the copy taken at the last checkpoint; what was done is returned as a warning.
    pub fn reopen(
        world: &SimpleCommunicator,
        dir: &Path,
        mesh: &LocalMesh,
        obs: Observers,
        (rows, fields): (usize, usize),
        backup: &Path,
    ) -> Result<(Recorder, Option<String>)> {
        let (cells, coords) = output_mesh(mesh);
        let mut warning = None;
        let fields = if obs.fields {
            let om = omesh(mesh, &coords, &cells);
            match FieldFile::reopen(dir, world, &om, fields) {
                Ok(f) => Some(f),
                Err(e) if crate::parallel::all(world, backup.is_file()) => {
                    let kept = crate::parallel::on_root(world, || restore_backup(dir, backup))?;
                    warning = Some(format!(
                        "{e}; continuing from the copy taken at the checkpoint ({}){}",
                        backup.display(),
                        kept.map(|k| format!("; the damaged file is kept as {}", k.display())).unwrap_or_default()
                    ));
                    Some(FieldFile::reopen(dir, world, &om, fields)?)
                }
                Err(e) => return Err(e),
            }
        } else {
            None
        };
        let cols = Self::columns(&obs);
        let colrefs: Vec<&str> = cols.iter().map(|c| c.as_str()).collect();
        let history =
            History::reopen(&dir.join("history.csv"), &colrefs, &integer_columns(&colrefs), rows, world.rank() == 0);
        let history = crate::parallel::agree(world, history)?;
        let rec = Recorder { dir: dir.to_path_buf(), fields, history, obs, mid_edges: mid_edge_nodes(mesh) };
        Ok((rec, warning))
    }

    /// Copies the fields file as it stands to `to` (collective; nothing without fields).
    pub fn backup_fields(&self, to: &Path) -> Result<()> {
        self.fields.as_ref().map_or(Ok(()), |f| f.backup(to))
    }

    /// Steps written to the fields file so far.
    pub fn fields_written(&self) -> usize {
        self.fields.as_ref().map_or(0, |f| f.n_steps())
    }

    /// The experiment's time-integrated outflow so far (0 without plates).
    pub fn outflow(&self) -> f64 {
        self.obs.experiment.as_ref().map_or(0.0, |e| e.outflow())
    }

    /// One history row (and fields if asked) for state `u` reached from `prev` in the step `row`.
    pub fn record(
        &mut self,
        world: &SimpleCommunicator,
        problem: &mut PoroProblem,
        u: &Vector,
        prev: &Vector,
        row: &StepRow,
        write_fields: bool,
    ) -> Result<()> {
        let write_fields = write_fields && self.fields.is_some();
        // The post-processing element loop (reactions, cell fields) only when something reads
        // it; probes and history alone need just the local state.
        let post = if self.obs.experiment.is_some() || write_fields || self.obs.remodelling {
            let dt_eff = if row.dt > 0.0 { row.dt } else { 1.0 };
            let udot = rate(u, prev, dt_eff)?;
            Some(problem.post_process(dt_eff, u, &udot)?)
        } else {
            None
        };
        let localized;
        let local: &[f64] = match &post {
            Some(p) => &p.local,
            None => {
                localized = problem.localize(u)?;
                &localized
            }
        };
        let pb = &*problem;
        let (mesh, dofs) = (&pb.disc.mesh, &pb.disc.dofs);
        let mut values = vec![row.step as f64, row.t, row.dt];
        let obs = match (&mut self.obs.experiment, &pb.plates, &post) {
            (Some(ex), Some(pl), Some(post)) => {
                Some(ex.observe(row.t, row.dt, pl, mesh, dofs, post, pb.drainage_gaps(), world))
            }
            _ => None,
        };
        if let Some(o) = &obs {
            values.extend(o.values);
        }
        if let (Some(post), true) = (&post, self.obs.remodelling) {
            values.extend(observables::observe(post, world));
        }
        values.extend(self.obs.probes.iter().map(|p| p.value(mesh, dofs, local, world)));
        values.extend(self.obs.exact.iter().map(|(_, f)| f(row.t)));
        values.extend([row.its.0 as f64, row.its.1 as f64, row.wall]);
        // Only rank 0 writes: all agree before the collective fields output.
        let written = self.history.row(&values);
        crate::parallel::agree(world, written)?;
        if let (Some(ff), Some(post), true) = (self.fields.as_mut(), &post, write_fields) {
            let n = mesh.n_owned_nodes;
            // Vectors with three components on both families ((u_r, 0, u_z) on the meridian).
            let nc = dofs.nc;
            let mut uo = vec![0.0; 3 * n];
            for node in 0..n {
                for (c, &a) in mesh.family.axes().iter().enumerate() {
                    uo[3 * node + a] = local[nc * node + c];
                }
            }
            let mut p = vec![0.0; n];
            for (node, pv) in p.iter_mut().enumerate() {
                let v = mesh.vertex_of_node[node];
                if v >= 0 {
                    *pv = local[dofs.p_local(v as usize)];
                }
            }
            for &(m, a, b) in &self.mid_edges {
                let pa = local[dofs.p_local(mesh.vertex_of_node[a] as usize)];
                let pb_ = local[dofs.p_local(mesh.vertex_of_node[b] as usize)];
                p[m] = 0.5 * (pa + pb_);
            }
            let rank = vec![world.rank() as f64; mesh.cells.len()];
            let mut fields = vec![
                Field { name: "u", kind: FieldKind::NodeVector, data: &uo },
                Field { name: "p", kind: FieldKind::NodeScalar, data: &p },
                Field { name: "J", kind: FieldKind::CellScalar, data: &post.cell_j },
                Field { name: "von_mises", kind: FieldKind::CellScalar, data: &post.cell_von_mises },
                Field { name: "darcy_flux", kind: FieldKind::CellVector, data: &post.cell_darcy },
                Field { name: "rank", kind: FieldKind::CellScalar, data: &rank },
            ];
            if pb.disc.model.solid_fraction().is_some() {
                fields.push(Field { name: "porosity", kind: FieldKind::CellScalar, data: &post.cell_porosity });
            }
            if let Some(o) = &obs {
                fields.push(Field { name: "contact", kind: FieldKind::NodeScalar, data: &o.node_contact });
            }
            if self.obs.remodelling {
                fields.push(Field { name: "norm_ep", kind: FieldKind::CellScalar, data: &post.cell_norm_ep });
            }
            ff.write_step(row.t, &fields)?;
        }
        Ok(())
    }
}

/// The integer columns among `cols`.
fn integer_columns<'a>(cols: &[&'a str]) -> Vec<&'a str> {
    const INTEGER: [&str; 5] = ["step", "newton_its", "ksp_its", "contact_nodes_upper", "contact_nodes_lower"];
    cols.iter().copied().filter(|c| INTEGER.contains(c)).collect()
}

/// This rank's cells (global node ids) and owned node coordinates, for the fields file.
fn output_mesh(mesh: &LocalMesh) -> (Vec<[u32; 10]>, Vec<[f64; 3]>) {
    let nn = mesh.family.cell_nodes();
    let cells = mesh
        .cells
        .iter()
        .map(|t| std::array::from_fn(|a| if a < nn { mesh.node_global[t[a] as usize] } else { 0 }))
        .collect();
    (cells, mesh.coords[..mesh.n_owned_nodes].to_vec())
}

fn omesh<'a>(mesh: &LocalMesh, coords: &'a [[f64; 3]], cells: &'a [[u32; 10]]) -> OutputMesh<'a> {
    OutputMesh {
        n_global_nodes: mesh.n_global_nodes,
        node_offset: mesh.node_offset,
        coords,
        n_global_cells: mesh.n_global_elems,
        cell_offset: mesh.elem_offset,
        cells,
        family: mesh.family,
    }
}

/// (mid-edge node, end a, end b) for owned mid-edge nodes, to show P1 pressure on P2 nodes.
fn mid_edge_nodes(mesh: &LocalMesh) -> Vec<(usize, usize, usize)> {
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
