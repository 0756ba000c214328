//! `activemuscle`: runs scene files (TOML) of active skeletal-muscle studies and writes the
//! curves, the figures and a report. Without arguments it runs the chapter's whole study.

use activemuscle::output::{tradeoff, write_run, RunMeta, Staging, Writer};
use activemuscle::scene::{Printing, Results, RunOptions, Scene};
use activemuscle::studies::tradeoff::{run_until as run_tradeoff, scene_options};
use activemuscle::studies::{Silent, Stop, StudyResult};
use activemuscle::AppError;
use clap::{Parser, Subcommand};
use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
use signal_hook::iterator::Signals;
use std::io::IsTerminal;
use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::sync::atomic::{AtomicI32, Ordering};
use std::time::{Duration, Instant};

/// `println!` that ignores a closed standard output (`activemuscle check scene.toml | head`):
/// the command goes on (a run still writes its files) instead of panicking on the broken pipe.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

/// [`say!`] for standard error.
macro_rules! say_err {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// Active skeletal-muscle mechanics after Giantesio & Musesti: homogeneous tests and an
/// axisymmetric FE cylinder, with loss of activation.
///
/// Without a subcommand, runs the chapter's whole study (the embedded scenes/paper.toml) and
/// writes curves.csv, the figures (PNG + SVG), report.html and VTK fields into out/.
#[derive(Parser, Debug)]
#[command(name = "activemuscle", version, about, long_about, after_help = EXIT_STATUS)]
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
    /// committed all or nothing: a run that fails leaves the previous outputs as they were,
    /// except on a full disk, where the data written first (the CSV tables, datapackage.json)
    /// is kept (exit 4). DIR
    /// belongs to one run at a time (.activemuscle.lock); a re-run replaces its own files and
    /// removes those it no longer writes (.activemuscle-manifest), never the files `tradeoff`
    /// wrote into DIR; a non-empty directory that no run wrote is refused without --force; /, your home, . and its ancestors always.
    #[command(after_help = EXIT_STATUS)]
    Run {
        /// Scene file (TOML). Omit to run the chapter's study (scenes/paper.toml, embedded).
        scene: Option<PathBuf>,
        /// Output directory (created if missing).
        #[arg(long, short, value_name = "DIR", default_value = "out")]
        out: PathBuf,
        /// No progress bars or log lines; print only the summary.
        #[arg(long, short)]
        quiet: bool,
        /// Write into DIR even if it holds files that no activemuscle run wrote (they are left
        /// alone unless an output has the same name).
        #[arg(long)]
        force: bool,
        /// Stop after this many seconds of wall time as an interruption does (the sweeps keep
        /// the stretches they solved, everything computed is written), and exit 3.
        #[arg(long, value_name = "SECONDS")]
        max_seconds: Option<f64>,
    },
    /// Measure speed against accuracy for every option that trades one for the other.
    ///
    /// Activation law (0D and FE), derivative route, frozen tangent, mesh, Newton tolerance and 0D
    /// vs FE, each timed (wall time) and compared with a reference at its accurate end. Writes
    /// into DIR: tradeoff.csv, tradeoff.md, tradeoff_*.png/svg (log–log error vs time, Pareto
    /// front) and tradeoff.html (self-contained), listed in .activemuscle-manifest-tradeoff: a
    /// re-run replaces and removes only those, a run's outputs in DIR stay. Uses the scene's material and activation; the
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
        /// Write into DIR even if it holds files that no activemuscle run wrote.
        #[arg(long)]
        force: bool,
        /// Stop after this many seconds of wall time as an interruption does (the group
        /// measuring then is finished, the groups after it are listed as not run, what was
        /// measured is written), and exit 3.
        #[arg(long, value_name = "SECONDS")]
        max_seconds: Option<f64>,
    },
    /// Check the tangents of a scene's own material: the Taylor test of every model it can build.
    ///
    /// Runs one `kind = "tangent"` study with its defaults on the scene's material and activation
    /// (every law the material supports, both couplings, the scene's damages; states along and
    /// across the fibres, in shear, equibiaxial, random, near λ_min and at large fibre stretch)
    /// and, if the scene has a cylinder study, the finite-element level on a small mesh of its
    /// geometry; the scene's own studies are not run. Writes into DIR as `run` does:
    /// tangent_summary.csv (one row per model and state: orders, flags and why), tangent.csv
    /// (every remainder), the figures, report.html and scene.toml (the tangent study that ran).
    #[command(after_help = EXIT_STATUS)]
    Tangent {
        /// Scene file (TOML). Omit to check the chapter's (scenes/paper.toml, embedded).
        scene: Option<PathBuf>,
        /// Output directory (created if missing).
        #[arg(long, short, value_name = "DIR", default_value = "out/tangent")]
        out: PathBuf,
        /// No progress lines; print only the summary.
        #[arg(long, short)]
        quiet: bool,
        /// Write into DIR even if it holds files that no activemuscle run wrote.
        #[arg(long)]
        force: bool,
    },
    /// Validate a scene and print it with every default resolved (nothing is computed).
    Check {
        /// Scene file (TOML).
        scene: PathBuf,
    },
    /// Print the scene reference: every key a scene file takes, its type and what it is, and
    /// the shipped energies, curves, approaches and study kinds (Markdown, as
    /// docs/scene-reference.md).
    Keys,
}

