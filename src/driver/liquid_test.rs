//! The liquid test of tissue surface tensiometry (Forgacs et al. 1998, Biophys. J. 74:2227): an
//! aggregate is a liquid if its apparent surface tension σ_app does not depend on the
//! compression. Read on a run's holds at two or more compressions (`holds`), with the biases
//! that make it unreliable where they apply.
//!
//! The tolerance, from docs/studies.md's tensiometry study (`tst_two_compressions`-like runs,
//! 15% then 30%): the liquid's two readings are 3.7% apart (σ_app's own scatter, its contact
//! radius R3 read between surface nodes, is −3% to +1% a reading), a yielding aggregate's 27%
//! (its yield part depends on the compression). [`TOLERANCE`] = 10% is their geometric mean: a
//! margin of 2.7× from either.

use super::holds::HoldReading;
use crate::io::fmt_short as g;
use crate::scene::medium::weighing_density;
use crate::scene::{Scene, SolidSpec};

/// The largest relative spread (largest σ_app over smallest, less 1) of a liquid.
pub(crate) const TOLERANCE: f64 = 0.10;

/// A Bond number ρ g R² / γ from which the weight matters. The aggregate's weight acts without
/// the buoyancy of a lab's medium and flattens it, which lowers σ_app: on `tst_two_compressions`
/// weighed in air (without its `[medium]`) by 6.0% at 15% and 1.6% at 30% at Bo = 0.0196, by 1.5% and 1.2% (within the reading's own
/// scatter) at Bo = 0.0098 (docs/reference-run-directory.md, "The liquid test").
pub(crate) const BOND_SMALL: f64 = 0.01;

/// A liquid's σ_app is within 5% of γ once its hold has lasted both RELAXATION_TIMES relaxation
/// times 1/(λp µ) (the elastic deviator's) and CAPILLARY_TIMES capillary times R/(λp γ) (the
/// shape's viscous flow towards Young–Laplace): measured over 10 holds, µR/γ = 40–4000
/// (docs/studies.md, "When the reading equals γ"; scripts/tensiometry.py's `rule`).
pub(crate) const RELAXATION_TIMES: f64 = 16.0;
pub(crate) const CAPILLARY_TIMES: f64 = 0.2;

/// What the scene says that bears on the test: the surface tension, the weight, the relaxation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Tensiometry {
    /// γ (mN/m).
    pub(crate) gamma: f64,
    /// The plates' work of adhesion w (mN/m; 0: non-adhesive).
    pub(crate) adhesion: f64,
    /// |ρ| g R² / γ with the mixture's density ρ = Φs ρs + (1 − Φs) ρf, less the medium's if it
    /// has one (the excess weight); None without gravity.
    pub(crate) bond: Option<f64>,
    /// Whether the aggregate sits in a medium (`[medium]`: the weight is the excess over it).
    pub(crate) buoyed: bool,
    /// 1/(λp µ) (s): the deviatoric stress's relaxation time; infinite without remodelling (an
    /// elastic solid), None where µ is not given (a solid given by its α's).
    pub(crate) relaxation_s: Option<f64>,
    /// R/(λp γ) (s): the capillary time of the relaxed liquid; None without remodelling.
    pub(crate) capillary_s: Option<f64>,
}

impl Tensiometry {
    /// The scene's, None without surface tension or plates.
    pub(crate) fn of(scene: &Scene) -> Option<Tensiometry> {
        let surface = scene.surface.as_ref().filter(|s| s.tension > 0.0)?;
        let (gamma, adhesion) = (surface.tension, surface.adhesion);
        let radius = scene.plates.as_ref()?.radius();
        let (bond, relaxation_s, capillary_s) = match scene.material.mixture() {
            None => (None, Some(f64::INFINITY), None),
            Some(m) => {
                let (g, rho) = (m.gravity_magnitude(), weighing_density(m, scene.medium.as_ref()).abs());
                // kg/m³ · m/s² · (1e-6 m)² / (1e-3 N/m).
                let bond = (g > 0.0).then(|| rho * g * radius * radius * 1e-9 / gamma);
                let relaxation = match (&m.remodelling, m.solid()) {
                    (None, _) => Some(f64::INFINITY),
                    (Some(r), Ok(SolidSpec::MuNu { mu, .. })) => Some(1.0 / (r.lambda_p * mu)),
                    _ => None,
                };
                // µm / ((kPa s)⁻¹ · mN/m) = s, since kPa / (mN/m) = 1/µm.
                let capillary = m.remodelling.as_ref().map(|r| radius / (r.lambda_p * gamma));
                (bond, relaxation, capillary)
            }
        };
        Some(Tensiometry { gamma, adhesion, bond, relaxation_s, capillary_s, buoyed: scene.medium.is_some() })
    }
}

