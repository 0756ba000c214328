//! The tables of a run, projected from its typed results for writing.
//!
//! `curves.csv`: one row per computed point, long ("tidy") form, columns [`COLUMNS`]. A cell that
//! does not apply is empty, never `NaN`; a non-finite number is an error naming the quantity and
//! the row. `fits.csv`: one row per fitted parameter, its correlations with the other parameters
//! in one readable cell (`w0: 0.99988`). `stability.csv`: one row per model and stretch.
//! `history.csv`: one row per activation-in-time model and time step.

use super::datapackage::{names, table_fields, Field, Resource};
use crate::app_error::{finite, AppError};
use crate::scene::Results;
use crate::studies::curves::{sweep_row, uniaxial_row, Row};
use crate::studies::cylinder::CylinderResult;
use crate::studies::fit::{correlations, FitOutcome};
use crate::studies::history::HistoryResult;
use crate::studies::outputs::OwnTable;
use crate::studies::stability::StabilityCurve;
use crate::studies::table::{Table, Values};
use crate::studies::StudyResult;

/// The columns of `curves.csv`.
pub const CURVE_FIELDS: [Field; 20] = [
    Field::text("study", "the study's name"),
    Field::text("model", "uniaxial (homogeneous 0D tension) or cylinder (axisymmetric FE)"),
    Field::text("direction", "along or across the fibres (uniaxial rows)"),
    Field::text("bases", "sliding or clamped (cylinder rows)"),
    Field::text("energy", "the strain energy's name"),
    Field::text("law", "passive, constant, implicit, explicit or energy"),
    Field::text("coupling", "frozen or consistent (active rows)"),
    Field::number("d", "-", "damage d (active rows); in a cylinder with regions, the body's outside its regions (see regions)"),
    Field::number("lambda", "-", "stretch λ along the loading (cylinder: the imposed L/L₀)"),
    Field::number("gamma", "-", "γ at the point (uniaxial), at the quadrature point nearest the centre (cylinder)"),
    Field::number("P", "kPa", "nominal (first Piola–Kirchhoff) stress along the stretch; cylinder: axial reaction / πR²"),
    Field::number("P_pas", "kPa", "passive stress of the material at λ (active uniaxial rows along the fibres)"),
    Field::number("P_act", "kPa", "target active stress (1 − d) P_act(λ) (same rows)"),
    Field::count("newton_iterations", "Newton iterations from the previous stretch to this one (cylinder rows)"),
    Field::number("cauchy", "kPa", "Cauchy stress along the stretch, σ = J⁻¹ P Fᵀ (uniaxial rows)"),
    Field::number("J", "-", "volume ratio (uniaxial rows of a nearly incompressible scene; empty: J = 1)"),
    Field::number("P_0d", "kPa", "homogeneous uniaxial (0D) stress of the same model at λ (cylinder rows; with regions, the uniform model's at d)"),
    Field::count("dofs", "free degrees of freedom of the FE solve (cylinder rows)"),
    Field::text("element", "finite element, Q2/Q1 or Q1/P0 (cylinder rows)"),
    Field::text("regions", "the cylinder's regions with their own damage or activation, '; '-separated (empty: a uniform body)"),
];

/// The header of `curves.csv`.
pub const COLUMNS: [&str; 20] = names(&CURVE_FIELDS);

/// The rows of `curves.csv`, in study order.
pub fn rows(results: &Results) -> Vec<Row<'_>> {
    let mut rows = Vec::new();
    for s in &results.studies {
        let study = s.name.as_str();
        match &s.result {
            StudyResult::Uniaxial(u) => {
                for c in &u.curves {
                    rows.extend(
                        c.points
                            .iter()
                            .map(|p| uniaxial_row(study, u.direction, c, p)),
                    );
                }
            }
            StudyResult::Cylinder(c) => {
                for sweep in &c.sweeps {
                    rows.extend(sweep.points.iter().map(|p| sweep_row(study, c, sweep, p)));
                }
            }
            _ => {}
        }
    }
    rows
}

fn number(x: f64, quantity: &str, row: &Row) -> Result<String, AppError> {
    finite(x, quantity, || {
        format!(
            "study {:?}: {} {} {}, d = {:?}, lambda = {}",
            row.study, row.model, row.energy, row.law, row.d, row.lambda
        )
    })
    .map(shortest)
}

fn optional(x: Option<f64>, quantity: &str, row: &Row) -> Result<String, AppError> {
    x.map_or(Ok(String::new()), |v| number(v, quantity, row))
}

