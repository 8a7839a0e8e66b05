//! The drainage of the body's surface into the bath, sealed where it touches an impermeable
//! plate or tool ([`SurfaceDrainage`]): for the plates (model.md §1, §5) and the scene's
//! `[[tools]]` alike; what seals is the caller's gap of each node (`drains`).
//!
//! The outward flux through a surface vertex m is Q·N = Σ_f β(g_fm) (p_m − p_medium) A_fm, lumped
//! on its shares A_fm = ∫_f L_m dA of its faces f, with β(g) = β_c + (β_max − β_c) S(g / g_s), S
//! the smoothstep from 0 (g ≤ 0, in contact) to 1 (g ≥ g_s, free), and g_fm the smaller of m's gap
//! and the largest gap of f's other nodes: a face drains at m only where it opens towards the bath,
//! so a vertex lifted inside a contact patch stays sealed (why: [`SurfaceDrainage::drains`]). A
//! node's gap is its distance to the nearest sealing surface: the plates', or a sealing tool's
//! signed distance φ (a tool with `drainage = "free"` seals nothing). β_c is the plates' own
//! conductance: 0 for impermeable plates (sealed contact, the default), or k_β / L for the paper's
//! slightly permeable plates (permeability k_β, thickness L), a Robin outflow through the contact
//! area into plates drained at their far face — an upper bound on what a closed porous plate can
//! take (the paper's plates are impermeable on their other faces, so fluid entering them can only
//! move sideways). Tools are impermeable (β_c = 0). β_max = γ k0 / h (γ = 100 by default) makes
//! the free surface a stiff Robin condition, p ≈ p_medium (51a); g_s is the seal distance
//! (plates: default 0.01 R, below the gap of the first vertex outside the contact edge on the
//! default meshes). Why not the paper's much smaller contact distance: it gives the same forces
//! but a drainage switch so steep that Newton cycles between sealed and drained states at the
//! lower contact edge (docs/numerics.md, *Drainage that follows contact*). Why not switch p = 0
//! on and off: opening a Dirichlet condition on a pressurised vertex is a jump in the boundary
//! data; its discrete response (undrained compaction of the adjacent element) grows as Δt
//! shrinks, so step cuts cannot resolve it, and at the contact edge a vertex can be bistable
//! (drained it is drawn onto the plate, sealed it lifts off). A conductance that opens
//! continuously with the gap keeps the residual differentiable, so Newton converges while the
//! split follows the contact state within the step; the film's finite conductance is also the
//! physics of a gap opening.
//!
//! Whose gap (`DrainageGap`): with plates, by default the gap of the step's predictor (the
//! previous velocity extrapolated, nodes on the lower plate moved with it), fixed during the
//! Newton iteration — a semi-implicit conductance c(g̃ⁿ⁺¹) pⁿ⁺¹. Why: with the iterate's own gap,
//! a vertex at a contact edge that is bistable (above) flips between sealed and drained from one
//! Newton iterate to the next, and the active set cycles with it; the fixed gap costs a small
//! time-discretisation error at contact events (measured in docs/numerics.md, *Whose gap opens
//! the drainage*). `Current` keeps the fully implicit form, differentiated exactly; it is the
//! only form without plates (a scene of tools alone has no predictor).

use crate::fem::dofmap::DofMap;
use crate::fem::surface::FaceRule;
use crate::mesh::dist::LocalMesh;
pub(crate) use crate::scene::DrainageGap;

/// How the surface drains (module docs); conductances per area in µm³/(nN s) per µm².
#[derive(Debug, Clone, Copy)]
pub(crate) struct Drainage {
    /// Drain the surface at all — off for a sealed aggregate.
    pub(crate) on: bool,
    /// β_max, the free surface's conductance.
    pub(crate) beta_max: f64,
    /// β_c, the plates' conductance where the surface touches them (0: impermeable).
    pub(crate) beta_plate: f64,
    /// Seal distance g_s: the conductance opens fully over this gap.
    pub(crate) seal_gap: f64,
    /// Whose gap sets the conductance within a step.
    pub(crate) gap: DrainageGap,
}

