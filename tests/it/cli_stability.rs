//! A stability study through the binary: the intervals table in the report, `stability.csv` with
//! one row per model and stretch, the figure; and its rules.

use std::process::Command;

use crate::binary;
use crate::scratch;
use scratch::scratch;

const BIN: &str = env!("CARGO_BIN_EXE_activemuscle");

#[test]
fn a_stability_study_writes_its_table_csv_and_figure() {
    let d = scratch("cli-stability");
    let scene = d.join("stability.toml");
    std::fs::write(
        &scene,
        "[[study]]\nkind = \"stability\"\nname = \"map\"\nlaws = [\"implicit\"]\ncouplings = [\"frozen\"]\n\
         damage = [0.0]\nstretch = { from = 1.10, to = 1.35, step = 0.01 }\nnormals = 50\n",
    )
    .expect("scene");
    let out_dir = d.join("out");
    binary::run_quiet(Some(&scene), &out_dir);
    let csv = std::fs::read_to_string(out_dir.join("stability.csv")).expect("stability.csv");
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "study,law,coupling,d,lambda,P,dP_dlambda,ellipticity_min,ellipticity_relative,strongly_elliptic,softening,cauchy,approach,in_domain"
    );
    // Passive and implicit/frozen, 26 stretches each.
    assert_eq!(lines.len(), 1 + 2 * 26, "{csv}");
    // The implicit frozen model softens past the optimum (P_tot = P_pas + P_act falls).
    assert!(
        lines.iter().any(
            |l| l.starts_with("map,implicit,frozen,0,") && l.split(',').nth(10) == Some("true")
        ),
        "{csv}"
    );
    let report = std::fs::read_to_string(out_dir.join("report.html")).expect("report");
    assert!(report.contains("Material stability along the fibres"));
    assert!(report.contains("dP/dλ &lt; 0 on"));
    assert!(out_dir.join("fig_stability_map.png").exists());
    assert!(out_dir.join("fig_stability_map.svg").exists());
}

#[test]
fn stability_rules_name_the_key() {
    let d = scratch("cli-stability-rules");
    for (extra, needles) in [
        ("normals = 0\n", ["study[0].normals", "[1, 100000]"]),
        ("law = \"implicit\"\n", ["study[0].law", "laws = [...]"]),
        ("damage = [1.5]\n", ["study[0].damage[0]", "[0, 1]"]),
    ] {
        let scene = d.join("bad.toml");
        std::fs::write(&scene, format!("[[study]]\nkind = \"stability\"\n{extra}")).expect("scene");
        let out = Command::new(BIN)
            .arg("check")
            .arg(&scene)
            .output()
            .expect("run binary");
        let err = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{extra}: accepted");
        for n in needles {
            assert!(err.contains(n), "{extra}: lacks {n:?}: {err}");
        }
    }
}
