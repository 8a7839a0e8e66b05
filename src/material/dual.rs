//! Forward-mode dual numbers with N derivative directions, and the few 3 × 3 matrix operations
//! (products, deviator, exponential) that the remodelling update needs, generic over f64 and
//! [`Dual`]. Used to differentiate the local implicit update exactly (no finite differences):
//! a value a + Σ εᵢ ∂ᵢa with εᵢ εⱼ = 0.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A scalar the generic matrix code runs on: f64, or a dual number.
pub(crate) trait Scalar:
    Copy + Add<Output = Self> + Sub<Output = Self> + Mul<Output = Self> + Div<Output = Self> + Neg<Output = Self>
{
    fn cst(x: f64) -> Self;
    /// The value (real part).
    fn re(&self) -> f64;
    fn exp(self) -> Self;
    fn ln(self) -> Self;
    fn sqrt(self) -> Self;
    fn scale(self, s: f64) -> Self;
}

impl Scalar for f64 {
    #[inline]
    fn cst(x: f64) -> Self {
        x
    }
    #[inline]
    fn re(&self) -> f64 {
        *self
    }
    #[inline]
    fn exp(self) -> Self {
        f64::exp(self)
    }
    #[inline]
    fn ln(self) -> Self {
        f64::ln(self)
    }
    #[inline]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
    #[inline]
    fn scale(self, s: f64) -> Self {
        self * s
    }
}

/// a + Σ εᵢ dᵢ.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Dual<const N: usize> {
    pub(crate) re: f64,
    pub(crate) d: [f64; N],
}

impl<const N: usize> Dual<N> {
    /// The independent variable number `i` with value x.
    pub(crate) fn var(x: f64, i: usize) -> Self {
        let mut d = [0.0; N];
        d[i] = 1.0;
        Dual { re: x, d }
    }
    /// f(a) with f' = df at a.
    #[inline]
    fn chain(self, f: f64, df: f64) -> Self {
        self.each(f, |x| x * df)
    }
    /// `re` and each derivative mapped by `f`, written over a copy of `self` (not built by
    /// `array::from_fn`, which copies every entry: see [`m_mul`]).
    #[inline]
    fn each(mut self, re: f64, f: impl Fn(f64) -> f64) -> Self {
        self.re = re;
        self.d.iter_mut().for_each(|x| *x = f(*x));
        self
    }
    /// `re` and each derivative of `self` combined with that of `o` by `f`, in place as [`Self::each`].
    #[inline]
    fn with(mut self, o: &Self, re: f64, f: impl Fn(f64, f64) -> f64) -> Self {
        self.re = re;
        self.d.iter_mut().zip(&o.d).for_each(|(x, y)| *x = f(*x, *y));
        self
    }
}

impl<const N: usize> Add for Dual<N> {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        self.with(&o, self.re + o.re, |x, y| x + y)
    }
}
impl<const N: usize> Sub for Dual<N> {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        self.with(&o, self.re - o.re, |x, y| x - y)
    }
}
impl<const N: usize> Mul for Dual<N> {
    type Output = Self;
    // The product rule adds.
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline]
    fn mul(self, o: Self) -> Self {
        let (a, b) = (self.re, o.re);
        self.with(&o, a * b, |x, y| x * b + a * y)
    }
}
impl<const N: usize> Div for Dual<N> {
    type Output = Self;
    // The quotient rule subtracts and multiplies.
    #[allow(clippy::suspicious_arithmetic_impl)]
    #[inline]
    fn div(self, o: Self) -> Self {
        let inv = 1.0 / o.re;
        let q = self.re * inv;
        self.with(&o, q, |x, y| (x - q * y) * inv)
    }
}
impl<const N: usize> Neg for Dual<N> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self.each(-self.re, |x| -x)
    }
}

impl<const N: usize> Scalar for Dual<N> {
    #[inline]
    fn cst(x: f64) -> Self {
        Dual { re: x, d: [0.0; N] }
    }
    #[inline]
    fn re(&self) -> f64 {
        self.re
    }
    #[inline]
    fn exp(self) -> Self {
        let e = self.re.exp();
        self.chain(e, e)
    }
    #[inline]
    fn ln(self) -> Self {
        self.chain(self.re.ln(), 1.0 / self.re)
    }
    #[inline]
    fn sqrt(self) -> Self {
        let s = self.re.sqrt();
        self.chain(s, 0.5 / s)
    }
    #[inline]
    fn scale(self, s: f64) -> Self {
        self.chain(self.re * s, s)
    }
}

