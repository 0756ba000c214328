//! What a formula energy refuses: the key it is about, the value as written and the rule.

use thiserror::Error;

/// A formula or a parameter declaration that cannot be used: which key (relative to the energy's
/// table: `W`, `parameters.mu`, `parameters.mu.range`), the offending value as written (a piece
/// of the formula, a number) and the rule it breaks, with where in the formula and what to write
/// instead. A scene prefixes the key (`material.W`) and finds its line; Python names the keyword.
#[derive(Debug, Clone, PartialEq, Error)]
#[error("{key} = {value}: {rule}")]
pub struct FormulaError {
    /// The key, relative to the energy's table.
    pub key: String,
    /// The offending value as written.
    pub value: String,
    /// The rule it breaks.
    pub rule: String,
}

impl FormulaError {
    /// An error about the formula `W` itself.
    pub(crate) fn formula(value: impl Into<String>, rule: impl Into<String>) -> Self {
        Self {
            key: "W".into(),
            value: value.into(),
            rule: rule.into(),
        }
    }

    /// An error about the declaration of parameter `name` (`field`: `""` for the parameter as a
    /// whole, or `value`, `range`, `bounds`, ...).
    pub(crate) fn parameter(
        name: &str,
        field: &str,
        value: impl Into<String>,
        rule: impl Into<String>,
    ) -> Self {
        let key = if field.is_empty() {
            format!("parameters.{name}")
        } else {
            format!("parameters.{name}.{field}")
        };
        Self {
            key,
            value: value.into(),
            rule: rule.into(),
        }
    }
}
