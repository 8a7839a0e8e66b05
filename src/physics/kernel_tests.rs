//! The element kernel on one cell of either family, without MPI or PETSc, with the Table 1
//! biphasic model (Holmes–Mow, compaction penalty, deformation-dependent permeability, gravity):
//!
//! - homogeneous states: for an affine u (constant Grad u) the nodal residuals' moments are
//!   exact, Σ_a r_u[a,i] X_a,k = P_ik V (plus P_θθ V in the r–R moment on the meridian) and
//!   Σ_a r_u[a,i] = −b_i V, with P and b from the model at that state and V the cell's volume
//!   in closed form (Pappus on the meridian); and for constant Grad p and Grad u̇,
//!   Σ_m r_p[m] = ṡ V and Σ_m r_p[m] X_m,k = ṡ ∫X_k dV + W_k V. These identities hold for any
//!   correct weak form (partition of unity, isoparametric X), so they test the kernel's
//!   assembly of the pointwise terms, its weights and hoop terms, not its own formulas; the
//!   pressure stabilisation must add nothing to them (it tests with q − Πq).
//! - the element Jacobian (with remodelling, the faded stabilisation, and on tetrahedra the
//!   equal-order ties) against central differences of the element residual, U̇ moving with
//!   shift × the perturbation as the time integrator's does.
//! - the stabilisation's faded weight: full at the first step after a kink, gone once the steps
//!   have grown, for a slowly draining (soft) aggregate as for a stiff one.

use crate::fem::cell::{CellShape, Tet10, Tri6Axi};
use crate::fem::element::{tabulate_cell, ElementMatrix, MAX_DOF};
use crate::fem::kernel::{CellKernel, ElementInput, ElementKernel, ElementValues, Fade, Stabilisation};
use crate::fem::point::{PointModel, PointState, QpId, QpState};
use crate::fem::quadrature;
use crate::material::laws::HolmesMow;
use crate::material::tensor::to_sym6;
use crate::material::test_util::Rng;
use crate::material::{CompactionPenalty, Permeability, PermeabilityModel, Remodelling};
use crate::physics::biphasic::Biphasic;
use crate::reference_cell::shape::{MAX_NODES, MAX_VERTICES};
use crate::reference_cell::{Family, TET10_EDGES, TRI6_EDGES};
use nalgebra::{Matrix3, Vector3};
use std::marker::PhantomData;

/// Table 1 (µm, kPa, s): µ = 20 kPa, ν = 0.2, Φs = 0.6, the penalty, k0 = 3.7729 µm⁴/(nN s),
/// ρ = 1000 kg/m³ and g along −z.
pub(crate) fn table1(gravity: bool) -> Biphasic<HolmesMow> {
    let solid = HolmesMow::from_mu_nu(20.0, 0.2, 0.6).unwrap();
    let pen = CompactionPenalty::new(0.6, 1000.0, 0.7, 2.0, 0.5).unwrap();
    let perm = Permeability::new(3.7729, 0.6, 4.638, 0.0848, PermeabilityModel::Isotropic).unwrap();
    let g = if gravity { [0.0, 0.0, -9.81] } else { [0.0; 3] };
    Biphasic::new(solid, Some(pen), perm, 1000.0, 1000.0, g).unwrap()
}

/// A straight cell (mid-edge nodes at the midpoints) with distorted vertices, µm: a tetrahedron,
/// or a meridian triangle away from the axis (x = R, z = Z).
fn cell<C: CellShape>() -> [[f64; 3]; MAX_NODES] {
    let (verts, edges): (Vec<[f64; 3]>, &[(usize, usize)]) = match C::FAMILY {
        Family::Tet10 => (vec![[1.0, 2.0, 0.5], [13.0, 3.0, 1.5], [4.0, 12.0, -1.0], [3.0, 4.0, 11.0]], &TET10_EDGES),
        Family::Tri6 => (vec![[20.0, 0.0, 1.0], [31.0, 0.0, 3.0], [24.0, 0.0, 12.0]], &TRI6_EDGES),
    };
    let mut x = [[0.0; 3]; MAX_NODES];
    x[..verts.len()].copy_from_slice(&verts);
    for (k, &(a, b)) in edges.iter().enumerate() {
        x[verts.len() + k] = std::array::from_fn(|d| 0.5 * (verts[a][d] + verts[b][d]));
    }
    x
}