/// The drained surface: its parameters and the (face, vertex) shares of this rank's faces.
pub(crate) struct SurfaceDrainage {
    pub(crate) params: Drainage,
    shares: Vec<Share>,
}

/// Nodes of a surface face besides one vertex: 5 on a Tri6, 2 on the meridian's Line3.
const MAX_OTHERS: usize = 5;

/// One vertex's share of one surface face's drainage (see [`SurfaceDrainage::drains`]).
#[derive(Debug, Clone, Copy)]
struct Share {
    vertex: usize,
    /// ∫ L_m dA over the face.
    area: f64,
    /// The face's other nodes that can touch (`n_others` of them; its vertices only for P1–P1).
    others: [usize; MAX_OTHERS],
    n_others: usize,
}

/// The drainage term of one (face, vertex) share (see [`SurfaceDrainage::drains`]).
#[derive(Debug, Clone, Copy)]
pub(crate) struct Drain {
    /// The vertex's local node (its position sets the medium's pressure it drains towards).
    pub(crate) vertex: usize,
    pub(crate) p: usize,
    /// The local node whose gap sets the share's conductance.
    pub(crate) node: usize,
    pub(crate) conductance: f64,
    /// dc/du of that node's displacement components (the node's first `nc`).
    pub(crate) d_conductance: [f64; 3],
}

impl SurfaceDrainage {
    /// The drainage `params` of the local `faces` (their vertices' shares; the faces' other
    /// nodes whose gaps can seal a share: all of a face's nodes, or its vertices only with
    /// `on_vertices`, for equal-order P1–P1 whose mid-edge nodes are slaves of their edges).
    pub(crate) fn new(params: Drainage, mesh: &LocalMesh, faces: &[u32], on_vertices: bool) -> SurfaceDrainage {
        let per_face = if on_vertices { mesh.family.face_vertices() } else { mesh.family.face_nodes() };
        // ∫ L_m dA of every vertex of every face (P1 on the curved faces; whole-body areas on
        // the meridian), with the face's other nodes.
        let rule = FaceRule::with_degree(mesh.family, 2);
        let nv = mesh.family.face_vertices();
        let mut shares = Vec::with_capacity(faces.len() * nv);
        for &f in faces {
            let fnodes = mesh.face(f as usize);
            let coords: Vec<[f64; 3]> = fnodes.iter().map(|&n| mesh.coords[n as usize]).collect();
            let points = rule.points(&coords);
            for m in 0..nv {
                let mut others = [usize::MAX; MAX_OTHERS];
                for (k, &n) in fnodes[..per_face].iter().filter(|&&n| n != fnodes[m]).enumerate() {
                    others[k] = n as usize;
                }
                let area = points.iter().map(|p| p.l[m] * p.w).sum();
                shares.push(Share { vertex: fnodes[m] as usize, area, others, n_others: per_face - 1 });
            }
        }
        SurfaceDrainage { params, shares }
    }

