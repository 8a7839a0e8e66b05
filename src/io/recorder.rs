//! What a run writes per step: one `history.csv` row (the step, its observed values — the
//! experiment's observables, the remodelling summary, probes, exact columns — and its iteration
//! counts) and, when asked, the fields. The records are this module's: a column is declared
//! once ([`Declared`]: name, unit, meaning, value); the observers (`observe::observers`) give
//! their [`Column`]s and produce [`Observed`] values and [`StepFields`]; the recorder adds the
//! step's own columns ([`STEP`], [`ITERATIONS`]) around them.

use crate::error::Result;
use crate::io::fields::{restore_backup, Field, FieldFile, FieldKind, OutputMesh};
use crate::io::history::History;
use crate::mesh::dist::LocalMesh;
use mpi::topology::SimpleCommunicator;
use mpi::traits::*;
use std::path::{Path, PathBuf};

/// How a `history.csv` column prints.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum ColumnKind {
    /// The shortest decimal that parses back to the same value.
    Real,
    /// A count, printed as an integer (a non-integral value is an error).
    Integer,
}

/// A `history.csv` column as an observer declares it.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Column {
    pub(crate) name: String,
    pub(crate) kind: ColumnKind,
}

impl Column {
    pub(crate) fn real(name: impl Into<String>) -> Column {
        Column { name: name.into(), kind: ColumnKind::Real }
    }

    /// The column a declaration names.
    pub(crate) fn of(doc: &ColumnDoc, kind: ColumnKind) -> Column {
        Column { name: doc.name.into(), kind }
    }
}

/// A `history.csv` column declared once: its name, unit and meaning (the docs' column table,
/// `poroplast columns --table`), how it prints, and how its value is read from `R`, what its
/// observer reads in a step. The header and every row are made from the same declarations.
pub(crate) struct Declared<R> {
    pub(crate) doc: ColumnDoc,
    pub(crate) kind: ColumnKind,
    pub(crate) value: fn(&R) -> f64,
}

/// What the docs say of a column: its name (or, for columns a scene names, the pattern of their
/// names), its unit ("–": none) and its meaning (Markdown).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct ColumnDoc {
    pub(crate) name: &'static str,
    pub(crate) unit: &'static str,
    pub(crate) meaning: &'static str,
    /// The name is a pattern (`*probe name*`): the scene gives the names.
    pub(crate) pattern: bool,
}

impl ColumnDoc {
    /// Columns whose names the scene gives.
    pub(crate) const fn pattern(name: &'static str, unit: &'static str, meaning: &'static str) -> ColumnDoc {
        ColumnDoc { name, unit, meaning, pattern: true }
    }

    /// A column of this name.
    pub(crate) const fn named(name: &'static str, unit: &'static str, meaning: &'static str) -> ColumnDoc {
        ColumnDoc { name, unit, meaning, pattern: false }
    }
}

impl<R> Declared<R> {
    pub(crate) const fn real(
        name: &'static str,
        unit: &'static str,
        meaning: &'static str,
        value: fn(&R) -> f64,
    ) -> Self {
        Declared { doc: ColumnDoc::named(name, unit, meaning), kind: ColumnKind::Real, value }
    }

    /// A count (printed as an integer).
    pub(crate) const fn integer(
        name: &'static str,
        unit: &'static str,
        meaning: &'static str,
        value: fn(&R) -> f64,
    ) -> Self {
        Declared { doc: ColumnDoc::named(name, unit, meaning), kind: ColumnKind::Integer, value }
    }

    pub(crate) fn name(&self) -> &'static str {
        self.doc.name
    }

    /// The header's entries of `cols`, in order.
    pub(crate) fn header(cols: &[Self]) -> impl Iterator<Item = Column> + '_ {
        cols.iter().map(|c| Column::of(&c.doc, c.kind))
    }

    /// The values of `cols` read from `r`, in the header's order.
    pub(crate) fn row<'a>(cols: &'a [Self], r: &'a R) -> impl Iterator<Item = f64> + 'a {
        cols.iter().map(move |c| (c.value)(r))
    }
}

/// The observed values of a step: its `history.csv` columns between the step's (step, time,
/// dt) and its iteration counts, and its fields if asked.
pub(crate) struct Observed {
    pub(crate) values: Vec<f64>,
    pub(crate) fields: Option<StepFields>,
}