/// A 3 × 3 matrix, row-major `a[i][j]`.
pub(crate) type M3<T> = [[T; 3]; 3];

pub(crate) fn m_cst<T: Scalar>(a: &[[f64; 3]; 3]) -> M3<T> {
    a.map(|r| r.map(T::cst))
}

#[inline]
pub(crate) fn m_mul<T: Scalar>(a: &M3<T>, b: &M3<T>) -> M3<T> {
    // Written into a copy, not built by `array::from_fn`: for duals that copied each entry (a
    // third of a remodelling run's time went to memmove).
    let mut c = *a;
    for (ci, ai) in c.iter_mut().zip(a) {
        for (j, cij) in ci.iter_mut().enumerate() {
            *cij = ai[0] * b[0][j] + ai[1] * b[1][j] + ai[2] * b[2][j];
        }
    }
    c
}

#[inline]
pub(crate) fn m_add<T: Scalar>(a: &M3<T>, b: &M3<T>) -> M3<T> {
    let mut c = *a;
    for (ci, bi) in c.iter_mut().zip(b) {
        for (x, y) in ci.iter_mut().zip(bi) {
            *x = *x + *y;
        }
    }
    c
}

#[inline]
pub(crate) fn m_scale<T: Scalar>(a: &M3<T>, s: T) -> M3<T> {
    let mut c = *a;
    c.iter_mut().flatten().for_each(|x| *x = *x * s);
    c
}

#[inline]
pub(crate) fn m_transpose<T: Scalar>(a: &M3<T>) -> M3<T> {
    let mut c = *a;
    for i in 0..3 {
        for j in 0..i {
            c[i][j] = a[j][i];
            c[j][i] = a[i][j];
        }
    }
    c
}

#[inline]
pub(crate) fn m_trace<T: Scalar>(a: &M3<T>) -> T {
    a[0][0] + a[1][1] + a[2][2]
}

/// tr(A B) without forming the product.
#[inline]
pub(crate) fn m_trace_mul<T: Scalar>(a: &M3<T>, b: &M3<T>) -> T {
    let mut s = T::cst(0.0);
    for i in 0..3 {
        for k in 0..3 {
            s = s + a[i][k] * b[k][i];
        }
    }
    s
}

pub(crate) fn m_det<T: Scalar>(a: &M3<T>) -> T {
    a[0][0] * (a[1][1] * a[2][2] - a[1][2] * a[2][1]) - a[0][1] * (a[1][0] * a[2][2] - a[1][2] * a[2][0])
        + a[0][2] * (a[1][0] * a[2][1] - a[1][1] * a[2][0])
}

/// dev A = A − (tr A / 3) I.
#[inline]
pub(crate) fn m_dev<T: Scalar>(a: &M3<T>) -> M3<T> {
    let m = m_trace(a).scale(1.0 / 3.0);
    let mut d = *a;
    for i in 0..3 {
        d[i][i] = d[i][i] - m;
    }
    d
}

