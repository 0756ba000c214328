//! Scene files: what to compute, written in TOML.
//!
//! A scene names a material (`[material]`: a shipped energy and its parameters, the fibre
//! direction), the activation (`[activation]`) and a list of studies (`[[study]]`, each of a
//! kind of the registry [`crate::studies`]). Every key
//! is optional unless a study cannot do without it; defaults are the chapter's values. Unknown
//! keys, wrong types and values that break a rule are errors that name the file, the line, the
//! key path, the value and the rule ([`SceneError`]). `scenes/paper.toml` is the chapter's study
//! and documents every key; it is embedded in the binary as [`PAPER_SCENE`].
//!
//! From a file or a string to results, without a terminal:
//! [`Scene::load`] or [`Scene::parse`] → [`Scene`] (validated, every default resolved) →
//! [`Scene::run`] → [`Results`] (typed, one [`crate::studies::Outcome`] per study).

mod keypath;
mod parse;
pub mod reference;
mod resolve;
mod run;

pub use crate::app_error::SceneError;
pub use keypath::{key_path, line_of};
pub use run::{Printing, Results, RunOptions, StudyProgress};

use crate::app_error::AppError;
pub use crate::models::{ActivationSpec, ExplicitSpec};
use crate::models::{IncompressibilitySpec, MaterialSpec, ModelDefaults, Models};
use crate::studies::{Study, StudySpec};
use serde::{Deserialize, Serialize};
use std::path::Path;

/// The largest scene file \[bytes\] (the paper's is 9 kB).
pub const MAX_SCENE_BYTES: u64 = 1 << 20;
const SCENE_CAP_REASON: &str =
    "a scene is a page of settings; lists of values are written as ranges";

/// The chapter's whole study (`scenes/paper.toml`), compiled into the binary.
pub const PAPER_SCENE: &str = include_str!("../../scenes/paper.toml");

/// Name under which the embedded scene is reported.
pub const PAPER_SCENE_NAME: &str = "<embedded scenes/paper.toml>";

/// The scene file as written (and, resolved, as printed by `check`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneSpec {
    /// Free text shown in the report.
    pub title: Option<String>,
    /// The passive material and the fibre direction.
    #[serde(default)]
    pub material: MaterialSpec,
    /// Active curve, activation law, coupling and damage values shared by the studies.
    #[serde(default)]
    pub activation: ActivationSpec,
    /// Exact or near incompressibility (`[incompressibility]`; default exact).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub incompressibility: Option<IncompressibilitySpec>,
    /// The studies, in order (`[[study]]`).
    #[serde(default, rename = "study")]
    pub studies: Vec<StudySpec>,
}

/// A validated scene with every default resolved.
#[derive(Debug, Clone, PartialEq)]
pub struct Scene {
    /// File name (or the embedded scene's name).
    pub file: String,
    /// The scene text as read.
    pub source: String,
    /// Title.
    pub title: String,
    /// The material and activation every model shares.
    pub models: Models,
    /// The studies' default approach, law, coupling and damage values (`[activation]`).
    pub defaults: ModelDefaults,
    /// Studies in file order.
    pub studies: Vec<Study>,
    /// The resolved scene: every default written out (what `check` prints).
    pub resolved: SceneSpec,
}

impl Scene {
    /// Reads, validates and resolves the scene file at `path`.
    pub fn load(path: &Path) -> Result<Self, SceneError> {
        let file = path.display().to_string();
        let unreadable = |rule: String| SceneError {
            file: file.clone(),
            key: "(file)".into(),
            value: String::new(),
            rule: format!("cannot read the scene file: {rule}"),
            line: None,
        };
        let bytes = crate::user_file::read(path, MAX_SCENE_BYTES, SCENE_CAP_REASON)
            .map_err(|e| unreadable(e.to_string()))?;
        let text = String::from_utf8(bytes).map_err(|e| {
            unreadable(format!(
                "not UTF-8 text (byte {} is not valid UTF-8)",
                e.utf8_error().valid_up_to()
            ))
        })?;
        // Data files are read relative to the scene's directory as the system names it (a
        // path that is not UTF-8 is not the `file` shown in messages).
        let base = path.parent().unwrap_or(Path::new(""));
        Self::parse_in(&text, &file, base)
    }

    /// The embedded paper study.
    pub fn paper() -> Result<Self, SceneError> {
        Self::parse(PAPER_SCENE, PAPER_SCENE_NAME)
    }

    /// Validates and resolves scene `text`; `file` names it in error messages, and data files
    /// are read relative to its directory.
    pub fn parse(text: &str, file: &str) -> Result<Self, SceneError> {
        Self::parse_in(
            text,
            file,
            Path::new(file).parent().unwrap_or(Path::new("")),
        )
    }

    /// [`Self::parse`], data files read relative to the directory `base`.
    fn parse_in(text: &str, file: &str, base: &Path) -> Result<Self, SceneError> {
        let spec = parse::parse(text, file)?;
        resolve::resolve(spec, text, file, base)
    }

    /// The resolved scene as TOML, every default written out.
    pub fn resolved_toml(&self) -> Result<String, AppError> {
        toml::to_string_pretty(&self.resolved).map_err(|e| AppError::Output {
            file: "resolved scene".into(),
            message: e.to_string(),
        })
    }

    /// Runs every study, in order. A study that stops with an error does not stop the run: the
    /// error is that study's failure ([`crate::studies::Outcome::nothing`]); see
    /// [`Results::complete`].
    pub fn run(&self, options: &RunOptions) -> Results {
        run::run(self, options)
    }
}
