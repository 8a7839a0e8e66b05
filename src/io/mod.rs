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

/// A real for a log line: rounded to 5 significant digits, without trailing zeros (`130.08` for
/// 130.07980000000003, `2305` for 2305.0000000002); files keep every digit ([`fmt_real`]).
pub(crate) fn fmt_short(x: f64) -> String {
    if x == 0.0 || !x.is_finite() {
        return fmt_real(x);
    }
    let decimals = (4.0 - x.abs().log10().floor()).clamp(0.0, 12.0) as usize;
    let s = format!("{x:.decimals$}");
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    }
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
            (1.5e-14, "0"),
            (123456789.4, "123456789"),
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
