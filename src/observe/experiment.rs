//! Observables of the compression–release experiment (model.md §7), one row per step:
//!
//! * forces on the plates: the sum of the contact reactions R_z of the nodes touching each
//!   plate (reactions of the VI-active dofs: the raw residual there, the surface tension's
//!   included), less the adhesion's pull on the faces near the plate, split exactly into the
//!   pressure part (nodal forces of −p J F⁻ᵀ) and the constitutive rest; upper plate positive
//!   in compression, full-sphere equivalent, in mg-force under [`G`] = 9.81 m/s² (the paper's
//!   unit; 1 nN = 1.0194e-4 mg), each followed by the same force in µN (mg × G: the one g of
//!   every mg ↔ µN conversion);
//! * contact radii, height and width of the current shape;
//! * pressure and porosity at the material point X_U = (0.4 R, 0, 1.9 R) (`plates.probe_point`);
//! * fluid (mixture) volume ∫ J dV and the outflow through the drained surface, Σ c(g) (p − p_m)
//!   (the drainage term of the mass balance, so the volume change equals the integrated outflow
//!   exactly at convergence);
//! * the largest penetration of the quadratic surface into a plate, sampled between nodes;
//! * the lab's Laplace analysis of the profile: R1, R2, R3 and the apparent surface tension
//!   σ_app (`observe::laplace`).

use super::laplace::{self, Point};
use super::probe::{Probe, Quantity};
use crate::error::{Error, Result};
use crate::fem::dofmap::DofMap;
use crate::fem::surface::FaceRule;
use crate::io::recorder::{ColumnDoc, ColumnKind, Declared};
use crate::mesh::dist::LocalMesh;
use crate::parallel::{all_gather_vec, max, sum};
use crate::physics::contact::{Plates, Touch};
use crate::physics::problem::Post;
use mpi::topology::SimpleCommunicator;

/// The g of the forces in mg (m/s²): 1 mg-force = 9.81 µN. Every mg ↔ µN conversion uses it.
pub(crate) const G: f64 = 9.81;

/// nN → mg under g: 1e-9 N / 9.81 m/s² = 1.0194e-10 kg = 1.0194e-4 mg.
pub(crate) const NN_TO_MG: f64 = 1e-3 / G;

/// A force in mg as µN.
pub(crate) fn micro_newton(mg: f64) -> f64 {
    mg * G
}

