//! Scenes from Python: [`run_scene`] and [`check_scene`] take a scene file's path or its text
//! (the Python wrapper turns a dict into TOML text first), validate it with the scene's own parser
//! ([`Scene::load`], [`Scene::parse`]: its names, defaults and messages) and run it with the GIL
//! released. Each study's results come back as columns — one numpy array per field, one row per
//! point — that `pandas.DataFrame(...)` takes directly: numbers as float64 or int64 arrays,
//! names (law, coupling, direction, ...) as object arrays, a value that does not apply to a row
//! (P_pas of a passive curve, the damage of a passive model) masked in a `numpy.ma` array (pandas
//! reads it as missing), never a NaN. Files are written only when `out` is given, by the writer
//! the command line uses ([`output::write_run`]).

use activemuscle::app_error::{finite, AppError};
use activemuscle::output::{self, RunMeta, Staging, Writer};
use activemuscle::scene::{Results, RunOptions, Scene};
use activemuscle::studies::cylinder::{bases_name, CylinderResult};
use activemuscle::studies::fit::FitOutcome;
use activemuscle::studies::history::HistoryResult;
use activemuscle::studies::stability::StabilityCurve;
use activemuscle::studies::table::{Table, Values};
use activemuscle::studies::tradeoff::TradeoffResults;
use activemuscle::studies::uniaxial::{CurveModel, UniaxialResult};
use activemuscle::studies::{Outcome, StudyResult};
use numpy::PyArray1;
use pyo3::exceptions::{PyFloatingPointError, PyOSError, PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Where a scene comes from: a file, or text (a scene written as TOML, or a dict converted to
/// TOML by the Python wrapper: its errors name the key path, not a line of text nobody wrote).
fn load(path: Option<PathBuf>, text: Option<&str>, from_dict: bool) -> PyResult<Scene> {
    let scene = match (path, text) {
        (Some(p), None) => Scene::load(&p),
        (None, Some(t)) => Scene::parse(t, if from_dict { "<dict>" } else { "<string>" }),
        _ => {
            return Err(PyValueError::new_err(
                "give the scene as exactly one of a path or a text",
            ))
        }
    };
    scene.map_err(|mut e| {
        if from_dict {
            e.line = None;
        }
        PyValueError::new_err(e.to_string())
    })
}

/// The Python exception of a run's error: a scene's rule is a ValueError, a non-finite number a
/// FloatingPointError, a file an OSError, anything else (the solver, a fit) a RuntimeError.
fn app_error(e: AppError) -> PyErr {
    let message = e.to_string();
    match e {
        AppError::Scene(_) | AppError::Invalid(_) => PyValueError::new_err(message),
        AppError::NonFinite { .. } => PyFloatingPointError::new_err(message),
        AppError::Io { .. } => PyOSError::new_err(message),
        _ => PyRuntimeError::new_err(message),
    }
}

/// The resolved scene (every default written out) as TOML text: what `activemuscle check`
/// prints.
#[pyfunction]
#[pyo3(signature = (path = None, text = None, from_dict = false))]
pub fn check_scene(path: Option<PathBuf>, text: Option<&str>, from_dict: bool) -> PyResult<String> {
    load(path, text, from_dict)?
        .resolved_toml()
        .map_err(app_error)
}

/// Runs the scene with the GIL released; writes the run's outputs into `out` if given (VTK files
/// only then). Returns `{"title", "file", "out", "studies": [one dict per study]}`.
#[pyfunction]
#[pyo3(signature = (path = None, text = None, from_dict = false, out = None))]
pub fn run_scene<'py>(
    py: Python<'py>,
    path: Option<PathBuf>,
    text: Option<&str>,
    from_dict: bool,
    out: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let scene = load(path, text, from_dict)?;
    let started = Instant::now();
    let results = py
        .detach(|| run_and_write(&scene, out.as_deref(), started))
        .map_err(app_error)?;
    let d = PyDict::new(py);
    d.set_item("title", &scene.title)?;
    d.set_item("file", &scene.file)?;
    d.set_item("out", out.as_ref())?;
    let studies = PyList::empty(py);
    for s in &results.studies {
        studies.append(study(py, s, out.as_deref())?)?;
    }
    d.set_item("studies", studies)?;
    Ok(d)
}

/// The run, and its files if `out` is given (staged, then committed as the command line does).
fn run_and_write(scene: &Scene, out: Option<&Path>, started: Instant) -> Result<Results, AppError> {
    let Some(out) = out else {
        return Ok(scene.run(&RunOptions::default()));
    };
    let mut staging = Staging::new(out, Writer::Run)?;
    let options = RunOptions {
        vtk_dir: Some(staging.dir().join("vtk")),
        ..RunOptions::default()
    };
    let results = scene.run(&options);
    let meta = RunMeta {
        command: format!("activemuscle.run_scene({:?}, out={:?})", scene.file, out),
        started,
        rustc: None,
    };
    output::write_run(&mut staging, scene, &results, &meta)?;
    staging.commit()?;
    Ok(results)
}

/// Columns of one table, each checked as it is added: every number finite.
struct Columns<'py> {
    py: Python<'py>,
    dict: Bound<'py, PyDict>,
    /// Names the table in a non-finite number's message.
    table: String,
}

