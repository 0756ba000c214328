//! Numbers as text for people (messages, figure labels): a fixed count of significant digits,
//! trailing zeros dropped. (The CSV files write every digit: [`crate::output::csv::shortest`].)

/// `x` in fixed notation with `digits` significant digits, trailing zeros (and a trailing point)
/// dropped: `significant(1.1070312500000001, 10)` = `1.10703125`, `significant(73.5201, 4)` =
/// `73.52`; ±0 is `0`, a non-finite value as Rust writes it.
pub fn significant(x: f64, digits: usize) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if !x.is_finite() {
        return x.to_string();
    }
    let decimals = (digits as i32 - 1 - x.abs().log10().floor() as i32).clamp(0, 17) as usize;
    trim_zeros(&format!("{x:.decimals$}"))
}

/// `1.2500` → `1.25`, `2.000` → `2`; a number without a decimal point as it is.
pub fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::significant;

    #[test]
    fn significant_digits_without_the_binary_noise_or_trailing_zeros() {
        assert_eq!(significant(1.1070312500000001, 10), "1.10703125");
        assert_eq!(significant(1.17, 10), "1.17");
        assert_eq!(significant(2.0, 10), "2");
        assert_eq!(significant(-0.0, 4), "0");
        assert_eq!(significant(0.62430001, 4), "0.6243");
        assert_eq!(significant(15134.2, 4), "15134");
        for x in [
            0.123_456_789_123,
            1.000_000_000_1,
            12.345_678_912_3,
            1e-7 / 3.0,
        ] {
            let back: f64 = significant(x, 10).parse().unwrap();
            assert!(
                (back - x).abs() <= 1e-9 * x.abs(),
                "{x} written {}",
                significant(x, 10)
            );
        }
    }
}
