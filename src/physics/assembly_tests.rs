//! The one element loop (`fem::assembly`) with the Table 1 biphasic model on a small mesh of
//! each family: the assembled Jacobian against central differences of the assembled residual.

use crate::fem::kernel::Stabilisation;
use crate::fem::{quadrature, test_util::discretization};
use crate::material::test_util::Rng;
use crate::material::Remodelling;
use crate::physics::kernel_tests::table1;
use crate::reference_cell::Family;
use nalgebra::DMatrix;

/// The element loop on a small mesh of each family (the Table 1 model with remodelling, so
/// the qp state is gathered per element too): the assembled Jacobian equals central
/// differences of the assembled residual, U̇ moving with shift × the perturbation, and the
/// rows and columns of constrained dofs are zero.
#[test]
fn assembled_jacobian_matches_central_differences_of_the_assembled_residual() {
    for family in [Family::Tet10, Family::Tri6] {
        let q = match family {
            Family::Tet10 => quadrature::tet(4),
            Family::Tri6 => quadrature::tri(4),
        };
        let model = table1(true).with_remodelling(Remodelling::new(0.001, 2.0).unwrap());
        let stab = Stabilisation::new(0.5, None, &model);
        // The unit cube (square) scaled to 10 µm: the model's units.
        let mut disc = discretization(family, 2, Box::new(model), stab, &q);
        disc.mesh.coords.iter_mut().for_each(|x| x.iter_mut().for_each(|c| *c *= 10.0));
        let nd = disc.dofs.n_local();
        let mut rng = Rng::new(53);
        let u: Vec<f64> =
            (0..nd).map(|i| rng.uniform(-1.0, 1.0) * if i < disc.dofs.n_u_local() { 0.05 } else { 2.0 }).collect();
        let udot: Vec<f64> = (0..nd).map(|_| rng.uniform(-0.1, 0.1)).collect();
        for i in (0..nd).step_by(7) {
            disc.constrained[i] = true;
        }
        let (dt, shift) = (0.5, 2.0);
        let n = disc.ndof();
        let mut a = DMatrix::<f64>::zeros(nd, nd);
        disc.jacobian_loop(&u, &udot, dt, shift, None, |_, d, k| {
            for r in 0..n {
                for c in 0..n {
                    a[(d[r], d[c])] += k[r][c];
                }
            }
            Ok(())
        })
        .unwrap();
        let residual = |j: usize, s: f64| {
            let (mut up, mut vp) = (u.clone(), udot.clone());
            up[j] += s;
            vp[j] += shift * s;
            let mut f = vec![0.0; nd];
            disc.add_residual(&up, &vp, dt, &mut f).unwrap();
            f
        };
        let mut worst: f64 = 0.0;
        for j in 0..nd {
            if disc.constrained[j] {
                assert!(a.column(j).iter().all(|&v| v == 0.0), "{family:?}: constrained column {j} not zero");
                assert!(a.row(j).iter().all(|&v| v == 0.0), "{family:?}: constrained row {j} not zero");
                continue;
            }
            let eps = 1e-6 * u[j].abs().max(0.05);
            let (fp, fm) = (residual(j, eps), residual(j, -eps));
            let fd: Vec<f64> =
                (0..nd).map(|i| if disc.constrained[i] { 0.0 } else { (fp[i] - fm[i]) / (2.0 * eps) }).collect();
            let norm = fd.iter().map(|v| v * v).sum::<f64>().sqrt();
            let diff = (0..nd).map(|i| (a[(i, j)] - fd[i]).powi(2)).sum::<f64>().sqrt();
            worst = worst.max(diff / norm);
        }
        println!("{family:?}: {nd} dofs, largest relative column error {worst:.1e}");
        assert!(worst < 1e-6, "{family:?}: assembled Jacobian off by {worst:.1e}");
    }
}
