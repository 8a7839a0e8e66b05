//! The medium's viscous drag on the surface (issue 53, design §6.5): the traction −ζ_d u̇ with
//! ζ_d = 3η/(2R₀), the uniform traction that gives a sphere of radius R₀ moving at v Stokes'
//! drag 6πηR₀v. Why: with the suction off and no tool touching (a released aggregate on the
//! meridian, gravity along the dish), the body's translation along the pipette's axis is a free
//! mode; the drag makes it well posed at every instant, takes no load at rest (a pin would take
//! the suction's), and is what the medium does. Integrated on the reference surface (the drag is
//! a regulariser of order η u̇ / E, far below the accuracy of its uniform-traction model), so
//! its block is the constant surface mass matrix times ζ_d times the shift dU̇/dU.

use crate::fem::dofmap::DofMap;
use crate::mesh::dist::LocalMesh;
use crate::physics::surface_geometry::{face_state, norm, point_normal, Rule};

/// Pa s/µm × µm/s = Pa, in the solver's kPa.
const PA_TO_KPA: f64 = 1e-3;

/// The drag on a set of faces.
pub(crate) struct Drag {
    /// ζ_d in kPa s/µm.
    coefficient: f64,
    /// Per face the reference surface mass matrix M_ab = ∫ N_a N_b da (µm², 6 × 6 used nn × nn).
    mass: Vec<[[f64; 6]; 6]>,
    /// Displacement components per node.
    d: usize,
}

impl Drag {
    /// The drag of a medium of viscosity `viscosity` (Pa s) on a body of radius `radius` (µm)
    /// over the local `faces` (the rule's `outward` sign is irrelevant to |n da|).
    pub(crate) fn new(
        viscosity: f64,
        radius: f64,
        rule: &Rule,
        mesh: &LocalMesh,
        dofs: &DofMap,
        faces: &[u32],
    ) -> Drag {
        let (d, nn) = rule.layout();
        let zero = vec![0.0; dofs.n_local()];
        let mass = faces
            .iter()
            .map(|&f| {
                let (_, x, n) = face_state(rule, mesh, dofs, f, &zero);
                let mut m = [[0.0; 6]; 6];
                for q in 0..rule.w.len() {
                    let da = norm(&point_normal(rule, q, &x[..n], 1.0));
                    for a in 0..nn {
                        for b in 0..nn {
                            m[a][b] += rule.n[q][a] * rule.n[q][b] * da;
                        }
                    }
                }
                m
            })
            .collect();
        Drag { coefficient: 1.5 * viscosity / radius * PA_TO_KPA, mass, d }
    }

    /// Face k's drag on its nodes at the rates `udot` (local layout), the face's dofs `idx`: added
    /// to `r` (the face's rows, rule layout).
    pub(crate) fn add_face(&self, k: usize, idx: &[usize], udot: &[f64], r: &mut [f64]) {
        let (d, m) = (self.d, &self.mass[k]);
        let nn = idx.len() / d;
        for a in 0..nn {
            for b in 0..nn {
                for i in 0..d {
                    r[d * a + i] += self.coefficient * m[a][b] * udot[idx[d * b + i]];
                }
            }
        }
    }

    /// Face k's block, `shift` dU̇/dU, added to the row-major `block` of side n = idx.len().
    pub(crate) fn add_face_block(&self, k: usize, n: usize, shift: f64, block: &mut [f64]) {
        let (d, m) = (self.d, &self.mass[k]);
        for a in 0..n / d {
            for b in 0..n / d {
                for i in 0..d {
                    block[(d * a + i) * n + d * b + i] += shift * self.coefficient * m[a][b];
                }
            }
        }
    }
}
