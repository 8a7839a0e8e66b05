//! A tool's protocol in time (design of issue 53, §5.4): displacement or force control,
//! linear between consecutive rows of one control, held after the last; a switch is two rows
//! at one time. The rows and their checks are the scene's (`scene::protocol`).

use crate::scene::protocol::{Control, ProtocolRow};

/// µN in the solver's force unit (nN).
const UN_TO_NN: f64 = 1000.0;

/// What a tool does at a time.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Mode {
    /// At this displacement along its axis (µm).
    Displacement(f64),
    /// Pressing with this force (nN, full body): its position is an unknown.
    Force(f64),
}

/// A tool's protocol: (t, control) rows in the solver's units, checked.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ToolProtocol {
    rows: Vec<(f64, Control)>,
}

impl ToolProtocol {
    /// A tool that stays at its origin.
    pub(crate) fn fixed() -> ToolProtocol {
        ToolProtocol { rows: vec![(0.0, Control::Displacement(Some(0.0)))] }
    }

    /// The protocol of checked scene rows (`scene::protocol::check`).
    pub(crate) fn from_rows(rows: &[ProtocolRow]) -> ToolProtocol {
        let rows = rows
            .iter()
            .map(|r| {
                let c = match r.control("", 0).expect("checked when the scene was loaded") {
                    Control::Force(f) => Control::Force(f * UN_TO_NN),
                    c => c,
                };
                (r.t, c)
            })
            .collect();
        ToolProtocol { rows }
    }

    /// Displacements (t, d) in increasing t, linear between them (the lower plate's path as a tool).
    pub(crate) fn displacements(points: &[(f64, f64)]) -> ToolProtocol {
        ToolProtocol { rows: points.iter().map(|&(t, d)| (t, Control::Displacement(Some(d)))).collect() }
    }

    /// Whether any row is under force control.
    pub(crate) fn has_force(&self) -> bool {
        self.rows.iter().any(|r| matches!(r.1, Control::Force(_)))
    }

    /// The row that starts the segment (t_j, t_j+1] holding t: the last row before t (the
    /// first at or before the first row's time). A step ending at a switch is solved under the
    /// control before it.
    pub(crate) fn segment(&self, t: f64) -> usize {
        self.rows.iter().rposition(|r| r.0 < t).unwrap_or(0)
    }

    /// Whether the segment of `j` starts with `displacement = "held"`.
    pub(crate) fn holds_at(&self, j: usize) -> bool {
        matches!(self.rows[j].1, Control::Displacement(None))
    }

    /// The control at time t; `held` is the position reached at the segment's start (for a
    /// `"held"` row).
    pub(crate) fn at(&self, t: f64, held: f64) -> Mode {
        let j = self.segment(t);
        let (t0, c0) = self.rows[j];
        let value = |c: Control| match c {
            Control::Displacement(d) => d.unwrap_or(held),
            Control::Force(f) => f,
        };
        let v0 = value(c0);
        let v = match self.rows.get(j + 1) {
            Some(&(t1, c1)) if std::mem::discriminant(&c0) == std::mem::discriminant(&c1) && t1 > t0 => {
                let s = ((t - t0) / (t1 - t0)).clamp(0.0, 1.0);
                v0 + (value(c1) - v0) * s
            }
            _ => v0,
        };
        match c0 {
            Control::Displacement(_) => Mode::Displacement(v),
            Control::Force(_) => Mode::Force(v),
        }
    }

    /// The row times after 0: steps land on them.
    pub(crate) fn kinks(&self) -> Vec<f64> {
        self.rows.iter().map(|r| r.0).filter(|&t| t > 0.0).collect()
    }

    /// The position at t = 0 (0 under force control: the tool starts at its origin).
    fn start(&self) -> f64 {
        match self.at(0.0, 0.0) {
            Mode::Displacement(d) => d,
            Mode::Force(_) => 0.0,
        }
    }
}

/// Force control of `what` ("the upper plate", "tool \"bead\"") that touches nothing (at time
/// t, `gap` µm away): what to do instead.
pub(crate) fn untouched(what: &str, t: f64, gap: f64) -> String {
    format!(
        "force control from t = {t} s, but {what} is {} µm from the body there: it cannot press on nothing. \
         Reach the body under displacement control first (a displacement row before the force row)",
        crate::io::fmt_significant(gap, 4)
    )
}

/// A tool (or the upper plate) between steps: its committed position and its last step's rate,
/// the protocol segment of the last stage, the position a `"held"` row holds, and whether the
/// stage just switched to another segment (its first attempt: a switch to force control is
/// checked). A checkpoint keeps the first four ([`Progress::values`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Progress {
    pub(crate) d: f64,
    pub(crate) rate: f64,
    pub(crate) segment: usize,
    pub(crate) held: f64,
    pub(crate) switched: bool,
}

impl Progress {
    /// At t = 0.
    pub(crate) fn start(protocol: &ToolProtocol) -> Progress {
        let d = protocol.start();
        Progress { d, rate: 0.0, segment: 0, held: d, switched: false }
    }

    /// Where a run resumed at time t from a checkpoint without this tool's state stands: the
    /// protocol's position there (exact under displacement control).
    pub(crate) fn from_table(protocol: &ToolProtocol, t: f64) -> Progress {
        let segment = protocol.segment(t);
        let d = match protocol.at(t, 0.0) {
            Mode::Displacement(d) => d,
            Mode::Force(_) => 0.0,
        };
        Progress { d, rate: 0.0, segment, held: d, switched: false }
    }

