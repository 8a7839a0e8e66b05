//! A pipette's suction (issue 53, design §6.1): the medium's pressure in the pipette's bore is
//! lowered by Δp(t), so p_m gains the term −Δp(t) χ(x), χ the bore's smoothed indicator in the
//! pipette's frame (the frame moves with the tool):
//!
//!   χ(ρ, ζ) = H(ρ_cut − ρ) · S(1 − ζ/ℓ),   ρ_cut = Rp + wall/2,  ℓ = the rim's radius,
//!
//! S the C² smoothstep of the surface tension's adhesion: χ = 1 in the bore and up to the mouth
//! (ζ ≤ 0), 0 beyond ℓ in front of it. Why the ramp lies in front of the mouth and not inside it
//! (the design's −ℓ ≤ ζ ≤ 0): a surface sealed on the mouth lies at ζ = 0 across the bore, and
//! the bore's pressure acts there; with the ramp inside, S and S' vanish at ζ = 0 and a surface
//! touching the mouth would never be sucked. The step in ρ at mid-wall is met only by surface
//! points on the rim's front face, in contact: their extra load goes into the rim's reaction. The
//! load is C¹ in x elsewhere (Newton stays differentiable). χ is evaluated on the current
//! configuration, in duals where the caller differentiates.

use crate::material::dual::Scalar;
use crate::physics::contact::PlateLoading;
use crate::physics::surface_tension::smoothstep;
use crate::physics::tools::{Profile, Tool};

/// One pipette's suction.
#[derive(Debug, Clone)]
pub(crate) struct Suction {
    /// The pipette (a `Profile::Pipette`).
    pub(crate) tool: Tool,
    /// Its index in the scene's tools (its position comes from the tool set).
    pub(crate) tool_index: usize,
    /// Δp(t), kPa: linear between the rows, held after the last.
    table: PlateLoading,
    /// ρ_cut and ℓ of the profile (µm).
    rho_cut: f64,
    ramp: f64,
    /// Δp and the tool's position along its axis at the time being solved.
    dp: f64,
    position: f64,
}

impl Suction {
    /// The suction of the table (t s, Δp kPa) (checked by the scene) in the pipette `tool`.
    pub(crate) fn new(tool: Tool, tool_index: usize, table: Vec<(f64, f64)>) -> Suction {
        let Profile::Pipette { inner, wall, rim } = tool.profile else {
            unreachable!("the scene checks that a suction names a pipette")
        };
        let dp = table.first().map_or(0.0, |r| r.1);
        Suction {
            tool,
            tool_index,
            table: PlateLoading::table(table),
            rho_cut: inner + 0.5 * wall,
            ramp: rim,
            dp,
            position: 0.0,
        }
    }

    /// The bore's inner radius Rp (µm).
    pub(crate) fn inner_radius(&self) -> f64 {
        match self.tool.profile {
            Profile::Pipette { inner, .. } => inner,
            _ => unreachable!("a suction's tool is a pipette"),
        }
    }

    /// Moves to time t, the pipette at `position` along its axis.
    pub(crate) fn move_to(&mut self, t: f64, position: f64) {
        self.dp = self.table.displacement(t);
        self.position = position;
    }

    /// The times of the table's rows after 0: steps land on them.
    pub(crate) fn kinks(&self) -> Vec<f64> {
        self.table.kinks()
    }

    /// (ρ, ζ) of `x` in the pipette's frame, `meridian`: x is (r, z, ·) and the pipette lies on
    /// the z axis. ρ only as a value (χ is flat in ρ wherever a surface can be).
    pub(crate) fn frame<T: Scalar>(&self, x: &[T; 3], meridian: bool) -> (f64, T) {
        let c = self.tool.centre(self.position);
        let a = self.tool.axis;
        if meridian {
            return (x[0].re().abs(), (x[1] - T::cst(c[2])).scale(a[2]));
        }
        let v: [T; 3] = std::array::from_fn(|i| x[i] - T::cst(c[i]));
        let zeta = v[0].scale(a[0]) + v[1].scale(a[1]) + v[2].scale(a[2]);
        let z = zeta.re();
        let rho2: f64 = (0..3).map(|i| (v[i].re() - z * a[i]).powi(2)).sum();
        (rho2.sqrt(), zeta)
    }

    /// The suction's share of p_m at `x` (the rule's coordinates): −Δp χ(x).
    pub(crate) fn pressure<T: Scalar>(&self, x: &[T; 3], meridian: bool) -> T {
        if self.dp == 0.0 {
            return T::cst(0.0);
        }
        let (rho, zeta) = self.frame(x, meridian);
        if rho >= self.rho_cut {
            return T::cst(0.0);
        }
        let (s, _) = smoothstep(T::cst(1.0) - zeta.scale(1.0 / self.ramp));
        s.scale(-self.dp)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::material::dual::Dual;

    fn pipette() -> Suction {
        let profile = Profile::Pipette { inner: 20.0, wall: 10.0, rim: 2.0 };
        let mut s = Suction::new(
            Tool::new("p", profile, [0.0, 0.0, 100.0], [0.0, 0.0, -1.0]),
            0,
            vec![(0.0, 0.0), (10.0, 2.0)],
        );
        s.move_to(5.0, 3.0);
        s
    }

    /// Half way up the table Δp = 1 kPa; the mouth at z = 97 (moved 3 µm down), ζ = 97 − z:
    /// beyond ℓ = 2 µm in front of it p = 0, on the mouth and in the bore −Δp, in the wall's half
    /// beyond ρ_cut = 25 µm 0, and on the ramp the smoothstep's middle at ζ = ℓ/2.
    #[test]
    fn the_bore_is_at_minus_dp_and_the_outside_untouched() {
        let s = pipette();
        assert_eq!(s.dp, 1.0);
        assert_eq!(s.pressure(&[0.0, 94.9, 0.0], true), 0.0);
        assert_eq!(s.pressure(&[10.0, 100.0, 0.0], true), -1.0);
        assert_eq!(s.pressure(&[10.0, 97.0, 0.0], true), -1.0);
        assert_eq!(s.pressure(&[26.0, 100.0, 0.0], true), 0.0);
        assert!((s.pressure(&[10.0, 96.0, 0.0], true) + 0.5).abs() < 1e-15);
        // The same points in space (x, y, z).
        assert!((s.pressure(&[6.0, 8.0, 96.0], false) + 0.5).abs() < 1e-15);
        assert_eq!(s.pressure(&[6.0, 8.0, 94.9], false), 0.0);
        assert_eq!(s.pressure(&[26.0, 0.0, 100.0], false), 0.0);
    }

    /// The dual derivative along z on the ramp against a central difference; p falls towards
    /// the mouth (dp/dz < 0: z increases into the bore).
    #[test]
    fn the_ramp_is_differentiated_exactly() {
        let s = pipette();
        for z in [95.3, 96.0, 96.9] {
            let x = [Dual::<2>::cst(10.0), Dual::var(z, 1), Dual::cst(0.0)];
            let p = s.pressure(&x, true);
            let h = 1e-6;
            let fd = (s.pressure(&[10.0, z + h, 0.0], true) - s.pressure(&[10.0, z - h, 0.0], true)) / (2.0 * h);
            assert!((p.d[1] - fd).abs() < 1e-8, "z = {z}: {} vs {fd}", p.d[1]);
            assert!(p.d[1] < 0.0);
        }
    }
}
