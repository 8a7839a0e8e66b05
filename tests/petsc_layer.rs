//! The safe PETSc layer on its own (one process; MPI and PETSc initialised once): PETSc errors
//! come back as Rust errors with PETSc's message; TS trampolines integrate an ODE with the
//! exact backward-Euler recurrence, call the post-step and monitor hooks; an error raised in a
//! callback comes back unchanged; a domain error makes TS cut the step instead of failing.

use poroplast::error::{Error, Result};
use poroplast::petsc::{options, Int, Mat, Petsc, Ts, TsProblem, TsRef, Vector};

/// u̇ = −λ u on one dof, as F(t, u, u̇) = u̇ + λ u. Fails on demand to test error paths.
struct Decay {
    lambda: f64,
    post_steps: usize,
    monitored: usize,
    /// Residual returns a domain error when the step is larger than this.
    max_dt: f64,
    /// Residual fails hard at this time or later.
    fail_after: f64,
}

impl TsProblem for Decay {
    fn residual(&mut self, ts: TsRef, t: f64, u: &Vector, udot: &Vector, f: &mut Vector) -> Result<()> {
        if ts.time_step()? > self.max_dt {
            return Err(Error::Domain { cell: 7, point: 1, j: 0.5, msg: "test domain error".into() });
        }
        if t >= self.fail_after {
            return Err(Error::Material("deliberate failure inside the residual".into()));
        }
        let (u, ud) = (u.read()?, udot.read()?);
        let mut fw = f.write()?;
        for i in 0..fw.len() {
            fw[i] = ud[i] + self.lambda * u[i];
        }
        Ok(())
    }
    fn jacobian(
        &mut self,
        _ts: TsRef,
        _t: f64,
        _u: &Vector,
        _ud: &Vector,
        shift: f64,
        jac: &mut Mat,
        _pre: &mut Mat,
    ) -> Result<()> {
        jac.zero_entries()?;
        jac.add_values(&[0], &[0], &[shift + self.lambda])?;
        jac.assemble()
    }
    fn post_step(&mut self, _ts: TsRef) -> Result<()> {
        self.post_steps += 1;
        Ok(())
    }
    fn monitor(&mut self, _ts: TsRef, _step: usize, _t: f64, _u: &Vector) -> Result<()> {
        self.monitored += 1;
        Ok(())
    }
}

fn decay_ts(comm: poroplast::petsc::ffi::MPI_Comm, p: Decay) -> Result<(Ts<Decay>, Vector)> {
    let mut u = Vector::mpi(comm, 1)?;
    u.set(1.0)?;
    let f = u.duplicate()?;
    let jac = Mat::aij(comm, 1, &[1 as Int], &[0 as Int])?;
    let mut ts = Ts::new(comm, p, f, jac, None, None)?;
    ts.set_solution(&u)?;
    ts.set_time(0.0)?;
    ts.set_from_options()?;
    let snes = ts.snes()?;
    snes.ksp()?.set_type("preonly")?;
    snes.ksp()?.pc()?.set_type("lu")?;
    Ok((ts, u))
}

/// An unsymmetric sparse J (n = 40: a convection–diffusion stencil plus long-range couplings,
/// so that rows and columns differ) and the active-set operator "J with the rows and columns
/// of `active` replaced by d·I".
fn active_set_operator(comm: poroplast::petsc::ffi::MPI_Comm, n: usize, active: &[Int], d: f64) -> (Mat, Mat) {
    let far = |i: usize| (i * 7 + 3) % n;
    let mut entries = Vec::new();
    for i in 0..n {
        let mut row = vec![(i, 4.0 + 0.1 * i as f64)];
        if i > 0 {
            row.push((i - 1, -1.3));
        }
        if i + 1 < n {
            row.push((i + 1, -0.7));
        }
        if ![i, i.wrapping_sub(1), i + 1].contains(&far(i)) {
            row.push((far(i), 0.45));
        }
        entries.push(row);
    }
    let nnz: Vec<Int> = entries.iter().map(|r| r.len() as Int).collect();
    let mut j = Mat::aij(comm, n, &nnz, &vec![0; n]).unwrap();
    for (i, row) in entries.iter().enumerate() {
        for &(c, v) in row {
            j.add_values(&[i as Int], &[c as Int], &[v]).unwrap();
        }
    }
    j.assemble().unwrap();
    let mut b = j.duplicate_with_values().unwrap();
    b.zero_rows_columns(active, d, None).unwrap();
    (j, b)
}