/// The cell's volume and ∫X dV in closed form (on the meridian dV = 2πR dA: Pappus).
fn volume_and_moment<C: CellShape>(x: &[[f64; 3]; MAX_NODES]) -> (f64, [f64; 3]) {
    let d = |a: usize, b: usize| Vector3::from(x[a]) - Vector3::from(x[b]);
    let nv = C::NV;
    let c: [f64; 3] = std::array::from_fn(|k| (0..nv).map(|a| x[a][k]).sum::<f64>() / nv as f64);
    match C::FAMILY {
        Family::Tet10 => {
            let v = d(1, 0).dot(&d(2, 0).cross(&d(3, 0))) / 6.0;
            (v, c.map(|ck| v * ck))
        }
        Family::Tri6 => {
            let area = 0.5 * d(1, 0).cross(&d(2, 0)).norm();
            // ∫ R dA and ∫ R² dA, ∫ R Z dA over the triangle (exact for quadratics).
            let second =
                |i: usize, j: usize| area / 12.0 * (9.0 * c[i] * c[j] + (0..3).map(|a| x[a][i] * x[a][j]).sum::<f64>());
            let v = 2.0 * std::f64::consts::PI * area * c[0];
            let two_pi = 2.0 * std::f64::consts::PI;
            (v, [two_pi * second(0, 0), 0.0, two_pi * second(0, 2)])
        }
    }
}

fn kernel<'a, C: CellShape>(
    model: &'a dyn PointModel,
    tab: &'a crate::fem::element::Tabulation<MAX_NODES>,
    xi: &'a [[f64; 3]],
    stab: Stabilisation,
    equal_order: bool,
) -> ElementKernel<'a, C> {
    ElementKernel { model, tab, xi, stab, equal_order, family: PhantomData }
}

fn rule(family: Family) -> quadrature::Quadrature {
    match family {
        Family::Tet10 => quadrature::tet(4),
        Family::Tri6 => quadrature::tri(4),
    }
}

/// Nodal values of the affine fields u = G X, u̇ = L X, p = p0 + g·X, and a ṗ that varies
/// between vertices (`pdot`).
fn affine<C: CellShape>(
    x: &[[f64; 3]; MAX_NODES],
    g: &Matrix3<f64>,
    l: &Matrix3<f64>,
    p0: f64,
    gp: &Vector3<f64>,
    pdot: [f64; MAX_VERTICES],
) -> ElementValues {
    let at = |m: &Matrix3<f64>, a: usize| -> [f64; 3] {
        let v = m * Vector3::from(x[a]);
        std::array::from_fn(|c| if c < C::NC { v[C::AXES[c]] } else { 0.0 })
    };
    ElementValues {
        u: std::array::from_fn(|a| if a < C::NN { at(g, a) } else { [0.0; 3] }),
        udot: std::array::from_fn(|a| if a < C::NN { at(l, a) } else { [0.0; 3] }),
        p: std::array::from_fn(|m| if m < C::NV { p0 + gp.dot(&Vector3::from(x[m])) } else { 0.0 }),
        pdot,
    }
}