fn load(scene: Option<&Path>) -> Result<Scene, AppError> {
    Ok(match scene {
        Some(p) => Scene::load(p)?,
        None => Scene::paper()?,
    })
}

fn check(path: &Path) -> Result<Ended, AppError> {
    let scene = load(Some(path))?;
    say!(
        "# {}: valid. Resolved scene (every default written out):\n",
        scene.file
    );
    say!("{}", scene.resolved_toml()?);
    say!("# What `activemuscle run` would compute:");
    for study in &scene.studies {
        say!("#   {}", study.describe());
    }
    Ok(Ended::Complete)
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

/// Prints one `OUTSIDE:` line per study, law and coupling that left the law's domain.
fn outside_lines(results: &Results) {
    for s in &results.studies {
        for l in &s.left_domain {
            say!("OUTSIDE: {} — {}: {}", s.name, l.model, l.message);
        }
    }
}

/// Prints the table of studies, every failure and where the outputs are (`written`: all of
/// them; else the run stopped writing, said after); says whether the run is complete.
fn summary(results: &Results, rows: usize, out: &Path, wall: f64, written: bool) {
    say!();
    study_table(results);
    for s in &results.studies {
        for line in s.result.console(&s.name) {
            say!("{line}");
        }
    }
    for (study, f) in results.failures() {
        say!("FAILED: {study} — {}: {}", f.model, f.message);
    }
    outside_lines(results);
    for s in &results.studies {
        if s.failures.is_empty() && s.points < s.requested {
            say!(
                "FAILED: {} — {} of {} requested points computed",
                s.name,
                s.points,
                s.requested
            );
        }
    }
    // A scene without a curve study (stability or trade-off only) writes no curves.csv.
    let curves = match rows {
        0 => String::new(),
        n => format!("{n} rows in curves.csv; "),
    };
    let outputs = if written {
        "report.html, the CSV tables, figures"
    } else {
        "not all written: see DISK FULL below"
    };
    say!(
        "{curves}outputs in {} ({outputs}); wall time {wall:.1} s",
        out.display()
    );
    if !results.complete() {
        let failed = results.studies.iter().filter(|s| !s.complete()).count();
        say!(
            "INCOMPLETE: {failed} of {} studies did not compute everything requested (FAILED lines above); \
             everything computed was written",
            results.studies.len()
        );
    }
}

/// The table of studies: name, kind, models, points computed of those requested, wall time.
fn study_table(results: &Results) {
    // Columns as wide as their longest entry (study names and kinds such as
    // activation-in-time are the scene's).
    let name_w = results
        .studies
        .iter()
        .map(|s| s.name.chars().count())
        .fold(5, usize::max);
    let kind_w = results
        .studies
        .iter()
        .map(|s| s.kind.name().len())
        .fold(4, usize::max);
    say!(
        "{:<name_w$} {:>kind_w$} {:>7} {:>14} {:>9}",
        "study",
        "kind",
        "models",
        "points",
        "wall [s]"
    );
    say!("{}", "-".repeat(name_w + kind_w + 34));
    for s in &results.studies {
        let points = match s.result {
            StudyResult::Nothing => "FAILED".to_string(),
            _ => format!("{}/{}", s.points, s.requested),
        };
        say!(
            "{:<name_w$} {:>kind_w$} {:>7} {:>14} {:>9.2}",
            s.name,
            s.kind.name(),
            s.models,
            points,
            s.elapsed.as_secs_f64()
        );
    }
    if results.ran_together() {
        say!("(the studies ran at the same time, sharing the cores: their wall times overlap)");
    }
}

/// The command line as the report shows it; an argument that is not UTF-8 (a path with byte
/// 0xFF) is shown with U+FFFD in its place (the file itself is opened by its bytes).
fn command_line() -> String {
    std::env::args_os()
        .map(|a| a.to_string_lossy().into_owned())
        .collect::<Vec<_>>()
        .join(" ")
}

/// The exit statuses, for `--help`.
const EXIT_STATUS: &str = "Exit status:
  0    every requested point, sweep and fit was computed and written
  1    invalid input or usage (nothing computed), or the outputs could not be written
  3    something requested failed or the time limit (--max-seconds) was reached (named on
       the FAILED lines of the summary and in report.html); everything computed was written
  4    the disk filled up while writing the outputs: the files written before (the data
       first: the CSV tables and datapackage.json) are kept, the line DISK FULL names the
       disk, the file and the space left
  130  interrupted (Ctrl-C, SIGINT; 143 for SIGTERM, 129 for SIGHUP): the stretches solved
       so far were written; a second signal aborts at once and writes nothing

Progress: a bar per study on a terminal, else one line per solved stretch; --quiet: neither.";

/// Exit status of a run that wrote everything it computed but not everything requested.
const EXIT_INCOMPLETE: u8 = 3;

/// Exit status of a run whose disk filled up while it wrote: what was written before is kept.
const EXIT_DISK_FULL: u8 = 4;

/// How a command ended, when it did not end in an error (exit status 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Ended {
    /// Everything requested was computed and written (exit status 0).
    Complete,
    /// Something requested failed; everything computed was written (exit status 3).
    Incomplete,
    /// Interrupted by this signal; everything computed was written (exit status 128 + signal).
    Interrupted(i32),
    /// The disk filled up while writing; the files written before are kept (exit status 4).
    DiskFull,
}

