//! `curves.csv`: one row per computed point, long ("tidy") form.
//!
//! Columns: `model, direction, bases, energy, law, coupling, d, lambda, gamma, P, P_pas, P_act,
//! newton_iterations`. A cell that does not apply is empty, never `NaN`; a non-finite number is
//! an error naming the quantity and the row.

use super::atomic::OutputError;
use crate::scene::run::{Results, Row};
use crate::scene::{FitOutcome, StabilityCurve};

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

/// The header of `fits.csv`: one row per fitted parameter.
pub const FIT_COLUMNS: [&str; 14] = [
    "study",
    "fit",
    "case",
    "parameter",
    "value",
    "standard_error",
    "reference",
    "correlation",
    "converged",
    "rms",
    "rms_unit",
    "residual_norm",
    "iterations",
    "points",
];

/// The header of `stability.csv`: one row per model and stretch.
pub const STABILITY_COLUMNS: [&str; 11] = [
    "study",
    "law",
    "coupling",
    "d",
    "lambda",
    "P",
    "dP_dlambda",
    "ellipticity_min",
    "ellipticity_relative",
    "strongly_elliptic",
    "softening",
];

/// `x` as text if finite, else an error naming the quantity and where it came from.
pub fn finite(x: f64, quantity: &str, origin: impl Fn() -> String) -> Result<String, OutputError> {
    checked(x, quantity, origin).map(|x| x.to_string())
}

/// `x` if finite, else an error naming the quantity and where it came from.
pub fn checked(x: f64, quantity: &str, origin: impl Fn() -> String) -> Result<f64, OutputError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(OutputError(format!(
            "refusing to write non-finite {quantity} = {x} ({})",
            origin()
        )))
    }
}

/// `fits.csv` of the fits, converged or not.
pub fn fits_csv(fits: &[FitOutcome]) -> Result<Vec<u8>, OutputError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = |e: csv::Error| OutputError(format!("fits.csv: {e}"));
    w.write_record(FIT_COLUMNS).map_err(fail)?;
    for f in fits {
        for (j, name) in f.names.iter().enumerate() {
            let origin = || {
                format!(
                    "fits.csv: study {:?}, {}, parameter {name}",
                    f.study_name, f.case
                )
            };
            let opt =
                |x: Option<f64>, q: &str| x.map_or(Ok(String::new()), |v| finite(v, q, origin));
            let correlation = f.correlation.get(j).map_or(Ok(String::new()), |row| {
                row.iter()
                    .zip(&f.names)
                    .map(|(c, other)| Ok(format!("{other}:{}", opt(*c, "correlation")?)))
                    .collect::<Result<Vec<_>, OutputError>>()
                    .map(|v| v.join(";"))
            })?;
            w.write_record([
                f.study_name.clone(),
                f.fit.to_string(),
                f.case.clone(),
                name.clone(),
                finite(f.values[j], "fitted value", origin)?,
                opt(
                    f.standard_errors.get(j).copied().flatten(),
                    "standard error",
                )?,
                opt(f.reference.get(j).copied().flatten(), "reference value")?,
                correlation,
                f.converged.to_string(),
                finite(f.rms, "RMS error", origin)?,
                f.unit.to_string(),
                finite(f.residual_norm, "residual norm", origin)?,
                f.iterations.to_string(),
                f.points.to_string(),
            ])
            .map_err(fail)?;
        }
    }
    w.into_inner()
        .map_err(|e| OutputError(format!("fits.csv: {}", e.error())))
}

/// `stability.csv` of the stability curves.
pub fn stability_csv(curves: &[StabilityCurve], names: &[String]) -> Result<Vec<u8>, OutputError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = |e: csv::Error| OutputError(format!("stability.csv: {e}"));
    w.write_record(STABILITY_COLUMNS).map_err(fail)?;
    for c in curves {
        let study = names.get(c.study).cloned().unwrap_or_default();
        for p in &c.points {
            let origin = || {
                format!(
                    "stability.csv: study {study:?}, {}, d = {:?}, lambda = {}",
                    c.label(),
                    c.d,
                    p.lambda
                )
            };
            w.write_record([
                study.clone(),
                c.law.to_string(),
                c.coupling.unwrap_or("").to_string(),
                c.d.map_or(Ok(String::new()), |d| finite(d, "d", origin))?,
                finite(p.lambda, "lambda", origin)?,
                finite(p.stress, "P", origin)?,
                finite(p.slope, "dP/dlambda", origin)?,
                finite(p.least, "ellipticity minimum", origin)?,
                finite(p.relative, "relative ellipticity", origin)?,
                p.elliptic.to_string(),
                (p.slope < 0.0).to_string(),
            ])
            .map_err(fail)?;
        }
    }
    w.into_inner()
        .map_err(|e| OutputError(format!("stability.csv: {}", e.error())))
}

/// The extra tables a run has data for: `fits.csv`, `stability.csv`.
pub fn tables(results: &Results) -> Result<Vec<(&'static str, Vec<u8>)>, OutputError> {
    let mut out = Vec::new();
    if !results.fits.is_empty() {
        out.push(("fits.csv", fits_csv(&results.fits)?));
    }
    if !results.stability.is_empty() {
        let names: Vec<String> = results.studies.iter().map(|s| s.name.clone()).collect();
        out.push(("stability.csv", stability_csv(&results.stability, &names)?));
    }
    Ok(out)
}