fn csv_error(file: &str) -> impl Fn(csv::Error) -> AppError + '_ {
    move |e| AppError::Output {
        file: file.to_string(),
        message: e.to_string(),
    }
}

fn finish(w: csv::Writer<Vec<u8>>, file: &str) -> Result<Vec<u8>, AppError> {
    w.into_inner().map_err(|e| AppError::Output {
        file: file.to_string(),
        message: e.error().to_string(),
    })
}

/// The CSV text of `rows`.
pub fn to_csv(rows: &[Row]) -> Result<Vec<u8>, AppError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = csv_error("curves.csv");
    w.write_record(COLUMNS).map_err(&fail)?;
    for r in rows {
        let record = [
            r.study.to_string(),
            r.model.to_string(),
            r.direction.unwrap_or("").to_string(),
            r.bases.unwrap_or("").to_string(),
            r.energy.to_string(),
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
            optional(r.cauchy, "cauchy", r)?,
            optional(r.volume, "J", r)?,
            optional(r.p_0d, "P_0d", r)?,
            r.dofs.map(|n| n.to_string()).unwrap_or_default(),
            r.element.unwrap_or("").to_string(),
            r.regions.clone().unwrap_or_default(),
        ];
        w.write_record(&record).map_err(&fail)?;
    }
    finish(w, "curves.csv")
}

/// The columns of `fits.csv`: one row per fitted parameter.
pub const FIT_FIELDS: [Field; 16] = [
    Field::text("study", "the study's name"),
    Field::text("fit", "what was fitted (the fit kind)"),
    Field::text("case", "the data set or case fitted"),
    Field::text("parameter", "the fitted parameter's name"),
    Field::number("value", "the parameter's unit", "fitted value, in the parameter's own unit (kPa for moduli and stresses, - for exponents and fractions)"),
    Field::number("standard_error", "the parameter's unit", "standard error of the value from the Jacobian at the optimum (empty: not estimable)"),
    Field::number("reference", "the parameter's unit", "the chapter's (or the scene's) value for comparison (empty: none)"),
    Field::text("correlation", "correlations with the other parameters, 'name: value; …' (n/a: not estimable)"),
    Field::flag("converged", "whether the least-squares solver met its tolerance"),
    Field::number("rms", "see rms_unit", "root-mean-square residual of the fit"),
    Field::text("rms_unit", "the unit of rms (kPa for stresses)"),
    Field::number("residual_norm", "see rms_unit", "Euclidean norm of the residual vector"),
    Field::count("iterations", "iterations of the least-squares solver"),
    Field::count("points", "data points fitted"),
    Field::number("at_bound", "the parameter's unit", "the bound the parameter is held at, the least-squares minimum lying beyond it (empty: estimated inside its bounds)"),
    Field::text("weights", "how the residuals were weighted: equal, relative (to the datum) or sigma (each datum's standard deviation)"),
];

/// The header of `fits.csv`.
pub const FIT_COLUMNS: [&str; 16] = names(&FIT_FIELDS);

/// The columns of `stability.csv`: one row per model and stretch.
pub const STABILITY_FIELDS: [Field; 12] = [
    Field::text("study", "the study's name"),
    Field::text("law", "passive, implicit, explicit or energy"),
    Field::text("coupling", "frozen or consistent (active rows)"),
    Field::number("d", "-", "damage d (active rows)"),
    Field::number(
        "lambda",
        "-",
        "stretch λ of homogeneous uniaxial tension along the fibres",
    ),
    Field::number("P", "kPa", "nominal stress"),
    Field::number("dP_dlambda", "kPa", "slope of the nominal stress, dP/dλ"),
    Field::number(
        "ellipticity_min",
        "kPa",
        "min a·Q(N)a of the acoustic tensor over the sampled normals (strong ellipticity: > 0)",
    ),
    Field::number(
        "ellipticity_relative",
        "-",
        "ellipticity_min relative to the tangent's norm",
    ),
    Field::flag("strongly_elliptic", "whether ellipticity_relative > −1e-12"),
    Field::flag("softening", "whether dP/dλ < 0"),
    Field::number("cauchy", "kPa", "Cauchy stress along the stretch"),
];

/// The header of `stability.csv`.
pub const STABILITY_COLUMNS: [&str; 12] = names(&STABILITY_FIELDS);

/// `x` as text if finite, else an error naming the quantity and where it came from.
fn text(x: f64, quantity: &str, origin: impl Fn() -> String) -> Result<String, AppError> {
    finite(x, quantity, origin).map(shortest)
}

/// `x` with the fewest digits that read back to the same f64: [`crate::text::shortest`].
pub fn shortest(x: f64) -> String {
    crate::text::shortest(x)
}

