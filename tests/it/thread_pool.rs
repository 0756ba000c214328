//! The thread pool from the environment is bounded: `RAYON_NUM_THREADS=100000` spawned threads
//! for about ten minutes (the run doing nothing else, a SIGTERM unanswered); now it is cut to
//! four threads per available core, with a notice, and a signal is answered at once.
//!
//! The tests ask for a modest excess (a few threads above the bound), never a huge count: on a
//! build without the bound a huge count would start that many threads on a shared machine.

#![cfg(unix)]

use crate::scratch::scratch;
use std::io::{BufRead, BufReader};
use std::process::{Child, Command, Stdio};
use std::sync::mpsc;
use std::time::{Duration, Instant};

/// Waits at most `seconds` for `child`; kills it and fails past that.
fn wait_at_most(mut child: Child, seconds: u64, what: &str) -> std::process::Output {
    let start = Instant::now();
    while child.try_wait().expect("poll the child").is_none() {
        if start.elapsed() > Duration::from_secs(seconds) {
            let _ = child.kill();
            let _ = child.wait();
            panic!("{what}: not finished within {seconds} s");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    child.wait_with_output().expect("the child's output")
}

/// The available cores, as the binary counts them.
fn cores() -> usize {
    std::thread::available_parallelism().map_or(1, |n| n.get())
}

/// A thread count above the bound of four per core, small enough to start on any machine.
fn too_many() -> usize {
    4 * cores() + 3
}

fn activemuscle(args: &[&std::ffi::OsStr]) -> Command {
    let mut c = Command::new(env!("CARGO_BIN_EXE_activemuscle"));
    c.args(args)
        .env("RAYON_NUM_THREADS", too_many().to_string())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped());
    c
}

#[test]
fn a_thread_count_from_the_environment_above_four_per_core_is_bounded_with_a_notice() {
    let dir = scratch("threads-notice");
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "[[study]]\nkind = \"cylinder\"\nnr = 1\nnz = 4\nstretch = [0.9, 1.1]\n\
         [[study]]\nkind = \"uniaxial\"\nstretch = [0.9, 1.0, 1.1]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let child = activemuscle(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ])
    .spawn()
    .expect("spawn");
    let o = wait_at_most(child, 60, "a 2-stretch run with too many threads asked for");
    let stderr = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(0), "{stderr}");
    assert!(
        stderr.contains(&format!("RAYON_NUM_THREADS={}", too_many()))
            && stderr.contains(&format!("using {} threads", 4 * cores())),
        "{stderr}"
    );
    assert!(out.join("curves.csv").is_file());
}

#[test]
fn sigterm_is_answered_at_once_with_a_bounded_thread_count_from_the_environment() {
    let dir = scratch("threads-signal");
    let scene = dir.join("long.toml");
    std::fs::write(
        &scene,
        "[[study]]\nkind = \"cylinder\"\nname = \"long sweep\"\nnr = 1\nnz = 8\nbases = \"sliding\"\n\
         stretch = { from = 1.0005, to = 1.8, step = 0.0005 }\n",
    )
    .unwrap();
    let out = dir.join("out");
    let mut child = activemuscle(&[
        "run".as_ref(),
        scene.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
    ])
    .spawn()
    .expect("spawn");
    // The first solved stretch, read on a thread so that a run that never gets there fails.
    let stdout = child.stdout.take().expect("stdout");
    let (tx, rx) = mpsc::channel();
    std::thread::spawn(move || {
        // Reads to the end: a pipe left unread would block the run's last lines.
        for line in BufReader::new(stdout).lines().map_while(Result::ok) {
            if line.contains("solved") {
                let _ = tx.send(());
            }
        }
    });
    if rx.recv_timeout(Duration::from_secs(60)).is_err() {
        let _ = child.kill();
        let _ = child.wait();
        panic!("no stretch solved within 60 s");
    }
    let sent = Instant::now();
    let kill = Command::new("kill")
        .arg("-TERM")
        .arg(child.id().to_string())
        .status()
        .expect("kill");
    assert!(kill.success());
    let o = wait_at_most(child, 20, "the run after SIGTERM");
    assert_eq!(
        o.status.code(),
        Some(143),
        "{}",
        String::from_utf8_lossy(&o.stderr)
    );
    println!("exited {:.2} s after SIGTERM", sent.elapsed().as_secs_f64());
    assert!(
        out.join("curves.csv").is_file(),
        "what was solved is written"
    );
}
