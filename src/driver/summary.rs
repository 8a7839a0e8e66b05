//! The run summary: what a reader of a run wants first, written by rank 0 at the end of a
//! completed run as `DIR/summary.toml` and printed in a few lines of the run log. It is made
//! from the whole run's `history.csv` (all sessions of a resumed run) and the largest nodal
//! pressure of every step (`observe::pressure_peak`, carried by the checkpoints):
//!
//! - the run: scene, steps, end time, wall time, the accuracy class it announced;
//! - with plates: the protocol's phases (the ends of `plates.ramp`, `hold`, `release`), the peak
//!   force and its time, the force at the end of the hold, the time the upper
//!   plate leaves the aggregate on release (the first step of the release without upper
//!   contact), the final H/W; forces in mg, as in `history.csv` (mg-force under g = 9.81 m/s²,
//!   full-sphere equivalents), and in µN;
//! - with plates, the lab's Laplace analysis (`observe::laplace`): R1, R2, R3 and the apparent
//!   surface tension σ_app at the end of the hold and at the end of the run (without surface
//!   tension it reads the solid's stress, and the log says so);
//! - with plates, every hold of the protocol (`holds`): its times, ũ, the force at its end and,
//!   with surface tension, the Laplace reading there; with two compressions or more, the liquid
//!   test on them (`liquid_test`);
//! - the largest pore pressure, its time and the node's reference position;
//! - in the log, the command that plots the run.
//!
//! TOML, like the run's other records (`scene.toml`, `run.toml`): comments carry the units and
//! meanings, Python reads it with `tomllib`.

use super::holds::{self, Hold, HoldReading};
use super::liquid_test::{LiquidTest, Tensiometry, TOLERANCE};
use super::voice::Voice;
use crate::error::{Error, Result};
use crate::io::observable::{self, Columns};
use crate::io::{fmt_real, fmt_short as g, rundir};
use crate::observe::experiment::{micro_newton, G};
use crate::observe::laplace;
use crate::observe::pressure_peak::PressurePeak;
use crate::scene::{Protocol, Scene};
use std::fmt::Write;
use std::path::Path;

/// The file's name in the run directory.
pub(crate) const FILE: &str = "summary.toml";

/// What the plates experiment's history says (forces in mg).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PlateSummary {
    /// The plates' phases (the scene's; their ends: `Protocol::ends`).
    pub(crate) protocol: Protocol,
    pub(crate) peak_force: f64,
    pub(crate) peak_time: f64,
    /// NaN if the run ended before the hold did.
    pub(crate) hold_end_force: f64,
    /// None if the upper plate still touches at the end of the run.
    pub(crate) opening_time: Option<f64>,
    pub(crate) final_height_over_width: f64,
    /// R1, R2, R3 (µm) and σ_app (mN/m) at the end of the hold and of the run (NaN where they
    /// do not apply).
    pub(crate) laplace_hold_end: [f64; 4],
    pub(crate) laplace_final: [f64; 4],
    /// Every hold of the protocol, read at its end.
    pub(crate) holds: Vec<HoldReading>,
    /// The scene's surface tension and what bears on the liquid test; None without tension.
    pub(crate) tensiometry: Option<Tensiometry>,
    /// The liquid test, where holds at two compressions or more read a σ_app.
    pub(crate) liquid_test: Option<LiquidTest>,
}

impl PlateSummary {
    /// From a history with the experiment's columns (None without them, or without rows), the
    /// protocol's phases and holds, and the scene's surface tension (None: none).
    pub(crate) fn of(
        h: &Columns,
        protocol: Protocol,
        holds: &[Hold],
        tensiometry: Option<Tensiometry>,
    ) -> Option<PlateSummary> {
        let [_, hold_end, _] = protocol.ends();
        let (t, f) = (h.get("time")?, h.get("force_total_mg")?);
        let upper = h.get("contact_nodes_upper")?;
        // The first largest force.
        let peak = (0..f.len().min(t.len())).fold(None, |best: Option<usize>, i| match best {
            Some(b) if f[b] >= f[i] => Some(b),
            _ => Some(i),
        })?;
        let opening = (0..t.len().min(upper.len())).find(|&i| t[i] > hold_end && upper[i] == 0.0);
        let holds = holds::read(h, holds);
        let liquid_test = tensiometry.as_ref().and_then(|s| LiquidTest::of(&holds, s));
        Some(PlateSummary {
            protocol,
            peak_force: f[peak],
            peak_time: t[peak],
            hold_end_force: observable::at_time(h, "force_total_mg", hold_end),
            opening_time: opening.map(|i| t[i]),
            final_height_over_width: observable::observe(h, "last:height/width"),
            laplace_hold_end: laplace::COLUMNS.map(|c| observable::at_time(h, c.name(), hold_end)),
            laplace_final: laplace::COLUMNS.map(|c| observable::observe(h, &format!("last:{}", c.name()))),
            holds,
            tensiometry,
            liquid_test,
        })
    }

