//! Unattended runs that never lie (issue 11): a study that fails costs no other study its
//! results, the run writes everything it computed, names every failure in its summary and
//! report, and exits 3; invalid input exits 1; complete success alone exits 0.

use crate::binary;
use crate::scratch;

use binary::run_args;
use scratch::{scratch, Scratch};
use std::path::{Path, PathBuf};
use std::process::Output;

/// A fresh directory for one test, removed when it ends.
fn temp_dir(name: &str) -> Scratch {
    scratch(&format!("cli-runs-{name}"))
}

const HEAD: &str = r#"title = "one study fails"
[material]
energy = "giantesio-musesti"
[activation]
law = "explicit"
"#;

const UNIAXIAL: &str = r#"
[[study]]
kind = "uniaxial"
name = "along"
direction = "along"
laws = ["implicit"]
stretch = [0.9, 1.0, 1.1, 1.2]
"#;

/// Writes `text` as `dir/name.toml` and runs it into `dir/name`.
fn run_scene(dir: &Path, name: &str, text: &str) -> (Output, PathBuf) {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).expect("write scene");
    let out = dir.join(name);
    let output = run_args(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    (output, out)
}

fn read(p: &Path) -> String {
    std::fs::read_to_string(p).unwrap_or_else(|e| panic!("{}: {e}", p.display()))
}

/// The rows of `curves.csv` of study rows whose `model` column is `model`.
fn rows_of(csv: &str, model: &str) -> Vec<String> {
    csv.lines()
        .filter(|l| l.split(',').any(|c| c == model))
        .map(str::to_string)
        .collect()
}

/// Each of the issue's reproducers, beside a uniaxial study: the uniaxial rows are exactly those
/// of the uniaxial study run alone, the failure is named in the summary and the report, exit 3.
#[test]
fn a_failing_cylinder_study_costs_the_others_nothing_and_exits_3() {
    let dir = temp_dir("reproducers");
    let (alone, alone_out) = run_scene(&dir, "alone", &format!("{HEAD}{UNIAXIAL}"));
    assert_eq!(alone.status.code(), Some(0), "{alone:?}");
    let reference = rows_of(&read(&alone_out.join("curves.csv")), "uniaxial");
    assert_eq!(reference.len(), 4 * 2, "passive + implicit at 4 stretches");
    let cylinders = [
        // Reaches no stretch: the material refuses a trial state on the way to 9.
        ("far", "nr = 2\nnz = 8\nstretch = [9.0]"),
        // Reaches no stretch: the reference state is not found.
        (
            "needle",
            "nr = 2\nnz = 2\nradius = 1e-6\nlength = 1e6\nstretch = [1.1]",
        ),
    ];
    for (name, keys) in cylinders {
        let text = format!(
            "{HEAD}{UNIAXIAL}\n[[study]]\nkind = \"cylinder\"\nname = \"cyl {name}\"\n{keys}\n"
        );
        let (output, out) = run_scene(&dir, name, &text);
        let stdout = String::from_utf8_lossy(&output.stdout);
        assert_eq!(output.status.code(), Some(3), "{name}: {output:?}");
        assert_eq!(
            rows_of(&read(&out.join("curves.csv")), "uniaxial"),
            reference,
            "{name}"
        );
        assert!(
            stdout.contains(&format!("FAILED: cyl {name}")) && stdout.contains("INCOMPLETE"),
            "{name}: {stdout}"
        );
        let report = read(&out.join("report.html"));
        assert!(report.contains(&format!("cyl {name}")), "{name}");
        assert!(!report.contains("NaN"), "{name}");
    }
}

/// The explicit law's γ leaves its domain (b = 1e6): refused before anything is computed, exit
/// 1, naming the study's law, where eq. (14) fails and what to do instead.
#[test]
fn a_law_outside_its_domain_is_refused_before_computing() {
    let dir = temp_dir("law");
    let head = HEAD.replace(
        "law = \"explicit\"\n",
        "law = \"explicit\"\nexplicit = { a = 1.0133, b = 1e6 }\n",
    );
    let text = format!(
        "{head}{UNIAXIAL}\n[[study]]\nkind = \"cylinder\"\nname = \"cyl b\"\nnr = 2\nnz = 2\nstretch = [1.1]\n"
    );
    let (output, out) = run_scene(&dir, "b", &text);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{output:?}");
    for words in [
        "law = \"explicit\"",
        "eq. (14)",
        "b = 1000000",
        "fit = \"explicit-law\"",
    ] {
        assert!(stderr.contains(words), "{words:?} missing: {stderr}");
    }
    assert!(!out.join("curves.csv").exists());
}

