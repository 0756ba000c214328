//! Scenes from Python: [`run_scene`] and [`check_scene`] take a scene file's path or its text
//! (the Python wrapper turns a dict into TOML text first), validate it with the scene's own parser
//! ([`Scene::load`], [`Scene::parse`]: its names, defaults and messages) and run it with the GIL
//! released. Each study's results come back as columns — one numpy array per column of its
//! kind's table ([`activemuscle::studies::table::Table`]: the CSV file's columns, names, types
//! and values), one row per point — that `pandas.DataFrame(...)` takes directly: numbers as
//! float64, counts as int64, flags as bool arrays, names (law, coupling, direction, ...) as
//! object arrays, a value that does not apply to a row (P_pas of a passive curve, the damage of a
//! passive model) masked in a `numpy.ma` array (pandas reads it as missing), never a NaN. Files are written only when `out` is given, by the writer
//! the command line uses ([`output::write_run`]).

use activemuscle::app_error::AppError;
use activemuscle::output::{self, RunMeta, Staging, Writer};
use activemuscle::scene::{Results, RunOptions, Scene};
use activemuscle::studies::domain::LeftDomain;
use activemuscle::studies::table::{Table, Values};
use activemuscle::studies::{Failure, Outcome};
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

/// `values` as a numpy array (float64, int64 or bool), or, if some rows have no value, a
/// `numpy.ma` array masking them (pandas reads them as missing).
fn array<'py, T: numpy::Element + Copy + Default>(
    py: Python<'py>,
    values: &[Option<T>],
) -> PyResult<Bound<'py, PyAny>> {
    let data: Vec<T> = values.iter().map(|v| v.unwrap_or_default()).collect();
    let data = PyArray1::from_vec(py, data).into_any();
    if values.iter().all(Option::is_some) {
        return Ok(data);
    }
    let mask: Vec<bool> = values.iter().map(Option::is_none).collect();
    let kwargs = PyDict::new(py);
    kwargs.set_item("mask", PyArray1::from_vec(py, mask))?;
    py.import("numpy.ma")?
        .call_method("masked_array", (data,), Some(&kwargs))
}

/// Words as an object array (`None` where a row has none).
fn words<'py>(py: Python<'py>, values: &[Option<String>]) -> PyResult<Bound<'py, PyAny>> {
    let list = PyList::new(py, values.iter().map(|v| v.as_deref()))?;
    let kwargs = PyDict::new(py);
    kwargs.set_item("dtype", py.import("builtins")?.getattr("object")?)?;
    py.import("numpy")?
        .call_method("array", (list,), Some(&kwargs))
}

/// A study kind's table, column by column, as its CSV file holds it: words as object arrays,
/// numbers as float64, counts as int64 and flags as bool arrays, masked where a row has no value;
/// a non-finite number a FloatingPointError naming the column and row.
fn columns<'py>(py: Python<'py>, table: &Table, origin: &str) -> PyResult<Bound<'py, PyDict>> {
    table.check(origin).map_err(app_error)?;
    let dict = PyDict::new(py);
    for c in &table.columns {
        let column = match &c.values {
            Values::Text(v) => words(py, v)?,
            Values::Number(v) => array(py, v)?,
            Values::Integer(v) => array(py, v)?,
            Values::Boolean(v) => array(py, v)?,
        };
        dict.set_item(c.name, column)?;
    }
    Ok(dict)
}

/// One study: its summary, its failures and the models that left their law's domain (columns
/// `model`, `message`: `failures`, `outside_domain`), its tables by key
/// (`table`: its rows, as its CSV file holds them; `named_points` for a cylinder that names
/// points) with the CSV file of each (`files`), the VTK files it wrote (under `out`) and what it
/// found.
fn study<'py>(py: Python<'py>, s: &Outcome, out: Option<&Path>) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("name", &s.name)?;
    d.set_item("kind", s.kind.name())?;
    d.set_item("models", s.models)?;
    d.set_item("points", s.points)?;
    d.set_item("requested", s.requested)?;
    d.set_item("elapsed", s.elapsed.as_secs_f64())?;
    d.set_item("details", &s.details)?;
    let failures = PyDict::new(py);
    let text = |f: fn(&Failure) -> &String| -> Vec<Option<String>> {
        s.failures.iter().map(|x| Some(f(x).clone())).collect()
    };
    failures.set_item("model", words(py, &text(|f| &f.model))?)?;
    failures.set_item("message", words(py, &text(|f| &f.message))?)?;
    d.set_item("failures", failures)?;
    let outside = PyDict::new(py);
    let left = |f: fn(&LeftDomain) -> &String| -> Vec<Option<String>> {
        s.left_domain.iter().map(|x| Some(f(x).clone())).collect()
    };
    outside.set_item("model", words(py, &left(|l| &l.model))?)?;
    outside.set_item("message", words(py, &left(|l| &l.message))?)?;
    d.set_item("outside_domain", outside)?;
    // A study that stopped with an error has no table: its failures say why.
    d.set_item("table", PyDict::new(py))?;
    let files = PyDict::new(py);
    for t in s.result.tables(&s.name) {
        let origin = format!("study {:?}: {}", s.name, t.key);
        d.set_item(t.key, columns(py, &t.table, &origin)?)?;
        files.set_item(t.key, &t.file)?;
    }
    d.set_item("files", files)?;
    let root = out.map(|o| o.join("vtk"));
    let vtk: Vec<PathBuf> = s
        .result
        .vtk_files()
        .into_iter()
        .map(|f| root.as_ref().map_or(f.to_path_buf(), |r| r.join(f)))
        .collect();
    d.set_item("vtk", vtk)?;
    d.set_item("findings", s.result.findings())?;
    Ok(d)
}