    /// `[[hold]]` entries and `[liquid_test]`.
    fn holds_toml(&self, s: &mut String) {
        for (k, r) in self.holds.iter().enumerate() {
            let _ = writeln!(s, "\n[[hold]]  # hold {}: a phase of constant compression, read at its end", k + 1);
            entry(s, "start_s", r.hold.start, "s");
            entry(s, "end_s", r.hold.end, "s");
            entry(s, "compression", r.hold.compression, "ũ = u / (2R)");
            let _ = writeln!(s, "reached = {}  # the run reached its end", r.at_end.is_some());
            let Some(end) = r.at_end else { continue };
            entry(s, "force_mg", end.force_mg, "mg, the force at its end");
            entry(s, "force_uN", micro_newton(end.force_mg), "µN");
            if self.tensiometry.is_some() {
                let v = end.laplace;
                entry(s, "R1_um", v[0], "µm, the profile's radius of curvature at the equator");
                entry(s, "R2_um", v[1], "µm, the equatorial radius");
                entry(s, "R3_um", v[2], "µm, the radius of the upper contact");
                entry(s, "sigma_app_mN_m", v[3], "mN/m, the apparent surface tension");
            }
        }
        let Some(t) = &self.liquid_test else { return };
        s.push_str("\n[liquid_test]  # Forgacs et al. 1998: a liquid's sigma_app does not depend on the compression\n");
        entry(s, "ratio", t.ratio, "sigma_app at the largest compression over sigma_app at the smallest");
        entry(s, "spread", t.spread, "the holds' largest sigma_app over their smallest, less 1");
        entry(s, "tolerance", TOLERANCE, "the largest spread of a liquid");
        let _ = writeln!(s, "liquid = {}", t.liquid);
        let _ = writeln!(s, "verdict = {}", toml::Value::String(t.verdict().into()));
        if let Some(setting) = &self.tensiometry {
            entry(s, "gamma_mN_m", setting.gamma, "mN/m, the scene's surface tension");
            entry(s, "bond_number", setting.bond.unwrap_or(f64::NAN), "rho g R^2 / gamma, with gravity");
            let tau = setting.relaxation_s.unwrap_or(f64::NAN);
            entry(s, "relaxation_time_s", tau, "s, 1/(lambda_p mu), with remodelling");
        }
        let caveats: Vec<String> = t.caveats.iter().map(|c| toml::Value::String(c.clone()).to_string()).collect();
        let _ = writeln!(s, "caveats = [{}]  # the biases that apply", caveats.join(", "));
    }

    /// The log's lines on the holds and the liquid test.
    fn holds_lines(&self, lines: &mut Vec<String>) {
        for (k, r) in self.holds.iter().enumerate() {
            let what = format!(
                "summary: hold {} (t = {}–{} s, ũ = {})",
                k + 1,
                g(r.hold.start),
                g(r.hold.end),
                g(r.hold.compression)
            );
            let Some(end) = r.at_end else {
                lines.push(format!("{what}: not reached (the run ended before)"));
                continue;
            };
            let mut l = format!("{what}: {} mg = {} µN at its end", g(end.force_mg), g(micro_newton(end.force_mg)));
            if self.tensiometry.is_some() {
                let _ = write!(l, "; {}", reading(end.laplace));
            }
            lines.push(l);
        }
        let several = self.holds.iter().any(|r| r.hold.compression != self.holds[0].hold.compression);
        match (&self.liquid_test, &self.tensiometry) {
            (Some(t), _) => {
                let read: Vec<String> =
                    t.readings.iter().map(|&(u, s)| format!("{} mN/m at ũ = {}", g(s), g(u))).collect();
                lines.push(format!(
                    "summary: liquid test (Forgacs et al. 1998): σ_app {}; ratio {} (spread {:.1}%, a liquid's at most {}%): {}",
                    read.join(", "),
                    g(t.ratio),
                    100.0 * t.spread,
                    g(100.0 * TOLERANCE),
                    t.verdict()
                ));
                for c in &t.caveats {
                    lines.push(format!("summary: liquid test, unreliable here: {c}"));
                }
            }
            (None, Some(_)) if several => {
                lines.push("summary: liquid test: no verdict (σ_app was not read positive at two compressions)".into())
            }
            _ => {}
        }
    }
}