/// The `history.csv` columns of an [`Observation`], the Laplace analysis's after them
/// ([`columns`], [`Observation::values`]). Forces are full-sphere equivalents, positive in
/// compression; each in mg is followed by its µN twin.
pub(crate) const COLUMNS: &[Declared<Observation>] = &[
    Declared::real(
        "plate_disp",
        "µm",
        "height of the lower plate's top face, z_lower(t): 0 at rest, up to `compression` × 2R in the hold",
        |o| o.plate_disp,
    ),
    Declared::real(
        "force_total_mg",
        "mg",
        "force on the upper plate (the sum of its contact reactions), positive in compression, full-sphere equivalent",
        |o| o.force_total,
    ),
    Declared::real("force_total_uN", "µN", "`force_total_mg` in µN", |o| micro_newton(o.force_total)),
    Declared::real(
        "force_constitutive_mg",
        "mg",
        "the solid's part of the upper plate's force (total minus pressure part)",
        |o| o.force_constitutive,
    ),
    Declared::real("force_constitutive_uN", "µN", "`force_constitutive_mg` in µN", |o| {
        micro_newton(o.force_constitutive)
    }),
    Declared::real(
        "force_pressure_mg",
        "mg",
        "the pore pressure's part of the upper plate's force (nodal forces of −p J F⁻ᵀ)",
        |o| o.force_pressure,
    ),
    Declared::real("force_pressure_uN", "µN", "`force_pressure_mg` in µN", |o| micro_newton(o.force_pressure)),
    Declared::real(
        "force_lower_mg",
        "mg",
        "force on the lower plate (its contact reactions, the bottom pole's included), full-sphere equivalent",
        |o| o.force_lower,
    ),
    Declared::real("force_lower_uN", "µN", "`force_lower_mg` in µN", |o| micro_newton(o.force_lower)),
    Declared::real(
        "contact_radius_upper",
        "µm",
        "radius of the contact patch on the upper plate (current configuration)",
        |o| o.contact_radius_upper,
    ),
    Declared::real(
        "contact_radius_lower",
        "µm",
        "radius of the contact patch on the lower plate (current configuration)",
        |o| o.contact_radius_lower,
    ),
    Declared::real("height", "µm", "current height of the body (max z − min z)", |o| o.height),
    Declared::real("width", "µm", "current width (2 × the largest distance from the axis)", |o| o.width),
    Declared::real(
        "probe_p",
        "kPa",
        "pore pressure at the material point X_U = (0.4 R, 0, 1.9 R) (`plates.probe_point`)",
        |o| o.probe_p,
    ),
    Declared::real(
        "probe_porosity",
        "–",
        "porosity 1 − Φs/J at X_U; NaN for a material without a solid fraction Φs (`linear`)",
        |o| o.probe_porosity,
    ),
    Declared::real("fluid_volume", "µm³", "mixture volume ∫ J dV (full sphere)", |o| o.fluid_volume),
    Declared::real("outflow", "µm³/s", "rate of fluid leaving through the drained surface (full sphere)", |o| {
        o.outflow
    }),
    Declared::real(
        "outflow_total",
        "µm³",
        "the outflow's time integral since t = 0 (equals the volume change at convergence)",
        |o| o.outflow_total,
    ),
    Declared::real(
        "max_penetration",
        "µm",
        "largest penetration of the curved surface into a plate, sampled between nodes",
        |o| o.max_penetration,
    ),
    Declared::integer(
        "contact_nodes_upper",
        "–",
        "nodes in contact with the upper plate (of the meshed part: a quarter's nodes on the quarter)",
        |o| o.contact_nodes_upper,
    ),
    Declared::integer(
        "contact_nodes_lower",
        "–",
        "nodes in contact with the lower plate (of the meshed part)",
        |o| o.contact_nodes_lower,
    ),
];

/// The experiment's `history.csv` columns in order, as declared: its own, then the Laplace
/// analysis's (the order of [`Observation::values`]).
pub(crate) fn columns() -> impl Iterator<Item = (&'static ColumnDoc, ColumnKind)> {
    let own = COLUMNS.iter().map(|c| (&c.doc, c.kind));
    own.chain(laplace::COLUMNS.iter().map(|c| (&c.doc, c.kind)))
}

/// The contact states in the order of their gathered code ([`side_code`]).
const SIDES: [Touch; 3] = [Touch::Free, Touch::Lower, Touch::Upper];

/// A contact state as a gathered real: its index in [`SIDES`].
fn side_code(t: Touch) -> f64 {
    SIDES.iter().position(|&s| s == t).unwrap_or(0) as f64
}

pub(crate) struct Experiment {
    /// Full-sphere equivalent factor: 4π R³/3 over the meshed volume (4 for a quarter, 1 for the
    /// meridian, whose volume integrals already carry 2πR).
    pub(crate) symmetry: f64,
    probe_p: Probe,
    probe_porosity: Option<Probe>,
    /// Local faces of the contact surface (for penetration between nodes).
    faces: Vec<u32>,
    /// Time-integrated outflow so far (µm³, full sphere).
    outflow_total: f64,
}

/// One step's observables (full-sphere equivalents; forces in mg), what [`COLUMNS`] read, and the
/// per-node contact state.
pub(crate) struct Observation {
    plate_disp: f64,
    force_total: f64,
    force_constitutive: f64,
    force_pressure: f64,
    force_lower: f64,
    contact_radius_upper: f64,
    contact_radius_lower: f64,
    height: f64,
    width: f64,
    probe_p: f64,
    probe_porosity: f64,
    fluid_volume: f64,
    outflow: f64,
    outflow_total: f64,
    max_penetration: f64,
    contact_nodes_upper: f64,
    contact_nodes_lower: f64,
    laplace: laplace::Reading,
    /// Contact state of every owned node: 0 free, 1 lower plate, 2 upper plate.
    pub(crate) node_contact: Vec<f64>,
}