/// `fits.csv` of the fits of each study (name, fits), converged or not.
pub fn fits_csv(studies: &[(&str, &[FitOutcome])]) -> Result<Vec<u8>, AppError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = csv_error("fits.csv");
    w.write_record(FIT_COLUMNS).map_err(&fail)?;
    for &(study, fits) in studies {
        for f in fits {
            for (j, name) in f.names.iter().enumerate() {
                let origin = || format!("fits.csv: study {study:?}, {}, parameter {name}", f.case);
                let opt =
                    |x: Option<f64>, q: &str| x.map_or(Ok(String::new()), |v| text(v, q, origin));
                let correlation = f.correlation.get(j).map_or(Ok(String::new()), |row| {
                    correlations(row, &f.names, j, |c| {
                        finite(c, "correlation", origin).map(|c| format!("{c:.5}"))
                    })
                })?;
                w.write_record([
                    study.to_string(),
                    f.kind.name().to_string(),
                    f.case.clone(),
                    name.clone(),
                    text(f.values[j], "fitted value", origin)?,
                    opt(
                        f.standard_errors.get(j).copied().flatten(),
                        "standard error",
                    )?,
                    opt(f.reference.get(j).copied().flatten(), "reference value")?,
                    correlation,
                    f.converged.to_string(),
                    text(f.rms, "RMS error", origin)?,
                    f.unit.to_string(),
                    text(f.residual_norm, "residual norm", origin)?,
                    f.iterations.to_string(),
                    f.points.to_string(),
                    opt(
                        f.at_bound.get(j).copied().flatten().map(|b| b.bound),
                        "bound",
                    )?,
                    f.weights.name().to_string(),
                ])
                .map_err(&fail)?;
            }
        }
    }
    finish(w, "fits.csv")
}

/// `stability.csv` of the stability curves of each study (name, curves).
pub fn stability_csv(studies: &[(&str, &[StabilityCurve])]) -> Result<Vec<u8>, AppError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = csv_error("stability.csv");
    w.write_record(STABILITY_COLUMNS).map_err(&fail)?;
    for &(study, curves) in studies {
        for c in curves {
            for p in &c.points {
                let origin = || {
                    format!(
                        "stability.csv: study {study:?}, {}, d = {:?}, lambda = {}",
                        c.label(),
                        c.damage(),
                        p.lambda
                    )
                };
                w.write_record([
                    study.to_string(),
                    c.model.map_or("passive", |m| m.law.name()).to_string(),
                    c.model.map_or("", |m| m.coupling.name()).to_string(),
                    c.damage()
                        .map_or(Ok(String::new()), |d| text(d, "d", origin))?,
                    text(p.lambda, "lambda", origin)?,
                    text(p.stress, "P", origin)?,
                    text(p.slope, "dP/dlambda", origin)?,
                    text(p.least, "ellipticity minimum", origin)?,
                    text(p.relative, "relative ellipticity", origin)?,
                    p.elliptic.to_string(),
                    (p.slope < 0.0).to_string(),
                    text(p.cauchy, "cauchy", origin)?,
                ])
                .map_err(&fail)?;
            }
        }
    }
    finish(w, "stability.csv")
}

/// The columns of `history.csv`: one row per activation-in-time study, model and time step.
pub const HISTORY_FIELDS: [Field; 16] = [
    Field::text("study", "the study's name"),
    Field::text(
        "loading",
        "prescribed (the stretch as scheduled) or free (no load)",
    ),
    Field::text("energy", "the strain energy's name"),
    Field::text("law", "implicit, explicit or energy"),
    Field::text("coupling", "frozen or consistent"),
    Field::number("d", "-", "damage d"),
    Field::number("t", "s", "time"),
    Field::number("a_schedule", "-", "the activation schedule at t"),
    Field::number("a", "-", "the activation level used at t"),
    Field::number("lambda", "-", "stretch λ"),
    Field::number("gamma", "-", "γ"),
    Field::number("P", "kPa", "nominal stress along the stretch"),
    Field::number("cauchy", "kPa", "Cauchy stress σ₁₁ = P λ / J"),
    Field::number("J", "-", "volume ratio"),
    Field::number("P_pas", "kPa", "passive stress at λ"),
    Field::number("P_act", "kPa", "target active stress (1 − d) a P_act(λ)"),
];

/// The header of `history.csv`.
pub const HISTORY_COLUMNS: [&str; 16] = names(&HISTORY_FIELDS);