/// exp A by scaling and squaring: A/2^s with ‖A/2^s‖∞ ≤ 1/4, a Taylor polynomial (Horner) to
/// 1e-17 relative, then s squarings. The number of terms and squarings depends on the value only,
/// so derivatives are those of one fixed polynomial map (exact to the same truncation).
pub(crate) fn m_exp<T: Scalar>(a: &M3<T>) -> M3<T> {
    let norm = a.iter().map(|r| r.iter().map(|x| x.re().abs()).sum::<f64>()).fold(0.0, f64::max);
    let mut s = 0;
    let mut n = norm;
    while n > 0.25 {
        n *= 0.5;
        s += 1;
    }
    let x = m_scale(a, T::cst(0.5f64.powi(s)));
    // Terms: smallest m with n^(m+1)/(m+1)! < 1e-17 (n ≤ 1/4 gives m ≤ 12).
    let mut m = 1;
    let mut term = n;
    while term > 1e-17 && m < 20 {
        m += 1;
        term *= n / m as f64;
    }
    // Horner: I + X/1 (I + X/2 (I + ... (I + X/m))).
    let id = m_cst::<T>(&[[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);
    let mut e = id;
    for k in (1..=m).rev() {
        e = m_mul(&x, &e);
        e.iter_mut().flatten().for_each(|v| *v = v.scale(1.0 / k as f64));
        for (i, row) in e.iter_mut().enumerate() {
            row[i] = row[i] + T::cst(1.0);
        }
    }
    for _ in 0..s {
        e = m_mul(&e, &e);
    }
    e
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dual_arithmetic_matches_calculus() {
        let x = Dual::<2>::var(0.7, 0);
        let y = Dual::<2>::var(1.3, 1);
        // f = exp(x y) / sqrt(y) + ln(x) − x
        let f = (x * y).exp() / y.sqrt() + x.ln() - x;
        let (xv, yv) = (0.7f64, 1.3f64);
        let fx = yv * (xv * yv).exp() / yv.sqrt() + 1.0 / xv - 1.0;
        let fy = xv * (xv * yv).exp() / yv.sqrt() - 0.5 * (xv * yv).exp() * yv.powf(-1.5);
        assert!((f.re - ((xv * yv).exp() / yv.sqrt() + xv.ln() - xv)).abs() < 1e-15);
        assert!((f.d[0] - fx).abs() < 1e-14 && (f.d[1] - fy).abs() < 1e-14, "{:?} vs {fx} {fy}", f.d);
    }

    /// exp of a diagonalisable matrix against V exp(Λ) V⁻¹, and det exp A = exp tr A.
    #[test]
    fn matrix_exponential() {
        let v = [[1.0, 0.3, -0.2], [0.1, 1.2, 0.4], [-0.3, 0.2, 0.9]];
        let vm = nalgebra::Matrix3::from_fn(|i, j| v[i][j]);
        let vi = vm.try_inverse().unwrap();
        // (Large non-normal arguments lose digits to the squarings and det to cancellation; the
        // remodelling update uses ‖A‖ ≲ 1.)
        for scale in [1e-3, 0.3, 2.0, 6.0] {
            let lam = [0.5 * scale, -0.2 * scale, -0.3 * scale];
            let a = vm * nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::from(lam)) * vi;
            let want = vm * nalgebra::Matrix3::from_diagonal(&nalgebra::Vector3::from(lam.map(f64::exp))) * vi;
            let got = m_exp::<f64>(&std::array::from_fn(|i| std::array::from_fn(|j| a[(i, j)])));
            let err = (0..9).map(|k| (got[k / 3][k % 3] - want[(k / 3, k % 3)]).abs()).fold(0.0, f64::max);
            let det_err = (m_det(&got) - 1.0).abs();
            println!("scale {scale}: max error {err:e} (|exp A| = {:e}), det - 1 = {det_err:e}", want.norm());
            assert!(err < 1e-13 * want.norm());
            assert!(det_err < 1e-13 * (1.0 + scale * scale));
        }
    }

    /// Derivatives of exp A through the duals against central differences.
    #[test]
    fn matrix_exponential_derivative() {
        let a = [[0.1, 0.7, -0.3], [0.2, -0.4, 0.5], [0.6, 0.1, 0.3]];
        let ad: M3<Dual<9>> = std::array::from_fn(|i| std::array::from_fn(|j| Dual::var(a[i][j], 3 * i + j)));
        let e = m_exp(&ad);
        let h = 1e-6;
        for k in 0..9 {
            let mut ap = a;
            let mut am = a;
            ap[k / 3][k % 3] += h;
            am[k / 3][k % 3] -= h;
            let (ep, em) = (m_exp::<f64>(&ap), m_exp::<f64>(&am));
            for i in 0..3 {
                for j in 0..3 {
                    let fd = (ep[i][j] - em[i][j]) / (2.0 * h);
                    assert!((e[i][j].d[k] - fd).abs() < 1e-8, "d exp_{i}{j} / d a_{k}: {} vs {fd}", e[i][j].d[k]);
                }
            }
        }
    }
}
