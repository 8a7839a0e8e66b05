//! Run output: the run directory, per-step field files (HDF5 + XDMF for ParaView), the
//! `history.csv` log (and the observables read from it) and the checkpoint files.
pub mod checkpoint;
pub mod fields;
pub mod history;
pub mod observable;
pub mod recorder;
pub mod rundir;

/// Formats a real number so that it parses back to the identical `f64` (shortest round-trip digits),
/// in plain notation for moderate magnitudes and in exponent notation (`1.5e-7`) otherwise.
/// Non-finite values print as `NaN`, `inf`, `-inf` (all accepted by Python's `float`).
pub fn fmt_real(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-4..1e16).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// A time (s) for the log: ten significant digits, without the float noise of sums of steps
/// (`130.0798`, not `130.07980000000003`).
pub(crate) fn fmt_time(t: f64) -> String {
    fmt_real(format!("{t:.9e}").parse().unwrap_or(t))
}

/// A duration of `s` seconds for a progress line: `42s`, `3m07s`, `2h05m`.
pub(crate) fn fmt_duration(s: f64) -> String {
    if s < 60.0 {
        format!("{s:.0}s")
    } else if s < 3600.0 {
        format!("{}m{:02}s", (s / 60.0) as u64, (s % 60.0) as u64)
    } else {
        format!("{}h{:02}m", (s / 3600.0) as u64, ((s % 3600.0) / 60.0) as u64)
    }
}

#[cfg(test)]
mod tests {
    use super::{fmt_duration, fmt_real};

    #[test]
    fn times_without_float_noise() {
        assert_eq!(super::fmt_time(130.07980000000003), "130.0798");
        assert_eq!(super::fmt_time(0.1 + 0.2), "0.3");
        assert_eq!(super::fmt_time(1e-7 / 3.0), "3.333333333e-8");
        assert_eq!(super::fmt_time(35.0), "35");
    }

    #[test]
    fn durations() {
        assert_eq!(fmt_duration(42.4), "42s");
        assert_eq!(fmt_duration(187.0), "3m07s");
        assert_eq!(fmt_duration(7500.0), "2h05m");
    }

    #[test]
    fn fmt_real_round_trips() {
        for v in [
            0.0,
            -0.0,
            1.0,
            0.1,
            1.0 / 3.0,
            1e-4,
            9.99e-5,
            1e-300,
            123456789.125,
            1e16,
            -2.5e22,
            f64::MAX,
            f64::MIN_POSITIVE,
        ] {
            let s = fmt_real(v);
            assert_eq!(s.parse::<f64>().unwrap().to_bits(), v.to_bits(), "{v} -> {s}");
        }
        assert_eq!(fmt_real(1.0), "1");
        assert_eq!(fmt_real(0.5), "0.5");
        assert_eq!(fmt_real(1.5e-7), "1.5e-7");
        assert_eq!(fmt_real(f64::NAN), "NaN");
        assert_eq!(fmt_real(f64::NEG_INFINITY), "-inf");
    }
}