/// `history.csv` of the activation-in-time studies (name, result): t [s], the schedule a_s and
/// the activation level a [-], λ, γ [-], P, the Cauchy stress σ₁₁, the volume ratio J [-],
/// P_pas and the target (1 − d)·a·P_act(λ) \[kPa\].
pub fn history_csv(studies: &[(&str, &HistoryResult)]) -> Result<Vec<u8>, AppError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = csv_error("history.csv");
    w.write_record(HISTORY_COLUMNS).map_err(&fail)?;
    for &(study, r) in studies {
        for h in &r.histories {
            let m = h.model;
            for p in &h.points {
                let origin = || {
                    format!(
                        "history.csv: study {study:?}, d = {}, t = {} s",
                        m.damage, p.t
                    )
                };
                w.write_record([
                    study.to_string(),
                    r.loading.to_string(),
                    r.energy.clone(),
                    m.law.name().to_string(),
                    m.coupling.name().to_string(),
                    text(m.damage, "d", origin)?,
                    text(p.t, "t", origin)?,
                    text(p.schedule, "a_schedule", origin)?,
                    text(p.level, "a", origin)?,
                    text(p.lambda, "lambda", origin)?,
                    text(p.gamma, "gamma", origin)?,
                    text(p.stress, "P", origin)?,
                    text(p.cauchy, "cauchy", origin)?,
                    text(p.volume, "J", origin)?,
                    text(p.passive, "P_pas", origin)?,
                    text(p.active_target, "P_act", origin)?,
                ])
                .map_err(&fail)?;
            }
        }
    }
    finish(w, "history.csv")
}

/// The columns of a cylinder study's `points_<study>.csv`.
pub const POINT_FIELDS: [Field; 10] = [
    Field::text("study", "the study's name"),
    Field::text("point", "the point's name ([study.points])"),
    Field::number("r", "the mesh's length unit", "reference radial position"),
    Field::number("z", "the mesh's length unit", "reference axial position"),
    Field::text("law", "implicit, explicit or energy"),
    Field::text("coupling", "frozen or consistent"),
    Field::number("d", "-", "damage d"),
    Field::number("lambda", "-", "imposed stretch L/L₀"),
    Field::number("u_r", "the mesh's length unit", "radial displacement"),
    Field::number("u_z", "the mesh's length unit", "axial displacement"),
];

/// The header of a `points_<study>.csv`.
pub const POINT_COLUMNS: [&str; 10] = names(&POINT_FIELDS);

/// `points_<study>.csv` of a cylinder study with named points: the displacement (u_r, u_z) of
/// each point (reference r, z; the mesh's length unit, e.g. mm) per stretch per model.
pub fn points_csv(study: &str, c: &CylinderResult) -> Result<Vec<u8>, AppError> {
    let file = format!("points_{}.csv", crate::studies::slug(study));
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = csv_error(&file);
    w.write_record(POINT_COLUMNS).map_err(&fail)?;
    for sweep in &c.sweeps {
        for (p, u) in sweep.points.iter().zip(&sweep.displacements) {
            for ((name, at), u) in c.points.iter().zip(u) {
                let origin = || {
                    format!(
                        "{file}: {}, point {name}, lambda = {}",
                        sweep.label, p.lambda
                    )
                };
                w.write_record([
                    study.to_string(),
                    name.clone(),
                    text(at[0], "r", origin)?,
                    text(at[1], "z", origin)?,
                    sweep.model.law.name().to_string(),
                    sweep.model.coupling.name().to_string(),
                    text(sweep.model.damage, "d", origin)?,
                    text(p.lambda, "lambda", origin)?,
                    text(u[0], "u_r", origin)?,
                    text(u[1], "u_z", origin)?,
                ])
                .map_err(&fail)?;
            }
        }
    }
    finish(w, &file)
}