/// Invalid input exits 1 and names the file and line: a tolerance below round-off, a usage
/// error.
#[test]
fn invalid_input_exits_1() {
    let dir = temp_dir("invalid");
    let text = format!(
        "{HEAD}\n[[study]]\nkind = \"cylinder\"\nnr = 2\nnz = 2\nstretch = [1.1]\ntolerance = 1e-300\n"
    );
    let (output, out) = run_scene(&dir, "tol", &text);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("tol.toml:12") && stderr.contains("tolerance"),
        "{stderr}"
    );
    assert!(!out.join("curves.csv").exists());
    let usage = run_args(&["run", "--no-such-flag"]);
    assert_eq!(usage.status.code(), Some(1));
    let help = run_args(&["run", "--help"]);
    assert_eq!(help.status.code(), Some(0));
    let help = String::from_utf8_lossy(&help.stdout);
    assert!(
        help.contains("Exit status:") && help.contains("\n  3 "),
        "{help}"
    );
}

/// `check` on `text` (as `dir/name.toml`): exit 1, and stderr names `name.toml:line` and every
/// needle.
fn refused(dir: &Path, name: &str, text: &str, line: usize, needles: &[&str]) {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).expect("write scene");
    let output = run_args(&["check".as_ref(), scene.as_os_str()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{name}: {stderr}");
    assert!(
        stderr.contains(&format!("{name}.toml:{line}:")),
        "{name}: not at line {line}: {stderr}"
    );
    for n in needles {
        assert!(stderr.contains(n), "{name}: lacks {n:?}: {stderr}");
    }
}

const CYLINDER: &str = "\n[[study]]\nkind = \"cylinder\"\nnr = 2\nnz = 2\nstretch = [1.1]\n";

/// A fibre the axisymmetric cylinder cannot represent is refused where it is written, with the
/// reason; homogeneous studies alone accept it (they are relative to the fibre).
#[test]
fn an_oblique_fibre_with_a_cylinder_is_refused_at_its_line() {
    let dir = temp_dir("fibre");
    let head = HEAD.replace(
        "energy = \"giantesio-musesti\"\n",
        "energy = \"giantesio-musesti\"\nfibre = [1, 1, 0]\n",
    );
    refused(
        &dir,
        "oblique",
        &format!("{head}{UNIAXIAL}{CYLINDER}"),
        4,
        &["material.fibre", "study[1]", "axis"],
    );
    let alone = dir.join("alone.toml");
    std::fs::write(&alone, format!("{head}{UNIAXIAL}")).expect("write");
    assert_eq!(
        run_args(&["check".as_ref(), alone.as_os_str()])
            .status
            .code(),
        Some(0)
    );
}

/// Names that give the same output name, and a damage given twice, are refused at their line.
#[test]
fn colliding_names_and_duplicate_damages_are_refused_at_their_line() {
    let dir = temp_dir("names");
    let two = |kind: &str, a: &str, b: &str| {
        format!(
            "{HEAD}\n[[study]]\nkind = \"{kind}\"\nname = \"{a}\"\nstretch = [1.1]\n\
             \n[[study]]\nkind = \"{kind}\"\nname = \"{b}\"\nstretch = [1.1]\n"
        )
    };
    // The second name is on line 14 of each.
    refused(
        &dir,
        "cyl",
        &two("cylinder", "cyl A", "cyl-a"),
        14,
        &["study[1].name", "cyl_a", "study[0]"],
    );
    refused(
        &dir,
        "stab",
        &two("stability", "stab X", "stab-x"),
        14,
        &["study[1].name", "stab_x"],
    );
    refused(
        &dir,
        "damage",
        &format!("{HEAD}{CYLINDER}damage = [0.5, 0.5]\n"),
        12,
        &["study[0].damage[1]", "damage[0] is the same damage"],
    );
    refused(
        &dir,
        "defaults",
        &HEAD.replace(
            "law = \"explicit\"\n",
            "law = \"explicit\"\ndamage = [0.2, 0.2]\n",
        ),
        6,
        &["activation.damage[1]"],
    );
}

/// A sweep long by its many stretches on a small mesh, between two cheap studies.
const LONG: &str = r#"title = "long"
[[study]]
kind = "uniaxial"
name = "before"
stretch = [0.9, 1.0, 1.1]
[[study]]
kind = "cylinder"
name = "long sweep"
nr = 1
nz = 8
bases = "sliding"
stretch = { from = 1.0005, to = 1.8, step = 0.0005 }
[[study]]
kind = "uniaxial"
name = "after"
stretch = [0.9, 1.0, 1.1]
"#;

/// The stretches (column `lambda`) of the cylinder rows of `curves.csv`.
fn cylinder_stretches(csv: &str) -> Vec<String> {
    let head: Vec<&str> = csv.lines().next().expect("header").split(',').collect();
    let at = head.iter().position(|c| *c == "lambda").expect("lambda");
    rows_of(csv, "cylinder")
        .iter()
        .map(|r| r.split(',').nth(at).expect("lambda cell").to_string())
        .collect()
}

/// The stretches that progress lines (`[  t s] study: model: lambda = X solved, ...`) report.
fn reported_stretches(lines: &[String]) -> Vec<String> {
    let mut v: Vec<String> = lines
        .iter()
        .filter_map(|l| {
            let rest = l.split("lambda = ").nth(1)?;
            Some(rest.split(' ').next()?.to_string())
        })
        .collect();
    v.sort_by(|a, b| a.parse::<f64>().unwrap().total_cmp(&b.parse().unwrap()));
    v
}

/// Runs the binary with `args`, sends `signal` (`INT`, `TERM`) once a stdout line satisfies
/// `ready`, and returns the exit code and every stdout line.
fn signalled(
    args: &[&std::ffi::OsStr],
    signal: &str,
    ready: impl Fn(&str) -> bool,
) -> (Option<i32>, Vec<String>) {
    use std::io::{BufRead, BufReader};
    use std::process::{Command, Stdio};
    let mut child = Command::new(env!("CARGO_BIN_EXE_activemuscle"))
        .args(args)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn");
    let mut lines = BufReader::new(child.stdout.take().expect("stdout")).lines();
    let mut seen = Vec::new();
    for line in lines.by_ref() {
        let line = line.expect("line");
        let go = ready(&line);
        seen.push(line);
        if go {
            break;
        }
    }
    let kill = Command::new("kill")
        .arg(format!("-{signal}"))
        .arg(child.id().to_string())
        .status()
        .expect("kill");
    assert!(kill.success());
    seen.extend(lines.map(|l| l.expect("line")));
    (child.wait().expect("wait").code(), seen)
}

/// SIGINT (Ctrl-C) or SIGTERM (`kill`, a batch scheduler's time limit) during a long sweep,
/// stdout a pipe: a progress line per solved stretch (plain, stamped), and after the signal the
/// solved stretches are in curves.csv, exactly those the progress lines reported, the study
/// after is complete or recorded as not run, exit 128 + the signal.
#[test]
fn a_signal_keeps_the_solved_stretches_and_exits_128_plus_the_signal() {
    for (signal, status) in [("INT", 130), ("TERM", 143)] {
        signal_keeps_the_solved_stretches(signal, status);
    }
}

fn signal_keeps_the_solved_stretches(signal: &str, code: i32) {
    let dir = temp_dir(&format!("sig{signal}"));
    let scene = dir.join("long.toml");
    std::fs::write(&scene, LONG).expect("write scene");
    let out = dir.join("out");
    let (status, seen) = signalled(
        &[
            "run".as_ref(),
            scene.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ],
        signal,
        |line| line.starts_with('[') && line.contains("solved"),
    );
    let stdout = seen.join("\n");
    assert_eq!(status, Some(code), "{stdout}");
    let solved = cylinder_stretches(&read(&out.join("curves.csv")));
    assert!(
        !solved.is_empty() && solved.len() < 1599,
        "{}",
        solved.len()
    );
    assert_eq!(solved, reported_stretches(&seen));
    // The studies run at the same time: "after" either ran beside the long sweep (its rows are
    // written) or had not started when the signal came (recorded as not run), nothing else.
    let after_rows = rows_of(&read(&out.join("curves.csv")), "after").len();
    let not_run = stdout.contains("FAILED: after — the whole study: not run: interrupted");
    assert!(
        (after_rows > 0) != not_run,
        "after: {after_rows} rows, not run: {not_run}\n{stdout}"
    );
    let reason = format!("interrupted (SIG{signal})");
    assert!(
        stdout.contains(&format!("{reason}: sweep cancelled")),
        "{stdout}"
    );
    assert!(read(&out.join("report.html")).contains(&reason));
}

/// SIGTERM during `activemuscle tradeoff`: the option group running is finished, the groups after
/// it are named as not run, what was measured is written, exit 143.
#[test]
fn a_signal_during_a_tradeoff_keeps_what_was_measured() {
    let dir = temp_dir("tradeoff-signal");
    let scene = dir.join("tradeoff.toml");
    std::fs::write(
        &scene,
        "[[study]]\nkind = \"tradeoff\"\noptions = [\"activation-law\", \"newton-tolerance\", \"mesh\"]\n\
         stretch = { from = 0.7, to = 1.5, step = 0.01 }\nnr = 1\nnz = 4\nmeshes = [[1, 4], [2, 8]]\n",
    )
    .expect("write scene");
    let out = dir.join("out");
    // After the first measured variant the first group (activation law, 0D; each variant is
    // repeated for 0.3 s) has ≥ 0.6 s to go.
    let (status, seen) = signalled(
        &[
            "tradeoff".as_ref(),
            scene.as_os_str(),
            "--out".as_ref(),
            out.as_os_str(),
        ],
        "TERM",
        |line| line.contains("activation law (0D)"),
    );
    let stdout = seen.join("\n");
    assert_eq!(status, Some(143), "{stdout}");
    for group in ["newton-tolerance", "mesh"] {
        assert!(
            stdout.contains(&format!(
                "FAILED: option group {group}: not run: interrupted (SIGTERM)"
            )),
            "{group}: {stdout}"
        );
    }
    let csv = read(&out.join("tradeoff.csv"));
    assert!(csv.contains("activation law (0D)"), "{csv}");
    assert!(!csv.contains("Newton tolerance"), "{csv}");
}

/// `--max-seconds` stops like an interruption, names the time limit and exits 3.
#[test]
fn a_time_limit_keeps_the_solved_stretches_and_exits_3() {
    let dir = temp_dir("deadline");
    let scene = dir.join("long.toml");
    std::fs::write(&scene, LONG).expect("write scene");
    let out = dir.join("out");
    let output = run_args(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--max-seconds".as_ref(),
        "0.2".as_ref(),
    ]);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(3), "{stdout}");
    assert!(stdout.contains("time limit of 0.2 s (--max-seconds) reached"));
    let lines: Vec<String> = stdout.lines().map(str::to_string).collect();
    assert_eq!(
        cylinder_stretches(&read(&out.join("curves.csv"))),
        reported_stretches(&lines)
    );
    let bad = run_args(&["run", "--max-seconds", "-1", "--quiet"]);
    assert_eq!(bad.status.code(), Some(1));
}

