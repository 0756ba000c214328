//! A study kind's table: named columns, each with its type (words, numbers, counts, flags), its
//! unit and what it holds, one row per computed point. A kind builds its tables once from its
//! result ([`super::outputs::KindOutput::tables`]); the CSV writer
//! ([`crate::output::csv::table_csv`]), `datapackage.json` ([`crate::output::datapackage`]) and
//! the Python package read the same columns, so they cannot disagree.
//!
//! A kind declares its table where it builds it, one builder call per column:
//!
//! ```
//! use activemuscle::studies::table::Table;
//! let (k, sigma) = (vec![0.0, 0.5], vec![0.0, 1.25]);
//! let table = Table::default()
//!     .text("study", "the study's name", k.iter().map(|_| Some("shear".to_string())))
//!     .number("shear", "-", "amount of shear k", k.iter().map(|&k| Some(k)))
//!     .number("sigma_12", "kPa", "Cauchy shear stress σ₁₂", sigma.iter().map(|&s| Some(s)))
//!     .integer("iterations", "Newton iterations", k.iter().map(|_| Some(3)))
//!     .boolean("converged", "whether Newton converged", k.iter().map(|_| Some(true)));
//! assert_eq!(table.rows(), 2);
//! assert_eq!(table.columns[2].cell(1), "1.25");
//! assert!(table.check("shear.csv").is_ok());
//! ```

use crate::app_error::AppError;

/// The file of the curves that the uniaxial and cylinder kinds share (one table, a `study`
/// column naming each row's study).
pub const CURVES_FILE: &str = "curves.csv";

/// The values of one column, one per row; `None` is an empty cell (a value that does not apply
/// to the row).
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    /// Words (a model, an approach).
    Text(Vec<Option<String>>),
    /// Real numbers, written with the fewest digits that read back to the same f64.
    Number(Vec<Option<f64>>),
    /// Whole numbers (counts: Newton iterations, dofs, points).
    Integer(Vec<Option<i64>>),
    /// `true` or `false`.
    Boolean(Vec<Option<bool>>),
}

impl Values {
    /// Number of rows.
    pub fn len(&self) -> usize {
        match self {
            Values::Text(v) => v.len(),
            Values::Number(v) => v.len(),
            Values::Integer(v) => v.len(),
            Values::Boolean(v) => v.len(),
        }
    }

    /// Whether the column has no rows.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// One named column.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// Header name.
    pub name: &'static str,
    /// Unit of a number (`kPa`, `-` for a dimensionless one, `degree`); empty for words, counts
    /// and flags.
    pub unit: &'static str,
    /// What it holds (and what an empty cell means).
    pub description: &'static str,
    /// The values.
    pub values: Values,
}

impl Column {
    /// The text of the cell at `row` as a CSV file holds it: empty for `None`, a number in its
    /// shortest exact form ([`crate::text::shortest`]), `true`/`false`. A non-finite number
    /// has no text (see [`Table::check`]): it is written as `NaN`/`inf` only by a caller that did
    /// not check.
    pub fn cell(&self, row: usize) -> String {
        match &self.values {
            Values::Text(v) => v[row].clone().unwrap_or_default(),
            Values::Number(v) => v[row].map(crate::text::shortest).unwrap_or_default(),
            Values::Integer(v) => v[row].map(|n| n.to_string()).unwrap_or_default(),
            Values::Boolean(v) => v[row].map(|b| b.to_string()).unwrap_or_default(),
        }
    }

    /// Whether `other` has the same name, type and unit.
    fn same_kind(&self, other: &Column) -> bool {
        self.name == other.name
            && self.unit == other.unit
            && std::mem::discriminant(&self.values) == std::mem::discriminant(&other.values)
    }
}

/// The cells of a column with `text` in each of `rows` rows (the study's name, its energy).
pub fn every_row(text: &str, rows: usize) -> impl Iterator<Item = Option<String>> {
    std::iter::repeat_n(Some(text.to_string()), rows)
}

/// Columns of equal length.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// The columns in order.
    pub columns: Vec<Column>,
}