/// The test's outcome on a run's holds.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct LiquidTest {
    /// (ũ, σ_app) of the holds read, in time order.
    pub(crate) readings: Vec<(f64, f64)>,
    /// σ_app at the largest compression over σ_app at the smallest (the last hold at each).
    pub(crate) ratio: f64,
    /// The largest σ_app over the smallest, less 1.
    pub(crate) spread: f64,
    pub(crate) liquid: bool,
    /// The biases that apply, each a sentence.
    pub(crate) caveats: Vec<String>,
}

impl LiquidTest {
    /// The test on `holds` (None: fewer than two compressions with a positive σ_app read).
    pub(crate) fn of(holds: &[HoldReading], setting: &Tensiometry) -> Option<LiquidTest> {
        let read: Vec<(usize, f64, f64)> = holds
            .iter()
            .enumerate()
            .filter_map(|(k, h)| Some((k, h.hold.compression, h.at_end?.laplace[3])))
            .filter(|&(_, _, s)| s > 0.0 && s.is_finite())
            .collect();
        // The last hold at the smallest and at the largest compression.
        let last_at = |keep: fn(f64, f64) -> bool| {
            read.iter().fold(None, |best: Option<(f64, f64)>, &(_, u, s)| match best {
                Some((b, _)) if keep(b, u) => best,
                _ => Some((u, s)),
            })
        };
        let (low, high) = (last_at(|b, u| b < u)?, last_at(|b, u| b > u)?);
        if low.0 == high.0 {
            return None;
        }
        let (min, max) = read.iter().fold((f64::MAX, f64::MIN), |(a, b), r| (a.min(r.2), b.max(r.2)));
        let spread = max / min - 1.0;
        let mut caveats = Vec::new();
        if let (Some(bo), true) = (setting.bond.filter(|&b| b >= BOND_SMALL), setting.buoyed) {
            caveats.push(format!(
                "the aggregate's density differs from the medium's (Bond number |ρ_mix − ρ_m| g R²/γ = {}, not small \
                 against 1): its excess weight deforms it and biases σ_app",
                g(bo)
            ));
        } else if let Some(bo) = setting.bond.filter(|&b| b >= BOND_SMALL) {
            caveats.push(format!(
                "gravity is on without buoyancy (Bond number ρ g R²/γ = {}, not small against 1): the aggregate's \
                 weight flattens it and lowers σ_app, more at the smaller compression; a lab's medium buoys it \
                 (add [medium])",
                g(bo)
            ));
        }
        if setting.adhesion > 0.0 {
            caveats.push(format!(
                "the plates are adhesive (surface.adhesion = {} mN/m): the surface meets them at less than 180°, and \
                 σ_app, which counts the Laplace pressure on the contact alone, is not γ",
                g(setting.adhesion)
            ));
        }
        // The holds read, and how many relaxation and capillary times each lasts.
        let lasting: Vec<(usize, f64)> =
            read.iter().map(|&(k, _, _)| (k + 1, holds[k].hold.end - holds[k].hold.start)).collect();
        match setting.relaxation_s {
            Some(tau) if tau.is_infinite() => caveats
                .push("the solid does not relax (no material.remodelling): σ_app carries its elastic stress".into()),
            Some(tau) => {
                let needs =
                    |d: f64| d < RELAXATION_TIMES * tau || setting.capillary_s.is_some_and(|c| d < CAPILLARY_TIMES * c);
                let short: Vec<(usize, f64)> = lasting.iter().filter(|&&(_, d)| needs(d)).copied().collect();
                if !short.is_empty() {
                    let list = |f: &dyn Fn(&(usize, f64)) -> String| short.iter().map(f).collect::<Vec<_>>().join(", ");
                    let (which, last) = if short.len() == 1 { ("hold", "lasts") } else { ("holds", "last") };
                    let capillary = match setting.capillary_s {
                        Some(c) => format!(" and {} capillary times R/(λp γ) = {} s", list(&|(_, d)| g(d / c)), g(c)),
                        None => String::new(),
                    };
                    caveats.push(format!(
                        "{which} {} {last} {} relaxation times 1/(λp µ) = {} s{capillary}, fewer than the \
                         {RELAXATION_TIMES} and {CAPILLARY_TIMES} after which a liquid's σ_app is within 5% of γ: it may \
                         still carry the elastic stress or the shape's viscous flow",
                        list(&|(k, _)| k.to_string()),
                        list(&|(_, d)| g(d / tau)),
                        g(tau)
                    ));
                }
            }
            None => {}
        }
        Some(LiquidTest {
            readings: read.iter().map(|&(_, u, s)| (u, s)).collect(),
            ratio: high.1 / low.1,
            spread,
            liquid: spread <= TOLERANCE,
            caveats,
        })
    }