/// A time limit beyond what the clock holds (1e20 s; issue 24, item 5: a panic, exit 101) is no
/// limit: the run completes, exit 0. A limit that is no number of seconds is refused (exit 1)
/// with the value written short.
#[test]
fn a_huge_time_limit_is_no_limit_and_never_panics() {
    let dir = temp_dir("huge-limit");
    for limit in ["1e20", "1.7976931348623157e308"] {
        let out = dir.join(format!("out-{limit}"));
        let output = run_into(&dir, "a", SMALL, &out, &["--max-seconds", limit]);
        assert_eq!(
            output.status.code(),
            Some(0),
            "{limit}: {}",
            String::from_utf8_lossy(&output.stderr)
        );
        assert!(out.join("curves.csv").is_file(), "{limit}");
    }
    for (limit, shown) in [("-1e300", "-1e300"), ("NaN", "NaN"), ("0", "0")] {
        // `=`: clap would take a bare `-1e300` for an option.
        let arg = format!("--max-seconds={limit}");
        let output = run_into(&dir, "a", SMALL, &dir.join("refused"), &[&arg]);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(1), "{limit}: {stderr}");
        assert!(
            stderr.contains(&format!("--max-seconds {shown}:")) && stderr.len() < 200,
            "{limit}: {stderr}"
        );
    }
}