/// Homogeneous-state identities for family C: returns the largest relative defect.
fn homogeneous_defect<C: CellShape>() -> f64 {
    let mut rng = Rng::new(51);
    let x = cell::<C>();
    let (vol, moment) = volume_and_moment::<C>(&x);
    let q = rule(C::FAMILY);
    let tab = tabulate_cell(C::FAMILY, &q);
    let mut worst: f64 = 0.0;
    let mut check = |what: &str, got: f64, want: f64, scale: f64| {
        let e = (got - want).abs() / scale;
        assert!(e < 1e-10, "{:?}: {what}: {got} against {want} (relative {e:.1e})", C::FAMILY);
        worst = worst.max(e);
    };
    for gravity in [false, true] {
        let model = table1(gravity);
        let stab = Stabilisation::new(0.5, None, &model);
        let k = kernel::<C>(&model, &tab, &q.points, stab, false);
        // Constant gradients; on the meridian an axisymmetric one: u_r = α R, u_z = δ R + β Z
        // (so the hoop strain is α too), u̇ alike, and Grad p in the meridian plane.
        let (g, l, gp) = match C::FAMILY {
            Family::Tet10 => (rng.matrix(0.1), rng.matrix(0.02), rng.vector(0.3)),
            Family::Tri6 => {
                let m = |rng: &mut Rng, s: f64| {
                    let (a, d, b) = (rng.uniform(-s, s), rng.uniform(-s, s), rng.uniform(-s, s));
                    Matrix3::new(a, 0.0, 0.0, 0.0, 0.0, 0.0, d, 0.0, b)
                };
                (m(&mut rng, 0.1), m(&mut rng, 0.02), Vector3::new(rng.uniform(-0.3, 0.3), 0.0, 0.3))
            }
        };
        let pdot = std::array::from_fn(|_| rng.uniform(-1.0, 1.0));
        let input = ElementInput {
            elem: 0,
            coords: x,
            values: affine::<C>(&x, &g, &l, 2.0, &gp, pdot),
            dt: 0.5,
            qp_state: QpState::NONE,
        };
        let mut r = [0.0; MAX_DOF];
        k.residual(&input, &mut r).unwrap();
        // The model at the homogeneous state (hoop entries θθ = α on the meridian).
        let hoop = |m: &Matrix3<f64>| {
            let mut m = *m;
            if C::AXI {
                m[(1, 1)] = m[(0, 0)];
            }
            m
        };
        let s = PointState { grad_u: hoop(&g), grad_udot: hoop(&l), p: 0.0, grad_p: gp, dt: 0.5 };
        // P is affine in p at a fixed F: P = P(p = 0) + p ∂P/∂p, and p is linear over the cell,
        // so its moments need ∫ p dV = p0 V + Grad p · ∫X dV only.
        let at = QpId { elem: 0, point: 0 };
        let f0 = model.eval(at, &PointState { p: 0.0, ..s }, QpState::NONE).unwrap();
        let f1 = model.eval(at, &PointState { p: 1.0, ..s }, QpState::NONE).unwrap();
        let dpdp = f1.stress - f0.stress;
        let int_p = 2.0 * vol + gp.dot(&Vector3::from(moment));
        let scale_u = f0.stress.norm() * vol * 20.0;
        let nc = C::NC;
        for c in 0..nc {
            let i = C::AXES[c];
            // Σ_a r_u[a,i] = −b_i V (+ ∫ P_θθ / R dV on the meridian's r rows, not checked).
            if !(C::AXI && i == 0) {
                let sum: f64 = (0..C::NN).map(|a| r[nc * a + c]).sum();
                check("Σ_a r_u", sum, -f0.body[i] * vol, scale_u);
            }
            for kk in [0, 2].into_iter().chain((!C::AXI).then_some(1)) {
                let mom: f64 = (0..C::NN).map(|a| r[nc * a + c] * x[a][kk]).sum();
                let mut want = f0.stress[(i, kk)] * vol + dpdp[(i, kk)] * int_p - f0.body[i] * moment[kk];
                if C::AXI && i == 0 && kk == 0 {
                    want += f0.stress[(1, 1)] * vol + dpdp[(1, 1)] * int_p;
                }
                if C::AXI && i == 0 && kk == 2 {
                    continue; // holds P_θθ ∫ Z/R dV: not a closed moment
                }
                check(&format!("Σ_a r_u[a,{i}] X_a,{kk}"), mom, want, scale_u);
            }
        }
        // p rows: ṡ and W are constant (they do not depend on p's value); the stabilisation
        // tests with q − Πq, whose sum over the vertices vanishes.
        let rate = f0.rate;
        let scale_p = (rate.abs() * vol + f0.flux.norm() * vol) * 20.0;
        let sum: f64 = (0..C::NV).map(|m| r[C::NU + m]).sum();
        check("Σ_m r_p", sum, rate * vol, scale_p);
        // The moments X_m,k also see the stabilisation (q − Πq is not orthogonal to a ṗ that
        // varies): check them with a uniform ṗ, for which the stabilisation vanishes.
        let mut uniform = input;
        uniform.values.pdot = [0.7; MAX_VERTICES];
        let mut r = [0.0; MAX_DOF];
        k.residual(&uniform, &mut r).unwrap();
        for kk in [0, 2].into_iter().chain((!C::AXI).then_some(1)) {
            let mom: f64 = (0..C::NV).map(|m| r[C::NU + m] * x[m][kk]).sum();
            check(&format!("Σ_m r_p[m] X_m,{kk}"), mom, rate * moment[kk] + f0.flux[kk] * vol, scale_p);
        }
    }
    worst
}