/// The fields of a step: per owned node, u (three components on both families: (u_r, 0, u_z) on
/// the meridian) and p (P1, shown on the P2 nodes); per local element, the rest.
pub(crate) struct StepFields {
    pub(crate) u: Vec<f64>,
    pub(crate) p: Vec<f64>,
    pub(crate) j: Vec<f64>,
    pub(crate) von_mises: Vec<f64>,
    pub(crate) darcy_flux: Vec<f64>,
    /// With a solid fraction.
    pub(crate) porosity: Option<Vec<f64>>,
    /// With plates: 0 free, 1 lower plate, 2 upper plate (per owned node).
    pub(crate) contact: Option<Vec<f64>>,
    /// With qp state: the element's mean ‖E_p‖.
    pub(crate) norm_ep: Option<Vec<f64>>,
}

/// One step's row, besides the observed values.
pub(crate) struct StepRow {
    pub(crate) step: usize,
    pub(crate) t: f64,
    pub(crate) dt: f64,
    /// Newton and Krylov iterations of the step.
    pub(crate) its: (usize, usize),
    /// Wall time since the start of the run.
    pub(crate) wall: f64,
}

/// The open outputs of a run directory.
pub(crate) struct Recorder {
    pub(crate) dir: PathBuf,
    fields: Option<FieldFile>,
    history: History,
}

impl Recorder {
    /// Creates `fields.h5/.xdmf` (if `fields`) and `history.csv` with the `observed` columns in
    /// `dir` (collective).
    pub(crate) fn create(
        world: &SimpleCommunicator,
        dir: &Path,
        mesh: &LocalMesh,
        observed: &[Column],
        fields: bool,
    ) -> Result<Recorder> {
        let (cells, coords) = output_mesh(mesh);
        let fields = if fields { Some(FieldFile::create(dir, world, &omesh(mesh, &coords, &cells))?) } else { None };
        let cols = history_columns(observed);
        let (names, integer) = names(&cols);
        let history = History::create(&dir.join("history.csv"), &names, &integer, world.rank() == 0)?;
        Ok(Recorder { dir: dir.to_path_buf(), fields, history })
    }

    /// Reopens the outputs of `dir` to continue a run: `history.csv` after its first `rows`
    /// rows, the fields after their first `fields` steps (collective). A fields file that cannot
    /// be continued (damaged by a kill while it was written) is set aside and replaced by
    /// `backup`, the copy taken at the last checkpoint; what was done is returned as a warning.
    pub(crate) fn reopen(
        world: &SimpleCommunicator,
        dir: &Path,
        mesh: &LocalMesh,
        (observed, fields): (&[Column], bool),
        (rows, steps): (usize, usize),
        backup: &Path,
    ) -> Result<(Recorder, Option<String>)> {
        let (cells, coords) = output_mesh(mesh);
        let mut warning = None;
        let fields = if fields {
            let om = omesh(mesh, &coords, &cells);
            match FieldFile::reopen(dir, world, &om, steps) {
                Ok(f) => Some(f),
                Err(e) if crate::parallel::all(world, backup.is_file()) => {
                    let kept = crate::parallel::on_root(world, || restore_backup(dir, backup))?;
                    warning = Some(format!(
                        "{e}; continuing from the copy taken at the checkpoint ({}){}",
                        backup.display(),
                        kept.map(|k| format!("; the damaged file is kept as {}", k.display())).unwrap_or_default()
                    ));
                    Some(FieldFile::reopen(dir, world, &om, steps)?)
                }
                Err(e) => return Err(e),
            }
        } else {
            None
        };
        let cols = history_columns(observed);
        let (names, integer) = names(&cols);
        let history = History::reopen(&dir.join("history.csv"), &names, &integer, rows, world.rank() == 0);
        let history = crate::parallel::agree(world, history)?;
        let rec = Recorder { dir: dir.to_path_buf(), fields, history };
        Ok((rec, warning))
    }

    /// Copies the fields file as it stands to `to` (collective; nothing without fields).
    pub(crate) fn backup_fields(&self, to: &Path) -> Result<()> {
        self.fields.as_ref().map_or(Ok(()), |f| f.backup(to))
    }

