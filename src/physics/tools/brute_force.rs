//! The reference the signed distances are tested against, built without them: each profile's
//! boundary as a chain of segments and arcs (truncated at a depth), an inside test from the
//! solid's definition, and the distance to the boundary (or to the surface of revolution it
//! sweeps) by dense sampling, then zooming in on the best local minima.

use super::profile::Profile;
use std::f64::consts::PI;

/// A piece of a section's boundary (ρ ≥ 0), walked from one end to the other.
#[derive(Clone, Copy)]
enum Piece {
    Line([f64; 2], [f64; 2]),
    /// Centre, radius, start and end angles.
    Arc([f64; 2], f64, f64, f64),
}

impl Piece {
    fn length(&self) -> f64 {
        match *self {
            Piece::Line(p, q) => (q[0] - p[0]).hypot(q[1] - p[1]),
            Piece::Arc(_, r, t0, t1) => r * (t1 - t0).abs(),
        }
    }

    /// The point at the fraction `f` of the piece.
    fn at(&self, f: f64) -> [f64; 2] {
        match *self {
            Piece::Line(p, q) => [p[0] + f * (q[0] - p[0]), p[1] + f * (q[1] - p[1])],
            Piece::Arc(c, r, t0, t1) => {
                let t = t0 + f * (t1 - t0);
                [c[0] + r * t.cos(), c[1] + r * t.sin()]
            }
        }
    }
}

/// A profile's boundary in the half-plane ρ ≥ 0, by arc length; straight parts end at depth
/// `depth` (the plane at ρ = `depth`).
pub(crate) struct Boundary {
    pieces: Vec<Piece>,
    pub(crate) length: f64,
}

impl Boundary {
    pub(crate) fn of(profile: &Profile, depth: f64) -> Boundary {
        let pieces = match *profile {
            Profile::Plane => vec![Piece::Line([0.0, 0.0], [depth, 0.0])],
            Profile::Sphere { radius } => vec![Piece::Arc([0.0, 0.0], radius, -0.5 * PI, 0.5 * PI)],
            Profile::Punch { radius, edge } => vec![
                Piece::Line([0.0, 0.0], [radius - edge, 0.0]),
                Piece::Arc([radius - edge, -edge], edge, 0.5 * PI, 0.0),
                Piece::Line([radius, -edge], [radius, -depth]),
            ],
            Profile::Pipette { inner, wall, rim } => vec![
                Piece::Line([inner, -depth], [inner, -rim]),
                Piece::Arc([inner + rim, -rim], rim, PI, 0.5 * PI),
                Piece::Line([inner + rim, 0.0], [inner + wall - rim, 0.0]),
                Piece::Arc([inner + wall - rim, -rim], rim, 0.5 * PI, 0.0),
                Piece::Line([inner + wall, -rim], [inner + wall, -depth]),
            ],
        };
        let length = pieces.iter().map(Piece::length).sum();
        Boundary { pieces, length }
    }

    /// The point at arc length `s` (clamped to the boundary).
    pub(crate) fn at(&self, s: f64) -> [f64; 2] {
        let mut s = s.clamp(0.0, self.length);
        for p in &self.pieces {
            let l = p.length();
            if s <= l {
                return p.at(if l > 0.0 { s / l } else { 0.0 });
            }
            s -= l;
        }
        let last = self.pieces[self.pieces.len() - 1];
        last.at(1.0)
    }
}

/// Whether (ρ ≥ 0, ζ) lies strictly inside the solid, from its definition.
pub(crate) fn inside(profile: &Profile, rho: f64, zeta: f64) -> bool {
    // Outside the disc of radius r at c, in the corner it rounds (above and beside the centre).
    let cut = |c: [f64; 2], r: f64, outer: bool| {
        let beside = if outer { rho > c[0] } else { rho < c[0] };
        beside && zeta > c[1] && (rho - c[0]).hypot(zeta - c[1]) > r
    };
    match *profile {
        Profile::Plane => zeta < 0.0,
        Profile::Sphere { radius } => rho.hypot(zeta) < radius,
        Profile::Punch { radius, edge } => rho < radius && zeta < 0.0 && !cut([radius - edge, -edge], edge, true),
        Profile::Pipette { inner, wall, rim } => {
            rho > inner
                && rho < inner + wall
                && zeta < 0.0
                && !cut([inner + rim, -rim], rim, false)
                && !cut([inner + wall - rim, -rim], rim, true)
        }
    }
}

/// The least of `f` over a grid of `n` values of each parameter in `lo..hi`, refined around the
/// `keep` best local minima of the grid's rows (the first parameter) by zooming: returns the
/// least value and its parameters.
pub(crate) fn minimise<const D: usize>(
    f: impl Fn([f64; D]) -> f64,
    lo: [f64; D],
    hi: [f64; D],
    n: [usize; D],
    keep: usize,
) -> (f64, [f64; D]) {
    let step: [f64; D] = std::array::from_fn(|k| (hi[k] - lo[k]) / (n[k] - 1) as f64);
    // Best over the other parameters, for each value of the first.
    let rows: Vec<(f64, [f64; D])> = (0..n[0])
        .map(|i| {
            let mut best = (f64::INFINITY, lo);
            let others: usize = n[1..].iter().product();
            for m in 0..others {
                let mut p = lo;
                p[0] = lo[0] + i as f64 * step[0];
                let mut rest = m;
                for k in 1..D {
                    p[k] = lo[k] + (rest % n[k]) as f64 * step[k];
                    rest /= n[k];
                }
                let v = f(p);
                if v < best.0 {
                    best = (v, p);
                }
            }
            best
        })
        .collect();
    let mut minima: Vec<(f64, [f64; D])> = (0..rows.len())
        .filter(|&i| (i == 0 || rows[i].0 <= rows[i - 1].0) && (i + 1 == rows.len() || rows[i].0 <= rows[i + 1].0))
        .map(|i| rows[i])
        .collect();
    minima.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut best = (f64::INFINITY, lo);
    for &(_, mut p) in minima.iter().take(keep) {
        let mut half = step.map(|s| 2.0 * s);
        let mut v = f(p);
        for _ in 0..16 {
            let centre = p;
            for m in 0..21usize.pow(D as u32) {
                let mut q = centre;
                let mut rest = m;
                for k in 0..D {
                    q[k] = (centre[k] + half[k] * ((rest % 21) as f64 / 10.0 - 1.0)).clamp(lo[k], hi[k]);
                    rest /= 21;
                }
                let w = f(q);
                if w < v {
                    v = w;
                    p = q;
                }
            }
            half = half.map(|h| h / 5.0);
        }
        if v < best.0 {
            best = (v, p);
        }
    }
    best
}
