//! Outputs of a run, from its typed results: the CSV files of the study kinds' tables
//! (`curves.csv`, `fits.csv`, …) with `datapackage.json`, the figures (PNG + SVG), the
//! trade-off pages, `report.html` (self-contained) and the cylinder's VTK fields, all written
//! atomically through [`atomic::Staging`]. Each driver here iterates over the kinds.

pub mod atomic;
pub mod base64;
pub mod csv;
pub mod datapackage;
pub mod disk;
pub mod figures;

pub mod report;
pub mod tradeoff;

pub use atomic::{Staging, Writer};

use crate::app_error::AppError;
use crate::scene::{Results, Scene};
use report::RunInfo;
use std::path::Path;
use std::time::Instant;

/// What the report says about the run besides its results.
#[derive(Debug, Clone)]
pub struct RunMeta {
    /// The command line.
    pub command: String,
    /// When the run started (the report gives the wall time up to its writing).
    pub started: Instant,
    /// `rustc --version`, if known.
    pub rustc: Option<String>,
}

/// Writes every output of a run into `staging` (committed by the caller), the data first so that
/// a disk that fills up keeps it: the CSV files of the studies' tables (`curves.csv` first, if written),
/// `scene.toml` (the scene as given) and `datapackage.json`; then the VTK files the solver wrote
/// into `staging`'s `vtk/`, the figures, the trade-off pages and, last, `report.html`. Returns
/// the number of rows of `curves.csv` (0 without it). A full disk stops it with [`AppError::DiskFull`]; every
/// file staged before is whole, and the caller may commit them ([`Staging::staged`]).
pub fn write_run(
    staging: &mut Staging,
    scene: &Scene,
    results: &Results,
    meta: &RunMeta,
) -> Result<usize, AppError> {
    let tables = csv::files(results);
    let mut files = Vec::new();
    for t in &tables {
        staging.write(&t.file, &t.bytes()?)?;
        files.push(t.file.clone());
    }
    staging.write("scene.toml", scene.source.as_bytes())?;
    files.push("scene.toml".to_string());
    // Every column's type and unit, for the CSV files written above.
    let resources: Vec<datapackage::Resource> = tables.iter().map(csv::CsvFile::resource).collect();
    let package = datapackage::descriptor(&scene.title, &resources)?;
    staging.write("datapackage.json", &package)?;
    files.push("datapackage.json".to_string());
    for v in results.studies.iter().flat_map(|s| s.result.vtk_files()) {
        let rel = Path::new("vtk").join(v);
        staging.adopt(&rel)?;
        files.push(rel.display().to_string());
    }
    let mut rendered = Vec::new();
    for f in figures::figures(scene, results) {
        let (png, svg) = crate::plot::render_bytes(&f)?;
        staging.write(&format!("{}.png", f.stem), &png)?;
        staging.write(&format!("{}.svg", f.stem), svg.as_bytes())?;
        files.push(format!("{}.png", f.stem));
        files.push(format!("{}.svg", f.stem));
        rendered.push((f, png));
    }
    if let Some((_, t)) = results
        .of::<crate::studies::tradeoff::TradeoffResults>()
        .next()
    {
        let (staged, figures) = tradeoff::stage_pages(
            t,
            staging,
            &scene.title,
            &meta.command,
            meta.started.elapsed().as_secs_f64(),
        )?;
        files.extend(staged);
        rendered.extend(figures);
    }
    let info = RunInfo {
        command: meta.command.clone(),
        wall: meta.started.elapsed(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        rustc: meta.rustc.clone(),
        files,
        tables: tables.iter().map(report::DataFile::of).collect(),
    };
    let page = report::html(scene, results, &rendered, &info)?;
    staging.write("report.html", page.as_bytes())?;
    Ok(tables
        .iter()
        .find(|t| t.file == crate::studies::table::CURVES_FILE)
        .map_or(0, csv::CsvFile::rows))
}
