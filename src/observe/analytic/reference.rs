//! Independent numerical solutions the exact series are tested against: a Crank–Nicolson
//! column for Terzaghi and a coupled radial finite-volume sphere for Cryer, each with its own
//! banded solver (nothing shared with the series or with the finite-element code).

#![allow(clippy::needless_range_loop)] // index-heavy numerical schemes read better with indices

/// Banded LU with partial pivoting on dense row-major storage (`kl`, `ku`: band half-widths).
struct BandLu {
    n: usize,
    kl: usize,
    width: usize,
    a: Vec<f64>,
    piv: Vec<usize>,
}

impl BandLu {
    fn new(mut a: Vec<f64>, n: usize, kl: usize, ku: usize) -> Self {
        let width = kl + ku; // fill-in reach of the upper factor with pivoting
        let mut piv = vec![0; n];
        for j in 0..n {
            let last = (j + kl).min(n - 1);
            let mut p = j;
            for i in j..=last {
                if a[i * n + j].abs() > a[p * n + j].abs() {
                    p = i;
                }
            }
            piv[j] = p;
            if p != j {
                // LINPACK style: earlier multipliers stay in place (matches `solve`)
                for c in j..n {
                    a.swap(j * n + c, p * n + c);
                }
            }
            let d = a[j * n + j];
            assert!(d != 0.0, "singular matrix");
            let cend = (j + width).min(n - 1);
            for i in (j + 1)..=last {
                let m = a[i * n + j] / d;
                a[i * n + j] = m;
                if m != 0.0 {
                    for c in (j + 1)..=cend {
                        a[i * n + c] -= m * a[j * n + c];
                    }
                }
            }
        }
        BandLu { n, kl, width, a, piv }
    }

    fn solve(&self, b: &mut [f64]) {
        let n = self.n;
        for j in 0..n {
            b.swap(j, self.piv[j]);
            let last = (j + self.kl).min(n - 1);
            for i in (j + 1)..=last {
                b[i] -= self.a[i * n + j] * b[j];
            }
        }
        for j in (0..n).rev() {
            let cend = (j + self.width).min(n - 1);
            let mut s = b[j];
            for c in (j + 1)..=cend {
                s -= self.a[j * n + c] * b[c];
            }
            b[j] = s / self.a[j * n + j];
        }
    }
}

/// Crank–Nicolson (with implicit-Euler start-up steps) finite differences for the dimensionless
/// Terzaghi problem p_τ = p_ζζ, p_ζ(0) = 0, p(1) = 0, p(ζ, 0) = 1. Returns p at the requested
/// (ζ-node, τ) pairs on a grid of `n` intervals.
pub(super) fn terzaghi_fd(n: usize, dt: f64, times: &[f64]) -> Vec<Vec<f64>> {
    let h = 1.0 / n as f64;
    let m = n; // unknowns p_0..p_{n-1}; p_n = 0
    let mut p = vec![1.0; m];
    let mut out = Vec::new();
    let mut t = 0.0;
    // L p: (p_{i+1} - 2p_i + p_{i-1})/h², ghost p_{-1} = p_1, p_n = 0
    let lap = |p: &[f64], i: usize| -> f64 {
        let left = if i == 0 { p[1] } else { p[i - 1] };
        let right = if i + 1 < m { p[i + 1] } else { 0.0 };
        (left - 2.0 * p[i] + right) / (h * h)
    };
    // solve (I - θ dt L) x = rhs by the Thomas algorithm
    let solve = |theta_dt: f64, rhs: &mut Vec<f64>| {
        let r = theta_dt / (h * h);
        let mut sub = vec![-r; m];
        let mut diag = vec![1.0 + 2.0 * r; m];
        let sup = vec![-r; m];
        sub[0] = 0.0;
        // ghost: row 0 couples to p_1 with -2r
        let mut sup0 = sup.clone();
        sup0[0] = -2.0 * r;
        for i in 1..m {
            let w = sub[i] / diag[i - 1];
            diag[i] -= w * sup0[i - 1];
            rhs[i] -= w * rhs[i - 1];
            sub[i] = 0.0;
        }
        rhs[m - 1] /= diag[m - 1];
        for i in (0..m - 1).rev() {
            rhs[i] = (rhs[i] - sup0[i] * rhs[i + 1]) / diag[i];
        }
    };
    // start-up: 8 implicit Euler steps of dt/8 (damps the corner discontinuity)
    let small = dt / 8.0;
    for _ in 0..8 {
        let mut rhs = p.clone();
        solve(small, &mut rhs);
        p = rhs;
        t += small;
    }
    let mut next = 0;
    while next < times.len() {
        if (t - times[next]).abs() < 0.5 * dt {
            out.push(p.clone());
            next += 1;
            continue;
        }
        let mut rhs: Vec<f64> = (0..m).map(|i| p[i] + 0.5 * dt * lap(&p, i)).collect();
        solve(0.5 * dt, &mut rhs);
        p = rhs;
        t += dt;
    }
    out
}

/// Output of the coupled radial finite-volume Cryer solver at one time.
pub(super) struct CryerFdState {
    /// Pressure at the cell centres r = (j + 1/2) h.
    pub(super) p: Vec<f64>,
    /// Radial displacement at the nodes r = i h.
    pub(super) u: Vec<f64>,
}

