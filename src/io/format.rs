//! Numbers as the run's files and log write them: every digit of a file's reals (round-trip),
//! the log's times and short values without float noise, and progress durations.

/// Formats a real number so that it parses back to the identical `f64` (shortest round-trip digits),
/// in plain notation for moderate magnitudes and in exponent notation (`1.5e-7`) otherwise.
/// Non-finite values print as `NaN`, `inf`, `-inf` (all accepted by Python's `float`).
pub(crate) fn fmt_real(v: f64) -> String {
    let a = v.abs();
    if v == 0.0 || !v.is_finite() || (1e-4..1e16).contains(&a) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// `x` rounded to `digits` significant digits, written as [`fmt_real`] writes it: for the log,
/// where the float noise of sums of steps and every digit of a file's numbers get in the way.
pub(crate) fn fmt_significant(x: f64, digits: usize) -> String {
    fmt_real(format!("{x:.*e}", digits.clamp(1, 17) - 1).parse().unwrap_or(x))
}

/// A time (s) for the log: ten significant digits, without the float noise of sums of steps
/// (`130.0798`, not `130.07980000000003`).
pub(crate) fn fmt_time(t: f64) -> String {
    fmt_significant(t, 10)
}

/// A number of the run summary's log lines: five significant digits (`130.08`, `2305`;
/// `summary.toml` has every digit).
pub(crate) fn fmt_short(x: f64) -> String {
    fmt_significant(x, 5)
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
    use super::{fmt_duration, fmt_real, fmt_short};

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
    fn short_reals_lose_the_float_noise() {
        let cases = [
            (130.07980000000003, "130.08"),
            (2305.0000000002, "2305"),
            (17.447330666, "17.447"),
            (171.158313, "171.16"),
            (39.172863, "39.173"),
            (0.0, "0"),
            (-0.00123456, "-0.0012346"),
            (1.5e-14, "1.5e-14"),
            (123456789.4, "123460000"),
            (-1.2345678e-7, "-1.2346e-7"),
            (f64::NAN, "NaN"),
        ];
        for (x, want) in cases {
            assert_eq!(fmt_short(x), want, "{x}");
        }
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