const SMALL: &str = "title = \"small\"\n[[study]]\nkind = \"uniaxial\"\nname = \"along\"\nstretch = [0.9, 1.0, 1.1]\n";
const ACROSS: &str = "title = \"small\"\n[[study]]\nkind = \"uniaxial\"\nname = \"across\"\ndirection = \"across\"\nstretch = [0.9, 1.0, 1.1]\n";

/// `run SCENE --out OUT --quiet EXTRA…` with `text` written as `dir/name.toml`.
fn run_into(dir: &Path, name: &str, text: &str, out: &Path, extra: &[&str]) -> Output {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).expect("write scene");
    let mut args: Vec<&std::ffi::OsStr> = vec![
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ];
    args.extend(extra.iter().map(std::ffi::OsStr::new));
    run_args(&args)
}

/// The names in `dir`, sorted, hidden bookkeeping files included.
fn listing(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .expect("list")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// A re-run into its own directory leaves exactly the files a run into a fresh directory
/// writes: the first run's figures that the second does not draw are gone.
#[test]
fn a_rerun_leaves_no_stale_file() {
    let dir = temp_dir("rerun");
    let (out, fresh) = (dir.join("out"), dir.join("fresh"));
    assert_eq!(
        run_into(&dir, "along", SMALL, &out, &[]).status.code(),
        Some(0)
    );
    let first = listing(&out);
    assert_eq!(
        run_into(&dir, "across", ACROSS, &out, &[]).status.code(),
        Some(0)
    );
    assert_eq!(
        run_into(&dir, "across", ACROSS, &fresh, &[]).status.code(),
        Some(0)
    );
    assert_eq!(listing(&out), listing(&fresh));
    assert!(first.len() > listing(&out).len(), "{first:?}");
}

/// A directory another live run holds is refused; a dead run's lock and staging directory are
/// taken over and removed.
#[test]
fn a_second_run_refuses_a_directory_a_live_run_holds() {
    let dir = temp_dir("lock");
    let out = dir.join("out");
    std::fs::create_dir_all(&out).expect("mkdir");
    // This test's own process stands for a live run.
    std::fs::write(
        out.join(".activemuscle.lock"),
        std::process::id().to_string(),
    )
    .expect("lock");
    let refused = run_into(&dir, "a", SMALL, &out, &[]);
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(1), "{stderr}");
    assert!(stderr.contains(&format!("another run (pid {})", std::process::id())));
    assert!(!out.join("curves.csv").exists());
    // A pid above Linux's maximum (2^22) is no live process.
    std::fs::write(out.join(".activemuscle.lock"), "4294967").expect("lock");
    std::fs::create_dir_all(out.join(".activemuscle-partial-4294967/vtk")).expect("mkdir");
    assert_eq!(run_into(&dir, "a", SMALL, &out, &[]).status.code(), Some(0));
    let left = listing(&out);
    assert!(
        !left
            .iter()
            .any(|n| n.starts_with(".activemuscle-partial") || n == ".activemuscle.lock"),
        "{left:?}"
    );
}

