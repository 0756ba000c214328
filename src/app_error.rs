//! The application layer's errors: [`AppError`], the one error of a run (scene, models, FE,
//! fits, outputs), with [`SceneError`] (a scene file that cannot be used: file, line, key, value,
//! rule) and [`SpecError`] (a rule a study's spec breaks, before the scene names file and line).

use std::fmt;
use std::path::PathBuf;

/// Everything a run of the application can fail with. Each variant keeps its cause; the
/// constitutive, FE and fit errors convert with `?`.
#[derive(Debug, thiserror::Error)]
pub enum AppError {
    /// The scene file cannot be used.
    #[error("invalid scene: {0}")]
    Scene(#[from] SceneError),
    /// A model cannot be built or evaluated.
    #[error(transparent)]
    Model(#[from] crate::Error),
    /// The FE solver failed for a reason that is not the material's.
    #[error(transparent)]
    Fem(#[from] crate::fem::FemError),
    /// A fit could not be set up.
    #[error(transparent)]
    Fit(#[from] crate::fit::FitError),
    /// What was being done when `source` happened (a study, a model of it).
    #[error("{context}: {source}")]
    Context {
        /// Where, e.g. `cylinder clamped: giantesio-musesti, explicit law, frozen coupling, d = 0`.
        context: String,
        /// What went wrong there.
        source: Box<AppError>,
    },
    /// A request that cannot be run as asked (e.g. a trade-off without meshes).
    #[error("{0}")]
    Invalid(String),
    /// Reading or writing a file.
    #[error("cannot {action} {}: {source}", path.display())]
    Io {
        /// What was attempted (`write`, `create the output directory`, ...).
        action: &'static str,
        /// Which file or directory.
        path: PathBuf,
        /// The operating system's reason.
        source: std::io::Error,
    },
    /// The disk filled up (or a quota, or the largest file size, was reached) while writing an
    /// output file. A run keeps what it wrote before (the data first: the CSV tables and
    /// datapackage.json, then the figures, the report last).
    #[error("no space left on the disk mounted at {disk}: writing {file}{} failed with {} free", .size.map_or(String::new(), |n| format!(" ({})", crate::text::bytes(n))), .free.map_or("an unknown amount".to_string(), crate::text::bytes))]
    DiskFull {
        /// The file that could not be written (relative to the output directory).
        file: String,
        /// Its size \[bytes\], when known.
        size: Option<u64>,
        /// The disk: its mount point, file system and device.
        disk: String,
        /// Bytes left for an unprivileged writer, when known.
        free: Option<u64>,
    },
    /// A number that would be written is NaN or infinite.
    #[error("refusing to write non-finite {quantity} = {value} ({origin})")]
    NonFinite {
        /// What it is (`P`, `fitted value`, ...).
        quantity: String,
        /// The value.
        value: f64,
        /// Where it comes from (file, study, model, stretch).
        origin: String,
    },
    /// An output file that could not be formatted or drawn.
    #[error("{file}: {message}")]
    Output {
        /// The file (or figure).
        file: String,
        /// What went wrong.
        message: String,
    },
}

impl AppError {
    /// This error, as happening in `context`.
    pub fn within(self, context: impl Into<String>) -> Self {
        AppError::Context {
            context: context.into(),
            source: Box::new(self),
        }
    }

    /// A [`AppError::DiskFull`] for a file of `bytes`; any other error as it is.
    pub fn of_size(self, bytes: u64) -> Self {
        match self {
            AppError::DiskFull {
                file, disk, free, ..
            } => AppError::DiskFull {
                file,
                size: Some(bytes),
                disk,
                free,
            },
            other => other,
        }
    }

    /// An I/O error on `path`.
    pub fn io(action: &'static str, path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        AppError::Io {
            action,
            path: path.into(),
            source,
        }
    }
}

/// `x` if finite, else [`AppError::NonFinite`] naming the quantity and where it came from.
pub fn finite(x: f64, quantity: &str, origin: impl Fn() -> String) -> Result<f64, AppError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(AppError::NonFinite {
            quantity: quantity.to_string(),
            value: x,
            origin: origin(),
        })
    }
}

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
        // An error of the whole file (it cannot be read, or TOML names no place) has no key.
        if self.key != "(file)" {
            write!(f, ": {}", self.key)?;
        }
        if !self.value.is_empty() {
            write!(f, " = {}", self.value)?;
        }
        write!(f, ": {}", self.rule)
    }
}

impl std::error::Error for SceneError {}

/// A value of a spec (a study, the material, the activation) that breaks a rule: the key
/// relative to the spec (`nr`, `meshes[1]`, `compare[0].mu`), the value and the rule. The scene
/// prefixes the key (`study[2].`) and finds its line.
#[derive(Debug, Clone, PartialEq)]
pub struct SpecError {
    /// Key relative to the spec; empty for the spec as a whole.
    pub key: String,
    /// The offending value as written (or as resolved).
    pub value: String,
    /// The rule it breaks.
    pub rule: String,
}

/// A value as a message shows it: a number written exactly and short
/// ([`crate::text::shortest`]: `1e300`, not the 301 digits of Rust's `Display`), text as it is.
pub trait Shown {
    /// The value as text.
    fn shown(&self) -> String;
}

impl Shown for f64 {
    fn shown(&self) -> String {
        crate::text::shortest(*self)
    }
}

impl Shown for str {
    fn shown(&self) -> String {
        self.to_string()
    }
}

impl Shown for String {
    fn shown(&self) -> String {
        self.clone()
    }
}

/// Integers and other values whose `Display` is short.
macro_rules! shown_by_display {
    ($($t:ty),*) => {$(
        impl Shown for $t {
            fn shown(&self) -> String {
                self.to_string()
            }
        }
    )*};
}
shown_by_display!(usize, u32, u64, i32, i64, bool, char);

impl<T: Shown + ?Sized> Shown for &T {
    fn shown(&self) -> String {
        (**self).shown()
    }
}

impl SpecError {
    /// `key = value` breaks `rule`.
    pub fn new(key: impl Into<String>, value: impl Shown, rule: impl Into<String>) -> Self {
        Self {
            key: key.into(),
            value: value.shown(),
            rule: rule.into(),
        }
    }

    /// The same error with its key inside `prefix` (`prefix.key`, or `prefix` for the whole).
    pub fn within(self, prefix: &str) -> Self {
        let key = match (prefix.is_empty(), self.key.is_empty()) {
            (true, _) => self.key,
            (false, true) => prefix.to_string(),
            (false, false) if self.key.starts_with('[') => format!("{prefix}{}", self.key),
            (false, false) => format!("{prefix}.{}", self.key),
        };
        Self { key, ..self }
    }

    /// A constitutive error of the model built from the parameters under `key`: an invalid
    /// parameter is named as `key.<parameter>`.
    pub fn model(key: &str, e: crate::Error) -> Self {
        match e {
            crate::Error::InvalidParameter { name, value, rule } => {
                Self::new(name, value, rule).within(key)
            }
            crate::Error::ActivationOutOfRange { gamma } => {
                Self::new(key, gamma, "activation gamma must lie in [0, 1)")
            }
            other => Self::new(key, "", other.to_string()),
        }
    }
}

impl fmt::Display for SpecError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.key)?;
        if !self.value.is_empty() {
            write!(f, " = {}", self.value)?;
        }
        write!(f, ": {}", self.rule)
    }
}

impl std::error::Error for SpecError {}