    /// The stage time t of the step from `start`: the prescribed position, or under force
    /// control the committed one extrapolated with the last rate (`extrapolate`; the solver
    /// moves it from there) and the target force (nN, full body).
    pub(crate) fn stage(
        &mut self,
        protocol: &ToolProtocol,
        start: f64,
        t: f64,
        extrapolate: bool,
    ) -> (f64, Option<f64>) {
        let j = protocol.segment(t);
        if j != self.segment && protocol.holds_at(j) {
            self.held = self.d;
        }
        self.switched = j != self.segment || start == 0.0 && t > 0.0;
        self.segment = j;
        match protocol.at(t, self.held) {
            Mode::Displacement(d) => (d, None),
            Mode::Force(f) => (self.d + if extrapolate { (t - start) * self.rate } else { 0.0 }, Some(f)),
        }
    }

    /// Commits the position `d` of the accepted step of size dt (its rate kept with `keep_rate`).
    pub(crate) fn commit(&mut self, d: f64, dt: f64, keep_rate: bool) {
        self.rate = if keep_rate && dt > 0.0 { (d - self.d) / dt } else { 0.0 };
        self.d = d;
    }

    /// What a checkpoint keeps: d, rate, segment, held.
    pub(crate) fn values(&self) -> [f64; 4] {
        [self.d, self.rate, self.segment as f64, self.held]
    }

    /// From a checkpoint's [`values`](Self::values).
    pub(crate) fn from_values(v: &[f64]) -> Option<Progress> {
        match v {
            &[d, rate, segment, held] => Some(Progress { d, rate, segment: segment as usize, held, switched: false }),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::protocol::Displacement;

    fn row(t: f64, d: Option<f64>, f: Option<f64>) -> ProtocolRow {
        ProtocolRow { t, displacement: d.map(Displacement::Value), force: f }
    }

    #[test]
    fn ramp_then_force_hold_then_held() {
        let mut rows = vec![
            row(0.0, Some(0.0), None),
            row(5.0, Some(20.0), None),
            row(5.0, None, Some(0.5)),
            row(60.0, None, Some(1.5)),
        ];
        rows.push(ProtocolRow {
            t: 60.0,
            displacement: Some(Displacement::Held(crate::scene::protocol::HeldWord::Held)),
            force: None,
        });
        rows.push(row(70.0, Some(0.0), None));
        let p = ToolProtocol::from_rows(&rows);
        assert!(p.has_force());
        assert_eq!(p.at(0.0, 0.0), Mode::Displacement(0.0));
        assert_eq!(p.at(2.5, 0.0), Mode::Displacement(10.0));
        // The step ending at the switch is displacement-controlled; after it, force.
        assert_eq!(p.at(5.0, 0.0), Mode::Displacement(20.0));
        assert_eq!(p.at(5.0 + 1e-9, 0.0), Mode::Force(500.0 + 1000.0 * 1e-9 / 55.0));
        assert_eq!(p.at(32.5, 0.0), Mode::Force(1000.0));
        assert_eq!(p.at(60.0, 0.0), Mode::Force(1500.0));
        // Held where it was at 60 s (here 27 µm), then back to 0 by 70 s.
        assert!(p.holds_at(p.segment(61.0)));
        assert_eq!(p.at(65.0, 27.0), Mode::Displacement(13.5));
        assert_eq!(p.at(100.0, 27.0), Mode::Displacement(0.0));
        assert_eq!(p.kinks(), [5.0, 5.0, 60.0, 60.0, 70.0]);
        assert!(!ToolProtocol::fixed().has_force());
        assert_eq!(ToolProtocol::fixed().at(3.0, 1.0), Mode::Displacement(0.0));
    }

    /// Between steps: the prescribed positions, then under force control the committed position
    /// advanced by the last rate, a `"held"` row holding where force control left it, and the
    /// checkpoint's four values.
    #[test]
    fn progress_follows_the_switches() {
        let held = ProtocolRow {
            t: 6.0,
            displacement: Some(Displacement::Held(crate::scene::protocol::HeldWord::Held)),
            force: None,
        };
        let rows = [row(0.0, Some(0.0), None), row(5.0, Some(20.0), None), row(5.0, None, Some(0.5)), held];
        let p = ToolProtocol::from_rows(&rows);
        let mut g = Progress::start(&p);
        assert_eq!(g.d, 0.0);
        assert_eq!(g.stage(&p, 0.0, 5.0, true), (20.0, None));
        assert!(g.switched, "the first stage of a run");
        g.commit(20.0, 5.0, true);
        assert_eq!(g.rate, 4.0);
        // The first stage under force: from the committed 20 µm, advanced by 4 µm/s × 0.5 s.
        assert_eq!(g.stage(&p, 5.0, 5.5, true), (22.0, Some(500.0)));
        assert!(g.switched);
        assert_eq!(g.stage(&p, 5.0, 5.5, false), (20.0, Some(500.0)), "a retried stage, no extrapolation");
        assert!(!g.switched, "the retry is not a switch");
        g.commit(21.0, 1.0, true);
        assert_eq!(g.rate, 1.0);
        assert_eq!(g.stage(&p, 6.0, 7.0, true), (21.0, None), "held where force control left it");
        assert_eq!(Progress::from_values(&g.values()), Some(Progress { switched: false, ..g }));
        assert_eq!(Progress::from_values(&[1.0, 2.0]), None);
        // A checkpoint without the tool's state: the protocol's position at its time.
        assert_eq!(Progress::from_table(&p, 2.5).d, 10.0);
    }
}