    /// Drainage of every local (face, vertex) share: the vertex's p dof, the node whose gap sets
    /// the share's conductance c = β(g) A (outflow c (p − p_medium)), and dc/du of that node.
    /// `gap(n)`: local node n's gap to the nearest sealing surface and dg/du of its components.
    /// Empty without drainage.
    ///
    /// The gap of a share is the smaller of the vertex's and the largest of its face's other
    /// nodes': a face drains at a vertex only if it opens towards the bath. Why: a Tri6 face's
    /// consistent load puts 0 of a uniform pressure on its corners and A(p₁ − (p₂+p₃)/2)/30 of a
    /// linear one, so a corner inside a contact patch whose pressure dips below its
    /// neighbours' is pulled off the plate by a fraction of a µm; with its own gap it drained
    /// into the bath through a pocket sealed all round, its pressure collapsed and it lifted
    /// further, enough outflow to hold the 3-D forces low at every mesh size (docs/numerics.md,
    /// *Faces drain only towards the bath*). The meridian's Line3 corners take p/6 and cannot
    /// lift, so there the rule only seals the half of an edge vertex's share that faces the
    /// contact.
    pub(crate) fn drains(&self, mesh: &LocalMesh, dofs: &DofMap, gap: impl Fn(usize) -> (f64, [f64; 3])) -> Vec<Drain> {
        let d = &self.params;
        if !d.on {
            return Vec::new();
        }
        self.shares
            .iter()
            .map(|sh| {
                // The widest opening of the face's other nodes, then the smaller of it and m's.
                let widest =
                    sh.others[..sh.n_others].iter().map(|&n| (gap(n), n)).max_by(|a, b| a.0 .0.total_cmp(&b.0 .0));
                let own = (gap(sh.vertex), sh.vertex);
                let ((g, dg), n) = match widest {
                    Some(w) if w.0 .0 < own.0 .0 => w,
                    _ => own,
                };
                let (s, ds) = smoothstep(g / d.seal_gap);
                let (c, dc) = conductance(d.beta_plate, d.beta_max, s, ds);
                Drain {
                    vertex: sh.vertex,
                    p: dofs.p_local(mesh.vertex_of_node[sh.vertex] as usize),
                    node: n,
                    conductance: sh.area * c,
                    d_conductance: dg.map(|dg| sh.area * dc * dg / d.seal_gap),
                }
            })
            .collect()
    }
}

/// β = β_c + (β_max − β_c) S and dβ/dx for the smoothstep value S(x) and S'(x): from the plates'
/// conductance in contact to the free surface's.
fn conductance(beta_plate: f64, beta_max: f64, s: f64, ds: f64) -> (f64, f64) {
    (beta_plate + (beta_max - beta_plate) * s, (beta_max - beta_plate) * ds)
}

/// S(x) = 3x² − 2x³ on [0, 1], 0 below, 1 above, and S'(x).
fn smoothstep(x: f64) -> (f64, f64) {
    if x <= 0.0 {
        (0.0, 0.0)
    } else if x >= 1.0 {
        (1.0, 0.0)
    } else {
        (x * x * (3.0 - 2.0 * x), 6.0 * x * (1.0 - x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn smoothstep_is_c1() {
        assert_eq!(smoothstep(-0.5), (0.0, 0.0));
        assert_eq!(smoothstep(1.5), (1.0, 0.0));
        assert!((smoothstep(0.5).0 - 0.5).abs() < 1e-15);
        for x in [0.1, 0.3, 0.7, 0.9] {
            let h = 1e-6;
            let fd = (smoothstep(x + h).0 - smoothstep(x - h).0) / (2.0 * h);
            assert!((fd - smoothstep(x).1).abs() < 1e-8);
        }
        assert!(smoothstep(1e-9).1 < 1e-8 && smoothstep(1.0 - 1e-9).1 < 1e-8);
    }

    #[test]
    fn plate_conductance_in_contact_opens_to_the_free_surfaces() {
        let (bc, bm) = (3.7729e-6, 18.9);
        // In contact (S = 0) the plates' conductance, free (S = 1) the surface's; impermeable
        // plates seal.
        assert_eq!(conductance(bc, bm, 0.0, 0.0), (bc, 0.0));
        assert_eq!(conductance(bc, bm, 1.0, 0.0).0, bm);
        assert_eq!(conductance(0.0, bm, 0.0, 0.0).0, 0.0);
        // dβ/dx by central differences through the smoothstep.
        for x in [0.2, 0.5, 0.8] {
            let h = 1e-6;
            let at = |x: f64| {
                let (s, ds) = smoothstep(x);
                conductance(bc, bm, s, ds)
            };
            let fd = (at(x + h).0 - at(x - h).0) / (2.0 * h);
            assert!((fd - at(x).1).abs() < 1e-6 * bm);
        }
    }
}
