//! Text form of floats shared by the text writers (CSV, PVD).

use std::fmt::Write;

/// Appends `x` to `out` in the shortest text that parses back to the same `f64` bits.
///
/// Plain decimal (Rust's `{}`) for 0 and for magnitudes in [1e-5, 1e16), scientific (`{:e}`,
/// e.g. `1.5e-7`, `-2e20`) otherwise, so tiny and huge values stay short. Both forms are read
/// back exactly by Rust's `str::parse::<f64>`, C's `strtod`, Python's `float` and spreadsheets.
/// Non-finite values are written `nan`, `inf`, `-inf` (readable by Rust, Python, NumPy and
/// pandas, but not by every CSV consumer).
pub(crate) fn push_f64(out: &mut String, x: f64) {
    let a = x.abs();
    // Writing into a String cannot fail.
    let _ = if x.is_nan() {
        write!(out, "nan")
    } else if x.is_infinite() {
        write!(out, "{}", if x > 0.0 { "inf" } else { "-inf" })
    } else if a == 0.0 || (1e-5..1e16).contains(&a) {
        write!(out, "{x}")
    } else {
        write!(out, "{x:e}")
    };
}

#[cfg(test)]
mod tests {
    use super::push_f64;

    fn text(x: f64) -> String {
        let mut s = String::new();
        push_f64(&mut s, x);
        s
    }

    #[test]
    fn short_forms() {
        assert_eq!(text(0.0), "0");
        assert_eq!(text(-0.0), "-0");
        assert_eq!(text(1.5), "1.5");
        assert_eq!(text(1e-7), "1e-7");
        assert_eq!(text(-2.5e20), "-2.5e20");
        assert_eq!(text(f64::NAN), "nan");
        assert_eq!(text(f64::NEG_INFINITY), "-inf");
    }

    #[test]
    fn round_trips_bit_exactly() {
        let values = [
            0.1,
            1.0 / 3.0,
            -7.123456789012345e-300,
            f64::MIN_POSITIVE,
            5e-324,
            f64::MAX,
            123456789.12345679,
            1e16 - 2.0,
            1e16,
        ];
        for x in values {
            let back: f64 = text(x).parse().unwrap();
            assert_eq!(back.to_bits(), x.to_bits(), "{x:e} -> {}", text(x));
        }
    }
}