/// The tables of `results` beside `curves.csv`, with their file names: each cylinder study's
/// named points, `fits.csv`, `stability.csv`, `history.csv` (each only if there is something to
/// write).
pub fn tables(results: &Results) -> Result<Vec<(String, Vec<u8>)>, AppError> {
    let mut out = Vec::new();
    for (study, c) in results.cylinders() {
        if !c.points.is_empty() {
            out.push((
                format!("points_{}.csv", crate::studies::slug(study)),
                points_csv(study, c)?,
            ));
        }
    }
    let fits = results.fits();
    if fits.iter().any(|(_, f)| !f.is_empty()) {
        out.push(("fits.csv".into(), fits_csv(&fits)?));
    }
    let stability = results.stability();
    if stability.iter().any(|(_, c)| !c.is_empty()) {
        out.push(("stability.csv".into(), stability_csv(&stability)?));
    }
    let histories = results.histories();
    if histories.iter().any(|(_, h)| !h.histories.is_empty()) {
        out.push(("history.csv".into(), history_csv(&histories)?));
    }
    // The kinds that own their table: one file per kind, the tables of its studies appended.
    let own: Vec<OwnTable> = results
        .studies
        .iter()
        .filter_map(|s| s.result.own_table(&s.name))
        .filter(|t| t.table.rows() > 0)
        .collect();
    let files: Vec<&str> = own.iter().map(|t| t.file).collect();
    for (i, file) in files.iter().enumerate() {
        if files[..i].contains(file) {
            continue;
        }
        let tables: Vec<&Table> = own
            .iter()
            .filter(|t| t.file == *file)
            .map(|t| &t.table)
            .collect();
        out.push((file.to_string(), table_csv(file, &tables)?));
    }
    Ok(out)
}

/// The CSV text of tables with the same columns (a kind's own table, one per study), the header
/// once; empty cells for `None`, a non-finite number an error naming the column and row.
pub fn table_csv(file: &str, tables: &[&Table]) -> Result<Vec<u8>, AppError> {
    let mut w = csv::Writer::from_writer(Vec::new());
    let fail = csv_error(file);
    let Some(first) = tables.first() else {
        return finish(w, file);
    };
    w.write_record(first.columns.iter().map(|c| c.name))
        .map_err(&fail)?;
    for t in tables {
        for row in 0..t.rows() {
            let mut record = Vec::with_capacity(t.columns.len());
            for c in &t.columns {
                record.push(match &c.values {
                    Values::Text(v) => v[row].clone().unwrap_or_default(),
                    Values::Number(v) => match v[row] {
                        None => String::new(),
                        Some(x) => text(x, c.name, || format!("{file}, row {row}"))?,
                    },
                });
            }
            w.write_record(&record).map_err(&fail)?;
        }
    }
    finish(w, file)
}

/// The schema of each CSV file in `files` that a run of `results` wrote (`curves.csv`, the
/// tables of [`tables`], `tradeoff.csv`), for `datapackage.json`; other files are skipped.
pub fn resources(results: &Results, files: &[String]) -> Vec<Resource> {
    let own = |file: &str| {
        results
            .studies
            .iter()
            .filter_map(|s| s.result.own_table(&s.name))
            .find(|t| t.file == file)
    };
    files
        .iter()
        .filter_map(|file| {
            let (description, fields) = match file.as_str() {
                "curves.csv" => (
                    "one row per computed point of a uniaxial curve or a cylinder sweep",
                    CURVE_FIELDS.to_vec(),
                ),
                "fits.csv" => ("one row per fitted parameter", FIT_FIELDS.to_vec()),
                "stability.csv" => ("one row per model and stretch", STABILITY_FIELDS.to_vec()),
                "history.csv" => (
                    "one row per activation-in-time model and time step",
                    HISTORY_FIELDS.to_vec(),
                ),
                "tradeoff.csv" => (
                    "one row per measured variant of an option",
                    super::tradeoff::FIELDS.to_vec(),
                ),
                f if f.starts_with("points_") && f.ends_with(".csv") => (
                    "the displacement of each named point per model and stretch",
                    POINT_FIELDS.to_vec(),
                ),
                f => {
                    let t = own(f)?;
                    (t.rows_are, table_fields(&t.table))
                }
            };
            Some(Resource {
                path: file.clone(),
                description: description.into(),
                fields,
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::shortest;

    #[test]
    fn numbers_read_back_exactly_and_stay_short_at_every_magnitude() {
        let mut values = vec![
            0.0,
            -0.0,
            0.5,
            -1.25,
            1e-4,
            9.99e-5,
            1e15,
            9.99e14,
            2.85e266,
            -3.8e-100,
            8.128632865720501e-75,
            6.16e-16,
            f64::MIN_POSITIVE,
            f64::MAX,
            5e-324,
        ];
        // A deterministic spread of magnitudes and mantissas.
        let mut x = 0.123_456_789_f64;
        for k in -300..300 {
            x = (x * 997.0 + 0.317).fract();
            values.push((x + 0.01) * 10f64.powi(k));
        }
        assert_eq!(shortest(-0.0), "0");
        for v in values {
            let s = shortest(v);
            assert_eq!(s.parse::<f64>().ok(), Some(v), "{v:e} written as {s}");
            assert!(
                s.len() <= 25,
                "{v:e} written as {s} ({} characters)",
                s.len()
            );
        }
    }
}
