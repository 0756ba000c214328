//! `activemuscle`: runs scene files (TOML) of active skeletal-muscle studies and writes the
//! curves, the figures and a report. Without arguments it runs the chapter's whole study.

use activemuscle::output::csv::{tables, to_csv};
use activemuscle::output::figures::figures;
use activemuscle::output::plot::{render, Figure};
use activemuscle::output::report::{html, RunInfo};
use activemuscle::output::Staging;
use activemuscle::scene::run::{run, Results, RunOptions};
use activemuscle::scene::{Scene, Study};
use activemuscle::tradeoff::{report, TradeoffOptions};
use clap::{Parser, Subcommand};
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

/// Active skeletal-muscle mechanics after Giantesio & Musesti: homogeneous tests and an
/// axisymmetric FE cylinder, with loss of activation.
///
/// Without a subcommand, runs the chapter's whole study (the embedded scenes/paper.toml) and
/// writes curves.csv, the figures (PNG + SVG), report.html and VTK fields into out/.
#[derive(Parser, Debug)]
#[command(name = "activemuscle", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
}

#[derive(Subcommand, Debug)]
enum Command {
    /// Run a scene and write its outputs.
    ///
    /// Writes into DIR: curves.csv (one row per point), fig_*.png and fig_*.svg, report.html
    /// (self-contained), scene.toml (the scene that ran) and vtk/ (cylinder fields). Files are
    /// written atomically: a failed run leaves no half-written file.
    Run {
        /// Scene file (TOML). Omit to run the chapter's study (scenes/paper.toml, embedded).
        scene: Option<PathBuf>,
        /// Output directory (created if missing).
        #[arg(long, short, value_name = "DIR", default_value = "out")]
        out: PathBuf,
        /// No progress bars or log lines; print only the summary.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Measure speed against accuracy for every option that trades one for the other.
    ///
    /// Activation law (0D and FE), derivative route, frozen tangent, mesh, Newton tolerance and 0D
    /// vs FE, each timed (wall time) and compared with a reference at its accurate end. Writes
    /// into DIR: tradeoff.csv, tradeoff.md, tradeoff_*.png/svg (log–log error vs time, Pareto
    /// front) and tradeoff.html (self-contained). Uses the scene's material and activation; the
    /// options of its `kind = "tradeoff"` study if it has one (see scenes/tradeoff.toml), else
    /// every option on its first cylinder study's geometry.
    Tradeoff {
        /// Scene file (TOML). Omit to use the chapter's (scenes/paper.toml, embedded).
        scene: Option<PathBuf>,
        /// Output directory (created if missing).
        #[arg(long, short, value_name = "DIR", default_value = "out/tradeoff")]
        out: PathBuf,
        /// Print only the findings and where the outputs are.
        #[arg(long, short)]
        quiet: bool,
    },
    /// Validate a scene and print it with every default resolved (nothing is computed).
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
    },
}

fn load(scene: Option<&Path>) -> Result<Scene, String> {
    match scene {
        Some(p) => Scene::load(p),
        None => Scene::paper(),
    }
    .map_err(|e| format!("invalid scene: {e}"))
}

fn describe(scene: &Scene) -> Vec<String> {
    let mut v = Vec::new();
    for s in &scene.studies {
        match s {
            Study::Uniaxial(u) => v.push(format!(
                "{}: {} stretches, {} passive curve(s), {} constant-γ curve(s), {} active model(s)",
                u.name,
                u.stretches.len(),
                usize::from(u.passive) + u.compare.len(),
                u.constant_gamma.len(),
                u.models.len()
            )),
            Study::Cylinder(c) => v.push(format!(
                "{}: {} × {} cells, {} stretches, {} FE sweep(s)",
                c.name,
                c.nr,
                c.nz,
                c.stretches.len(),
                c.damages.len()
            )),
            Study::Fit(f) => v.push(format!(
                "{}: {} fit(s) of {} parameter(s) {:?} to {}",
                f.name,
                f.cases.len(),
                f.free.len(),
                f.free,
                f.source
            )),
            Study::Stability(st) => v.push(format!(
                "{}: {} model(s) × {} stretches, {} normals",
                st.name,
                st.models.len() + usize::from(st.passive),
                st.stretches.len(),
                st.normals
            )),
            Study::Tradeoff(t) => v.push(format!(
                "{}: option groups {}",
                t.name,
                t.options
                    .groups
                    .iter()
                    .map(|g| g.key())
                    .collect::<Vec<_>>()
                    .join(", ")
            )),
        }
    }
    v
}

fn check(path: &Path) -> Result<(), String> {
    let scene = load(Some(path))?;
    let text = toml::to_string_pretty(&scene.resolved)
        .map_err(|e| format!("cannot print the resolved scene: {e}"))?;
    println!(
        "# {}: valid. Resolved scene (every default written out):\n",
        scene.file
    );
    println!("{text}");
    println!("# What `activemuscle run` would compute:");
    for line in describe(&scene) {
        println!("#   {line}");
    }
    Ok(())
}