fn active_set_update_is_exact(world: &mpi::topology::SimpleCommunicator, comm: poroplast::petsc::ffi::MPI_Comm) {
    use poroplast::petsc::LuFactor;
    use poroplast::solver::ActiveSetUpdate;
    let (n, d) = (40, 2.5);
    // Dof 3 leaves the active set, 20 and 25 enter it, 10 and 11 stay (11's far coupling is 0).
    let (old, new): (&[Int], &[Int]) = (&[3, 10, 11], &[10, 11, 20, 25]);
    let (j, p) = active_set_operator(comm, n, old, d);
    let (_, b_new) = active_set_operator(comm, n, new, d);
    let p_lu = LuFactor::new(comm, &p).unwrap();
    let b_lu = LuFactor::new(comm, &b_new).unwrap();
    let update = ActiveSetUpdate::new(world, &j, p_lu.pc(), old, new, d).unwrap().expect("nonsingular");
    assert_eq!(update.n_changed(), 3);
    let mut rhs = Vector::mpi(comm, n).unwrap();
    for (i, r) in rhs.write().unwrap().iter_mut().enumerate() {
        *r = (0.3 * i as f64).sin() + 0.1;
    }
    let (mut x, mut exact, mut stale) = (rhs.duplicate().unwrap(), rhs.duplicate().unwrap(), rhs.duplicate().unwrap());
    update.solve(world, p_lu.pc(), &rhs, &mut x).unwrap();
    b_lu.pc().apply(&rhs, &mut exact).unwrap();
    p_lu.pc().apply(&rhs, &mut stale).unwrap();
    let scale = exact.norm_inf().unwrap();
    exact.axpy(-1.0, &x).unwrap();
    stale.axpy(-1.0, &x).unwrap();
    let err = exact.norm_inf().unwrap() / scale;
    assert!(err < 1e-12, "updated solve vs a factorisation of the new operator: {err:.2e}");
    // The update matters: the old factorisation alone is far off.
    assert!(stale.norm_inf().unwrap() > 1e-2 * scale, "the active-set change must change the solution");
}

/// Chord iterations x ← x + P⁻¹(b − A x) with P an operator that differs from A in the rows
/// and columns of 3 dofs (a rank-6 difference, so I − P⁻¹A has rank 6): Anderson mixing of
/// depth 6, equivalent to GMRES on a linear map, converges in 6 iterations after its first
/// (measured: residual 8.5e-11 after 8, 6.7e-14 after 9) to the solution of an LU factorisation
/// of A; the plain chord iterations are still far off after as many.
fn anderson_accelerates_chord_iterations(comm: poroplast::petsc::ffi::MPI_Comm) {
    use poroplast::petsc::LuFactor;
    use poroplast::solver::anderson::Anderson;
    let (n, d) = (40, 2.5);
    let (a, p) = active_set_operator(comm, n, &[3, 10, 11], d);
    let p_lu = LuFactor::new(comm, &p).unwrap();
    let a_lu = LuFactor::new(comm, &a).unwrap();
    let mut b = Vector::mpi(comm, n).unwrap();
    for (i, r) in b.write().unwrap().iter_mut().enumerate() {
        *r = (0.3 * i as f64).sin() + 0.1;
    }
    let mut exact = b.duplicate().unwrap();
    a_lu.pc().apply(&b, &mut exact).unwrap();
    let run = |depth: usize, its: usize| -> (f64, f64) {
        let mut mixing = Anderson::new(depth);
        let (mut x, mut r, mut step) = (b.duplicate().unwrap(), b.duplicate().unwrap(), b.duplicate().unwrap());
        x.zero().unwrap();
        for it in 0..its {
            a.mult(&x, &mut r).unwrap();
            r.scale(-1.0).unwrap();
            r.axpy(1.0, &b).unwrap();
            p_lu.pc().apply(&r, &mut step).unwrap();
            mixing.mix(&x, &mut step, it > 0).unwrap();
            x.axpy(1.0, &step).unwrap();
        }
        a.mult(&x, &mut r).unwrap();
        r.axpy(-1.0, &b).unwrap();
        let res = r.norm2().unwrap() / b.norm2().unwrap();
        x.axpy(-1.0, &exact).unwrap();
        (res, x.norm_inf().unwrap() / exact.norm_inf().unwrap())
    };
    let (res, err) = run(6, 9);
    assert!(res < 1e-12 && err < 1e-11, "Anderson(6), 9 iterations: residual {res:.2e}, error {err:.2e}");
    let (res0, _) = run(0, 9);
    assert!(res0 > 1e-4, "plain chord iterations, 9 iterations: residual {res0:.2e} (too easy a test)");
}

