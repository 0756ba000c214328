//! Bounded inputs (issue 24, item 6): a scene is read only from a regular file of at most
//! `MAX_SCENE_BYTES` (a device such as `/dev/zero` grew the process past 5.9 GB, a FIFO hung),
//! every list is capped with a message that says the cap and why (100 000 damages ran for 88 s
//! and wrote a 465 MB report; 2 million stretches a 198 MB CSV), and a legend never makes a
//! figure wider than a screen (a 566 148-pixel-wide PNG).

use crate::scratch::scratch;
use activemuscle::plot::{render, Figure, Panel, Series, Stroke};
use activemuscle::scene::{Scene, MAX_SCENE_BYTES};
use activemuscle::studies::spec::{MAX_DAMAGES, MAX_GRID_POINTS};
use std::sync::mpsc;
use std::time::Duration;

/// `Scene::load(path)`'s error, in words; fails the test if loading takes more than 10 s (a
/// blocked read) or succeeds.
fn load_error(path: &std::path::Path) -> String {
    let (send, receive) = mpsc::channel();
    let owned = path.to_path_buf();
    std::thread::spawn(move || {
        let _ = send.send(Scene::load(&owned).map(|_| ()).map_err(|e| e.to_string()));
    });
    receive
        .recv_timeout(Duration::from_secs(10))
        .expect("loading the scene returned within 10 s")
        .expect_err("the scene is refused")
}

#[cfg(unix)]
#[test]
fn a_device_a_fifo_and_a_directory_are_refused_as_scenes_without_reading_them() {
    assert!(load_error("/dev/zero".as_ref()).contains("a character device"));
    let dir = scratch("caps-fifo");
    let fifo = dir.join("scene.toml");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .expect("run mkfifo");
    assert!(made.success());
    assert!(load_error(&fifo).contains("a FIFO"));
    // A data file too: opening a FIFO blocks until a writer comes.
    let (send, receive) = mpsc::channel();
    let data = fifo.clone();
    std::thread::spawn(move || {
        let _ = send.send(activemuscle::fit::Data::from_csv_path(&data).map_err(|e| e.to_string()));
    });
    let e = receive
        .recv_timeout(Duration::from_secs(10))
        .expect("reading the data returned within 10 s")
        .expect_err("a FIFO is no data file");
    assert!(e.contains("a FIFO"), "{e}");
    // And through a scene's fit study, whose data file is opened once to read its header.
    let scene = dir.join("fit.toml");
    std::fs::write(
        &scene,
        "[[study]]\nkind = \"fit\"\nfit = \"passive\"\ndata = \"scene.toml\"\n",
    )
    .unwrap();
    let (send, receive) = mpsc::channel();
    std::thread::spawn(move || {
        let _ = send.send(Scene::load(&scene).map(|_| ()).map_err(|e| e.to_string()));
    });
    let e = receive
        .recv_timeout(Duration::from_secs(10))
        .expect("checking the scene returned within 10 s")
        .expect_err("a FIFO is no data file");
    assert!(e.contains("a FIFO") && e.contains("data"), "{e}");
    assert!(load_error(&dir).contains("a directory"));
}

#[test]
fn a_scene_file_larger_than_the_cap_is_refused_and_one_at_the_cap_is_read() {
    let dir = scratch("caps-size");
    let head = "[[study]]\nkind = \"uniaxial\"\nstretch = [1.1]\n";
    let at_cap = dir.join("at_cap.toml");
    let padding = "#".repeat(MAX_SCENE_BYTES as usize - head.len() - 1);
    std::fs::write(&at_cap, format!("{head}{padding}\n")).unwrap();
    assert_eq!(std::fs::metadata(&at_cap).unwrap().len(), MAX_SCENE_BYTES);
    Scene::load(&at_cap).expect("a scene of exactly the cap is read");
    let over = dir.join("over.toml");
    std::fs::write(&over, format!("{head}{padding}#\n")).unwrap();
    let e = load_error(&over);
    assert!(
        e.contains(&format!("larger than {MAX_SCENE_BYTES} bytes")),
        "{e}"
    );
}

