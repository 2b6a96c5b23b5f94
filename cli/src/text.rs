//! Numbers and counts as a reader sees them, in one style across the
//! terminal, `report.md`, the suite's reports and the pictures' titles.
//!
//! - Times of contact are written whole (every digit that round-trips, as
//!   a regression test pins them) and as plain decimals where those read
//!   well (`0.9578262102204965`, `12.5`); `8.898964890827e-13` outside
//!   `[1e-4, 1e9)`.
//! - Measured or derived magnitudes (distances, errors, tolerances) with a
//!   few significant digits (`4.33e-10`, `0.0025`).
//! - Wall times in the unit that reads best (`850 µs`, `1.2 ms`, `3.4 s`).
//! - Counts with their noun agreeing (`1 contact`, `2 contacts`).

use nearmiss::math::Real;

/// A time (or any value a user compares digit by digit): the shortest
/// decimal that reads back as the same `f64`, without an exponent between
/// 1e-4 and 1e9.
pub fn time(value: Real) -> String {
    let magnitude = value.abs();
    if value == 0.0 || (1e-4..1e9).contains(&magnitude) || !value.is_finite() {
        format!("{value}")
    } else {
        format!("{value:?}")
    }
}

/// A magnitude with `digits` significant digits (at least 1): plain
/// between 1e-3 and 1e6, else with an exponent; trailing zeros dropped.
pub fn approx(value: Real, digits: usize) -> String {
    let digits = digits.max(1);
    let magnitude = value.abs();
    if !value.is_finite() {
        return format!("{value}");
    }
    if value == 0.0 {
        return "0".into();
    }
    if (1e-3..1e6).contains(&magnitude) {
        // Decimals so that `digits` significant ones show.
        let decimals = (digits as i32 - 1 - magnitude.log10().floor() as i32).max(0) as usize;
        let text = format!("{value:.decimals$}");
        return trim_zeros(&text);
    }
    let text = format!("{value:.prec$e}", prec = digits - 1);
    match text.split_once('e') {
        Some((mantissa, exponent)) => format!("{}e{exponent}", trim_zeros(mantissa)),
        None => text,
    }
}

/// A signed difference (`+1.2e-9`, `-0.003`), [`approx`] with its sign.
pub fn signed(value: Real, digits: usize) -> String {
    let text = approx(value, digits);
    if value > 0.0 {
        format!("+{text}")
    } else {
        text
    }
}

/// A wall time in the unit that reads best: `850 ns`, `12.3 µs`, `1.2 ms`,
/// `3.40 s`, `2 min 5 s`.
pub fn wall(seconds: Real) -> String {
    if !seconds.is_finite() || seconds < 0.0 {
        return format!("{seconds} s");
    }
    if seconds >= 120.0 {
        let whole = seconds.round() as u64;
        return format!("{} min {} s", whole / 60, whole % 60);
    }
    let (value, unit) = match seconds {
        s if s >= 1.0 => (s, "s"),
        s if s >= 1e-3 => (s * 1e3, "ms"),
        s if s >= 1e-6 => (s * 1e6, "µs"),
        s => (s * 1e9, "ns"),
    };
    format!("{} {unit}", approx(value, 3))
}

/// `n` and the noun, plural unless `n` is 1 (`1 step`, `3 steps`; `body`
/// → `bodies`).
pub fn count(n: impl Into<u64>, noun: &str) -> String {
    let n = n.into();
    if n == 1 {
        return format!("1 {noun}");
    }
    let plural = match noun.strip_suffix('y') {
        Some(stem) if !stem.ends_with(['a', 'e', 'o', 'u']) => format!("{stem}ies"),
        _ if noun.ends_with('s') || noun.ends_with("sh") || noun.ends_with("ch") || noun.ends_with('x') => {
            format!("{noun}es")
        }
        _ => format!("{noun}s"),
    };
    format!("{n} {plural}")
}

fn trim_zeros(text: &str) -> String {
    if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        text.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn times_round_trip_and_read_plainly() {
        for t in [0.9578262102204965, 1.499999749999934, 12.5, 8.898964890827e-13, 1e12, 0.0, -0.25, 1e-4] {
            assert_eq!(time(t).parse::<Real>().unwrap(), t, "{}", time(t));
        }
        assert_eq!(time(0.9578262102204965), "0.9578262102204965");
        assert_eq!(time(10.0), "10");
        assert_eq!(time(8.898964890827e-13), "8.898964890827e-13");
    }

    #[test]
    fn magnitudes_have_their_digits() {
        assert_eq!(approx(4.331e-10, 3), "4.33e-10");
        assert_eq!(approx(0.0025, 3), "0.0025");
        assert_eq!(approx(1.0e-8, 2), "1e-8");
        assert_eq!(approx(123.456, 3), "123");
        assert_eq!(approx(-5.24e-17, 2), "-5.2e-17");
        assert_eq!(signed(9.341e-10, 2), "+9.3e-10");
        assert_eq!(signed(-0.003, 2), "-0.003");
    }

    #[test]
    fn wall_times_and_counts() {
        assert_eq!(wall(0.00085), "850 µs");
        assert_eq!(wall(0.0012), "1.2 ms");
        assert_eq!(wall(3.4), "3.4 s");
        assert_eq!(wall(125.0), "2 min 5 s");
        assert_eq!(wall(4e-8), "40 ns");
        assert_eq!(count(1u64, "step"), "1 step");
        assert_eq!(count(3u64, "step"), "3 steps");
        assert_eq!(count(2u64, "body"), "2 bodies");
        assert_eq!(count(0u64, "pass"), "0 passes");
        assert_eq!(count(2u64, "ray"), "2 rays");
    }
}
