//! Numbers as text for people (messages, figure labels, table cells): a fixed count of
//! significant digits, trailing zeros dropped. (The CSV files write every digit: [`crate::output::csv::shortest`].)

/// `x` with `digits` significant digits, trailing zeros (and a trailing point) dropped:
/// `significant(1.1070312500000001, 10)` = `1.10703125`, `significant(73.5201, 4)` = `73.52`;
/// ±0 is `0`, a non-finite value as Rust writes it. Fixed notation, except where it would
/// print digits f64 does not hold (|x| ≥ 1e16: `1e300`, not 301 digits) or need more than 17
/// decimals (`significant(1e-300, 4)` = `1e-300`, not `0`): there `<mantissa>e<exponent>`.
pub fn significant(x: f64, digits: usize) -> String {
    if x == 0.0 {
        return "0".into();
    }
    if !x.is_finite() {
        return x.to_string();
    }
    let digits = digits.max(1);
    let exponent = x.abs().log10().floor() as i32;
    let decimals = digits as i32 - 1 - exponent;
    if exponent >= 16 || decimals > 17 {
        let s = format!("{x:.*e}", digits - 1);
        let (mantissa, exponent) = s.split_once('e').unwrap_or((&s, "0"));
        return format!("{}e{exponent}", trim_zeros(mantissa));
    }
    let decimals = decimals.clamp(0, 17) as usize;
    trim_zeros(&format!("{x:.decimals$}"))
}

/// `x` with the fewest digits that read back to the same f64 (−0 as 0), in scientific notation
/// outside 1e-4 ≤ |x| < 1e15 (Rust's plain `Display` writes 1e300 as 301 digits and 6e-16 with
/// fifteen leading zeros): a value a user gave, written back exactly and short.
pub fn shortest(x: f64) -> String {
    if x == 0.0 {
        // −0 (a symmetry-axis displacement) is written 0.
        "0".to_string()
    } else if (1e-4..1e15).contains(&x.abs()) || !x.is_finite() {
        x.to_string()
    } else {
        format!("{x:e}")
    }
}

/// `1.2500` → `1.25`, `2.000` → `2`; a number without a decimal point as it is.
pub fn trim_zeros(s: &str) -> String {
    if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s.to_string()
    }
}

/// `1.5 MiB`, `200 KiB`, `12 bytes`: a size for people, three significant digits.
pub fn bytes(n: u64) -> String {
    const UNITS: [&str; 5] = ["KiB", "MiB", "GiB", "TiB", "PiB"];
    if n < 1024 {
        return format!("{n} bytes");
    }
    let mut x = n as f64 / 1024.0;
    let mut unit = 0;
    while x >= 1024.0 && unit + 1 < UNITS.len() {
        x /= 1024.0;
        unit += 1;
    }
    format!("{} {}", significant(x, 3), UNITS[unit])
}

/// `n` with its digits grouped by three, a space between groups: `918 102`.
pub fn grouped(n: u64) -> String {
    let digits = n.to_string();
    let mut out = String::with_capacity(digits.len() + digits.len() / 3);
    for (i, c) in digits.chars().enumerate() {
        if i > 0 && (digits.len() - i).is_multiple_of(3) {
            out.push(' ');
        }
        out.push(c);
    }
    out
}

/// A table cell of a measured number: scientific notation with `digits` digits; `failed` for an
/// infinite one (a measurement that failed), `–` for none.
pub fn cell(x: Option<f64>, digits: usize) -> String {
    match x {
        Some(v) if v.is_finite() => format!("{v:.digits$e}"),
        Some(v) if v.is_infinite() => "failed".into(),
        _ => "–".into(),
    }
}

/// A ratio (a speed-up): fixed-point in [0.1, 1000), scientific outside ([`cell`]).
pub fn ratio(x: f64) -> String {
    if (0.1..1000.0).contains(&x.abs()) {
        format!("{x:.2}")
    } else {
        cell(Some(x), 1)
    }
}

/// Escapes text for HTML.
pub fn escape_html(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The word of `candidates` nearest to the misspelt `key`, if within two edits (Levenshtein):
/// what a "did you mean" names.
pub fn closest<'a>(key: &str, candidates: &[&'a str]) -> Option<&'a str> {
    let distance = |a: &str, b: &str| {
        let b: Vec<char> = b.chars().collect();
        let mut row: Vec<usize> = (0..=b.len()).collect();
        for (i, ca) in a.chars().enumerate() {
            let mut diagonal = row[0];
            row[0] = i + 1;
            for (j, &cb) in b.iter().enumerate() {
                let above = row[j + 1];
                row[j + 1] = (above + 1)
                    .min(row[j] + 1)
                    .min(diagonal + usize::from(ca != cb));
                diagonal = above;
            }
        }
        row[b.len()]
    };
    candidates
        .iter()
        .map(|&c| (distance(key, c), c))
        .filter(|&(d, _)| d <= 2)
        .min_by_key(|&(d, _)| d)
        .map(|(_, c)| c)
}

#[cfg(test)]
mod tests {
    use super::significant;

    #[test]
    fn large_counts_are_grouped_by_three_digits() {
        assert_eq!(super::grouped(0), "0");
        assert_eq!(super::grouped(999), "999");
        assert_eq!(super::grouped(1000), "1 000");
        assert_eq!(super::grouped(918_102), "918 102");
        assert_eq!(super::grouped(18_362_040), "18 362 040");
    }

    #[test]
    fn sizes_are_written_for_people() {
        assert_eq!(super::bytes(12), "12 bytes");
        assert_eq!(super::bytes(200 * 1024), "200 KiB");
        assert_eq!(super::bytes(3 * 1024 * 1024 / 2), "1.5 MiB");
        assert_eq!(super::bytes(918_102 * 161), "141 MiB");
    }

    #[test]
    fn significant_digits_without_the_binary_noise_or_trailing_zeros() {
        assert_eq!(significant(1.1070312500000001, 10), "1.10703125");
        assert_eq!(significant(1.17, 10), "1.17");
        assert_eq!(significant(2.0, 10), "2");
        assert_eq!(significant(-0.0, 4), "0");
        assert_eq!(significant(0.62430001, 4), "0.6243");
        assert_eq!(significant(15134.2, 4), "15134");
        assert_eq!(significant(1e15, 4), "1000000000000000");
    }

    #[test]
    fn extreme_magnitudes_are_written_short_with_an_exponent() {
        assert_eq!(significant(1e300, 10), "1e300");
        assert_eq!(significant(-2.5e300, 4), "-2.5e300");
        assert_eq!(significant(1.7976931348623157e308, 4), "1.798e308");
        assert_eq!(significant(1e16, 4), "1e16");
        assert_eq!(significant(1e-300, 10), "1e-300");
        assert_eq!(significant(5e-324, 1), "5e-324");
        assert_eq!(significant(1.25e-20, 4), "1.25e-20");
        for x in [1e300, -3.75e-200, 6.02214076e23, 1e-300] {
            let back: f64 = significant(x, 10).parse().unwrap();
            assert!(
                (back - x).abs() <= 1e-9 * x.abs(),
                "{x}: {}",
                significant(x, 10)
            );
            assert!(significant(x, 10).len() < 20, "{x}: {}", significant(x, 10));
        }
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