/// A uniaxial study of `stretch` (TOML) with `damage` (TOML) in `[activation]`.
fn uniaxial(stretch: &str, damage: &str) -> String {
    format!(
        "[activation]\ndamage = {damage}\n\n[[study]]\nkind = \"uniaxial\"\nstretch = {stretch}\n"
    )
}

/// A TOML list of `n` stretches 1 + i·10⁻⁵.
fn stretches(n: usize) -> String {
    let v: Vec<String> = (0..n)
        .map(|i| format!("{}", 1.0 + i as f64 * 1e-5))
        .collect();
    format!("[{}]", v.join(", "))
}

#[test]
fn lists_longer_than_their_cap_are_refused_naming_the_key_the_cap_and_why() {
    let parse = |text: &str| Scene::parse(text, "caps.toml").map(|_| ());
    parse(&uniaxial(&stretches(MAX_GRID_POINTS), "[0.0]")).expect("a list at the cap");
    let e = parse(&uniaxial(&stretches(MAX_GRID_POINTS + 1), "[0.0]"))
        .expect_err("one stretch more")
        .to_string();
    assert!(e.contains("study[0].stretch"), "{e}");
    assert!(e.contains(&format!("at most {MAX_GRID_POINTS}")), "{e}");
    // A range that gives one value too many.
    let range = format!(
        "{{ from = 1.0, to = {}, step = 0.0001 }}",
        1.0 + MAX_GRID_POINTS as f64 * 1e-4
    );
    let e = parse(&uniaxial(&range, "[0.0]"))
        .expect_err("a range of one value too many")
        .to_string();
    assert!(e.contains("study[0].stretch.step"), "{e}");
    assert!(
        e.contains(&format!("more than {MAX_GRID_POINTS} values")),
        "{e}"
    );
    // Damages: each is a model and a curve in every figure.
    let damages = |n: usize| {
        let v: Vec<String> = (0..n).map(|i| format!("{}", i as f64 / 32.0)).collect();
        format!("[{}]", v.join(", "))
    };
    parse(&uniaxial("[1.1]", &damages(MAX_DAMAGES))).expect("damages at the cap");
    let e = parse(&uniaxial("[1.1]", &damages(MAX_DAMAGES + 1)))
        .expect_err("one damage more")
        .to_string();
    assert!(e.contains("activation.damage"), "{e}");
    assert!(e.contains(&format!("at most {MAX_DAMAGES} damages")), "{e}");
    assert!(e.contains("curve in every figure"), "{e}");
}

/// Width and height \[px\] of the PNG `bytes` (its IHDR chunk).
fn png_size(bytes: &[u8]) -> (u32, u32) {
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    let word = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (word(16), word(20))
}

#[test]
fn a_legend_of_many_curves_keeps_the_figure_as_wide_as_three_legend_columns() {
    let dir = scratch("caps-legend");
    let figure = |n: usize| {
        let series = (0..n)
            .map(|i| {
                let y = i as f64;
                Series::new(
                    format!("curve {i:04}"),
                    vec![(0.0, y), (1.0, y + 1.0)],
                    Stroke::Solid,
                    i,
                )
            })
            .collect();
        Figure::new(
            "many",
            "Many curves",
            "",
            vec![Panel::new("many", "x", "y", series)],
        )
    };
    let width = |n: usize| {
        let (png, svg) = (dir.join(format!("{n}.png")), dir.join(format!("{n}.svg")));
        render(&figure(n), &png, &svg).expect("render");
        png_size(&std::fs::read(&png).unwrap()).0
    };
    // One column of a 560-pixel panel holds (560 − 70) / 21 = 23 rows: 40 curves take two.
    let (one, two_columns) = (width(1), width(40));
    assert!(two_columns > one + 50, "{two_columns} px against {one} px");
    // Past three full columns the legend says how many it leaves out ("… 1932 more"), and the
    // figure grows no wider: 2000 curves in 23-row columns would be 87 columns, ≈ 10⁴ px.
    let (many, more) = (width(2000), width(5000));
    assert_eq!(many, more, "2000 and 5000 curves make figures of one width");
    assert!(
        many < 2 * one,
        "{many} px for 2000 curves ({one} px for one)"
    );
}
