//! Reports that say only what is so (issue 24, item 7): a cylinder with regions is not captioned
//! as the 0D model's twin, a sweep that reached no stretch gets no empty figure and no
//! "0.00e0", and the studies table names what its number measures.

use crate::binary;
use crate::scratch::scratch;

fn run(name: &str, scene: &str) -> (crate::scratch::Scratch, String) {
    let dir = scratch(name);
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let out = dir.join("out");
    let _ = binary::run_args(&[
        "run".as_ref(),
        path.as_os_str(),
        "--out".as_ref(),
        out.as_os_str(),
        "--quiet".as_ref(),
    ]);
    let report = std::fs::read_to_string(out.join("report.html")).expect("report.html");
    (dir, report)
}

#[test]
fn a_cylinder_with_regions_is_compared_with_the_uniform_model_and_says_so() {
    let (_dir, report) = run(
        "regions-report",
        "[[study]]\nkind = \"cylinder\"\nname = \"shell\"\nnr = 2\nnz = 4\nstretch = [1.1, 1.2]\n\
         [[study.regions]]\nr = [0.5, 1.0]\ndamage = 0.5\n",
    );
    assert!(!report.contains("the homogeneous uniaxial (0D) curve of the same model."));
    assert!(
        report.contains("without the regions (r/R ∈ [0.5, 1]"),
        "fig_cylinder caption"
    );
    assert!(
        report.contains("mostly the regions"),
        "fig_fe_vs_0d caption and table"
    );
    // The studies table's number is the table's: an absolute difference in kPa, and where.
    assert!(report.contains("largest |P_FE − P_0D| = "));
    assert!(!report.contains("max(|P_0D|, 1 kPa)"));
}

#[test]
fn a_sweep_that_reached_no_stretch_has_no_figure_and_no_zero_difference() {
    // λ = 9 is beyond what the chapter's energy lets the cylinder reach (det F < 0 near 4.87).
    let (dir, report) = run(
        "failed-report",
        "[[study]]\nkind = \"cylinder\"\nname = \"far\"\nnr = 1\nnz = 2\nstretch = [9.0]\n",
    );
    assert!(!dir.join("out/fig_cylinder.png").exists());
    assert!(!dir.join("out/fig_fe_vs_0d.png").exists());
    assert!(report.contains("no stretch converged"));
    assert!(!report.contains("0.00e0"));
}

#[test]
fn only_studies_that_ran_together_are_said_to_overlap() {
    let overlap = "wall times overlap";
    let uniaxial = |name: &str| {
        format!("[[study]]\nkind = \"uniaxial\"\nname = \"{name}\"\nstretch = [0.9, 1.1]\n")
    };
    let (_one, alone) = run("one-study-report", &uniaxial("a"));
    assert!(!alone.contains(overlap), "one study said to overlap");
    let two = format!("{}{}", uniaxial("a"), uniaxial("b"));
    let (_two, together) = run("two-study-report", &two);
    assert!(
        together.contains(overlap),
        "two studies not said to overlap"
    );
}