impl Table {
    fn push(
        mut self,
        name: &'static str,
        unit: &'static str,
        description: &'static str,
        values: Values,
    ) -> Self {
        self.columns.push(Column {
            name,
            unit,
            description,
            values,
        });
        self
    }

    /// A column of words (an empty word is an empty cell, `None`).
    pub fn text(
        self,
        name: &'static str,
        description: &'static str,
        values: impl IntoIterator<Item = Option<String>>,
    ) -> Self {
        let values = values.into_iter().map(|v| v.filter(|s| !s.is_empty()));
        self.push(name, "", description, Values::Text(values.collect()))
    }

    /// A column of numbers in `unit` (`-`: dimensionless).
    pub fn number(
        self,
        name: &'static str,
        unit: &'static str,
        description: &'static str,
        values: impl IntoIterator<Item = Option<f64>>,
    ) -> Self {
        self.push(
            name,
            unit,
            description,
            Values::Number(values.into_iter().collect()),
        )
    }

    /// A column of counts.
    pub fn integer(
        self,
        name: &'static str,
        description: &'static str,
        values: impl IntoIterator<Item = Option<i64>>,
    ) -> Self {
        self.push(
            name,
            "",
            description,
            Values::Integer(values.into_iter().collect()),
        )
    }

    /// A column of `true`/`false`.
    pub fn boolean(
        self,
        name: &'static str,
        description: &'static str,
        values: impl IntoIterator<Item = Option<bool>>,
    ) -> Self {
        self.push(
            name,
            "",
            description,
            Values::Boolean(values.into_iter().collect()),
        )
    }

    /// Number of rows (0 without columns).
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, |c| c.values.len())
    }

    /// The header: the columns' names in order.
    pub fn names(&self) -> Vec<&'static str> {
        self.columns.iter().map(|c| c.name).collect()
    }

    /// Whether `other` has the same columns (names, types and units, in order): two tables that
    /// may share a file.
    pub fn same_columns(&self, other: &Table) -> bool {
        self.columns.len() == other.columns.len()
            && self
                .columns
                .iter()
                .zip(&other.columns)
                .all(|(a, b)| a.same_kind(b))
    }

    /// That the table can be written: every column as long as the first, every number finite.
    /// A non-finite number is [`AppError::NonFinite`] naming its column, `origin` (the file or
    /// the study) and the row: its number and the cells to the left of the offending one.
    pub fn check(&self, origin: &str) -> Result<(), AppError> {
        self.check_from(origin, 0)
    }

    /// [`Self::check`] of a table whose rows follow `before` rows of its file (rows numbered in
    /// the file, from 1 after the header).
    pub fn check_from(&self, origin: &str, before: usize) -> Result<(), AppError> {
        let rows = self.rows();
        for c in &self.columns {
            if c.values.len() != rows {
                return Err(AppError::Output {
                    file: origin.to_string(),
                    message: format!(
                        "column {} has {} rows where the table has {rows}",
                        c.name,
                        c.values.len()
                    ),
                });
            }
        }
        for (j, c) in self.columns.iter().enumerate() {
            let Values::Number(v) = &c.values else {
                continue;
            };
            if let Some((row, x)) = v
                .iter()
                .enumerate()
                .find_map(|(i, x)| x.filter(|x| !x.is_finite()).map(|x| (i, x)))
            {
                return Err(AppError::NonFinite {
                    quantity: c.name.to_string(),
                    value: x,
                    origin: format!(
                        "{origin}, row {}: {}",
                        before + row + 1,
                        self.row_words(row, j)
                    ),
                });
            }
        }
        Ok(())
    }

    /// The non-empty cells of `row` left of column `before`, `name = text`, `, `-separated.
    fn row_words(&self, row: usize, before: usize) -> String {
        self.columns[..before]
            .iter()
            .map(|c| (c.name, c.cell(row)))
            .filter(|(_, text)| !text.is_empty())
            .map(|(name, text)| format!("{name} = {text}"))
            .collect::<Vec<_>>()
            .join(", ")
    }
}