/// A trade-off that measures little (one option, two tolerances, a 1 × 4 mesh): about a second.
const TINY_TRADEOFF: &str = "[[study]]\nkind = \"tradeoff\"\noptions = [\"newton-tolerance\"]\n\
                             stretch = [1.0, 1.1]\nnr = 1\nnz = 4\ntolerances = [1e-6, 1e-10]\n";

/// `tradeoff dir/name.toml --out OUT --quiet` with `text` written as the scene.
fn tradeoff_into(dir: &Path, name: &str, text: &str, out: &Path) -> Output {
    let scene = dir.join(format!("{name}.toml"));
    std::fs::write(&scene, text).expect("write scene");
    run_args(&[
        "tradeoff".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ])
}

/// `run` and `tradeoff` into one directory (issue 24, item 4): each command replaces only its own
/// files, so the run's curves.csv, report.html and figures survive a trade-off written beside
/// them (they were deleted, exit 0), and the trade-off's files survive a re-run.
#[test]
fn run_and_tradeoff_into_one_directory_keep_each_others_outputs() {
    let dir = temp_dir("mixed");
    let out = dir.join("mixed");
    assert_eq!(run_into(&dir, "a", SMALL, &out, &[]).status.code(), Some(0));
    let run_files: Vec<String> = listing(&out)
        .into_iter()
        .filter(|n| !n.starts_with('.'))
        .collect();
    for expected in ["curves.csv", "report.html", "scene.toml"] {
        assert!(run_files.iter().any(|n| n == expected), "{run_files:?}");
    }
    assert!(
        run_files.iter().any(|n| n.ends_with(".png")),
        "{run_files:?}"
    );
    let curves = read(&out.join("curves.csv"));
    let report = read(&out.join("report.html"));
    let trade = tradeoff_into(&dir, "t", TINY_TRADEOFF, &out);
    assert_eq!(
        trade.status.code(),
        Some(0),
        "{}",
        String::from_utf8_lossy(&trade.stderr)
    );
    let after = listing(&out);
    for f in &run_files {
        assert!(after.contains(f), "{f} of the run is gone: {after:?}");
    }
    assert_eq!(read(&out.join("curves.csv")), curves);
    assert_eq!(read(&out.join("report.html")), report);
    for f in ["tradeoff.csv", "tradeoff.md", "tradeoff.html"] {
        assert!(out.join(f).is_file(), "{f}: {after:?}");
    }
    // A re-run of each replaces its own files and leaves the other's.
    assert_eq!(run_into(&dir, "a", SMALL, &out, &[]).status.code(), Some(0));
    assert_eq!(listing(&out), after, "a re-run of `run`");
    assert_eq!(
        tradeoff_into(&dir, "t", TINY_TRADEOFF, &out).status.code(),
        Some(0)
    );
    assert_eq!(listing(&out), after, "a re-run of `tradeoff`");
    assert_eq!(read(&out.join("curves.csv")), curves);
}