    /// Steps written to the fields file so far.
    pub(crate) fn fields_written(&self) -> usize {
        self.fields.as_ref().map_or(0, |f| f.n_steps())
    }

    /// One history row — the step, its observed values, its iterations and wall time — and its
    /// fields if they were observed (collective).
    pub(crate) fn record(&mut self, world: &SimpleCommunicator, row: &StepRow, observed: &Observed) -> Result<()> {
        let mut values: Vec<f64> = Declared::row(&STEP, row).collect();
        values.extend(&observed.values);
        values.extend(Declared::row(&ITERATIONS, row));
        // Only rank 0 writes: all agree before the collective fields output.
        let written = self.history.row(&values);
        crate::parallel::agree(world, written)?;
        let (Some(ff), Some(f)) = (self.fields.as_mut(), &observed.fields) else { return Ok(()) };
        let rank = vec![world.rank() as f64; f.j.len()];
        let mut fields = vec![
            Field { name: "u", kind: FieldKind::NodeVector, data: &f.u },
            Field { name: "p", kind: FieldKind::NodeScalar, data: &f.p },
            Field { name: "J", kind: FieldKind::CellScalar, data: &f.j },
            Field { name: "von_mises", kind: FieldKind::CellScalar, data: &f.von_mises },
            Field { name: "darcy_flux", kind: FieldKind::CellVector, data: &f.darcy_flux },
            Field { name: "rank", kind: FieldKind::CellScalar, data: &rank },
        ];
        if let Some(porosity) = &f.porosity {
            fields.push(Field { name: "porosity", kind: FieldKind::CellScalar, data: porosity });
        }
        if let Some(contact) = &f.contact {
            fields.push(Field { name: "contact", kind: FieldKind::NodeScalar, data: contact });
        }
        if let Some(norm_ep) = &f.norm_ep {
            fields.push(Field { name: "norm_ep", kind: FieldKind::CellScalar, data: norm_ep });
        }
        ff.write_step(row.t, &fields)
    }
}

/// The step's own columns before the observed ones.
pub(crate) const STEP: [Declared<StepRow>; 3] = [
    Declared::integer(
        "step",
        "–",
        "step number (row 0: the initial state at t = 0; with plates, the state settled under gravity)",
        |r| r.step as f64,
    ),
    Declared::real("time", "s", "time at the end of the step", |r| r.t),
    Declared::real("dt", "s", "the step's size", |r| r.dt),
];

/// The step's own columns after the observed ones.
pub(crate) const ITERATIONS: [Declared<StepRow>; 3] = [
    Declared::integer("newton_its", "–", "nonlinear iterations of the step (failed attempts included)", |r| {
        r.its.0 as f64
    }),
    Declared::integer("ksp_its", "–", "Krylov iterations of the step", |r| r.its.1 as f64),
    Declared::real("wall_s", "s", "wall time since the start of the run", |r| r.wall),
];

/// `history.csv`'s columns in [`Recorder::record`]'s order: the step's own ([`STEP`],
/// [`ITERATIONS`]) around the `observed` ones.
pub(crate) fn history_columns(observed: &[Column]) -> Vec<Column> {
    let mut cols: Vec<Column> = Declared::header(&STEP).collect();
    cols.extend_from_slice(observed);
    cols.extend(Declared::header(&ITERATIONS));
    cols
}

/// The names of `cols`, and those of its integer columns.
fn names(cols: &[Column]) -> (Vec<&str>, Vec<&str>) {
    let integer = cols.iter().filter(|c| c.kind == ColumnKind::Integer);
    (cols.iter().map(|c| c.name.as_str()).collect(), integer.map(|c| c.name.as_str()).collect())
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_step_columns_frame_the_observed_ones() {
        let observed = [Column::real("force"), Column { name: "contact_nodes".into(), kind: ColumnKind::Integer }];
        let cols = history_columns(&observed);
        let (names, integer) = names(&cols);
        assert_eq!(names, ["step", "time", "dt", "force", "contact_nodes", "newton_its", "ksp_its", "wall_s"]);
        assert_eq!(integer, ["step", "contact_nodes", "newton_its", "ksp_its"]);
    }
}
