//! Reading a scene file into a [`SceneSpec`], keeping every error's place in the file.
//!
//! The document is parsed once into spanned TOML values; the top level (title, material,
//! activation) is deserialised from them, then each `[[study]]` by the spec of its `kind`
//! ([`StudySpec::of_kind`]). Deserialising each study from its own spanned table keeps the
//! position of an error inside it, which serde's internally tagged enums would lose.

use super::keypath::key_path;
use super::SceneSpec;
use crate::app_error::SceneError;
use crate::studies::{StudyKind, StudySpec};
use serde::Deserialize;
use toml::de::{DeTable, DeValue, Deserializer, ValueDeserializer};
use toml::Spanned;

/// The scene file `text` (named `file` in errors) as written.
pub(super) fn parse(text: &str, file: &str) -> Result<SceneSpec, SceneError> {
    let error = |e: toml::de::Error| from_toml(text, file, &e, None);
    let mut doc = DeTable::parse(text).map_err(error)?;
    if let Some((span, n)) = doc.get_ref().values().find_map(too_long) {
        return Err(at(
            text,
            file,
            span,
            "",
            &format!(
                "a list of {n} values: at most {MAX_ARRAY} (the outputs of longer lists are \
                 larger than a reader can use; write a range with a coarser step)"
            ),
        ));
    }
    let studies = doc.get_mut().remove("study");
    let curve_parameters = match doc.get_mut().get_mut("activation") {
        Some(activation) => curve_parameters(activation.get_mut()).map_err(error)?,
        None => Vec::new(),
    };
    let mut spec = SceneSpec::deserialize(Deserializer::from(doc)).map_err(error)?;
    spec.activation.curve_parameters = curve_parameters;
    if let Some(studies) = studies {
        let span = studies.span();
        let DeValue::Array(items) = studies.into_inner() else {
            return Err(at(
                text,
                file,
                span,
                "study",
                "studies are an array of tables: [[study]] with kind = \"...\"",
            ));
        };
        for item in items {
            spec.studies.push(study(text, file, item)?);
        }
    }
    Ok(spec)
}

/// The most values one array of a scene may hold: a backstop for every list (the lists of
/// stretches and damages have their own, smaller caps).
pub(crate) const MAX_ARRAY: usize = 10_000;

/// The first array in `value` longer than [`MAX_ARRAY`]: its span and length.
fn too_long(value: &Spanned<DeValue>) -> Option<(std::ops::Range<usize>, usize)> {
    match value.get_ref() {
        DeValue::Array(items) if items.len() > MAX_ARRAY => Some((value.span(), items.len())),
        DeValue::Array(items) => items.iter().find_map(too_long),
        DeValue::Table(table) => table.values().find_map(too_long),
        _ => None,
    }
}

/// Takes the parameters of the shipped active curves out of `[activation]` (they sit flat beside
/// `curve = "..."`, and which of them apply depends on the curve, checked when the models are
/// built), each read as a number where it is written.
fn curve_parameters(activation: &mut DeValue) -> Result<Vec<(String, f64)>, toml::de::Error> {
    let DeValue::Table(table) = activation else {
        return Ok(Vec::new());
    };
    let mut found: Vec<(usize, String, f64)> = Vec::new();
    for name in crate::models::curve_parameter_names() {
        if let Some(value) = table.remove(name) {
            let at = value.span().start;
            let v = f64::deserialize(ValueDeserializer::from(value))?;
            found.push((at, name.to_string(), v));
        }
    }
    // In the order written.
    found.sort_by_key(|(at, _, _)| *at);
    Ok(found.into_iter().map(|(_, n, v)| (n, v)).collect())
}

/// One `[[study]]`: its kind, then the spec of that kind from the rest of the table.
fn study(text: &str, file: &str, item: Spanned<DeValue>) -> Result<StudySpec, SceneError> {
    let span = item.span();
    let DeValue::Table(mut table) = item.into_inner() else {
        return Err(at(
            text,
            file,
            span,
            "study",
            "a study is a table: [[study]] with kind = \"...\"",
        ));
    };
    let Some(kind) = table.remove("kind") else {
        return Err(at(
            text,
            file,
            span,
            "kind",
            &format!("every study needs kind = {}", StudyKind::names()),
        ));
    };
    let kind = StudyKind::deserialize(ValueDeserializer::from(kind))
        .map_err(|e| from_toml(text, file, &e, None))?;
    let table = Spanned::new(span, DeValue::Table(table));
    StudySpec::of_kind(kind, ValueDeserializer::from(table))
        .map_err(|e| from_toml(text, file, &e, Some(kind)))
}

/// An error about the value at `span`: its key path and line from the text.
fn at(text: &str, file: &str, span: std::ops::Range<usize>, what: &str, rule: &str) -> SceneError {
    let mut key = key_path(text, span.start);
    if !key.ends_with(what) {
        key = format!("{key}.{what}");
    }
    SceneError {
        file: file.to_string(),
        key,
        value: String::new(),
        rule: rule.to_string(),
        line: Some(line(text, span.start)),
    }
}

fn line(text: &str, offset: usize) -> usize {
    text[..offset.min(text.len())].matches('\n').count() + 1
}

/// A TOML or serde error with the key path, value and line of its span. Inside a study of
/// `kind`, a key the kind does not take is named as such, with a hint.
fn from_toml(text: &str, file: &str, e: &toml::de::Error, kind: Option<StudyKind>) -> SceneError {
    let (key, value, line) = match e.span() {
        Some(s) => {
            let v = text.get(s.clone()).unwrap_or("").trim();
            let v = if v.chars().count() > 60 {
                format!("{}…", v.chars().take(60).collect::<String>())
            } else {
                v.to_string()
            };
            (key_path(text, s.start), v, Some(line(text, s.start)))
        }
        None => ("(file)".to_string(), String::new(), None),
    };
    let unknown = e
        .message()
        .strip_prefix("unknown field `")
        .and_then(|m| m.split('`').next());
    // An unknown key inside an inline table gets the table's span: name the key itself.
    let key = match unknown {
        Some(field) if !key.ends_with(field) => format!("{key}.{field}"),
        _ => key,
    };
    // A key of the study itself (not of a table inside it).
    let of_the_study = |field: &str| {
        key.rsplit_once('.')
            .is_some_and(|(head, last)| last == field && !head.contains('.'))
    };
    // serde's list of the keys the table takes: `expected one of `a`, `b``.
    let expected: Vec<&str> = e
        .message()
        .split_once("expected one of ")
        .or_else(|| e.message().split_once("expected "))
        .map(|(_, list)| list.split('`').skip(1).step_by(2).collect())
        .unwrap_or_default();
    let suggestion = unknown
        .and_then(|field| crate::text::closest(field, &expected))
        .map_or(String::new(), |k| format!(" (did you mean `{k}`?)"));
    match (unknown, kind) {
        (Some(field), Some(kind)) if of_the_study(field) => SceneError {
            file: file.to_string(),
            key,
            value: "(given)".into(),
            rule: format!(
                "not a key of a {} study{}{suggestion}; its keys: {}",
                kind.name(),
                kind.hint(field),
                expected.join(", ")
            ),
            line,
        },
        (Some(_), _) => SceneError {
            file: file.to_string(),
            key,
            value: "(given)".into(),
            rule: format!("{}{suggestion}", e.message().trim()),
            line,
        },
        _ => SceneError {
            file: file.to_string(),
            key,
            value,
            rule: e.message().trim().to_string(),
            line,
        },
    }
}