impl<'py> Columns<'py> {
    fn new(py: Python<'py>, table: String) -> Self {
        Self {
            py,
            dict: PyDict::new(py),
            table,
        }
    }

    fn numbers(&self, name: &str, values: Vec<f64>) -> PyResult<&Self> {
        for (row, &x) in values.iter().enumerate() {
            finite(x, name, || format!("{}, row {row}", self.table))
                .map_err(|e| PyFloatingPointError::new_err(e.to_string()))?;
        }
        self.dict
            .set_item(name, PyArray1::from_vec(self.py, values))?;
        Ok(self)
    }

    /// A column where some rows have no value: a `numpy.ma` array masking them.
    fn optional(&self, name: &str, values: Vec<Option<f64>>) -> PyResult<&Self> {
        let mask: Vec<bool> = values.iter().map(Option::is_none).collect();
        let data: Vec<f64> = values.iter().map(|v| v.unwrap_or(0.0)).collect();
        for (row, &x) in data.iter().enumerate() {
            finite(x, name, || format!("{}, row {row}", self.table))
                .map_err(|e| PyFloatingPointError::new_err(e.to_string()))?;
        }
        let kwargs = PyDict::new(self.py);
        kwargs.set_item("mask", PyArray1::from_vec(self.py, mask))?;
        let masked = self.py.import("numpy.ma")?.call_method(
            "masked_array",
            (PyArray1::from_vec(self.py, data),),
            Some(&kwargs),
        )?;
        self.dict.set_item(name, masked)?;
        Ok(self)
    }

    fn counts(&self, name: &str, values: Vec<i64>) -> PyResult<&Self> {
        self.dict
            .set_item(name, PyArray1::from_vec(self.py, values))?;
        Ok(self)
    }

    fn flags(&self, name: &str, values: Vec<bool>) -> PyResult<&Self> {
        self.dict
            .set_item(name, PyArray1::from_vec(self.py, values))?;
        Ok(self)
    }

    /// Names as an object array (`None` where a row has none).
    fn names<S: ToString>(&self, name: &str, values: Vec<Option<S>>) -> PyResult<&Self> {
        let list = PyList::new(
            self.py,
            values.iter().map(|v| v.as_ref().map(ToString::to_string)),
        )?;
        let kwargs = PyDict::new(self.py);
        kwargs.set_item("dtype", self.py.import("builtins")?.getattr("object")?)?;
        let array = self
            .py
            .import("numpy")?
            .call_method("array", (list,), Some(&kwargs))?;
        self.dict.set_item(name, array)?;
        Ok(self)
    }
}

