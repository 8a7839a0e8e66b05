//! The geometry of the aggregate's current boundary faces, shared by the loads that live on it
//! (`surface_tension`, `medium`): the face quadrature rule, the tangents and the meridian's
//! point, a point's area and its area-weighted normal (with their gradients), each face's
//! outward sign, and a face's dofs and current coordinates. Written generic over
//! [`Scalar`] so the loads' Hessians are their gradients differentiated by duals.
//!
//! On a 6-node triangle (3-D) a point's area is w_q |x_ξ × x_η| and its normal area
//! (n da)_q = w_q x_ξ × x_η; on a 3-node meridian edge the face is the surface it sweeps,
//! a_q = 2π w_q r |x_s| (the hoop term: r varies) and (n da)_q = 2π w_q r (t_z, −t_r).

use crate::fem::dofmap::DofMap;
use crate::fem::element::tabulate_tri6;
use crate::fem::quadrature;
use crate::fem::surface::{gauss3_line, gauss4_line, line3};
use crate::material::dual::Scalar;
use crate::mesh::dist::LocalMesh;
use crate::reference_cell::Family;

/// Coordinates of one face's nodes: 18 for a 6-node triangle (x, y, z per node), 6 for a
/// 3-node edge (r, z per node).
pub(crate) const MAX: usize = 18;

/// The face rule: per point the weight and the reference derivatives (and values, for the hoop
/// term on the meridian) of the face functions.
pub(crate) struct Rule {
    pub(crate) family: Family,
    pub(crate) w: Vec<f64>,
    pub(crate) n: Vec<[f64; 6]>,
    pub(crate) dn: Vec<[[f64; 2]; 6]>,
}

impl Rule {
    /// tri(4) on the 6-node triangle (exact for degree 4), Gauss-3 on the meridian's edge
    /// (degree 5): the surface tension's rule.
    pub(crate) fn new(family: Family) -> Rule {
        Rule::of(family, 4, &gauss3_line())
    }

    /// tri(6) on the 6-node triangle, Gauss-4 on the meridian's edge (degree 7): exact for a
    /// linear field times a face function times n da on a curved face (3-D: 1·2 + 2 + 2 = 6;
    /// meridian, with the hoop r: 2 + 2 + 2 + 1 = 7), so a load p(x) N_b n da is the exact
    /// gradient of ∫_V p dv and its tangent over a closed surface symmetric.
    pub(crate) fn exact_for_linear_fields(family: Family) -> Rule {
        Rule::of(family, 6, &gauss4_line())
    }

    /// The triangle rule of `degree` (3-D) or the line rule `line` (meridian).
    fn of(family: Family, degree: usize, line: &[(f64, f64)]) -> Rule {
        match family {
            Family::Tet10 => {
                let tab = tabulate_tri6(&quadrature::tri(degree));
                let dn = tab.dn.iter().map(|d| std::array::from_fn(|a| [d[a][0], d[a][1]])).collect();
                Rule { family, w: tab.weights, n: tab.n, dn }
            }
            Family::Tri6 => {
                let mut r = Rule { family, w: vec![], n: vec![], dn: vec![] };
                for &(s, w) in line {
                    let (n, dn) = line3(s);
                    r.w.push(w);
                    r.n.push([n[0], n[1], n[2], 0.0, 0.0, 0.0]);
                    r.dn.push([[dn[0], 0.0], [dn[1], 0.0], [dn[2], 0.0], [0.0; 2], [0.0; 2], [0.0; 2]]);
                }
                r
            }
        }
    }

    /// Coordinates per node (3, or 2 on the meridian) and nodes per face.
    pub(crate) fn layout(&self) -> (usize, usize) {
        match self.family {
            Family::Tet10 => (3, 6),
            Family::Tri6 => (2, 3),
        }
    }

    /// The current position of point q (the rule's coordinates: x, y, z or r, z).
    pub(crate) fn point<T: Scalar>(&self, q: usize, x: &[T]) -> [T; 3] {
        let (d, nn) = self.layout();
        let mut p = [T::cst(0.0); 3];
        for node in 0..nn {
            for (i, pi) in p.iter_mut().enumerate().take(d) {
                *pi = *pi + x[d * node + i].scale(self.n[q][node]);
            }
        }
        p
    }
}

/// Point q's share of the face's area, a_q = w_q |x_ξ × x_η| (3-D) or 2π w_q r |x_s| (meridian),
/// and its gradient ∂a_q/∂x.
pub(crate) fn point_area<T: Scalar>(rule: &Rule, q: usize, x: &[T]) -> (T, [T; MAX]) {
    let (d, nn) = rule.layout();
    let mut g = [T::cst(0.0); MAX];
    let w = rule.w[q];
    match rule.family {
        Family::Tet10 => {
            // d|m| = n̂ · (dx_ξ × x_η + x_ξ × dx_η): node b along e_i gives
            // N_b,ξ (x_η × n̂)_i + N_b,η (n̂ × x_ξ)_i.
            let (t1, t2) = tangents(rule, q, x, d, nn);
            let m = cross(&t1, &t2);
            let len = norm(&m);
            let nh = [m[0] / len, m[1] / len, m[2] / len];
            let (a, b) = (cross(&t2, &nh), cross(&nh, &t1));
            for node in 0..nn {
                let [dx, dy] = rule.dn[q][node];
                for i in 0..3 {
                    g[3 * node + i] = (a[i].scale(dx) + b[i].scale(dy)).scale(w);
                }
            }
            (len.scale(w), g)
        }
        Family::Tri6 => {
            // A_q = 2π w r |t|: ∂/∂r_b = 2π w (N_b |t| + r t_r N_b' / |t|), ∂/∂z_b = 2π w r t_z N_b' / |t|.
            let (r, t) = meridian_point(rule, q, x, nn);
            let len = (t[0] * t[0] + t[1] * t[1]).sqrt();
            let c = 2.0 * std::f64::consts::PI * w;
            for node in 0..nn {
                let (nb, db) = (rule.n[q][node], rule.dn[q][node][0]);
                g[2 * node] = (len.scale(nb) + r * t[0] / len * T::cst(db)).scale(c);
                g[2 * node + 1] = (r * t[1] / len).scale(c * db);
            }
            ((r * len).scale(c), g)
        }
    }
}

