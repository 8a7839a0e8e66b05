//! The holds of a plate protocol, and what a run's history reads at the end of each: a hold is a
//! phase of constant ũ > 0 in the plate's path (`PlatesSpec::path`): the hold of
//! `plates.ramp/hold/release`, each plateau of a `plates.table` (consecutive rows at the same
//! ũ > 0; a table whose last row has ũ > 0 holds it to the run's end, as the plate does). A
//! plateau at ũ = 0 (the plates apart) is not a hold.

use crate::io::observable::{self, Columns};
use crate::observe::laplace;

/// A phase of constant ũ > 0 (s, s, ũ = u / (2R)).
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Hold {
    pub(crate) start: f64,
    pub(crate) end: f64,
    pub(crate) compression: f64,
}

/// The holds of the plate's path `rows` ([t, ũ] from [0, 0], linear between rows, the last held)
/// in a run that ends at `t_end`, in time order.
pub(crate) fn holds(rows: &[[f64; 2]], t_end: f64) -> Vec<Hold> {
    let mut found: Vec<Hold> = Vec::new();
    let mut push = |start: f64, end: f64, compression: f64| match found.last_mut() {
        // A plateau over several rows is one hold.
        Some(h) if h.end == start && h.compression == compression => h.end = end,
        _ => found.push(Hold { start, end, compression }),
    };
    for w in rows.windows(2) {
        let ([t0, u0], [t1, u1]) = (w[0], w[1]);
        if u0 == u1 && u0 > 0.0 && t1 > t0 {
            push(t0, t1, u0);
        }
    }
    if let Some(&[t, u]) = rows.last() {
        if u > 0.0 && t_end > t {
            push(t, t_end, u);
        }
    }
    found
}

/// What the history reads at the end of a hold: the upper plate's force (mg) and the Laplace
/// reading [R1, R2, R3, σ_app] (µm, mN/m), interpolated at the hold's end; None if the run
/// ended before it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct AtEnd {
    pub(crate) force_mg: f64,
    pub(crate) laplace: [f64; 4],
}

/// A hold and its reading.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct HoldReading {
    pub(crate) hold: Hold,
    pub(crate) at_end: Option<AtEnd>,
}

/// The readings of `holds` in the history `h`. A hold that ends at the run's end is read at the
/// last row when that row is its end up to round-off in the step times.
pub(crate) fn read(h: &Columns, holds: &[Hold]) -> Vec<HoldReading> {
    let last = h.get("time").and_then(|t| t.last().copied()).unwrap_or(f64::NAN);
    holds
        .iter()
        .map(|&hold| {
            let when = if (last - hold.end).abs() <= 1e-9 * hold.end.abs().max(1.0) { last } else { hold.end };
            let force_mg = observable::at_time(h, "force_total_mg", when);
            let at_end = force_mg
                .is_finite()
                .then(|| AtEnd { force_mg, laplace: laplace::COLUMNS.map(|c| observable::at_time(h, c.name(), when)) });
            HoldReading { hold, at_end }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn hold(start: f64, end: f64, compression: f64) -> Hold {
        Hold { start, end, compression }
    }

    /// `tst_two_compressions`' table: two plateaus, the rest between them (ũ = 0) not a hold.
    #[test]
    fn a_table_holds_at_each_plateau_above_zero() {
        let rows = [
            [0.0, 0.0],
            [5.0, 0.15],
            [1005.0, 0.15],
            [1010.0, 0.0],
            [1300.0, 0.0],
            [1305.0, 0.3],
            [2305.0, 0.3],
            [2310.0, 0.0],
        ];
        assert_eq!(holds(&rows, 2400.0), [hold(5.0, 1005.0, 0.15), hold(1305.0, 2305.0, 0.3)]);
        // A plateau over three rows is one hold; a ramp between two levels is none; a single row
        // at a level (a peak) is none.
        let rows = [[0.0, 0.0], [5.0, 0.1], [10.0, 0.1], [20.0, 0.1], [25.0, 0.2], [30.0, 0.1], [35.0, 0.0]];
        assert_eq!(holds(&rows, 40.0), [hold(5.0, 20.0, 0.1)]);
        // Two plateaus at the same ũ with a ramp between: two holds.
        let rows = [[0.0, 0.0], [1.0, 0.1], [2.0, 0.1], [3.0, 0.2], [4.0, 0.1], [5.0, 0.1]];
        assert_eq!(holds(&rows, 5.0), [hold(1.0, 2.0, 0.1), hold(4.0, 5.0, 0.1)]);
    }

    /// A table ending at ũ > 0 holds it to the run's end (joined to the plateau it ends); a table
    /// ending at 0 does not.
    #[test]
    fn a_table_ending_in_a_hold_holds_to_the_end_of_the_run() {
        assert_eq!(holds(&[[0.0, 0.0], [0.5, 0.15]], 10.0), [hold(0.5, 10.0, 0.15)]);
        assert_eq!(holds(&[[0.0, 0.0], [0.5, 0.15], [1.0, 0.15]], 10.0), [hold(0.5, 10.0, 0.15)]);
        assert_eq!(holds(&[[0.0, 0.0], [0.5, 0.15], [1.0, 0.15]], 1.0), [hold(0.5, 1.0, 0.15)]);
        assert_eq!(holds(&[[0.0, 0.0], [0.5, 0.15], [1.0, 0.0]], 10.0), []);
        // Plates that only rest: no hold.
        assert_eq!(holds(&[[0.0, 0.0], [5.0, 0.0]], 10.0), []);
    }

    /// The phases' path (`PlatesSpec::path`): one hold from the ramp's end; none with hold = 0.
    #[test]
    fn the_phases_have_one_hold() {
        assert_eq!(holds(&[[0.0, 0.0], [2.0, 0.3], [8.0, 0.3], [10.0, 0.0]], 12.0), [hold(2.0, 8.0, 0.3)]);
        assert_eq!(holds(&[[0.0, 0.0], [2.0, 0.3], [2.0, 0.3], [4.0, 0.0]], 12.0), []);
    }

    /// The readings interpolate at each hold's end; a hold the run did not reach has none; a
    /// hold ending at the run's end reads the last row even when the step times carry round-off.
    #[test]
    fn each_hold_is_read_at_its_end() {
        let h: Columns = [
            ("time", vec![0.0, 1.0, 2.0, 3.0, 4.0 - 1e-12]),
            ("force_total_mg", vec![0.0, 2.0, 1.0, 3.0, 2.0]),
            ("R1", vec![f64::NAN, 10.0, 20.0, 30.0, 40.0]),
            ("R2", vec![f64::NAN, 11.0, 21.0, 31.0, 41.0]),
            ("R3", vec![f64::NAN, 12.0, 22.0, 32.0, 42.0]),
            ("sigma_app", vec![f64::NAN, 1.0, 2.0, 3.0, 4.0]),
        ]
        .into_iter()
        .map(|(k, v)| (k.to_string(), v))
        .collect();
        let r = read(&h, &[hold(0.5, 1.5, 0.1), hold(2.5, 4.0, 0.2), hold(4.5, 6.0, 0.3)]);
        assert_eq!(r[0].at_end, Some(AtEnd { force_mg: 1.5, laplace: [15.0, 16.0, 17.0, 1.5] }));
        assert_eq!(r[1].at_end, Some(AtEnd { force_mg: 2.0, laplace: [40.0, 41.0, 42.0, 4.0] }));
        assert_eq!((r[2].hold, r[2].at_end), (hold(4.5, 6.0, 0.3), None));
    }
}