/// One study: its summary, its failures (columns `model`, `message`) and its table.
fn study<'py>(py: Python<'py>, s: &Outcome, out: Option<&Path>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &s.name)?;
    d.set_item("kind", s.kind.name())?;
    d.set_item("models", s.models)?;
    d.set_item("points", s.points)?;
    d.set_item("requested", s.requested)?;
    d.set_item("elapsed", s.elapsed.as_secs_f64())?;
    d.set_item("details", &s.details)?;
    let failures = Columns::new(py, format!("study {:?}: failures", s.name));
    failures
        .names("model", s.failures.iter().map(|f| Some(&f.model)).collect())?
        .names(
            "message",
            s.failures.iter().map(|f| Some(&f.message)).collect(),
        )?;
    d.set_item("failures", failures.dict)?;
    let table = Columns::new(py, format!("study {:?}", s.name));
    let mut vtk = Vec::new();
    let mut findings = Vec::new();
    match &s.result {
        StudyResult::Uniaxial(u) => uniaxial(&table, u)?,
        StudyResult::Cylinder(c) => {
            cylinder(&table, c)?;
            let named = Columns::new(py, format!("study {:?}: named points", s.name));
            named_points(&named, c)?;
            d.set_item("named_points", named.dict)?;
            let root = out.map(|o| o.join("vtk"));
            vtk = c
                .sweeps
                .iter()
                .flat_map(|w| w.vtk_files.iter())
                .map(|f| root.as_ref().map_or(f.clone(), |r| r.join(f)))
                .collect();
        }
        StudyResult::Fit(f) => fits(&table, f)?,
        StudyResult::Stability(c) => stability(&table, c)?,
        StudyResult::ActivationInTime(h) => history(&table, h)?,
        StudyResult::Tradeoff(t) => {
            tradeoff(&table, t)?;
            findings.clone_from(&t.findings);
        }
        // A kind that owns its table (shear, biaxial): the columns of its CSV file. A study that
        // stopped with an error has none: its failures say why, the table stays empty.
        other => {
            if let Some(own) = other.own_table(&s.name) {
                own_table(&table, &own.table)?;
            }
        }
    }
    d.set_item("table", table.dict)?;
    d.set_item("vtk", vtk)?;
    d.set_item("findings", findings)?;
    Ok(d)
}

/// A kind's own table, column by column, as its CSV file holds it (words as object arrays,
/// numbers as float arrays, masked where a row has no value).
fn own_table(t: &Columns, table: &Table) -> PyResult<()> {
    for c in &table.columns {
        match &c.values {
            Values::Text(v) => {
                t.names(c.name, v.clone())?;
            }
            Values::Number(v) if v.iter().all(Option::is_some) => {
                t.numbers(c.name, v.iter().map(|x| x.unwrap_or_default()).collect())?;
            }
            Values::Number(v) => {
                t.optional(c.name, v.clone())?;
            }
        }
    }
    Ok(())
}

/// One row per point of every curve: direction, energy, law, coupling, d, λ, γ, P, P_pas,
/// (1 − d) P_act (`P_act`), as `curves.csv`.
fn uniaxial(t: &Columns, u: &UniaxialResult) -> PyResult<()> {
    let rows: Vec<_> = u
        .curves
        .iter()
        .flat_map(|c| c.points.iter().map(move |p| (c, p)))
        .collect();
    let model = |c: &activemuscle::studies::uniaxial::Curve| match c.model {
        CurveModel::Passive => ("passive", None, None),
        CurveModel::Constant(_) => ("constant", None, None),
        CurveModel::Active(m) => (m.law.name(), Some(m.coupling.name()), Some(m.damage)),
    };
    t.names(
        "direction",
        rows.iter().map(|_| Some(u.direction.name())).collect(),
    )?
    .names(
        "energy",
        rows.iter().map(|(c, _)| Some(&c.energy)).collect(),
    )?
    .names("law", rows.iter().map(|(c, _)| Some(model(c).0)).collect())?
    .names("coupling", rows.iter().map(|(c, _)| model(c).1).collect())?
    .optional("d", rows.iter().map(|(c, _)| model(c).2).collect())?
    .numbers("lambda", rows.iter().map(|(_, p)| p.lambda).collect())?
    .numbers("gamma", rows.iter().map(|(_, p)| p.gamma).collect())?
    .numbers("P", rows.iter().map(|(_, p)| p.stress).collect())?
    .numbers("cauchy", rows.iter().map(|(_, p)| p.cauchy).collect())?
    .optional("P_pas", rows.iter().map(|(_, p)| p.passive).collect())?
    .optional("P_act", rows.iter().map(|(_, p)| p.active_target).collect())?
    .optional("J", rows.iter().map(|(_, p)| p.volume).collect())?;
    Ok(())
}

