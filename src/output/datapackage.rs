//! `datapackage.json` beside the CSV files: a [Frictionless data package] that says, for every
//! column of every table a run wrote, its name, its type, its unit and what it holds. A reader
//! (`frictionless validate datapackage.json`, pandas with the schema, a person) learns the units
//! from it; the CSV headers stay plain names (`P`, not `P [kPa]`), so that scripts indexing by
//! column name keep working.
//!
//! [Frictionless data package]: https://specs.frictionlessdata.io/data-package/

use crate::app_error::AppError;
use crate::studies::table::{Table, Values};
use serde_json::{json, Value};

/// The Frictionless type of a column's cells.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FieldType {
    /// Words.
    String,
    /// A real number, written with the fewest digits that read back to the same f64.
    Number,
    /// A whole number (counts: Newton iterations, dofs, points).
    Integer,
    /// `true` or `false`.
    Boolean,
}

impl FieldType {
    /// The name the Frictionless table schema uses.
    pub const fn name(self) -> &'static str {
        match self {
            FieldType::String => "string",
            FieldType::Number => "number",
            FieldType::Integer => "integer",
            FieldType::Boolean => "boolean",
        }
    }
}

/// One column of a CSV file: its header name, type, unit and meaning.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Field {
    /// The header name.
    pub name: &'static str,
    /// The type of its cells.
    pub kind: FieldType,
    /// The unit of a number (`kPa`, `s`, `-` for a dimensionless one); empty for words, counts
    /// and flags.
    pub unit: &'static str,
    /// What it holds.
    pub description: &'static str,
}

/// The fields of a study kind's table ([`Table`]): its columns' names, types, units and
/// descriptions.
pub fn table_fields(table: &Table) -> Vec<Field> {
    table
        .columns
        .iter()
        .map(|c| Field {
            name: c.name,
            kind: match c.values {
                Values::Text(_) => FieldType::String,
                Values::Number(_) => FieldType::Number,
                Values::Integer(_) => FieldType::Integer,
                Values::Boolean(_) => FieldType::Boolean,
            },
            unit: c.unit,
            description: c.description,
        })
        .collect()
}

/// A CSV file of a run and the schema of its columns.
#[derive(Debug, Clone, PartialEq)]
pub struct Resource {
    /// The file name, relative to the output directory.
    pub path: String,
    /// What one row is.
    pub description: String,
    /// Its columns, in the file's order.
    pub fields: Vec<Field>,
}

/// A Frictionless resource name, `[a-z0-9._-]`: the file's stem in lower case; a stem with other
/// characters (a Unicode study name) has them as `-` and its index appended, to stay unique.
fn resource_name(path: &str, index: usize) -> String {
    let stem = path.strip_suffix(".csv").unwrap_or(path);
    let name: String = stem
        .chars()
        .map(|c| match c.to_ascii_lowercase() {
            c @ ('a'..='z' | '0'..='9' | '.' | '_' | '-') => c,
            _ => '-',
        })
        .collect();
    if name == stem.to_ascii_lowercase() {
        name
    } else {
        format!("{name}-{index}")
    }
}

/// The text of `datapackage.json` for `resources`, titled `title`. An empty cell is a missing
/// value (`missingValues: [""]`), as in every table activemuscle writes.
pub fn descriptor(title: &str, resources: &[Resource]) -> Result<Vec<u8>, AppError> {
    let resources: Vec<Value> = resources
        .iter()
        .enumerate()
        .map(|(i, r)| {
            let fields: Vec<Value> = r
                .fields
                .iter()
                .map(|f| {
                    let mut field = json!({
                        "name": f.name,
                        "type": f.kind.name(),
                        "description": f.description,
                    });
                    if !f.unit.is_empty() {
                        field["unit"] = json!(f.unit);
                    }
                    field
                })
                .collect();
            json!({
                "name": resource_name(&r.path, i),
                "path": r.path,
                "profile": "tabular-data-resource",
                "format": "csv",
                "mediatype": "text/csv",
                "encoding": "utf-8",
                "description": r.description,
                "schema": { "fields": fields, "missingValues": [""] },
            })
        })
        .collect();
    let package = json!({
        "name": "activemuscle-run",
        "title": title,
        "profile": "tabular-data-package",
        "description": "Tables written by activemuscle; every column's type and unit in its schema (kPa for stresses, - for dimensionless numbers).",
        "resources": resources,
    });
    serde_json::to_vec_pretty(&package).map_err(|e| AppError::Output {
        file: "datapackage.json".into(),
        message: e.to_string(),
    })
}