impl Ended {
    /// How a run ended that was not stopped by a full disk: the signal that stopped it (0: none),
    /// else whether everything requested was computed.
    fn from(signal: i32, complete: bool) -> Ended {
        if signal != 0 {
            Ended::Interrupted(signal)
        } else if complete {
            Ended::Complete
        } else {
            Ended::Incomplete
        }
    }
}

/// The signal that stopped the run (0: none). Its exit status is 128 + the signal, the shell's
/// convention (130 for SIGINT, 143 for SIGTERM, 129 for SIGHUP).
static STOPPED_BY: AtomicI32 = AtomicI32::new(0);

/// The reason an interrupted run gives.
fn interrupted(signal: i32) -> String {
    let name = match signal {
        SIGINT => "SIGINT",
        SIGTERM => "SIGTERM",
        SIGHUP => "SIGHUP",
        _ => "a signal",
    };
    format!("interrupted ({name})")
}

/// Stops `stop` on the first SIGINT (Ctrl-C), SIGTERM (`kill`, `timeout`, a batch scheduler's
/// time limit) or SIGHUP (the terminal closed); exits at once on the second.
fn on_interrupt(stop: &Stop) {
    let stop = stop.clone();
    let mut signals = match Signals::new([SIGINT, SIGTERM, SIGHUP]) {
        Ok(s) => s,
        Err(e) => {
            say_err!("warning: no signal handler ({e}): Ctrl-C or SIGTERM will end the run without writing");
            return;
        }
    };
    std::thread::spawn(move || {
        for signal in signals.forever() {
            if STOPPED_BY.swap(signal, Ordering::SeqCst) != 0 {
                say_err!("second interrupt: aborting without writing");
                std::process::exit(128 + signal);
            }
            say_err!(
                "{}: stopping after the current Newton iteration (a trade-off: after the current \
                 option group) and writing what was computed (interrupt again to abort)",
                interrupted(signal)
            );
            stop.stop(&interrupted(signal));
        }
    });
}