/// "σ_app … mN/m (R1 …, R2 …, R3 … µm)".
fn reading(v: [f64; 4]) -> String {
    format!("σ_app {} mN/m (R1 {}, R2 {}, R3 {} µm)", g(v[3]), g(v[0]), g(v[1]), g(v[2]))
}

/// A completed run in numbers.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Summary {
    pub(crate) scene: String,
    pub(crate) steps: usize,
    pub(crate) t: f64,
    pub(crate) wall_s: f64,
    pub(crate) accuracy: Option<String>,
    pub(crate) plates: Option<PlateSummary>,
    pub(crate) pressure: PressurePeak,
    /// The command that plots the run, as it can be pasted into a shell.
    pub(crate) plot_command: Option<String>,
}

/// Without surface tension the Laplace reading is the solid's stress over the same geometry.
const NO_TENSION: &str = "no surface tension in this scene: σ_app reads the solid's stress, not a tension";

/// `key = value` with a comment, the value as the shortest decimal that reads back the same;
/// nothing for a value that is not finite (an entry that does not apply).
fn entry(out: &mut String, key: &str, v: f64, comment: &str) {
    if v.is_finite() {
        let _ = writeln!(out, "{key} = {}  # {comment}", toml_real(v));
    }
}

/// A real as TOML reads it: `fmt_real`, with `.0` after an integer (a TOML float, not an integer).
fn toml_real(v: f64) -> String {
    let s = fmt_real(v);
    if s.contains(['.', 'e', 'n', 'i']) {
        s
    } else {
        format!("{s}.0")
    }
}

impl Summary {
    /// `summary.toml`.
    pub(crate) fn toml(&self) -> String {
        let mut s = String::from(
            "# poroplast run summary: the whole run (all sessions of a resumed one), from history.csv and the\n\
             # largest nodal pore pressure of every step. Units: s, kPa, µm; forces on the upper plate, full-sphere\n\
             # equivalents, positive in compression, in mg (as in history.csv: mg-force under g) and in µN.\n",
        );
        let _ = writeln!(s, "scene = {}", toml::Value::String(self.scene.clone()));
        let _ = writeln!(s, "steps = {}", self.steps);
        entry(&mut s, "t_end_s", self.t, "s, the end of the run");
        entry(&mut s, "wall_s", self.wall_s, "s, wall time of the whole run (set-up and every session)");
        if let Some(a) = &self.accuracy {
            let _ = writeln!(s, "accuracy = {}", toml::Value::String(a.clone()));
        }
        if let Some(p) = &self.plates {
            s.push_str("\n[plates]\n");
            entry(&mut s, "g_m_s2", G, "m/s², the g of the mg: 1 mg = g µN");
            let [ramp_end, hold_end, release_end] = p.protocol.ends();
            entry(&mut s, "ramp_end_s", ramp_end, "s, end of the compression ramp (plates.ramp)");
            entry(&mut s, "hold_end_s", hold_end, "s, end of the hold (plates.ramp + plates.hold)");
            entry(&mut s, "release_end_s", release_end, "s, end of the release (+ plates.release)");
            entry(&mut s, "peak_force_mg", p.peak_force, "mg, the largest force");
            entry(&mut s, "peak_force_uN", micro_newton(p.peak_force), "µN");
            entry(&mut s, "peak_force_time_s", p.peak_time, "s, the step of the largest force");
            entry(&mut s, "hold_end_force_mg", p.hold_end_force, "mg, the force at the end of the hold");
            entry(&mut s, "hold_end_force_uN", micro_newton(p.hold_end_force), "µN");
            if let Some(t) = p.opening_time {
                entry(&mut s, "contact_opening_time_s", t, "s, the first step of the release without upper contact");
            }
            entry(&mut s, "final_height_over_width", p.final_height_over_width, "H/W at the end of the run");
            s.push_str("\n[laplace]  # the lab's analysis of the profile: sigma_app = F / (pi R3^2 (1/R1 + 1/R2))\n");
            if p.tensiometry.is_none() {
                let _ = writeln!(s, "# {NO_TENSION}");
            }
            for (when, v) in [("hold_end", p.laplace_hold_end), ("final", p.laplace_final)] {
                entry(&mut s, &format!("{when}_R1_um"), v[0], "µm, the profile's radius of curvature at the equator");
                entry(&mut s, &format!("{when}_R2_um"), v[1], "µm, the equatorial radius");
                entry(&mut s, &format!("{when}_R3_um"), v[2], "µm, the radius of the upper contact");
                entry(&mut s, &format!("{when}_sigma_app_mN_m"), v[3], "mN/m, the apparent surface tension");
            }
            p.holds_toml(&mut s);
        }
        if self.pressure.p.is_finite() {
            s.push_str("\n[pressure]\n");
            entry(&mut s, "max_p_kPa", self.pressure.p, "kPa, the largest nodal pore pressure of any step");
            entry(&mut s, "max_p_time_s", self.pressure.t, "s, its step");
            let at: Vec<String> = self.pressure.at.iter().map(|&x| toml_real(x)).collect();
            let _ = writeln!(
                s,
                "max_p_at_um = [{}]  # µm, its node's reference position (meridian: r, 0, z)",
                at.join(", ")
            );
        }
        s
    }