/// One row per stretch of every sweep: sweep label, law, coupling, d, dofs, λ, γ at the centre,
/// P, the 0D curve's P where the study compares with it, Newton iterations.
fn cylinder(t: &Columns, c: &CylinderResult) -> PyResult<()> {
    let rows: Vec<_> = c
        .sweeps
        .iter()
        .flat_map(|w| w.points.iter().map(move |p| (w, p)))
        .collect();
    t.names("sweep", rows.iter().map(|(w, _)| Some(&w.label)).collect())?
        .names("energy", rows.iter().map(|_| Some(&c.energy)).collect())?
        .names(
            "bases",
            rows.iter().map(|_| Some(bases_name(c.bases))).collect(),
        )?
        .names(
            "element",
            rows.iter().map(|_| Some(c.element.name())).collect(),
        )?
        .names(
            "law",
            rows.iter().map(|(w, _)| Some(w.model.law.name())).collect(),
        )?
        .names(
            "coupling",
            rows.iter()
                .map(|(w, _)| Some(w.model.coupling.name()))
                .collect(),
        )?
        .numbers("d", rows.iter().map(|(w, _)| w.model.damage).collect())?
        .counts("dofs", rows.iter().map(|(w, _)| w.dofs as i64).collect())?
        .numbers("lambda", rows.iter().map(|(_, p)| p.lambda).collect())?
        .numbers(
            "gamma_centre",
            rows.iter().map(|(_, p)| p.gamma_centre).collect(),
        )?
        .numbers("P", rows.iter().map(|(_, p)| p.stress).collect())?
        .optional("P_0d", rows.iter().map(|(_, p)| p.stress_0d).collect())?
        .counts(
            "newton_iterations",
            rows.iter()
                .map(|(_, p)| p.newton_iterations as i64)
                .collect(),
        )?;
    Ok(())
}

/// One row per named point, stretch and sweep, as `points_<study>.csv`: sweep label, point, its
/// reference r and z, law, coupling, d, λ, and its displacement u_r, u_z (the mesh's unit).
fn named_points(t: &Columns, c: &CylinderResult) -> PyResult<()> {
    let mut rows = Vec::new();
    for w in &c.sweeps {
        for (p, u) in w.points.iter().zip(&w.displacements) {
            for ((name, at), u) in c.points.iter().zip(u) {
                rows.push((w, name, *at, p.lambda, *u));
            }
        }
    }
    t.names("sweep", rows.iter().map(|r| Some(&r.0.label)).collect())?
        .names("point", rows.iter().map(|r| Some(r.1)).collect())?
        .numbers("r", rows.iter().map(|r| r.2[0]).collect())?
        .numbers("z", rows.iter().map(|r| r.2[1]).collect())?
        .names(
            "law",
            rows.iter().map(|r| Some(r.0.model.law.name())).collect(),
        )?
        .names(
            "coupling",
            rows.iter()
                .map(|r| Some(r.0.model.coupling.name()))
                .collect(),
        )?
        .numbers("d", rows.iter().map(|r| r.0.model.damage).collect())?
        .numbers("lambda", rows.iter().map(|r| r.3).collect())?
        .numbers("u_r", rows.iter().map(|r| r.4[0]).collect())?
        .numbers("u_z", rows.iter().map(|r| r.4[1]).collect())?;
    Ok(())
}

/// One row per fitted parameter, as `fits.csv`: kind, case, parameter, value, standard error,
/// reference value, converged, RMS error, unit, residual norm, iterations, points, the bound a
/// parameter is held at, the weights.
fn fits(t: &Columns, fits: &[FitOutcome]) -> PyResult<()> {
    let rows: Vec<_> = fits
        .iter()
        .flat_map(|f| (0..f.names.len()).map(move |j| (f, j)))
        .collect();
    t.names(
        "fit",
        rows.iter().map(|(f, _)| Some(f.kind.name())).collect(),
    )?
    .names("case", rows.iter().map(|(f, _)| Some(&f.case)).collect())?
    .names(
        "parameter",
        rows.iter().map(|(f, j)| Some(&f.names[*j])).collect(),
    )?
    .numbers("value", rows.iter().map(|(f, j)| f.values[*j]).collect())?
    .optional(
        "standard_error",
        rows.iter()
            .map(|(f, j)| f.standard_errors.get(*j).copied().flatten())
            .collect(),
    )?
    .optional(
        "reference",
        rows.iter()
            .map(|(f, j)| f.reference.get(*j).copied().flatten())
            .collect(),
    )?
    .flags("converged", rows.iter().map(|(f, _)| f.converged).collect())?
    .numbers("rms", rows.iter().map(|(f, _)| f.rms).collect())?
    .names("unit", rows.iter().map(|(f, _)| Some(f.unit)).collect())?
    .numbers(
        "residual_norm",
        rows.iter().map(|(f, _)| f.residual_norm).collect(),
    )?
    .counts(
        "iterations",
        rows.iter().map(|(f, _)| f.iterations as i64).collect(),
    )?
    .counts(
        "points",
        rows.iter().map(|(f, _)| f.points as i64).collect(),
    )?
    .names(
        "termination",
        rows.iter().map(|(f, _)| Some(&f.termination)).collect(),
    )?
    .optional(
        "at_bound",
        rows.iter()
            .map(|(f, j)| f.at_bound.get(*j).copied().flatten().map(|b| b.bound))
            .collect(),
    )?
    .names(
        "weights",
        rows.iter().map(|(f, _)| Some(f.weights.name())).collect(),
    )?;
    Ok(())
}