#[test]
fn petsc_layer() {
    let universe = mpi::initialize().expect("MPI");
    let world = universe.world();
    let petsc = Petsc::init(&world, &[]).expect("PetscInitialize");
    let comm = petsc.comm();

    // 1. A PETSc error carries PETSc's own message.
    let mut v = Vector::mpi(comm, 4).unwrap();
    match v.set_block_size(3) {
        Err(Error::Petsc { code, msg }) => {
            assert!(code != 0);
            assert!(msg.contains("block size") || msg.contains("blocksize"), "message: {msg}");
            assert!(
                msg.contains("VecSetBlockSize") || msg.contains("PetscLayoutSetBlockSize"),
                "no function name in: {msg}"
            );
        }
        other => panic!("expected a PETSc error, got {other:?}"),
    }

    // 2. Options: set, query, unused detection.
    options::set("poroplast_test_option", Some("3")).unwrap();
    assert!(options::unused().unwrap().iter().any(|o| o == "-poroplast_test_option"));
    assert!(options::has("poroplast_test_option").unwrap());
    assert!(
        !options::unused().unwrap().iter().any(|o| o == "-poroplast_test_option"),
        "a queried option counts as used"
    );

    // 3. Backward Euler through the trampolines: u_n = (1 + λΔt)^-n exactly (linear, LU).
    let (lambda, dt, n) = (2.0, 0.1, 10);
    let p = Decay { lambda, post_steps: 0, monitored: 0, max_dt: f64::MAX, fail_after: f64::MAX };
    let (mut ts, mut u) = decay_ts(comm, p).unwrap();
    ts.set_time_step(dt).unwrap();
    ts.set_max_time(n as f64 * dt).unwrap();
    ts.solve(&mut u).unwrap();
    let exact = (1.0 + lambda * dt).powi(-(n as i32));
    let got = u.read().unwrap()[0];
    assert!((got - exact).abs() < 1e-12 * exact, "BE: {got} vs {exact}");
    assert_eq!(ts.step_number().unwrap(), n);
    assert_eq!(ts.problem().post_steps, n, "post-step hook calls");
    assert!(ts.problem().monitored >= n, "monitor calls: {}", ts.problem().monitored);
    drop(ts);

    // 4. An error in a callback comes back as that error.
    let p = Decay { lambda, post_steps: 0, monitored: 0, max_dt: f64::MAX, fail_after: 0.25 };
    let (mut ts, _u) = decay_ts(comm, p).unwrap();
    ts.set_time_step(0.1).unwrap();
    ts.set_max_time(1.0).unwrap();
    let mut failed = None;
    for _ in 0..10 {
        if let Err(e) = ts.step() {
            failed = Some(e);
            break;
        }
    }
    match failed {
        Some(Error::Material(m)) => assert!(m.contains("deliberate")),
        other => panic!("expected the callback's material error, got {other:?}"),
    }
    drop(ts);

    // 5. A domain error is a step cut: a step of 0.4 is cut by TSAdapt's factor (0.25, its
    //    default -ts_adapt_scale_solve_failed) to 0.1 and then accepted.
    let p = Decay { lambda, post_steps: 0, monitored: 0, max_dt: 0.1, fail_after: f64::MAX };
    let (mut ts, _u) = decay_ts(comm, p).unwrap();
    ts.set_time_step(0.4).unwrap();
    ts.set_max_time(1.0).unwrap();
    ts.set_max_rejections(5).unwrap();
    ts.step().unwrap();
    let t = ts.time().unwrap();
    assert!((t - 0.1).abs() < 1e-14, "accepted step ends at {t}, expected 0.1 after one cut");
    assert_eq!(ts.rejections().unwrap(), 1);
    assert_eq!(ts.domain_errors().0, 1);
    assert!(ts.domain_errors().1.unwrap().contains("element 7"));
    drop(ts);

    // 6. The low-rank update of a factorised active-set operator solves with the operator of
    //    the new active set: against a factorisation of that operator itself.
    active_set_update_is_exact(&universe.world(), comm);
    anderson_accelerates_chord_iterations(comm);

    drop(v);
    drop(petsc);
    drop(universe);
}
