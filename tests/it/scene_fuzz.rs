//! Bad scene input never panics the parser and always gets a message that names a key or a line:
//! random TOML-like text, the paper scene cut at random bytes, and the paper scene with one value
//! replaced by a wrong type or an extreme number. The library's parser and validator are called
//! directly (what `activemuscle check` runs, without the process start-up).

use activemuscle::scene::{Scene, SceneError, PAPER_SCENE};
use proptest::prelude::*;

const FILE: &str = "fuzz.toml";

/// Values that break types or ranges somewhere in a scene.
const BAD_VALUES: [&str; 18] = [
    "1e308",
    "-1e308",
    "nan",
    "inf",
    "-inf",
    "0",
    "-1",
    "-0.5",
    "1e-308",
    "99999999999999999999",
    "\"text\"",
    "\"\"",
    "[]",
    "[1e308, -1e308]",
    "{}",
    "true",
    "{ from = 1e308, to = -1e308, step = 0 }",
    "[nan]",
];

/// The parse result is a valid scene or an error that says where and why.
fn well_reported(text: &str) -> Result<(), TestCaseError> {
    match Scene::parse(text, FILE) {
        Ok(scene) => {
            prop_assert!(!scene.studies.is_empty(), "a valid scene without studies");
            Ok(())
        }
        Err(e) => check_error(&e),
    }
}

fn check_error(e: &SceneError) -> Result<(), TestCaseError> {
    let shown = e.to_string();
    prop_assert!(!e.rule.trim().is_empty(), "empty rule: {shown}");
    prop_assert!(
        e.line.is_some() || (!e.key.is_empty() && e.key != "(file)"),
        "message names neither a key nor a line: {shown}"
    );
    prop_assert!(
        shown.contains(FILE),
        "message does not name the file: {shown}"
    );
    Ok(())
}

/// Byte offsets of the value after every `key = ` of the paper scene, and where it ends (before a
/// comment or the end of the line).
fn value_spans() -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = 0;
    for line in PAPER_SCENE.split_inclusive('\n') {
        let body = line.trim_start();
        if !body.starts_with('#') && !body.starts_with('[') {
            if let Some(eq) = line.find('=') {
                let from = eq + 1;
                let to = line[from..]
                    .find(" #")
                    .map_or(line.trim_end().len(), |c| from + c);
                if to > from {
                    spans.push((start + from, start + to));
                }
            }
        }
        start += line.len();
    }
    spans
}

/// Byte offsets of every number in the paper scene outside comments (inside inline tables and
/// lists too).
fn number_spans() -> Vec<(usize, usize)> {
    let mut spans = Vec::new();
    let mut start = 0;
    for line in PAPER_SCENE.split_inclusive('\n') {
        let code = line.find('#').map_or(line, |c| &line[..c]);
        let bytes = code.as_bytes();
        let mut i = 0;
        while i < bytes.len() {
            let begins = bytes[i].is_ascii_digit()
                && (i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_'));
            if begins {
                let mut j = i;
                while j < bytes.len()
                    && (bytes[j].is_ascii_digit() || matches!(bytes[j], b'.' | b'e' | b'-'))
                {
                    j += 1;
                }
                spans.push((start + i, start + j));
                i = j;
            } else {
                i += 1;
            }
        }
        start += line.len();
    }
    spans
}

fn splice(span: (usize, usize), value: &str) -> String {
    format!(
        "{} {value}{}",
        &PAPER_SCENE[..span.0],
        &PAPER_SCENE[span.1..]
    )
}

#[test]
fn the_paper_scene_is_valid_and_the_splices_find_values() {
    assert!(Scene::parse(PAPER_SCENE, FILE).is_ok());
    assert!(value_spans().len() > 60, "{}", value_spans().len());
    assert!(number_spans().len() > 60, "{}", number_spans().len());
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, ..ProptestConfig::default() })]

    #[test]
    fn random_toml_like_text_is_an_error_or_a_scene(
        text in "(\\[\\[study\\]\\]\n|\\[material\\]\n|kind = \"(fit|stability|uniaxial|cylinder)\"\n|[a-z_]{1,8} ?= ?|[0-9.e+-]{1,6}|\"[a-z ]{0,5}\"|[\\[\\]{},=\"\n #.]){0,40}"
    ) {
        well_reported(&text)?;
    }

    #[test]
    fn truncated_paper_scenes_are_an_error_or_a_scene(cut in 0usize..PAPER_SCENE.len()) {
        let mut at = cut;
        while !PAPER_SCENE.is_char_boundary(at) {
            at -= 1;
        }
        well_reported(&PAPER_SCENE[..at])?;
    }

    #[test]
    fn a_wrong_or_extreme_value_is_reported_with_its_key(
        which in 0usize..1000,
        bad in 0usize..BAD_VALUES.len(),
    ) {
        let spans = value_spans();
        let text = splice(spans[which % spans.len()], BAD_VALUES[bad]);
        well_reported(&text)?;
    }

    #[test]
    fn an_extreme_number_anywhere_is_reported_with_its_key(
        which in 0usize..1000,
        bad in 0usize..10,
    ) {
        let spans = number_spans();
        let text = splice(spans[which % spans.len()], BAD_VALUES[bad]);
        if let Err(e) = Scene::parse(&text, FILE) {
            check_error(&e)?;
            // A substituted number that breaks a rule is named by a key, not only a line.
            prop_assert!(
                !e.key.is_empty() && !e.key.starts_with('('),
                "no key in {e}"
            );
        }
    }
}