/// Coupled finite-volume solution of the radially symmetric Cryer problem in the unknowns
/// u(r) (radial displacement, at the nodes r_i = i h) and p(r) (at the cell centres), with
/// µ = 1, a = 1, P = 1 and k = 1/(λ + 2µ) so that c = 1. Per cell, the volumetric strain is
/// the exact cell average ε_j = 3 (r_{j+1}² u_{j+1} − r_j² u_j)/(r_{j+1}³ − r_j³).
/// * equilibrium at interior nodes: (λ+2µ)(ε_{j} − ε_{j−1}) = p_{j} − p_{j−1}, u(0) = 0;
/// * traction σ_rr(a) = (λ+2µ) ε(a) − 4µ u(a)/a − p(a) = −P, with ε(a) taken from the last
///   cell through equilibrium ((λ+2µ)ε − p is uniform) and p(a) = 0;
/// * mass per cell: V_j dε_j/dt = k [r² ∂p/∂r]_{r_j}^{r_{j+1}}, no flux at r = 0, p(a) = 0;
/// * initially u = 0 (no volume change). BDF2 in time, restarted with one implicit Euler
///   step at the start of each constant-step phase.
pub(super) fn cryer_fd(nu: f64, n: usize, times: &[f64]) -> Vec<CryerFdState> {
    let mu = 1.0;
    let lam = 2.0 * mu * nu / (1.0 - 2.0 * nu);
    let mm = lam + 2.0 * mu;
    let k = 1.0 / mm;
    let h = 1.0 / n as f64;
    let nn = 2 * n + 1;
    // interleaved unknowns: u_i at 2i, p_j (cell j) at 2j + 1
    let iu = |i: usize| 2 * i;
    let ip = |j: usize| 2 * j + 1;
    let r = |i: usize| i as f64 * h;
    let vol = |j: usize| (r(j + 1).powi(3) - r(j).powi(3)) / 3.0;
    // ε_j = (r_{j+1}² u_{j+1} − r_j² u_j) / V_j: coefficients on u_j, u_{j+1}
    let ecoef = |j: usize| (-r(j) * r(j) / vol(j), r(j + 1) * r(j + 1) / vol(j));
    let eps = |x: &[f64]| -> Vec<f64> {
        (0..n)
            .map(|j| {
                let (c0, c1) = ecoef(j);
                c0 * x[iu(j)] + c1 * x[iu(j + 1)]
            })
            .collect()
    };
    let matrix = |alpha: f64| -> BandLu {
        let mut a = vec![0.0; nn * nn];
        let mut set = |row: usize, col: usize, v: f64| a[row * nn + col] += v;
        set(iu(0), iu(0), 1.0);
        for i in 1..n {
            // M ε_i − p_i − (M ε_{i−1} − p_{i−1}) = 0
            let row = iu(i);
            let (c0, c1) = ecoef(i);
            set(row, iu(i), mm * c0);
            set(row, iu(i + 1), mm * c1);
            let (c0, c1) = ecoef(i - 1);
            set(row, iu(i - 1), -mm * c0);
            set(row, iu(i), -mm * c1);
            set(row, ip(i), -1.0);
            set(row, ip(i - 1), 1.0);
        }
        // traction: M ε_{n−1} − p_{n−1} − 4µ u_n = −P
        let (c0, c1) = ecoef(n - 1);
        set(iu(n), iu(n - 1), mm * c0);
        set(iu(n), iu(n), mm * c1 - 4.0 * mu);
        set(iu(n), ip(n - 1), -1.0);
        // mass: α V_j ε_j − k (A_{j+1} g_{j+1} − A_j g_j) = rhs
        for j in 0..n {
            let row = ip(j);
            let (c0, c1) = ecoef(j);
            set(row, iu(j), alpha * vol(j) * c0);
            set(row, iu(j + 1), alpha * vol(j) * c1);
            // outer face r_{j+1}
            let ao = r(j + 1) * r(j + 1);
            if j + 1 < n {
                set(row, ip(j + 1), -k * ao / h);
                set(row, ip(j), k * ao / h);
            } else {
                // p(a) = 0 at half a cell
                set(row, ip(j), k * ao / (0.5 * h));
            }
            if j > 0 {
                let ai = r(j) * r(j);
                set(row, ip(j), k * ai / h);
                set(row, ip(j - 1), -k * ai / h);
            }
        }
        BandLu::new(a, nn, 4, 4)
    };
    let phases = [(1e-6, 1e-4), (1e-5, 1e-3), (5e-5, 1e-2), (1e-4, 0.1), (5e-4, 1.0)];
    let mut x;
    let mut e_prev = vec![0.0; n];
    let mut e_now = vec![0.0; n];
    let mut t: f64 = 0.0;
    let mut out = Vec::new();
    let mut next = 0;
    for &(dt, t_end) in &phases {
        if next >= times.len() {
            break;
        }
        let steps = ((t_end - t) / dt).round() as usize;
        let be = matrix(1.0 / dt);
        let bdf = matrix(1.5 / dt);
        for s in 0..steps {
            let mut b = vec![0.0; nn];
            b[iu(n)] = -1.0;
            if s == 0 {
                for j in 0..n {
                    b[ip(j)] = vol(j) * e_now[j] / dt;
                }
                be.solve(&mut b);
            } else {
                for j in 0..n {
                    b[ip(j)] = vol(j) * (4.0 * e_now[j] - e_prev[j]) / (2.0 * dt);
                }
                bdf.solve(&mut b);
            }
            x = b;
            e_prev = std::mem::replace(&mut e_now, eps(&x));
            t += dt;
            while next < times.len() && (t - times[next]).abs() < 0.25 * dt {
                out.push(CryerFdState {
                    p: (0..n).map(|j| x[ip(j)]).collect(),
                    u: (0..=n).map(|i| x[iu(i)]).collect(),
                });
                next += 1;
            }
        }
    }
    out
}

/// max that propagates NaN (f64::max ignores it).
pub(super) fn nanmax(acc: f64, d: f64) -> f64 {
    if d.is_nan() || acc.is_nan() {
        f64::NAN
    } else {
        acc.max(d.abs())
    }
}