/// A non-empty directory no run of ours wrote is refused (`tradeoff` too, before computing)
/// unless `--force`, which leaves the user's file alone; `/`, `.` and `..` are always refused.
#[test]
fn foreign_and_user_directories_are_refused() {
    let dir = temp_dir("foreign");
    let out = dir.join("mine");
    std::fs::create_dir_all(&out).expect("mkdir");
    std::fs::write(out.join("notes.txt"), "mine").expect("write");
    let refused = run_into(&dir, "a", SMALL, &out, &[]);
    assert_eq!(refused.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&refused.stderr).contains("--force"));
    assert_eq!(listing(&out), ["notes.txt"]);
    let tradeoff = run_args(&[
        "tradeoff".as_ref(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    assert_eq!(tradeoff.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&tradeoff.stderr).contains("--force"));
    assert!(tradeoff.stdout.is_empty(), "computed before refusing");
    assert_eq!(
        run_into(&dir, "a", SMALL, &out, &["--force"]).status.code(),
        Some(0)
    );
    assert_eq!(read(&out.join("notes.txt")), "mine");
    assert!(out.join("curves.csv").exists());
    let scene = dir.join("a.toml");
    for target in ["/", ".", ".."] {
        let output = std::process::Command::new(env!("CARGO_BIN_EXE_activemuscle"))
            .current_dir(&out)
            .args([
                "run".as_ref(),
                scene.as_os_str(),
                "--out".as_ref(),
                target.as_ref(),
                "--force".as_ref(),
            ])
            .output()
            .expect("run");
        assert_eq!(output.status.code(), Some(1), "{target}");
    }
    assert_eq!(listing(&dir), ["a.toml", "mine"]);
}

/// A commit that cannot complete (report.html blocked by a directory) changes nothing: the
/// previous run's files stay as they were, no new file appears beside them.
#[test]
fn a_blocked_commit_leaves_the_previous_outputs_unchanged() {
    let dir = temp_dir("blocked");
    let out = dir.join("out");
    assert_eq!(
        run_into(&dir, "across", ACROSS, &out, &[]).status.code(),
        Some(0)
    );
    std::fs::remove_file(out.join("report.html")).expect("rm");
    std::fs::create_dir_all(out.join("report.html").join("x")).expect("block");
    let before = listing(&out);
    let csv = read(&out.join("curves.csv"));
    let output = run_into(&dir, "along", SMALL, &out, &[]);
    assert_eq!(output.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&output.stderr).contains("nothing of this run was committed"));
    assert_eq!(listing(&out), before);
    assert_eq!(read(&out.join("curves.csv")), csv);
}