/// Prints the one line of a run whose disk filled up: which disk, which file, the space left,
/// and what of the run is kept in `out` (`kept`: the files committed).
fn disk_full(error: &AppError, out: &Path, kept: &[PathBuf]) {
    let names: Vec<String> = kept
        .iter()
        .filter_map(|p| p.strip_prefix(out).ok())
        .filter(|p| p.parent().is_none_or(|d| d.as_os_str().is_empty()))
        .map(|p| p.display().to_string())
        .collect();
    let shown = match names.len() {
        0 => "nothing".to_string(),
        n if n > 8 => format!("{}, … ({} files)", names[..8].join(", "), kept.len()),
        _ => format!("{} ({} files)", names.join(", "), kept.len()),
    };
    say!(
        "DISK FULL: {error}; kept in {}: {shown}; free space and run again",
        out.display()
    );
}

/// The free space of a simulated disk for the outputs, from `ACTIVEMUSCLE_TEST_DISK_SPACE`
/// (bytes): how the tests fill a disk without one (they run on the release build, as users do).
/// Unset, as in every run but theirs, the outputs go to the real disk.
fn simulated_disk() -> Option<u64> {
    std::env::var("ACTIVEMUSCLE_TEST_DISK_SPACE")
        .ok()?
        .parse()
        .ok()
}

/// Bounds the thread pool from the environment ([`activemuscle::threads`]), with a notice on
/// standard error when the count asked for is cut.
fn limit_threads() {
    if let Some(notice) = activemuscle::threads::limit_global_pool() {
        say_err!("{notice}");
    }
}

/// Stops `stop` once `seconds` of wall time have passed (a detached timer thread). `seconds`
/// must be finite and > 0; a limit beyond what a [`Duration`] holds (about 5.8e11 years) is no
/// limit.
fn time_limit(stop: &Stop, seconds: f64) -> Result<(), AppError> {
    if !(seconds.is_finite() && seconds > 0.0) {
        return Err(AppError::Invalid(format!(
            "--max-seconds {}: must be a finite number of seconds > 0",
            activemuscle::text::significant(seconds, 6)
        )));
    }
    let Ok(limit) = Duration::try_from_secs_f64(seconds) else {
        return Ok(());
    };
    let stop = stop.clone();
    std::thread::spawn(move || {
        std::thread::sleep(limit);
        stop.stop(&format!(
            "time limit of {} s (--max-seconds) reached",
            activemuscle::text::significant(seconds, 6)
        ));
    });
    Ok(())
}