/// One row per model and stretch, as `stability.csv`: law, coupling, d, λ, P, dP/dλ, the
/// ellipticity minimum, relative, elliptic.
fn stability(t: &Columns, curves: &[StabilityCurve]) -> PyResult<()> {
    let rows: Vec<_> = curves
        .iter()
        .flat_map(|c| c.points.iter().map(move |p| (c, p)))
        .collect();
    t.names(
        "law",
        rows.iter()
            .map(|(c, _)| Some(c.model.map_or("passive", |m| m.law.name())))
            .collect(),
    )?
    .names(
        "coupling",
        rows.iter()
            .map(|(c, _)| c.model.map(|m| m.coupling.name()))
            .collect(),
    )?
    .optional("d", rows.iter().map(|(c, _)| c.damage()).collect())?
    .numbers("lambda", rows.iter().map(|(_, p)| p.lambda).collect())?
    .numbers("P", rows.iter().map(|(_, p)| p.stress).collect())?
    .numbers("cauchy", rows.iter().map(|(_, p)| p.cauchy).collect())?
    .numbers("dP_dlambda", rows.iter().map(|(_, p)| p.slope).collect())?
    .numbers(
        "ellipticity_min",
        rows.iter().map(|(_, p)| p.least).collect(),
    )?
    .numbers(
        "ellipticity_relative",
        rows.iter().map(|(_, p)| p.relative).collect(),
    )?
    .flags("elliptic", rows.iter().map(|(_, p)| p.elliptic).collect())?;
    Ok(())
}

/// One row per model and time step, as `history.csv`: law, coupling, d, t, a_s, a, λ, γ, P,
/// σ₁₁, J, P_pas, P_act.
fn history(t: &Columns, r: &HistoryResult) -> PyResult<()> {
    let rows: Vec<_> = r
        .histories
        .iter()
        .flat_map(|h| h.points.iter().map(move |p| (h.model, p)))
        .collect();
    t.names(
        "law",
        rows.iter().map(|(m, _)| Some(m.law.name())).collect(),
    )?
    .names(
        "coupling",
        rows.iter().map(|(m, _)| Some(m.coupling.name())).collect(),
    )?
    .numbers("d", rows.iter().map(|(m, _)| m.damage).collect())?
    .numbers("t", rows.iter().map(|(_, p)| p.t).collect())?
    .numbers("a_schedule", rows.iter().map(|(_, p)| p.schedule).collect())?
    .numbers("a", rows.iter().map(|(_, p)| p.level).collect())?
    .numbers("lambda", rows.iter().map(|(_, p)| p.lambda).collect())?
    .numbers("gamma", rows.iter().map(|(_, p)| p.gamma).collect())?
    .numbers("P", rows.iter().map(|(_, p)| p.stress).collect())?
    .numbers("cauchy", rows.iter().map(|(_, p)| p.cauchy).collect())?
    .numbers("J", rows.iter().map(|(_, p)| p.volume).collect())?
    .numbers("P_pas", rows.iter().map(|(_, p)| p.passive).collect())?
    .numbers("P_act", rows.iter().map(|(_, p)| p.active_target).collect())?;
    Ok(())
}

/// One row per measured variant: option, variant, reference, time, speed-up, error ratio,
/// Pareto, note.
fn tradeoff(t: &Columns, r: &TradeoffResults) -> PyResult<()> {
    let rows = &r.rows;
    t.names("option", rows.iter().map(|m| Some(&m.option)).collect())?
        .names("variant", rows.iter().map(|m| Some(&m.variant)).collect())?
        .flags("reference", rows.iter().map(|m| m.reference).collect())?
        .numbers("time_s", rows.iter().map(|m| m.time.median).collect())?
        .numbers("time_low_s", rows.iter().map(|m| m.time.low).collect())?
        .numbers("time_high_s", rows.iter().map(|m| m.time.high).collect())?
        .numbers("speedup", rows.iter().map(|m| m.speedup).collect())?
        .numbers("error_ratio", rows.iter().map(|m| m.error_ratio).collect())?
        .flags("pareto", rows.iter().map(|m| m.pareto).collect())?
        .names("note", rows.iter().map(|m| Some(&m.note)).collect())?;
    Ok(())
}
