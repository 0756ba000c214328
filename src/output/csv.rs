//! `curves.csv`: one row per computed point, long ("tidy") form.
//!
//! Columns: `model, direction, bases, energy, law, coupling, d, lambda, gamma, P, P_pas, P_act,
//! newton_iterations`. A cell that does not apply is empty, never `NaN`; a non-finite number is
//! an error naming the quantity and the row.

use super::atomic::OutputError;
use crate::scene::run::Row;

/// The header of `curves.csv`.
pub const COLUMNS: [&str; 13] = [
    "model",
    "direction",
    "bases",
    "energy",
    "law",
    "coupling",
    "d",
    "lambda",
    "gamma",
    "P",
    "P_pas",
    "P_act",
    "newton_iterations",
];

fn number(x: f64, quantity: &str, row: &Row) -> Result<String, OutputError> {
    if x.is_finite() {
        Ok(x.to_string())
    } else {
        Err(OutputError(format!(
            "refusing to write non-finite {quantity} = {x} ({} {} {}, d = {:?}, lambda = {})",
            row.model, row.energy, row.law, row.d, row.lambda
        )))
    }
}

fn optional(x: Option<f64>, quantity: &str, row: &Row) -> Result<String, OutputError> {
    x.map_or(Ok(String::new()), |v| number(v, quantity, row))
}

/// The CSV text of `rows`.
pub fn to_csv(rows: &[Row]) -> Result<Vec<u8>, OutputError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = |e: csv::Error| OutputError(format!("CSV: {e}"));
    w.write_record(COLUMNS).map_err(fail)?;
    for r in rows {
        let record = [
            r.model.to_string(),
            r.direction.unwrap_or("").to_string(),
            r.bases.unwrap_or("").to_string(),
            r.energy.clone(),
            r.law.to_string(),
            r.coupling.unwrap_or("").to_string(),
            optional(r.d, "d", r)?,
            number(r.lambda, "lambda", r)?,
            optional(r.gamma, "gamma", r)?,
            number(r.p, "P", r)?,
            optional(r.p_pas, "P_pas", r)?,
            optional(r.p_act, "P_act", r)?,
            r.newton_iterations
                .map(|n| n.to_string())
                .unwrap_or_default(),
        ];
        w.write_record(&record).map_err(fail)?;
    }
    w.into_inner()
        .map_err(|e| OutputError(format!("CSV: {}", e.error())))
}