fn run_command(
    scene: Option<&Path>,
    out: &Path,
    quiet: bool,
    force: bool,
    max_seconds: Option<f64>,
) -> Result<Ended, AppError> {
    let started = Instant::now();
    // Signals first: a SIGTERM while the scene is read or the threads start stops the run.
    let stop = Stop::new();
    on_interrupt(&stop);
    let scene = load(scene)?;
    if let Some(seconds) = max_seconds {
        time_limit(&stop, seconds)?;
    }
    let mut staging = Staging::open(out, Writer::Run, force)?;
    if let Some(space) = simulated_disk() {
        staging = staging.with_space(space);
    }
    let options = RunOptions {
        verbose: !quiet,
        progress: std::io::stdout().is_terminal(),
        vtk_dir: Some(staging.dir().join("vtk")),
        stop: Some(stop.clone()),
    };
    if !quiet {
        say!(
            "activemuscle {}: {} ({})",
            env!("CARGO_PKG_VERSION"),
            scene.title,
            scene.file
        );
    }
    let results = scene.run(&options);
    // A time limit reached after the last study is no stop.
    let signal = STOPPED_BY.load(Ordering::SeqCst);
    let reason = stop.reason().filter(|_| signal != 0 || !results.complete());
    let meta = RunMeta {
        command: command_line(),
        started,
        rustc: rustc_version(),
    };
    let (rows, full) = match write_run(&mut staging, &scene, &results, &meta) {
        Ok(rows) => (rows, None),
        Err(e @ AppError::DiskFull { .. }) => (0, Some(e)),
        Err(e) => return Err(e),
    };
    let kept = staging.commit()?;
    summary(
        &results,
        rows,
        out,
        started.elapsed().as_secs_f64(),
        full.is_none(),
    );
    if let Some(reason) = &reason {
        say!("STOPPED: {reason}; what was solved before is written");
    }
    if let Some(full) = full {
        disk_full(&full, out, &kept);
        return Ok(Ended::DiskFull);
    }
    Ok(Ended::from(signal, results.complete()))
}

fn tradeoff_command(
    scene: Option<&Path>,
    out: &Path,
    quiet: bool,
    force: bool,
    max_seconds: Option<f64>,
) -> Result<Ended, AppError> {
    let started = Instant::now();
    let stop = Stop::new();
    on_interrupt(&stop);
    let scene = load(scene)?;
    if let Some(seconds) = max_seconds {
        time_limit(&stop, seconds)?;
    }
    // The output directory is taken before computing: a refusal costs nothing.
    let mut staging = Staging::open(out, Writer::Tradeoff, force)?;
    if let Some(space) = simulated_disk() {
        staging = staging.with_space(space);
    }
    // The scene's tradeoff study if it has one, else every option on the scene's cylinder.
    let options = scene_options(&scene.studies, &scene.defaults);
    let printing = Printing::new(true, false);
    let bar = printing.study();
    let progress: &dyn activemuscle::studies::Progress = if quiet { &Silent } else { &bar };
    let results = run_tradeoff(&scene.models, &options, progress, Some(&stop))?;
    let wall = started.elapsed().as_secs_f64();
    let full = match tradeoff::stage(&results, &mut staging, &scene.title, &command_line(), wall) {
        Ok(_) => None,
        Err(e @ AppError::DiskFull { .. }) => Some(e),
        Err(e) => return Err(e),
    };
    let files = staging.commit()?;
    if let Some(full) = full {
        disk_full(&full, out, &files);
        return Ok(Ended::DiskFull);
    }
    if !quiet {
        say!("\n{}", tradeoff::markdown(&results.rows));
    }
    for f in &results.findings {
        say!("{f}");
    }
    say!(
        "{} files in {} (tradeoff.html, tradeoff.csv); wall time {:.1} s",
        files.len(),
        out.display(),
        started.elapsed().as_secs_f64()
    );
    // A group or a reference that could not be measured is a failure of what was asked; a
    // variant that did not converge is a measured result (its row says so).
    let failed = results.failed();
    for f in &failed {
        say!("FAILED: {}: {}", f.model, f.message);
    }
    let signal = STOPPED_BY.load(Ordering::SeqCst);
    // A time limit reached after the last group is no stop.
    let reason = stop.reason().filter(|_| signal != 0 || !failed.is_empty());
    if let Some(reason) = reason {
        say!("STOPPED: {reason}; what was measured before is written");
    }
    Ok(Ended::from(signal, failed.is_empty()))
}

