//! Bounded work and output: a scene's rows, figures, files, bytes, FE work and memory are
//! estimated when it is read (the product of its lists and the number of studies, not each list
//! alone) and a scene beyond the documented limits is refused with the estimate in the message,
//! before anything runs.

use activemuscle::output::{write_run, RunMeta, Staging, Writer};
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::studies::size::{check_within, scene_size, size_of, LIMITS};
use activemuscle::text::grouped;

fn refused(text: &str) -> String {
    match Scene::parse(text, "scene.toml") {
        Ok(_) => panic!("accepted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn the_rows_of_every_list_multiplied_are_refused_with_the_count() {
    // The 12-line study: 9 001 stretches × (1 passive + 3 laws × 2 couplings × 16
    // damages) curves.
    let damages: Vec<String> = (0..16)
        .map(|i| format!("{}", f64::from(i) * 0.02))
        .collect();
    let text = format!(
        "[activation]\ndamage = [{}]\n[[study]]\nkind = \"uniaxial\"\n\
         stretch = {{ from = 0.7, to = 1.6, step = 0.0001 }}\n\
         laws = [\"implicit\", \"explicit\", \"energy\"]\ncouplings = [\"frozen\", \"consistent\"]\n",
        damages.join(", ")
    );
    let e = refused(&text);
    let rows = 9001 * (1 + 3 * 2 * 16);
    assert!(
        e.contains(&format!("{} rows", grouped(rows))) && e.contains("500 000 rows"),
        "{e}"
    );
    assert!(
        e.contains("study[0]") && e.contains(":3:"),
        "the study's line: {e}"
    );
}

#[test]
fn thousands_of_one_point_studies_are_refused_for_their_figures_and_report() {
    let text: String = (0..3000)
        .map(|i| {
            format!("[[study]]\nkind = \"uniaxial\"\nname = \"s{i}\"\nstretch = [1.1]\nlaws = []\n")
        })
        .collect();
    let e = refused(&text);
    assert!(
        e.contains("3 002 figures") && e.contains("report.html") && e.contains("the limit is 300"),
        "{e}"
    );
}

#[test]
fn fe_work_and_files_beyond_the_limits_are_refused() {
    // 9 001 stretches of 16 sweeps on a 64 × 256 mesh.
    let damages: Vec<String> = (0..16)
        .map(|i| format!("{}", f64::from(i) * 0.05))
        .collect();
    let e = refused(&format!(
        "[activation]\ndamage = [{}]\n[[study]]\nkind = \"cylinder\"\nnr = 64\nnz = 256\n\
         stretch = {{ from = 0.6, to = 1.5, step = 0.0001 }}\n",
        damages.join(", ")
    ));
    assert!(
        e.contains("unknowns × stretches") && e.contains("the limit is 1e10"),
        "{e}"
    );
    // A VTK file at each of 400 stretches of 16 sweeps.
    let stretches: Vec<String> = (0..400)
        .map(|i| format!("{}", 0.6 + 0.002 * f64::from(i)))
        .collect();
    let stretches = format!("[{}]", stretches.join(", "));
    let e = refused(&format!(
        "[activation]\ndamage = [{}]\n[[study]]\nkind = \"cylinder\"\nnr = 1\nnz = 4\n\
         stretch = {stretches}\nvtk = {stretches}\n",
        damages.join(", ")
    ));
    assert!(
        e.contains("files") && e.contains("VTK") && e.contains("5 000"),
        "{e}"
    );
}

#[test]
fn memory_beyond_what_is_available_is_refused() {
    let scene = Scene::parse(
        "[[study]]\nkind = \"uniaxial\"\nstretch = { from = 0.7, to = 1.6, step = 0.001 }\n\
         laws = [\"implicit\", \"explicit\"]\n",
        "scene.toml",
    )
    .unwrap();
    let size = scene_size(&scene.studies);
    let needed = size.memory(2);
    assert!(check_within(&scene.studies, Some(needed + 1), 2).is_ok());
    let e = check_within(&scene.studies, Some(needed / 2), 2)
        .unwrap_err()
        .to_string();
    assert!(e.contains("in memory") && e.contains("available"), "{e}");
}

/// The number of data rows of every CSV file in `dir` whose first column is `study`.
fn rows_written(dir: &std::path::Path, study: &str) -> u64 {
    std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "csv"))
        .map(|p| {
            let mut reader = csv::Reader::from_path(&p).unwrap();
            reader
                .records()
                .filter(|r| r.as_ref().unwrap().get(0) == Some(study))
                .count() as u64
        })
        .sum()
}

#[test]
fn the_estimated_rows_are_the_rows_each_kind_writes() {
    let text = "[activation]\ndamage = [0.0, 0.3]\n\
        [[study]]\nkind = \"uniaxial\"\nname = \"u\"\nstretch = [0.9, 1.0, 1.1]\n\
        laws = [\"implicit\", \"explicit\"]\nconstant_gamma = [0.1]\n\
        [[study]]\nkind = \"cylinder\"\nname = \"c\"\nnr = 1\nnz = 4\nstretch = [0.95, 1.05]\n\
        [study.points]\ncorner = [1.0, 4.0]\n\
        [[study]]\nkind = \"stability\"\nname = \"s\"\nstretch = [0.9, 1.0, 1.1]\n\
        [[study]]\nkind = \"activation-in-time\"\nname = \"h\"\ntime = [0, 0.5, 1]\n\
        [[study]]\nkind = \"shear\"\nname = \"sh\"\nshear = [0.1, 0.2]\nfibre_angles = [0, 90]\n\
        [[study]]\nkind = \"biaxial\"\nname = \"b\"\npairs = [[1.1, 1.0], [1.2, 1.1]]\n\
        [[study]]\nkind = \"tangent\"\nname = \"t\"\nuniaxial_along = [1.1]\nrandom_directions = 1\n\
        h = { largest = 0.015625, smallest = 0.001953125 }\n\
        [[study]]\nkind = \"fit\"\nname = \"f\"\nfit = \"damage\"\ntrue_damage = [0.2, 0.4]\n\
        stretch = { from = 0.8, to = 1.4, step = 0.1 }\n";
    let scene = Scene::parse(text, "scene.toml").unwrap();
    let results = scene.run(&RunOptions::default());
    assert!(
        results.complete(),
        "{:?}",
        results.failures().collect::<Vec<_>>()
    );
    let dir = crate::scratch::scratch("work-bounds-rows");
    let out = dir.join("out");
    let mut staging = Staging::open(&out, Writer::Run, false).unwrap();
    let meta = RunMeta {
        command: "test".into(),
        started: std::time::Instant::now(),
        rustc: None,
    };
    write_run(&mut staging, &scene, &results, &meta).unwrap();
    staging.commit().unwrap();
    for study in &scene.studies {
        let written = rows_written(&out, study.name());
        assert!(written > 0, "{}", study.name());
        assert_eq!(size_of(study).rows, written, "{}", study.name());
    }
    // The paper's scene is far inside every limit.
    let paper = scene_size(&Scene::paper().unwrap().studies);
    println!(
        "the paper's scene: {} rows, {} figures, {} files, {} bytes, report {} bytes",
        paper.rows,
        paper.figures,
        paper.files(),
        paper.output_bytes(),
        paper.report_bytes()
    );
    assert!(paper.rows * 20 < LIMITS.rows && paper.figures * 5 < LIMITS.figures);
    assert!(paper.files() * 10 < LIMITS.files, "{paper:?}");
}