/// Point q's area-weighted outward normal (n da)_q in the rule's coordinates (`outward` = ±1:
/// the face's node order gives n or −n, [`orientation`]): w_q (x_ξ × x_η) in 3-D,
/// 2π w_q r (t_z, −t_r) on the meridian (the third entry 0).
pub(crate) fn point_normal<T: Scalar>(rule: &Rule, q: usize, x: &[T], outward: f64) -> [T; 3] {
    let (d, nn) = rule.layout();
    let c = outward * rule.w[q];
    match rule.family {
        Family::Tet10 => {
            let (t1, t2) = tangents(rule, q, x, d, nn);
            cross(&t1, &t2).map(|v| v.scale(c))
        }
        Family::Tri6 => {
            let (r, t) = meridian_point(rule, q, x, nn);
            let c = 2.0 * std::f64::consts::PI * c;
            [(r * t[1]).scale(c), (r * t[0]).scale(-c), T::cst(0.0)]
        }
    }
}

/// The tangents x_ξ, x_η at point q of a 6-node triangle.
pub(crate) fn tangents<T: Scalar>(rule: &Rule, q: usize, x: &[T], d: usize, nn: usize) -> ([T; 3], [T; 3]) {
    let (mut t1, mut t2) = ([T::cst(0.0); 3], [T::cst(0.0); 3]);
    for node in 0..nn {
        let [a, b] = rule.dn[q][node];
        for i in 0..3 {
            t1[i] = t1[i] + x[d * node + i].scale(a);
            t2[i] = t2[i] + x[d * node + i].scale(b);
        }
    }
    (t1, t2)
}

/// r and the tangent (dr/ds, dz/ds) at point q of a meridian edge.
pub(crate) fn meridian_point<T: Scalar>(rule: &Rule, q: usize, x: &[T], nn: usize) -> (T, [T; 2]) {
    let (mut r, mut t) = (T::cst(0.0), [T::cst(0.0); 2]);
    for node in 0..nn {
        r = r + x[2 * node].scale(rule.n[q][node]);
        let db = rule.dn[q][node][0];
        t[0] = t[0] + x[2 * node].scale(db);
        t[1] = t[1] + x[2 * node + 1].scale(db);
    }
    (r, t)
}

pub(crate) fn cross<T: Scalar>(a: &[T; 3], b: &[T; 3]) -> [T; 3] {
    [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]]
}

pub(crate) fn norm<T: Scalar>(a: &[T; 3]) -> T {
    (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt()
}

/// ±1: whether face f's node order gives the normal pointing away from its cell (its
/// reference normal at the first point against the direction from the cell's centroid).
pub(crate) fn orientation(rule: &Rule, mesh: &LocalMesh, f: u32) -> f64 {
    let (d, nn) = rule.layout();
    let axes = mesh.family.axes();
    let x: Vec<f64> = mesh.face(f as usize)[..nn]
        .iter()
        .flat_map(|&n| axes.iter().map(move |&a| mesh.coords[n as usize][a]))
        .collect();
    let normal: Vec<f64> = match rule.family {
        Family::Tet10 => {
            let (t1, t2) = tangents(rule, 0, &x, d, nn);
            cross(&t1, &t2).to_vec()
        }
        Family::Tri6 => {
            let (_, t) = meridian_point(rule, 0, &x, nn);
            vec![t[1], -t[0]]
        }
    };
    let cell = mesh.cell(mesh.face_cell[f as usize].0 as usize);
    let centroid =
        |nodes: &[u32], a: usize| nodes.iter().map(|&n| mesh.coords[n as usize][a]).sum::<f64>() / nodes.len() as f64;
    let face = mesh.face(f as usize);
    let dot: f64 = axes.iter().enumerate().map(|(k, &a)| normal[k] * (centroid(face, a) - centroid(cell, a))).sum();
    if dot >= 0.0 {
        1.0
    } else {
        -1.0
    }
}

/// A face's displacement dofs (local) and current node coordinates, in the rule's layout
/// (the first `n` entries of each), at the local displacement `u`.
pub(crate) fn face_state(
    rule: &Rule,
    mesh: &LocalMesh,
    dofs: &DofMap,
    f: u32,
    u: &[f64],
) -> ([usize; MAX], [f64; MAX], usize) {
    let (_, nn) = rule.layout();
    let (mut idx, mut x, mut n) = ([0; MAX], [0.0; MAX], 0);
    for &node in &mesh.face(f as usize)[..nn] {
        for (c, &axis) in mesh.family.axes().iter().enumerate() {
            idx[n] = dofs.u_local(node as usize, c);
            x[n] = mesh.coords[node as usize][axis] + u[idx[n]];
            n += 1;
        }
    }
    (idx, x, n)
}