    /// The lines of the run log.
    pub(crate) fn lines(&self) -> Vec<String> {
        let mut lines = Vec::new();
        if let Some(p) = &self.plates {
            let mut l = format!(
                "summary: peak force {} mg = {} µN at t = {} s",
                g(p.peak_force),
                g(micro_newton(p.peak_force)),
                g(p.peak_time)
            );
            if p.hold_end_force.is_finite() {
                let f = p.hold_end_force;
                let _ = write!(
                    l,
                    "; {} mg = {} µN at the end of the hold (t = {} s)",
                    g(f),
                    g(micro_newton(f)),
                    g(p.protocol.ends()[1])
                );
            }
            lines.push(l);
            let opening = p
                .opening_time
                .map_or("does not leave the aggregate".into(), |t| format!("leaves the aggregate at t = {} s", g(t)));
            lines.push(format!("summary: the upper plate {opening}; final H/W {}", g(p.final_height_over_width)));
            let caveat = if p.tensiometry.is_none() { format!(" ({NO_TENSION})") } else { String::new() };
            match (p.laplace_hold_end[3].is_finite(), p.laplace_final[3].is_finite()) {
                (true, _) => lines.push(format!(
                    "summary: Laplace analysis: {} at the end of the hold{caveat}",
                    reading(p.laplace_hold_end)
                )),
                (false, true) => lines.push(format!(
                    "summary: Laplace analysis: {} at the end of the run{caveat}",
                    reading(p.laplace_final)
                )),
                _ => {}
            }
            p.holds_lines(&mut lines);
        }
        if self.pressure.p.is_finite() {
            let [x, y, z] = self.pressure.at;
            lines.push(format!(
                "summary: largest p {} kPa at t = {} s, at the node of reference position ({}, {}, {}) µm",
                g(self.pressure.p),
                g(self.pressure.t),
                g(x),
                g(y),
                g(z)
            ));
        }
        if let Some(c) = &self.plot_command {
            lines.push(format!("summary: plot it: {c}"));
        }
        lines
    }

    /// One line for `status.txt`.
    pub(crate) fn headline(&self) -> String {
        let what = match &self.plates {
            Some(p) => format!(
                "peak force {} mg = {} µN at t = {} s",
                g(p.peak_force),
                g(micro_newton(p.peak_force)),
                g(p.peak_time)
            ),
            None => format!("largest p {} kPa at t = {} s", g(self.pressure.p), g(self.pressure.t)),
        };
        format!("{what}; the summary is in {FILE}")
    }
}