/// `scene` with its studies replaced by the tangent study of its material
/// ([`activemuscle::studies::tangent::for_scene`]); its source, written as scene.toml, is that
/// study's scene with every default written out.
fn tangent_scene(mut scene: Scene) -> Result<Scene, AppError> {
    let (study, spec) = {
        let choices = scene.resolved.activation.defaults();
        let defaults = activemuscle::studies::spec::Defaults {
            models: &scene.models,
            approach: choices.approach,
            law: choices.law,
            coupling: choices.coupling,
            damage: &choices.damage,
            base: Path::new(&scene.file).parent().unwrap_or(Path::new("")),
        };
        activemuscle::studies::tangent::for_scene(&scene.studies, &defaults)
            .map_err(|e| AppError::Invalid(format!("{}: the tangent study: {e}", scene.file)))?
    };
    scene.studies = vec![activemuscle::studies::Study::Tangent(study)];
    scene.resolved.studies = vec![activemuscle::studies::StudySpec::Tangent(spec)];
    scene.source = format!(
        "# The tangent study `activemuscle tangent` ran on the material of {}.\n{}",
        scene.file,
        scene.resolved_toml()?
    );
    Ok(scene)
}

fn tangent_command(
    scene: Option<&Path>,
    out: &Path,
    quiet: bool,
    force: bool,
) -> Result<Ended, AppError> {
    let started = Instant::now();
    let scene = tangent_scene(load(scene)?)?;
    let mut staging = Staging::open(out, Writer::Run, force)?;
    let stop = Stop::new();
    on_interrupt(&stop);
    let options = RunOptions {
        verbose: !quiet,
        progress: std::io::stdout().is_terminal(),
        vtk_dir: None,
        stop: Some(stop.clone()),
    };
    let results = scene.run(&options);
    let meta = RunMeta {
        command: command_line(),
        started,
        rustc: rustc_version(),
    };
    write_run(&mut staging, &scene, &results, &meta)?;
    staging.commit()?;
    for s in &results.studies {
        for line in s.result.console(&s.name) {
            say!("{line}");
        }
    }
    for (study, f) in results.failures() {
        say!("FAILED: {study} — {}: {}", f.model, f.message);
    }
    outside_lines(&results);
    say!(
        "outputs in {} (report.html, tangent_summary.csv: why each flagged state is flagged); wall time {:.1} s",
        out.display(),
        started.elapsed().as_secs_f64()
    );
    let signal = STOPPED_BY.load(Ordering::SeqCst);
    Ok(Ended::from(signal, results.complete()))
}

fn main() -> ExitCode {
    limit_threads();
    let cli = match Cli::try_parse() {
        Ok(cli) => cli,
        // --help and --version print and succeed; a usage error is an invalid input (1).
        Err(e) => {
            let _ = e.print();
            return if e.use_stderr() {
                ExitCode::FAILURE
            } else {
                ExitCode::SUCCESS
            };
        }
    };
    let outcome = match &cli.command {
        None => run_command(None, Path::new("out"), false, false, None),
        Some(Command::Run {
            scene,
            out,
            quiet,
            force,
            max_seconds,
        }) => run_command(scene.as_deref(), out, *quiet, *force, *max_seconds),
        Some(Command::Check { scene }) => check(scene),
        Some(Command::Keys) => {
            say!("{}", activemuscle::scene::reference::markdown().trim_end());
            Ok(Ended::Complete)
        }
        Some(Command::Tangent {
            scene,
            out,
            quiet,
            force,
        }) => tangent_command(scene.as_deref(), out, *quiet, *force),
        Some(Command::Tradeoff {
            scene,
            out,
            quiet,
            force,
            max_seconds,
        }) => tradeoff_command(scene.as_deref(), out, *quiet, *force, *max_seconds),
    };
    match outcome {
        Ok(Ended::Complete) => ExitCode::SUCCESS,
        Ok(Ended::Incomplete) => ExitCode::from(EXIT_INCOMPLETE),
        Ok(Ended::DiskFull) => ExitCode::from(EXIT_DISK_FULL),
        Ok(Ended::Interrupted(signal)) => ExitCode::from(u8::try_from(128 + signal).unwrap_or(1)),
        Err(e @ AppError::DiskFull { .. }) => {
            say_err!("error: {e}");
            ExitCode::from(EXIT_DISK_FULL)
        }
        Err(e) => {
            say_err!("error: {e}");
            ExitCode::FAILURE
        }
    }
}