#[test]
fn homogeneous_states_give_exact_nodal_moments() {
    let (t, m) = (homogeneous_defect::<Tet10>(), homogeneous_defect::<Tri6Axi>());
    println!("largest relative defect: tetrahedron {t:.1e}, meridian triangle {m:.1e}");
}

/// Largest relative difference between the element Jacobian and central differences of the
/// element residual, over the columns, for family C.
fn jacobian_defect<C: CellShape>(equal_order: bool, remodelling: bool) -> f64 {
    let mut rng = Rng::new(52);
    let x = cell::<C>();
    let q = rule(C::FAMILY);
    let tab = tabulate_cell(C::FAMILY, &q);
    let mut model = table1(true);
    if remodelling {
        model = model.with_remodelling(Remodelling::new(0.001, 2.0).unwrap());
    }
    let n = model.qp_state_len();
    let committed: Vec<f64> = (0..q.len()).flat_map(|_| to_sym6(&rng.remodelling_metric()).to_vec()).collect();
    let committed = if n == 0 { Vec::new() } else { committed };
    let (dt, shift) = (0.5, 2.0);
    // A faded weight that is not yet zero at this step and cell size.
    let stab = Stabilisation::new(0.5, Some(Fade { tau0: 1e3, dt0: 0.25, steps: 4.0 }), &model);
    let k = kernel::<C>(&model, &tab, &q.points, stab, equal_order);
    let mut values = affine::<C>(&x, &Matrix3::zeros(), &Matrix3::zeros(), 0.0, &Vector3::zeros(), [0.0; 4]);
    for a in 0..C::NN {
        for c in 0..C::NC {
            values.u[a][c] = rng.uniform(-0.6, 0.6);
            values.udot[a][c] = rng.uniform(-0.2, 0.2);
        }
    }
    for m in 0..C::NV {
        values.p[m] = rng.uniform(-3.0, 3.0);
        values.pdot[m] = rng.uniform(-1.0, 1.0);
    }
    let input = |v: ElementValues| ElementInput {
        elem: 0,
        coords: x,
        values: v,
        dt,
        qp_state: QpState { committed: &committed, evolve: true },
    };
    let mut kk: ElementMatrix = [[0.0; MAX_DOF]; MAX_DOF];
    let mut schur = [[0.0; MAX_VERTICES]; MAX_VERTICES];
    k.jacobian(&input(values), shift, &mut kk, &mut schur).unwrap();
    let ndof = C::NU + C::NV;
    let mut worst: f64 = 0.0;
    for col in 0..ndof {
        let eps = if col < C::NU { 1e-6 } else { 1e-5 };
        let perturbed = |s: f64| {
            let mut v = values;
            if col < C::NU {
                v.u[col / C::NC][col % C::NC] += s * eps;
                v.udot[col / C::NC][col % C::NC] += s * shift * eps;
            } else {
                v.p[col - C::NU] += s * eps;
                v.pdot[col - C::NU] += s * shift * eps;
            }
            let mut r = [0.0; MAX_DOF];
            k.residual(&input(v), &mut r).unwrap();
            r
        };
        let (rp, rm) = (perturbed(1.0), perturbed(-1.0));
        let fd: Vec<f64> = (0..ndof).map(|row| (rp[row] - rm[row]) / (2.0 * eps)).collect();
        let norm = fd.iter().map(|v| v * v).sum::<f64>().sqrt().max(1e-300);
        let diff = (0..ndof).map(|row| (kk[row][col] - fd[row]).powi(2)).sum::<f64>().sqrt();
        worst = worst.max(diff / norm);
    }
    worst
}

