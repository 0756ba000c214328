//! Lists of a fixed length read from a scene: `[r0, r1]`, `[nr, nz]`, `[x, y, z]`, `[t, value]`.
//!
//! serde reads an array `[T; N]` by taking its first N values; the TOML reader does not look
//! at the rest, so `pairs = [[1.0, 1.1, 1.2]]` would run (1.0, 1.1) and drop 1.2 without a word
//! (too few values were always refused). [`Exactly`] reads exactly N values and refuses more,
//! from inside the list itself, so that the scene's error names the list's own key and line.
//! Every fixed-length field of a scene goes through it: a field declared `[T; N]`, or a
//! `Vec`, `Option` or name-keyed `BTreeMap` of them, takes
//! `#[serde(default, deserialize_with = "crate::fixed_length::exact")]`; a hand-written reader
//! asks for [`Exactly`] in place of `[T; N]`.

use serde::de::{DeserializeOwned, Error as _, IgnoredAny, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer};
use std::collections::BTreeMap;
use std::fmt;
use std::marker::PhantomData;

/// N values of `T`, read from a list of exactly N.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exactly<T, const N: usize>(pub [T; N]);

impl<'de, T: Deserialize<'de>, const N: usize> Deserialize<'de> for Exactly<T, N> {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V<T, const N: usize>(PhantomData<T>);
        impl<'de, T: Deserialize<'de>, const N: usize> Visitor<'de> for V<T, N> {
            type Value = Exactly<T, N>;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                write!(f, "a list of exactly {N} values")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut values = Vec::with_capacity(N);
                while values.len() < N {
                    match seq.next_element::<T>()? {
                        Some(v) => values.push(v),
                        None => break,
                    }
                }
                let mut extra = 0usize;
                while seq.next_element::<IgnoredAny>()?.is_some() {
                    extra += 1;
                }
                let given = values.len() + extra;
                match <[T; N]>::try_from(values) {
                    Ok(array) if extra == 0 => Ok(Exactly(array)),
                    _ => Err(A::Error::custom(format!(
                        "a list of {given} value{}: this key takes exactly {N}",
                        if given == 1 { "" } else { "s" }
                    ))),
                }
            }
        }
        deserializer.deserialize_seq(V(PhantomData))
    }
}

/// A field's type made of fixed-length lists: `[T; N]`, and `Option`s, `Vec`s and
/// `BTreeMap`s of them. [`Self::Exact`] is the same shape with [`Exactly`] in place of each
/// `[T; N]`.
pub trait FixedLength: Sized {
    /// The shape read, with [`Exactly`] for each `[T; N]`.
    type Exact: DeserializeOwned;
    /// The value of the field from what was read.
    fn from_exact(read: Self::Exact) -> Self;
}

impl<T: DeserializeOwned, const N: usize> FixedLength for [T; N] {
    type Exact = Exactly<T, N>;
    fn from_exact(read: Self::Exact) -> Self {
        read.0
    }
}

impl<X: FixedLength> FixedLength for Option<X> {
    type Exact = Option<X::Exact>;
    fn from_exact(read: Self::Exact) -> Self {
        read.map(X::from_exact)
    }
}

impl<X: FixedLength> FixedLength for Vec<X> {
    type Exact = Vec<X::Exact>;
    fn from_exact(read: Self::Exact) -> Self {
        read.into_iter().map(X::from_exact).collect()
    }
}

impl<K: DeserializeOwned + Ord, X: FixedLength> FixedLength for BTreeMap<K, X> {
    type Exact = BTreeMap<K, X::Exact>;
    fn from_exact(read: Self::Exact) -> Self {
        read.into_iter()
            .map(|(k, v)| (k, X::from_exact(v)))
            .collect()
    }
}

/// Reads a field of fixed-length lists, refusing a list longer than its length (for
/// `#[serde(deserialize_with = "crate::fixed_length::exact")]`).
pub fn exact<'de, D: Deserializer<'de>, X: FixedLength>(deserializer: D) -> Result<X, D::Error> {
    X::Exact::deserialize(deserializer).map(X::from_exact)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[derive(Debug, Deserialize)]
    struct Fields {
        #[serde(default, deserialize_with = "exact")]
        pair: Option<[f64; 2]>,
        #[serde(default, deserialize_with = "exact")]
        rows: Option<Vec<[i64; 2]>>,
        #[serde(default, deserialize_with = "exact")]
        named: Option<BTreeMap<String, [f64; 2]>>,
    }

    fn read(text: &str) -> Result<Fields, String> {
        toml::from_str(text).map_err(|e| e.to_string())
    }

    #[test]
    fn exactly_n_values_are_read_and_an_absent_key_is_none() {
        let f = read("pair = [1, 2.5]\nrows = [[1, 2], [3, 4]]\nnamed = { a = [0, 1] }\n").unwrap();
        assert_eq!(f.pair, Some([1.0, 2.5]));
        assert_eq!(f.rows, Some(vec![[1, 2], [3, 4]]));
        assert_eq!(f.named.unwrap()["a"], [0.0, 1.0]);
        assert!(read("").unwrap().pair.is_none());
    }

    #[test]
    fn more_or_fewer_values_are_refused_where_the_list_is_written() {
        for (text, given) in [
            ("pair = [1, 2, 3]", "3 values"),
            ("pair = [1]", "1 value:"),
            ("rows = [[1, 2], [3, 4, 5]]", "3 values"),
            ("named = { a = [0, 1, 2, 3] }", "4 values"),
        ] {
            let e = read(text).unwrap_err();
            assert!(e.contains(given) && e.contains("exactly"), "{text}: {e}");
        }
        // The error points at the inner list that is too long, not at the outer one.
        let e = read("rows = [[1, 2],\n  [3, 4, 5]]").unwrap_err();
        assert!(e.contains("line 2"), "{e}");
    }
}
