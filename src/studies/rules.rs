//! The rules a study's values keep, written once for every kind's `resolve`: a key that must be
//! given, a list that must not be empty, items that each keep a rule and are each given once,
//! lengths and counts in their ranges, and a study that asks for something. Each refusal names
//! the key (relative to the study: `fibre_angles[1]`), the value as written and why.

use crate::app_error::{Shown, SpecError};
use std::ops::RangeInclusive;

/// The value of a required key; left out (`None`), `key` is refused with `rule` (what to give).
pub fn required<T>(v: Option<T>, key: &str, rule: impl Into<String>) -> Result<T, SpecError> {
    v.ok_or_else(|| SpecError::new(key, "(missing)", rule))
}

/// A list that must not be empty; `rule` says what to give.
pub fn non_empty<T>(key: &str, v: &[T], rule: &str) -> Result<(), SpecError> {
    if v.is_empty() {
        Err(SpecError::new(key, "[]", rule))
    } else {
        Ok(())
    }
}

/// Every item of the list `key` keeps `ok`; the first that does not is refused as `key[j]`.
pub fn each<T: Shown>(
    key: &str,
    v: &[T],
    ok: impl Fn(&T) -> bool,
    rule: &str,
) -> Result<(), SpecError> {
    match v.iter().position(|x| !ok(x)) {
        Some(j) => Err(SpecError::new(format!("{key}[{j}]"), &v[j], rule)),
        None => Ok(()),
    }
}

/// Every item of the list `key` given once: the first `key[j]` that is `same` as an earlier
/// `key[i]` is refused with `why(i)` (each item is one model, curve or run: twice is a mistake).
pub fn once<T: Shown>(
    key: &str,
    v: &[T],
    same: impl Fn(&T, &T) -> bool,
    why: impl Fn(usize) -> String,
) -> Result<(), SpecError> {
    for (j, x) in v.iter().enumerate() {
        if let Some(i) = v[..j].iter().position(|e| same(e, x)) {
            return Err(SpecError::new(format!("{key}[{j}]"), x, why(i)));
        }
    }
    Ok(())
}

/// An integer `key` in `range`: "`what` must be an integer in [lo, hi]" (`what` empty: "must be
/// …").
pub fn integer_in(
    key: &str,
    v: i64,
    range: RangeInclusive<i64>,
    what: &str,
) -> Result<usize, SpecError> {
    if range.contains(&v) {
        return Ok(v as usize);
    }
    let rule = format!("must be an integer in [{}, {}]", range.start(), range.end());
    let rule = if what.is_empty() {
        rule
    } else {
        format!("{what} {rule}")
    };
    Err(SpecError::new(key, v, rule))
}

/// A length or tolerance: finite and > 0.
pub fn positive(key: &str, v: f64) -> Result<f64, SpecError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(SpecError::new(key, v, "must be finite and > 0"))
    }
}

/// A number of cells along one direction: an integer in [1, 10000].
pub fn cell_count(key: &str, v: i64) -> Result<usize, SpecError> {
    integer_in(key, v, 1..=10_000, "the number of cells")
}

/// The middle/base cell-height ratio of a cylinder mesh: finite and ≥ 1.
pub fn grading(key: &str, v: f64) -> Result<f64, SpecError> {
    if v.is_finite() && v >= 1.0 {
        Ok(v)
    } else {
        Err(SpecError::new(
            key,
            v,
            "must be finite and ≥ 1 (1 = uniform)",
        ))
    }
}

/// A study of `kind` that asks for nothing to compute (`anything` false) is refused: it `needs`
/// what it says (`passive = true or laws`).
pub fn something(kind: &str, anything: bool, needs: &str) -> Result<(), SpecError> {
    if anything {
        Ok(())
    } else {
        Err(SpecError::new(
            "",
            "(nothing to compute)",
            format!("a {kind} study needs {needs}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_rule_names_the_first_item_that_breaks_it() {
        let e = each(
            "x",
            &[1.0, f64::NAN, f64::INFINITY],
            |x| x.is_finite(),
            "finite",
        )
        .unwrap_err();
        assert_eq!(e.key, "x[1]");
        let e = once(
            "x",
            &[1.0, 2.0, 1.0, 2.0],
            |a, b| a == b,
            |i| format!("x[{i}]"),
        )
        .unwrap_err();
        assert_eq!((e.key.as_str(), e.rule.as_str()), ("x[2]", "x[0]"));
        let e = integer_in("n", 0, 1..=10, "").unwrap_err();
        assert_eq!(e.rule, "must be an integer in [1, 10]");
        assert_eq!(
            cell_count("nr", 10_001).unwrap_err().rule,
            "the number of cells must be an integer in [1, 10000]"
        );
        assert_eq!(integer_in("n", 10, 1..=10, "").unwrap(), 10);
        assert!(
            required(None::<f64>, "k", "give k")
                .unwrap_err()
                .to_string()
                == "k = (missing): give k"
        );
        assert!(something("shear", false, "x").is_err() && something("shear", true, "x").is_ok());
    }
}
