//! A study kind's own table: named columns with their units, one row per computed point. The
//! kind builds it once from its result; the CSV writer ([`crate::output::csv::table_csv`]) and the
//! Python package read the same table, so the two cannot disagree.

/// The values of one column; `None` is an empty cell.
#[derive(Debug, Clone, PartialEq)]
pub enum Values {
    /// Words (a model, an approach).
    Text(Vec<Option<String>>),
    /// Numbers.
    Number(Vec<Option<f64>>),
}

impl Values {
    /// Number of rows.
    pub fn len(&self) -> usize {
        match self {
            Values::Text(v) => v.len(),
            Values::Number(v) => v.len(),
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
    /// Unit (`kPa`, `-`, `degree`; empty for words).
    pub unit: &'static str,
    /// What it holds.
    pub description: &'static str,
    /// The values.
    pub values: Values,
}

/// Columns of equal length.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Table {
    /// The columns in order.
    pub columns: Vec<Column>,
}

impl Table {
    /// A column of words.
    pub fn text(
        mut self,
        name: &'static str,
        description: &'static str,
        values: impl IntoIterator<Item = Option<String>>,
    ) -> Self {
        self.columns.push(Column {
            name,
            unit: "",
            description,
            values: Values::Text(values.into_iter().collect()),
        });
        self
    }

    /// A column of numbers in `unit`.
    pub fn number(
        mut self,
        name: &'static str,
        unit: &'static str,
        description: &'static str,
        values: impl IntoIterator<Item = Option<f64>>,
    ) -> Self {
        self.columns.push(Column {
            name,
            unit,
            description,
            values: Values::Number(values.into_iter().collect()),
        });
        self
    }

    /// Number of rows (0 without columns).
    pub fn rows(&self) -> usize {
        self.columns.first().map_or(0, |c| c.values.len())
    }
}