impl Observation {
    /// The values of [`columns`], in order.
    pub(crate) fn values(&self) -> impl Iterator<Item = f64> + '_ {
        Declared::row(COLUMNS, self).chain(Declared::row(&laplace::COLUMNS, &self.laplace))
    }
}

impl Experiment {
    /// Sets up probes (collective) at `probe_point`, which loading the scene resolves (its
    /// default, X_U, is decided there: `scene::plates::default_probe_point`). `volume` is the
    /// meshed reference volume (all ranks).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        mesh: &LocalMesh,
        faces: Vec<u32>,
        radius: f64,
        probe_point: Option<[f64; 3]>,
        volume: f64,
        solid_fraction: Option<f64>,
        world: &SimpleCommunicator,
        context: &str,
    ) -> Result<Experiment> {
        let symmetry = crate::physics::contact::symmetry(radius, volume);
        let Some(x_u) = probe_point else {
            return Err(Error::Scene { path: context.into(), msg: "plates.probe_point is not resolved".into() });
        };
        let probe_p = Probe::at_point("probe_p", Quantity::Pressure, x_u, mesh, world, context)?;
        let probe_porosity = match solid_fraction {
            Some(phi) => Some(Probe::at_point("probe_porosity", Quantity::Porosity(phi), x_u, mesh, world, context)?),
            None => None,
        };
        Ok(Experiment { symmetry, probe_p, probe_porosity, faces, outflow_total: 0.0 })
    }

    /// The time-integrated outflow so far (µm³, full sphere), for a checkpoint.
    pub(crate) fn outflow(&self) -> f64 {
        self.outflow_total
    }

    /// Restores the outflow of a checkpoint.
    pub(crate) fn set_outflow(&mut self, v: f64) {
        self.outflow_total = v;
    }

    /// Observables at time t after a step of size dt (collective). `outflow_local`: this rank's
    /// outflow through the drained surface (`PoroProblem::drainage_outflow`).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn observe(
        &mut self,
        t: f64,
        dt: f64,
        plates: &Plates,
        mesh: &LocalMesh,
        dofs: &DofMap,
        post: &Post,
        outflow_local: f64,
        world: &SimpleCommunicator,
    ) -> Observation {
        let local = &post.local;
        let states = plates.states(dofs, local, t, post.upper_d);
        let axes = mesh.family.axes();
        let pos = |n: usize| -> [f64; 3] {
            let mut x = mesh.coords[n];
            for (c, &a) in axes.iter().enumerate() {
                x[a] += local[dofs.u_local(n, c)];
            }
            x
        };
        let (mut f_up, mut fp_up, mut f_lo) = (0.0, 0.0, 0.0);
        let (mut r_up, mut r_lo, mut n_up, mut n_lo) = (0.0f64, 0.0f64, 0.0, 0.0);
        let mut node_contact = vec![0.0; mesh.n_owned_nodes];
        // The owned surface nodes as (r, z, side) for the Laplace analysis.
        let mut profile = Vec::with_capacity(3 * plates.nodes.len());
        for (k, &n) in plates.nodes.iter().enumerate() {
            let x = pos(n);
            let r = (x[0] * x[0] + x[1] * x[1]).sqrt();
            if n < mesh.n_owned_nodes {
                profile.extend([r, x[2], side_code(states[k])]);
            }
            let owned = dofs.local_to_owned(dofs.uz_local(n));
            match states[k] {
                Touch::Upper => {
                    r_up = r_up.max(r);
                    if let Some(i) = owned {
                        f_up -= post.reaction[i];
                        fp_up -= post.reaction_pressure[i];
                        n_up += 1.0;
                        node_contact[n] = 2.0;
                    }
                }
                Touch::Lower => {
                    r_lo = r_lo.max(r);
                    if let Some(i) = owned {
                        f_lo += post.reaction[i];
                        n_lo += 1.0;
                        node_contact[n] = 1.0;
                    }
                }
                Touch::Free => {}
            }
        }
        let (mut zmin, mut zmax, mut rmax) = (f64::MAX, f64::MIN, 0.0f64);
        for n in 0..mesh.n_owned_nodes {
            let x = pos(n);
            zmin = zmin.min(x[2]);
            zmax = zmax.max(x[2]);
            rmax = rmax.max((x[0] * x[0] + x[1] * x[1]).sqrt());
        }
        // Outflow through the drained surface: Σ c(g) (p − p_m) over this rank's face shares.
        let sym = self.symmetry;
        let outflow = sym * sum(world, outflow_local);
        self.outflow_total += dt * outflow;
        let pen = self.max_penetration(plates, mesh, dofs, local, (t, post.upper_d));
        let probe_p = self.probe_p.value(mesh, dofs, local, world);
        let probe_por = self.probe_porosity.as_ref().map_or(f64::NAN, |p| p.value(mesh, dofs, local, world));
        // The adhesion pulls the plates towards the aggregate besides the contact reactions.
        let [pull_lo, pull_up] = post.adhesion_pull;
        let (f_up, fp_up) = (sum(world, f_up - pull_up), sum(world, fp_up));
        let profile: Vec<Point> = all_gather_vec(world, &profile)
            .chunks_exact(3)
            .map(|p| Point { r: p[0], z: p[1], side: SIDES[p[2] as usize] })
            .collect();
        let laplace = laplace::read(&profile, plates.z_lower(t), plates.z_upper_at(post.upper_d), sym * f_up);
        let mg = [f_up, f_up - fp_up, fp_up, sum(world, f_lo - pull_lo)].map(|f| sym * f * NN_TO_MG);
        Observation {
            plate_disp: plates.z_lower(t),
            force_total: mg[0],
            force_constitutive: mg[1],
            force_pressure: mg[2],
            force_lower: mg[3],
            contact_radius_upper: max(world, r_up),
            contact_radius_lower: max(world, r_lo),
            height: max(world, zmax) + max(world, -zmin),
            width: 2.0 * max(world, rmax),
            probe_p,
            probe_porosity: probe_por,
            fluid_volume: sym * sum(world, post.volume_j),
            outflow,
            outflow_total: self.outflow_total,
            max_penetration: max(world, pen),
            contact_nodes_upper: sum(world, n_up),
            contact_nodes_lower: sum(world, n_lo),
            laplace,
            node_contact,
        }
    }

    /// Largest distance by which the quadratic contact surface enters a plate, sampled at the
    /// nodes and at the interior points of a degree-5 rule on every face (7 on a triangle, 3 on
    /// a meridian line); the plates at time t with the upper one at displacement d.
    fn max_penetration(
        &self,
        plates: &Plates,
        mesh: &LocalMesh,
        dofs: &DofMap,
        local: &[f64],
        (t, d): (f64, f64),
    ) -> f64 {
        let nf = mesh.family.face_nodes();
        let (zl, zu) = (plates.z_lower(t), plates.z_upper_at(d));
        let rule = FaceRule::new(mesh.family);
        let mut pen = 0.0f64;
        for &f in &self.faces {
            let nodes = mesh.face(f as usize);
            let z: Vec<f64> =
                nodes.iter().map(|&n| mesh.coords[n as usize][2] + local[dofs.uz_local(n as usize)]).collect();
            let coords: Vec<[f64; 3]> = nodes.iter().map(|&n| mesh.coords[n as usize]).collect();
            let inner = rule.points(&coords).into_iter().map(|p| (0..nf).map(|a| p.n[a] * z[a]).sum::<f64>());
            for zq in inner.chain(z.iter().copied()) {
                pen = pen.max(zl - zq).max(zq - zu);
            }
        }
        pen
    }
}