fn rustc_version() -> Option<String> {
    let out = std::process::Command::new("rustc")
        .arg("--version")
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn summary(results: &Results, out: &Path, wall: f64) {
    println!();
    println!(
        "{:<48} {:>9} {:>7} {:>14} {:>9}",
        "study", "kind", "models", "points", "time [s]"
    );
    println!("{}", "-".repeat(91));
    for s in &results.studies {
        println!(
            "{:<48} {:>9} {:>7} {:>14} {:>9.2}",
            s.name,
            s.kind,
            s.models,
            format!("{}/{}", s.points, s.requested),
            s.elapsed.as_secs_f64()
        );
    }
    for c in &results.fe_vs_0d {
        if c.bases == "sliding" {
            let worst = c
                .points
                .iter()
                .map(|p| (p.1 - p.2).abs())
                .fold(0.0f64, f64::max);
            println!(
                "verification (sliding bases, {}): max |P_FE − P_0D| = {worst:.2e} kPa",
                c.label
            );
        }
    }
    for n in &results.notes {
        println!("note: {} — {}: {}", n.study, n.model, n.message);
    }
    let failed = results.fits.iter().filter(|f| !f.converged).count();
    if failed > 0 {
        println!(
            "{failed} of {} fit(s) did NOT converge (best points reported in fits.csv and report.html); the run continued",
            results.fits.len()
        );
    }
    println!(
        "{} rows; outputs in {} (report.html, curves.csv, figures); wall time {wall:.1} s",
        results.rows.len(),
        out.display()
    );
}

fn run_command(scene: Option<&Path>, out: &Path, quiet: bool) -> Result<(), String> {
    let start = Instant::now();
    let scene = load(scene)?;
    let mut staging = Staging::new(out).map_err(|e| e.to_string())?;
    let vtk_dir = staging.dir().join("vtk");
    let options = RunOptions {
        verbose: !quiet,
        progress: std::io::stdout().is_terminal(),
        vtk_dir: Some(vtk_dir),
    };
    if !quiet {
        println!(
            "activemuscle {}: {} ({})",
            env!("CARGO_PKG_VERSION"),
            scene.title,
            scene.file
        );
    }
    let results = run(&scene, &options).map_err(|e| e.to_string())?;

    let mut files = Vec::new();
    staging
        .write(
            "curves.csv",
            &to_csv(&results.rows).map_err(|e| e.to_string())?,
        )
        .map_err(|e| e.to_string())?;
    files.push("curves.csv".to_string());
    for (name, bytes) in tables(&results).map_err(|e| e.to_string())? {
        staging.write(name, &bytes).map_err(|e| e.to_string())?;
        files.push(name.to_string());
    }
    staging
        .write("scene.toml", scene.source.as_bytes())
        .map_err(|e| e.to_string())?;
    files.push("scene.toml".to_string());
    let mut rendered = Vec::new();
    for f in figures(&scene, &results) {
        let png = staging
            .path(Path::new(&format!("{}.png", f.stem)))
            .map_err(|e| e.to_string())?;
        let svg = staging
            .path(Path::new(&format!("{}.svg", f.stem)))
            .map_err(|e| e.to_string())?;
        render(&f, &png, &svg).map_err(|e| e.to_string())?;
        let bytes =
            std::fs::read(&png).map_err(|e| format!("cannot read back {}: {e}", png.display()))?;
        files.push(format!("{}.png", f.stem));
        files.push(format!("{}.svg", f.stem));
        rendered.push((f, bytes));
    }
    for v in &results.vtk_files {
        let rel = Path::new("vtk").join(v);
        staging.adopt(&rel).map_err(|e| e.to_string())?;
        files.push(rel.display().to_string());
    }
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    if let Some(t) = &results.tradeoff {
        let (staged, pngs) = report::stage(
            t,
            &mut staging,
            &scene.title,
            &command,
            start.elapsed().as_secs_f64(),
        )
        .map_err(|e| e.to_string())?;
        files.extend(staged);
        for f in pngs {
            let figure = Figure {
                heading: format!("Speed versus accuracy: {}", f.option),
                caption: report::caption(&f.option, &t.rows),
                stem: f.stem,
                panels: Vec::new(),
            };
            rendered.push((figure, f.png));
        }
    }
    let info = RunInfo {
        command,
        wall: start.elapsed(),
        version: env!("CARGO_PKG_VERSION").to_string(),
        rustc: rustc_version(),
        files,
    };
    let page = html(&scene, &results, &rendered, &info).map_err(|e| e.to_string())?;
    staging
        .write("report.html", page.as_bytes())
        .map_err(|e| e.to_string())?;
    staging.commit().map_err(|e| e.to_string())?;
    summary(&results, out, start.elapsed().as_secs_f64());
    Ok(())
}

fn tradeoff_command(scene: Option<&Path>, out: &Path, quiet: bool) -> Result<(), String> {
    use activemuscle::tradeoff::run as run_tradeoff;
    let start = Instant::now();
    let scene = load(scene)?;
    // The scene's tradeoff study if it has one, else every option on the scene's cylinder.
    let chosen = scene.studies.iter().find_map(|s| match s {
        Study::Tradeoff(t) => Some(t.options.clone()),
        _ => None,
    });
    let options = TradeoffOptions {
        verbose: !quiet,
        ..chosen.unwrap_or_default()
    };
    let results = run_tradeoff(&scene, &options).map_err(|e| e.to_string())?;
    let command = std::env::args().collect::<Vec<_>>().join(" ");
    let wall = start.elapsed().as_secs_f64();
    let files = report::write_all(&results, out, &scene.title, &command, wall)
        .map_err(|e| e.to_string())?;
    if !quiet {
        println!("\n{}", report::markdown(&results.rows));
    }
    for f in &results.findings {
        println!("{f}");
    }
    println!(
        "{} files in {} (tradeoff.html, tradeoff.csv); wall time {:.1} s",
        files.len(),
        out.display(),
        start.elapsed().as_secs_f64()
    );
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let outcome = match &cli.command {
        None => run_command(None, Path::new("out"), false),
        Some(Command::Run { scene, out, quiet }) => run_command(scene.as_deref(), out, *quiet),
        Some(Command::Check { scene }) => check(scene),
        Some(Command::Tradeoff { scene, out, quiet }) => {
            tradeoff_command(scene.as_deref(), out, *quiet)
        }
    };
    match outcome {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