    /// "consistent with a liquid" or what the spread means.
    pub(crate) fn verdict(&self) -> &'static str {
        if self.liquid {
            "consistent with a liquid"
        } else {
            "not: the apparent tension depends on the compression (yield/elasticity)"
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::holds::{AtEnd, Hold, HoldReading};
    use super::*;
    use crate::scene::LoadedScene;

    /// Holds of 1000 s at (ũ, σ_app), in time order (σ_app NaN: not reached).
    fn holds(read: &[(f64, f64)]) -> Vec<HoldReading> {
        read.iter()
            .enumerate()
            .map(|(k, &(compression, sigma))| {
                let start = 1300.0 * k as f64 + 5.0;
                HoldReading {
                    hold: Hold { start, end: start + 1000.0, compression },
                    at_end: (!sigma.is_nan()).then_some(AtEnd { force_mg: 0.1, laplace: [90.0, 110.0, 30.0, sigma] }),
                }
            })
            .collect()
    }

    /// No weight; a relaxation time of 40 s, of which a 1000-s hold lasts 25 (over the 21 needed).
    const QUIET: Tensiometry = Tensiometry {
        gamma: 5.0,
        adhesion: 0.0,
        bond: None,
        relaxation_s: Some(40.0),
        capillary_s: Some(5000.0),
        buoyed: false,
    };

    /// docs/studies.md's two compressions at γ = 5 mN/m: the liquid's 0.972 and 1.008 γ (4.86 and
    /// 5.04 mN/m) pass, the yielding aggregate's 3.140 and 2.476 γ (15.70 and 12.38) do not.
    #[test]
    fn the_studys_liquid_passes_and_its_yielding_aggregate_does_not() {
        let t = LiquidTest::of(&holds(&[(0.15, 4.86), (0.3, 5.04)]), &QUIET).unwrap();
        assert!(t.liquid && t.caveats.is_empty(), "{t:?}");
        assert!((t.ratio - 5.04 / 4.86).abs() < 1e-15 && (t.spread - 0.037037).abs() < 1e-6, "{t:?}");
        assert_eq!(t.verdict(), "consistent with a liquid");
        let t = LiquidTest::of(&holds(&[(0.15, 15.70), (0.3, 12.38)]), &QUIET).unwrap();
        assert!(!t.liquid && (t.ratio - 12.38 / 15.70).abs() < 1e-15, "{t:?}");
        assert!((t.spread - (15.70 / 12.38 - 1.0)).abs() < 1e-15, "{t:?}");
        assert!(t.verdict().starts_with("not: the apparent tension depends on the compression"));
    }

    /// The verdict turns at a spread of 10%, whichever hold reads higher.
    #[test]
    fn the_verdict_turns_at_the_tolerance() {
        for (a, b) in [(1.0, 1.1), (1.1, 1.0)] {
            let (below, above) = (1.0 - 1e-9, 1.0 + 1e-9);
            let at = |f: f64| if a > b { (a * f, b) } else { (a, b * f) };
            let (x, y) = at(below);
            assert!(LiquidTest::of(&holds(&[(0.15, x), (0.3, y)]), &QUIET).unwrap().liquid, "{x} {y}");
            let (x, y) = at(above);
            assert!(!LiquidTest::of(&holds(&[(0.15, x), (0.3, y)]), &QUIET).unwrap().liquid, "{x} {y}");
        }
        // Three holds: the spread is over all of them; the ratio is the last hold at the largest
        // compression over the last at the smallest.
        let t = LiquidTest::of(&holds(&[(0.15, 1.0), (0.3, 1.05), (0.15, 0.9)]), &QUIET).unwrap();
        assert!((t.ratio - 1.05 / 0.9).abs() < 1e-15 && !t.liquid, "{t:?}");
    }

    /// One compression, a hold not reached, a σ_app not positive: no verdict.
    #[test]
    fn without_two_compressions_read_there_is_no_verdict() {
        assert!(LiquidTest::of(&holds(&[(0.15, 1.0)]), &QUIET).is_none());
        assert!(LiquidTest::of(&holds(&[(0.15, 1.0), (0.15, 1.0)]), &QUIET).is_none());
        assert!(LiquidTest::of(&holds(&[(0.15, 1.0), (0.3, f64::NAN)]), &QUIET).is_none());
        assert!(LiquidTest::of(&holds(&[(0.15, -1.0), (0.3, 1.0)]), &QUIET).is_none());
        let t = LiquidTest::of(&holds(&[(0.15, 1.0), (0.2, -1.0), (0.3, 1.02)]), &QUIET).unwrap();
        assert_eq!(t.readings, [(0.15, 1.0), (0.3, 1.02)]);
    }

    /// The weight is named from a Bond number of 0.01; a hold under 16 relaxation times or 0.2
    /// capillary times is named; a solid that does not relax is named once; adhesive plates are
    /// named.
    #[test]
    fn the_biases_are_named_where_they_apply() {
        let two = holds(&[(0.15, 1.0), (0.3, 1.02)]);
        let caveats = |s: Tensiometry| LiquidTest::of(&two, &s).unwrap().caveats;
        assert!(caveats(Tensiometry { bond: Some(0.0099), ..QUIET }).is_empty());
        let c = caveats(Tensiometry { bond: Some(0.0196), ..QUIET });
        assert!(
            c.len() == 1 && c[0].starts_with("gravity is on without buoyancy (Bond number ρ g R²/γ = 0.0196"),
            "{c:?}"
        );
        // 1000 s holds: 12.5 relaxation times of 80 s, under 16; 25 of 40 s, not.
        let c = caveats(Tensiometry { relaxation_s: Some(80.0), bond: Some(0.02), ..QUIET });
        assert_eq!(c.len(), 2, "{c:?}");
        assert!(
            c[1].starts_with(
                "holds 1, 2 last 12.5, 12.5 relaxation times 1/(λp µ) = 80 s and 0.2, 0.2 capillary times R/(λp γ) = \
                 5000 s, fewer than the 16 and 0.2"
            ),
            "{c:?}"
        );
        // 25 relaxation times, but 0.1 capillary times of 10000 s: short too.
        let c = caveats(Tensiometry { capillary_s: Some(10_000.0), ..QUIET });
        assert!(
            c.len() == 1 && c[0].contains("last 25, 25 relaxation times 1/(λp µ) = 40 s and 0.1, 0.1 capillary"),
            "{c:?}"
        );
        let mut three = two.clone();
        three.push(HoldReading { hold: Hold { start: 3000.0, end: 3300.0, compression: 0.2 }, ..two[0] });
        let c = LiquidTest::of(&three, &QUIET).unwrap().caveats;
        assert!(
            c.len() == 1 && c[0].starts_with("hold 3 lasts 7.5 relaxation times 1/(λp µ) = 40 s and 0.06 capillary"),
            "{c:?}"
        );
        let c = caveats(Tensiometry { relaxation_s: Some(f64::INFINITY), ..QUIET });
        assert!(c.len() == 1 && c[0].starts_with("the solid does not relax"), "{c:?}");
        assert!(caveats(Tensiometry { relaxation_s: None, ..QUIET }).is_empty());
        let c = caveats(Tensiometry { adhesion: 2.5, ..QUIET });
        assert!(c.len() == 1 && c[0].starts_with("the plates are adhesive (surface.adhesion = 2.5 mN/m)"), "{c:?}");
    }

    /// The two thresholds are the measured rule the docs state (docs/studies.md, whose sentence
    /// scripts/tests/test_tensiometry.py checks against the study's table).
    #[test]
    fn the_thresholds_are_the_studys_rule() {
        let studies = include_str!("../../docs/studies.md").split_whitespace().collect::<Vec<_>>().join(" ");
        let rule = format!("once t > {RELAXATION_TIMES}/(λp µ) and t > {CAPILLARY_TIMES} R/(λp γ)");
        assert!(studies.contains(&rule), "docs/studies.md does not state {rule}");
    }

    /// The shipped scene's numbers weighed in air (its `[medium]` taken out): γ = 5 mN/m,
    /// ρ = 0.6 × 1000 + 0.4 × 1000 kg/m³, g = 9.81 m/s², R = 100 µm: Bo = 1000 × 9.81 × 1e-8 / 5e-3
    /// = 0.01962; 1/(λp µ) = 1/(0.001 × 20) = 50 s. As shipped, in its medium of the pores' fluid's
    /// density, Bo = 0. Without gravity no Bond number; without surface tension nothing.
    #[test]
    fn a_scenes_setting() {
        let scene = |sets: &[&str]| {
            let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
            LoadedScene::load("tst_two_compressions", &sets).unwrap().scene
        };
        let shipped = Tensiometry::of(&scene(&[])).unwrap();
        assert_eq!((shipped.buoyed, shipped.bond), (true, Some(0.0)));
        let load = |sets: &[&str]| Tensiometry::of(&crate::scene::Scene { medium: None, ..scene(sets) });
        let t = load(&[]).unwrap();
        assert_eq!((t.gamma, t.adhesion, t.buoyed), (5.0, 0.0, false));
        assert!((t.bond.unwrap() - 0.01962).abs() < 1e-12 && (t.relaxation_s.unwrap() - 50.0).abs() < 1e-12, "{t:?}");
        // R/(λp γ) = 100 µm / (0.001 (kPa s)⁻¹ × 5 mN/m) = 20000 s.
        assert!((t.capillary_s.unwrap() - 20_000.0).abs() < 1e-9, "{t:?}");
        let t = load(&["material.gravity=[0, 0, 0]", "material.rho_s=1100"]).unwrap();
        assert_eq!(t.bond, None);
        let t = load(&["material.rho_s=1100", "mesh.params.R=150"]).unwrap();
        // ρ = 0.6 × 1100 + 0.4 × 1000 = 1060.
        assert!((t.bond.unwrap() - 1060.0 * 9.81 * 2.25e-8 / 5e-3).abs() < 1e-12, "{t:?}");
        // In the medium (ρ_m = ρf = 1000) the excess: 1060 − 1000 = 60; ρs = ρf: none.
        let in_medium = |sets: &[&str]| Tensiometry::of(&scene(sets));
        let t = in_medium(&["material.rho_s=1100", "mesh.params.R=150", "medium.density=1000"]).unwrap();
        assert!(t.buoyed && (t.bond.unwrap() - 60.0 * 9.81 * 2.25e-8 / 5e-3).abs() < 1e-12, "{t:?}");
        assert!(load(&["surface.tension=0"]).is_none());
    }
}