#[test]
fn element_jacobian_matches_central_differences() {
    let cases = [
        ("tetrahedron", jacobian_defect::<Tet10>(false, false)),
        ("tetrahedron, remodelling", jacobian_defect::<Tet10>(false, true)),
        ("tetrahedron, equal order", jacobian_defect::<Tet10>(true, false)),
        ("meridian triangle", jacobian_defect::<Tri6Axi>(false, false)),
        ("meridian triangle, remodelling", jacobian_defect::<Tri6Axi>(false, true)),
    ];
    for (name, e) in cases {
        println!("{name}: largest relative column error {e:.1e}");
        assert!(e < 1e-6, "{name}: element Jacobian off by {e:.1e}");
    }
}

/// The area of the meridian triangle of edge h.
fn area(h: f64) -> f64 {
    3f64.sqrt() / 4.0 * h * h
}

#[test]
fn the_fade_is_full_at_a_kink_and_gone_once_the_steps_have_grown_whatever_c_v() {
    let fade = Some(Fade { tau0: 0.03, dt0: 0.02, steps: 4.0 });
    // A soft aggregate's bulk element (c_v = 6.1 µm²/s, h = 44 µm): c_v Δt / h² stays below
    // τ₀ for any step of its ramp, so the drainage alone never faded the term.
    let soft = Stabilisation { c_s: 1.0, fade, c_v: 6.1 };
    let m = area(44.0);
    let first = 1.0 - (6.1f64 * 0.02 / (44.0 * 44.0 * 0.03)).powi(2);
    assert!((soft.weight::<Tri6Axi>(m, 0.02) - first).abs() < 1e-12 && first > 0.999_99, "first step");
    assert!(soft.weight::<Tri6Axi>(m, 0.01) > 0.999_99, "a cut step keeps the full weight");
    assert!((soft.weight::<Tri6Axi>(m, 0.04) - (1.0 - 1.0 / 9.0)).abs() < 1e-6, "Δt = 2 Δt₀: r = 1/3");
    assert_eq!(soft.weight::<Tri6Axi>(m, 0.08), 0.0, "gone at Δt = 4 Δt₀");
    assert_eq!(soft.weight::<Tri6Axi>(m, 2.0), 0.0);
    // A stiff one's pole element (c_v = 120 µm²/s, h = 3 µm): the drainage fades it first.
    let stiff = Stabilisation { c_v: 120.0, ..soft };
    assert_eq!(stiff.weight::<Tri6Axi>(area(3.0), 0.02), 0.0);
    // Without a fade, constant.
    let constant = Stabilisation { fade: None, ..soft };
    assert_eq!(constant.weight::<Tri6Axi>(m, 2.0), 1.0);
}