/// The summary of the completed run of `scene` in `dir` (rank 0 reads its history), its
/// `accuracy` line and largest pressure `pressure`: written to `summary.toml` and printed; None
/// on the other ranks.
pub(super) fn summarise(
    voice: &Voice,
    scene: &Scene,
    accuracy: Option<String>,
    pressure: PressurePeak,
    dir: &Path,
    (wall_s, steps, t): (f64, usize, f64),
) -> Result<Option<Summary>> {
    crate::parallel::on_root(voice.world(), || {
        let h = observable::read_history(dir)
            .ok_or_else(|| Error::io(dir.join("history.csv"), "cannot be read for the summary"))?;
        let summary = Summary {
            scene: scene.name.clone(),
            steps,
            t,
            wall_s,
            accuracy,
            plates: scene.plates.as_ref().and_then(|p| {
                let holds = holds::holds(&p.path(), scene.time.t_end);
                PlateSummary::of(&h, p.protocol(), &holds, Tensiometry::of(scene))
            }),
            pressure,
            plot_command: Some(crate::launch::command(1, &["plot", &dir.to_string_lossy()])),
        };
        rundir::write_text(dir, FILE, &summary.toml())?;
        for l in summary.lines() {
            voice.say(&l);
        }
        Ok(summary)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn history(cols: &[(&str, &[f64])]) -> Columns {
        cols.iter().map(|(k, v)| (k.to_string(), v.to_vec())).collect()
    }

    /// A protocol with exact answers: ramp to 2 s, hold to 6 s, release to 8 s.
    fn protocol() -> (Columns, Protocol) {
        let h = history(&[
            ("time", &[0.0, 1.0, 2.0, 4.0, 5.0, 7.0, 7.5, 9.0]),
            ("force_total_mg", &[0.0, 2.0, 4.0, 3.0, 2.5, 1.0, 0.0, 0.0]),
            ("contact_nodes_upper", &[1.0, 3.0, 5.0, 5.0, 5.0, 2.0, 0.0, 0.0]),
            ("height", &[200.0, 180.0, 140.0, 140.0, 140.0, 150.0, 160.0, 190.0]),
            ("width", &[200.0, 210.0, 230.0, 230.0, 230.0, 220.0, 210.0, 200.0]),
            ("R1", &[f64::NAN, 90.0, 70.0, 70.0, 70.0, 80.0, f64::NAN, f64::NAN]),
            ("R2", &[100.0, 105.0, 115.0, 115.0, 115.0, 110.0, 105.0, 100.0]),
            ("R3", &[f64::NAN, 20.0, 40.0, 40.0, 42.0, 30.0, f64::NAN, f64::NAN]),
            ("sigma_app", &[f64::NAN, 5.0, 6.0, 4.0, 3.0, 2.0, f64::NAN, f64::NAN]),
        ]);
        (h, Protocol { ramp: 2.0, hold: 4.0, release: 2.0 })
    }

    #[test]
    fn the_plates_numbers_of_a_history() {
        let (h, phases) = protocol();
        let p = PlateSummary::of(&h, phases, &[], None).unwrap();
        assert_eq!((p.peak_force, p.peak_time), (4.0, 2.0));
        // Between t = 5 (2.5 mg) and t = 7 (1 mg): 1.75 mg at t = 6.
        assert_eq!(p.hold_end_force, 1.75);
        assert_eq!(p.opening_time, Some(7.5));
        assert_eq!(p.final_height_over_width, 190.0 / 200.0);
        // The Laplace reading at t = 6, halfway between t = 5 and 7; none at the end (no contact).
        assert_eq!(p.laplace_hold_end, [75.0, 112.5, 36.0, 2.5]);
        assert!(p.laplace_final[3].is_nan() && p.laplace_final[1] == 100.0);
        // A run that ends in the hold: no end-of-hold force, no opening.
        let short: Columns = h.iter().map(|(k, v)| (k.clone(), v[..4].to_vec())).collect();
        let p = PlateSummary::of(&short, phases, &[], None).unwrap();
        assert!(p.hold_end_force.is_nan() && p.opening_time.is_none());
        assert!(PlateSummary::of(&history(&[("time", &[0.0])]), phases, &[], None).is_none());
    }

    #[test]
    fn the_file_reads_back_with_its_units() {
        let (h, phases) = protocol();
        let pressure = PressurePeak { p: 3.5, t: 2.0, at: [0.0, 0.0, 190.0] };
        let s = Summary {
            scene: "reference \"x\"".into(),
            steps: 7,
            t: 9.0,
            wall_s: 1.25,
            accuracy: Some("expected accuracy: within 1%".into()),
            plates: PlateSummary::of(&h, phases, &[Hold { start: 2.0, end: 6.0, compression: 0.3 }], None),
            pressure,
            plot_command: Some(crate::launch::command(1, &["plot", "my runs/x"])),
        };
        let t: toml::Table = toml::from_str(&s.toml()).unwrap();
        assert_eq!(t["scene"].as_str(), Some("reference \"x\""));
        assert_eq!(t["steps"].as_integer(), Some(7));
        let plates = t["plates"].as_table().unwrap();
        let f = |k: &str| plates[k].as_float().unwrap();
        assert_eq!(f("peak_force_mg"), 4.0);
        // 1 mg-force = 1e-6 kg × 9.81 m/s² = 9.81 µN.
        assert_eq!(f("peak_force_uN"), 39.24);
        assert_eq!(f("hold_end_force_uN"), 1.75 * 9.81);
        assert_eq!((f("hold_end_s"), f("contact_opening_time_s")), (6.0, 7.5));
        let l = t["laplace"].as_table().unwrap();
        assert_eq!(l["hold_end_sigma_app_mN_m"].as_float(), Some(2.5));
        assert_eq!(l["hold_end_R3_um"].as_float(), Some(36.0));
        assert!(!l.contains_key("final_sigma_app_mN_m") && l["final_R2_um"].as_float() == Some(100.0));
        // Without surface tension the reading is the solid's stress, and the log says so; the
        // hold has no Laplace entries.
        let lines = s.lines();
        assert!(lines.contains(
            &"summary: Laplace analysis: σ_app 2.5 mN/m (R1 75, R2 112.5, R3 36 µm) at the end of the hold (no surface \
              tension in this scene: σ_app reads the solid's stress, not a tension)"
                .to_string()
        ));
        assert!(lines.contains(&"summary: hold 1 (t = 2–6 s, ũ = 0.3): 1.75 mg = 17.168 µN at its end".to_string()));
        let exe = std::env::current_exe().unwrap().display().to_string();
        assert_eq!(lines.last().unwrap(), &format!("summary: plot it: {exe} plot 'my runs/x'"));
        let hold = t["hold"].as_array().unwrap()[0].as_table().unwrap();
        assert_eq!(hold["force_uN"].as_float(), Some(1.75 * 9.81));
        assert!(hold["reached"].as_bool().unwrap() && !hold.contains_key("sigma_app_mN_m"));
        let p = t["pressure"].as_table().unwrap();
        assert_eq!(p["max_p_kPa"].as_float(), Some(3.5));
        assert_eq!(p["max_p_at_um"].as_array().unwrap()[2].as_float(), Some(190.0));
        assert!(s.headline().starts_with("peak force 4 mg = 39.24 µN at t = 2 s"), "{}", s.headline());
        assert_eq!(
            (g(17.447330666), g(171.158313), g(0.0), g(39.172863)),
            ("17.447".into(), "171.16".into(), "0".into(), "39.173".into())
        );
        // A scene without plates: no [plates].
        let s = Summary { plates: None, accuracy: None, ..s };
        let t: toml::Table = toml::from_str(&s.toml()).unwrap();
        assert!(!t.contains_key("plates") && t.contains_key("pressure") && !t.contains_key("hold"));
    }

    /// Two holds of a table (15% from 1 to 3 s, 20% from 6 s to the run's end at 8 s) with surface
    /// tension: each hold's entry and line read the history at its end (σ_app 2 and 2.1 mN/m,
    /// ratio 1.05: a liquid), the weight named; a third hold past the run's end not reached.
    #[test]
    fn every_hold_is_summarised_with_the_liquid_test() {
        let h = history(&[
            ("time", &[0.0, 1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0, 8.0]),
            ("force_total_mg", &[0.0, 3.0, 2.0, 1.0, 0.0, 0.0, 4.0, 3.0, 2.5]),
            ("contact_nodes_upper", &[1.0, 3.0, 3.0, 3.0, 0.0, 0.0, 5.0, 5.0, 5.0]),
            ("height", &[200.0; 9]),
            ("width", &[200.0; 9]),
            ("R1", &[f64::NAN, 90.0, 90.0, 91.0, f64::NAN, f64::NAN, 80.0, 80.0, 81.0]),
            ("R2", &[100.0, 105.0, 105.0, 106.0, 100.0, 100.0, 110.0, 110.0, 111.0]),
            ("R3", &[f64::NAN, 20.0, 20.0, 21.0, f64::NAN, f64::NAN, 30.0, 30.0, 31.0]),
            ("sigma_app", &[f64::NAN, 5.0, 3.0, 2.0, f64::NAN, f64::NAN, 4.0, 3.0, 2.1]),
        ]);
        let rows = [[0.0, 0.0], [1.0, 0.15], [3.0, 0.15], [4.0, 0.0], [5.0, 0.0], [6.0, 0.2], [8.0, 0.2], [11.0, 0.0]];
        let holds = holds::holds(&rows, 8.0);
        let setting = Tensiometry {
            gamma: 2.0,
            adhesion: 0.0,
            bond: Some(0.0196),
            relaxation_s: Some(0.01),
            capillary_s: None,
            buoyed: false,
        };
        let protocol = Protocol { ramp: 6.0, hold: 4.0, release: 1.0 };
        let mut holds = holds;
        holds.push(Hold { start: 12.0, end: 13.0, compression: 0.3 });
        let s = Summary {
            scene: "two".into(),
            steps: 8,
            t: 8.0,
            wall_s: 1.0,
            accuracy: None,
            plates: PlateSummary::of(&h, protocol, &holds, Some(setting)),
            pressure: PressurePeak { p: f64::NAN, t: f64::NAN, at: [0.0; 3] },
            plot_command: None,
        };
        let t: toml::Table = toml::from_str(&s.toml()).unwrap_or_else(|e| panic!("{e}\n{}", s.toml()));
        let hold = |k: usize| t["hold"].as_array().unwrap()[k].as_table().unwrap().clone();
        let num = |k: usize, key: &str| hold(k)[key].as_float().unwrap();
        assert_eq!((num(0, "start_s"), num(0, "end_s"), num(0, "compression")), (1.0, 3.0, 0.15));
        assert_eq!((num(0, "force_mg"), num(0, "force_uN")), (1.0, 9.81));
        assert_eq!(
            [num(0, "R1_um"), num(0, "R2_um"), num(0, "R3_um"), num(0, "sigma_app_mN_m")],
            [91.0, 106.0, 21.0, 2.0]
        );
        assert_eq!((num(1, "start_s"), num(1, "end_s"), num(1, "sigma_app_mN_m")), (6.0, 8.0, 2.1));
        assert_eq!(num(1, "force_mg"), 2.5);
        assert!(!hold(2)["reached"].as_bool().unwrap() && !hold(2).contains_key("force_mg"));
        let l = t["liquid_test"].as_table().unwrap();
        assert!((l["ratio"].as_float().unwrap() - 1.05).abs() < 1e-15 && l["liquid"].as_bool().unwrap());
        assert_eq!(l["verdict"].as_str(), Some("consistent with a liquid"));
        assert_eq!((l["tolerance"].as_float(), l["bond_number"].as_float()), (Some(0.1), Some(0.0196)));
        assert!(l["caveats"].as_array().unwrap()[0].as_str().unwrap().starts_with("gravity is on without buoyancy"));
        let lines = s.lines();
        let want = [
            "summary: hold 1 (t = 1–3 s, ũ = 0.15): 1 mg = 9.81 µN at its end; σ_app 2 mN/m (R1 91, R2 106, R3 21 µm)",
            "summary: hold 2 (t = 6–8 s, ũ = 0.2): 2.5 mg = 24.525 µN at its end; σ_app 2.1 mN/m (R1 81, R2 111, R3 31 µm)",
            "summary: hold 3 (t = 12–13 s, ũ = 0.3): not reached (the run ended before)",
            "summary: liquid test (Forgacs et al. 1998): σ_app 2 mN/m at ũ = 0.15, 2.1 mN/m at ũ = 0.2; ratio 1.05 \
             (spread 5.0%, a liquid's at most 10%): consistent with a liquid",
        ];
        for w in want {
            assert!(lines.contains(&w.to_string()), "no `{w}` in\n{}", lines.join("\n"));
        }
        assert!(lines.iter().any(|l| l.starts_with("summary: liquid test, unreliable here: gravity is on")));
        assert!(!lines.iter().any(|l| l.contains("no surface tension")));
        // Two compressions, one not reached: no verdict, and the log says why.
        let p = PlateSummary::of(&h, protocol, &[holds[0], holds[2]], Some(setting)).unwrap();
        assert!(p.liquid_test.is_none());
        let s = Summary { plates: Some(p), ..s };
        let lines = s.lines();
        assert!(lines
            .contains(&"summary: liquid test: no verdict (σ_app was not read positive at two compressions)".into()));
        assert!(!toml::from_str::<toml::Table>(&s.toml()).unwrap().contains_key("liquid_test"));
    }
}
