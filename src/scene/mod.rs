//! Scene files: what to compute, written in TOML.
//!
//! A scene names a material (`[material]`), the activation (`[activation]`) and a list of studies
//! (`[[study]]`, kind `uniaxial`, `cylinder`, `fit`, `stability` or `tradeoff`). Every key is optional unless a study cannot do
//! without it; defaults are the chapter's values (Tables D:parpass, D:paratt; a = 1.0133,
//! b = 0.2050). Unknown keys, wrong types and values that break a rule are errors that name the
//! file, the key path, the value and the rule ([`SceneError`]). `scenes/paper.toml` is the
//! chapter's study and documents every key; it is embedded in the binary as [`PAPER_SCENE`].
//!
//! [`Scene::parse`] validates and resolves a file into a [`Scene`]; [`run`] computes its studies.

pub mod fit;
mod keypath;
mod resolve;
pub mod run;
pub mod schema;
pub mod stability;
pub mod tradeoff;

pub use fit::{FitCase, FitOutcome, FitStudy};
pub use keypath::{key_path, line_of};
pub use resolve::{CylinderStudy, ModelChoice, Scene, Study, UniaxialStudy};
pub use stability::{StabilityCurve, StabilityPoint, StabilityStudy};
pub use tradeoff::TradeoffStudy;

use std::fmt;
use std::path::Path;

/// The chapter's whole study (`scenes/paper.toml`), compiled into the binary.
pub const PAPER_SCENE: &str = include_str!("../../scenes/paper.toml");

/// Name under which the embedded scene is reported.
pub const PAPER_SCENE_NAME: &str = "<embedded scenes/paper.toml>";

/// A scene that cannot be used: which file, which key, which value, which rule.
#[derive(Debug, Clone, PartialEq)]
pub struct SceneError {
    /// The scene file (path as given, or the embedded scene's name).
    pub file: String,
    /// Dotted key path (`study[1].nr`), or `(file)` for errors about the file as a whole.
    pub key: String,
    /// The offending value as written (or as resolved).
    pub value: String,
    /// The rule it breaks.
    pub rule: String,
    /// Line in the file (1-based), when known.
    pub line: Option<usize>,
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file)?;
        if let Some(l) = self.line {
            write!(f, ":{l}")?;
        }
        write!(f, ": {}", self.key)?;
        if !self.value.is_empty() {
            write!(f, " = {}", self.value)?;
        }
        write!(f, ": {}", self.rule)
    }
}

impl std::error::Error for SceneError {}

impl Scene {
    /// Reads, validates and resolves the scene file at `path`.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let file = path.display().to_string();
        let text = std::fs::read_to_string(path).map_err(|e| SceneError {
            file: file.clone(),
            key: "(file)".into(),
            value: String::new(),
            rule: format!("cannot read the scene file: {e}"),
            line: None,
        })?;
        Self::parse(&text, &file)
    }

    /// The embedded paper study.
    pub fn paper() -> Result<Self, SceneError> {
        Self::parse(PAPER_SCENE, PAPER_SCENE_NAME)
    }

    /// Validates and resolves scene `text`; `file` names it in error messages.
    pub fn parse(text: &str, file: &str) -> Result<Self, SceneError> {
        let raw: schema::SceneFile = toml::from_str(text).map_err(|e| {
            let span = e.span();
            let (key, value, line) = match &span {
                Some(s) => {
                    let v = text.get(s.clone()).unwrap_or("").trim();
                    let v = if v.chars().count() > 60 {
                        format!("{}…", v.chars().take(60).collect::<String>())
                    } else {
                        v.to_string()
                    };
                    let line = text[..s.start.min(text.len())].matches('\n').count() + 1;
                    (key_path(text, s.start), v, Some(line))
                }
                None => ("(file)".to_string(), String::new(), None),
            };
            // An unknown key inside an inline table gets the table's span: name the key itself.
            let key = match e
                .message()
                .strip_prefix("unknown field `")
                .and_then(|m| m.split('`').next())
            {
                Some(field) if !key.ends_with(field) => format!("{key}.{field}"),
                _ => key,
            };
            SceneError {
                file: file.to_string(),
                key,
                value,
                rule: e.message().trim().to_string(),
                line,
            }
        })?;
        // Validation knows the key; the line is where the text writes it (or what encloses it).
        resolve::resolve(raw, text, file).map_err(|e| SceneError {
            line: e.line.or_else(|| keypath::line_of(text, &e.key)),
            ..e
        })
    }
}