/// Meshes far beyond the memory limit (5000 × 10000 cells: thousands of GiB) are refused before
/// anything is allocated: a cylinder study's when the scene is read (exit 1, naming the key), a
/// trade-off study's before it computes, costing the other studies nothing; `tradeoff` refuses
/// before computing.
#[test]
fn meshes_beyond_the_memory_limit_are_refused_before_allocating() {
    let dir = temp_dir("memory");
    let cylinder = format!(
        "{HEAD}{UNIAXIAL}\n[[study]]\nkind = \"cylinder\"\nname = \"huge\"\nnr = 5000\nnz = 10000\nstretch = [1.1]\n"
    );
    let (output, out) = run_scene(&dir, "huge-cylinder", &cylinder);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{output:?}");
    assert!(
        stderr.contains("nr = 5000")
            && stderr.contains("5000 × 10000")
            && stderr.contains("of memory, above the limit"),
        "{stderr}"
    );
    assert!(!out.join("curves.csv").exists());
    let text = format!(
        "{HEAD}{UNIAXIAL}\n[[study]]\nkind = \"tradeoff\"\nname = \"huge tradeoff\"\nmeshes = [[2, 8], [5000, 10000]]\n"
    );
    // A tradeoff mesh beyond the limit is refused when the scene is read, as `check` does.
    let (output, out) = run_scene(&dir, "huge", &text);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{output:?}");
    assert!(
        stderr.contains("study[1].meshes")
            && stderr.contains("5000 × 10000")
            && stderr.contains("of memory, above the limit"),
        "{stderr}"
    );
    assert!(!out.join("curves.csv").exists());
    let tradeoff = run_args(&[
        "tradeoff".as_ref(),
        dir.join("huge.toml").as_os_str(),
        "--out".as_ref(),
        dir.join("tr").as_os_str(),
        "--quiet".as_ref(),
    ]);
    let stderr = String::from_utf8_lossy(&tradeoff.stderr);
    assert_eq!(tradeoff.status.code(), Some(1), "{stderr}");
    assert!(
        stderr.contains("study[1].meshes") && stderr.contains("of memory"),
        "{stderr}"
    );
    assert!(
        !dir.join("tr").exists(),
        "an output directory created for nothing"
    );
}

/// The literal energy law (γ = 0 below λ_min) on the clamped cylinder stops near λ = 0.73, where
/// its smallest fibre stretch reaches λ_min (README, findings): the stretches before are
/// written, the stop is named, exit 3 (it was 0).
#[test]
fn a_clamped_sweep_that_stops_early_exits_3() {
    let dir = temp_dir("clamped");
    let text = "title = \"clamped\"\n[activation]\nlaw = \"energy\"\nbelow_minimum = \"inactive\"\n\
                [[study]]\nkind = \"cylinder\"\nname = \"clamped\"\nnr = 2\nnz = 8\nstretch = [0.9, 0.8, 0.7]\n";
    let (output, out) = run_scene(&dir, "clamped", text);
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert_eq!(output.status.code(), Some(3), "{stdout}");
    assert_eq!(
        cylinder_stretches(&read(&out.join("curves.csv"))),
        ["0.8", "0.9"]
    );
    assert!(
        stdout.contains("FAILED: clamped") && stdout.contains("converged up to lambda = 0.73"),
        "{stdout}"
    );
}
