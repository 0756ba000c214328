//! What the outputs say matches what was computed: each test runs (or checks) a small scene and
//! reads the words a user reads — the summary, report.html, an error message — against the
//! scene it was given.

use crate::binary;
use crate::explicit_law_domain::check;
use crate::scratch::scratch;
use activemuscle::volumetric::{Volumetric, VolumetricForm};
use std::ffi::OsStr;
use std::path::Path;

/// A quiet run of `scene` into `dir/out`: its stdout and report.html.
fn run(scene: &str, dir: &Path) -> (String, String) {
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene).unwrap();
    let out = binary::run_quiet(Some(&path), &dir.join("out"));
    let report = std::fs::read_to_string(dir.join("out/report.html")).unwrap_or_default();
    (String::from_utf8_lossy(&out.stdout).into_owned(), report)
}

#[test]
fn a_fibre_direction_is_scale_free_and_its_refusal_says_what_is_wrong() {
    let scene = |fibre: &str| {
        format!(
            "[material]\nfibre = {fibre}\n[[study]]\nkind = \"uniaxial\"\nstretch = [1.0, 1.1]\n"
        )
    };
    // Tiny and huge components are directions like any other: no underflow, no overflow.
    for fibre in ["[1e-300, 0, 0]", "[1e300, 1e300, 0]", "[3, 4, 0]"] {
        let (rc, err) = check("fibre-scale", &scene(fibre));
        assert_eq!(rc, 0, "{fibre}: {err}");
    }
    let (rc, err) = check("fibre-zero", &scene("[0, 0, 0]"));
    assert!(
        rc == 1 && err.contains("must be a non-zero vector"),
        "{err}"
    );
    let (rc, err) = check("fibre-inf", &scene("[inf, 0, 0]"));
    assert!(
        rc == 1 && err.contains("must have finite components"),
        "{err}"
    );
}

#[test]
fn a_shear_study_refuses_the_same_fibre_or_approach_twice_as_it_does_a_damage() {
    let scene = |angles: &str, approaches: &str| {
        format!(
            "[[study]]\nkind = \"shear\"\nshear = [0.0, 0.1]\nfibre_angles = {angles}\n\
             approaches = {approaches}\n"
        )
    };
    let strain = "[\"active-strain\"]";
    // θ and θ + 180° are the same fibre tensor a⊗a.
    for (angles, j, i) in [("[0.0, 360.0]", 1, 0), ("[45.0, 90.0, 225.0]", 2, 0)] {
        let (rc, err) = check("shear-angles", &scene(angles, strain));
        assert_eq!(rc, 1, "{err}");
        assert!(
            err.contains(&format!("fibre_angles[{j}]"))
                && err.contains(&format!("fibre_angles[{i}]"))
                && err.contains("same fibre"),
            "{err}"
        );
    }
    let (rc, err) = check(
        "shear-approaches",
        &scene(
            "[0.0]",
            "[\"active-strain\", \"active-stress\", \"active-strain\"]",
        ),
    );
    assert!(
        rc == 1
            && err.contains("approaches[2]")
            && err.contains("approaches[0] is the same approach"),
        "{err}"
    );
    let (rc, err) = check("shear-distinct", &scene("[0.0, 90.0, 135.0]", strain));
    assert_eq!(rc, 0, "{err}");
}

#[test]
fn a_shear_study_says_that_material_fibre_does_not_apply() {
    let dir = scratch("shear-fibre");
    let (_, report) = run(
        "[material]\nfibre = [0.0, 1.0, 0.0]\n[[study]]\nkind = \"shear\"\nshear = [0.0, 0.1]\n\
         fibre_angles = [0.0]\napproaches = [\"active-stress\"]\n",
        &dir,
    );
    assert!(
        report.contains("material.fibre = [0.0000, 1.0000, 0.0000] does not apply"),
        "{report}"
    );
}

#[test]
fn biaxial_curves_that_coincide_are_named_on_the_figure_and_in_its_caption() {
    // Active stress adds (1 − d) P_act(λ₁) to P₁₁ alone: its P₂₂ is the passive one, drawn
    // over it.
    let dir = scratch("biaxial-hidden");
    let (_, report) = run(
        "[[study]]\nkind = \"biaxial\"\nname = \"b\"\npath = \"equibiaxial\"\n\
         stretch = [1.0, 1.1, 1.2]\napproaches = [\"active-stress\"]\ndamage = [0.0]\n",
        &dir,
    );
    let across =
        "In &quot;Nominal stress across the fibres P₂₂&quot;, &quot;passive&quot; lies under";
    assert!(report.contains(across), "{report}");
    // Along the fibres the two differ by the active stress: no note.
    assert!(
        !report.contains("In &quot;Nominal stress along the fibres P₁₁&quot;"),
        "{report}"
    );
}

#[test]
fn a_sliding_cylinder_with_regions_is_no_verification_and_says_so() {
    let dir = scratch("sliding-regions");
    let (stdout, report) = run(
        "[[study]]\nkind = \"cylinder\"\nname = \"c\"\nbases = \"sliding\"\nnr = 2\nnz = 4\n\
         law = \"implicit\"\ndamage = [0.0]\nstretch = [1.0, 1.1]\n\
         [study.points]\naxis = [0.0, 4.0]\n\
         [[study.regions]]\nr = [0.5, 1.0]\ndamage = 0.5\n",
        &dir,
    );
    assert!(
        stdout.contains("sliding bases with regions") && stdout.contains("not a verification"),
        "{stdout}"
    );
    assert!(!stdout.contains("verification (sliding bases"), "{stdout}");
    assert!(
        report.contains("the body with its regions against the uniform model")
            && report.contains("its sliding bases add no end effect")
            && !report.contains("end effect of clamped bases on top"),
        "{report}"
    );
    // u_r on the axis is −0 or 0: written 0, never `-0.000000e0`.
    assert!(!report.contains("e0<"), "{report}");
}

#[test]
fn the_linear_term_of_a_volumetric_energy_is_part_of_u_not_of_its_modulus() {
    // U = (κ/2)(J − 1)² + c (J − 1), c = −s₀ for a reference stress s₀ (U′(1) = −s₀).
    let v = Volumetric::new(VolumetricForm::Quadratic { kappa: 1000.0 }, 0.07995).unwrap();
    assert_eq!(v.shift(), -0.07995);
    assert_eq!(
        v.formula(),
        "(κ/2)(J − 1)² − 0.07995 kPa (J − 1), κ = 1000 kPa"
    );
    let plain = Volumetric::new(VolumetricForm::Quadratic { kappa: 1000.0 }, 0.0).unwrap();
    assert_eq!(plain.formula(), "(κ/2)(J − 1)², κ = 1000 kPa");
}

#[test]
fn tradeoff_takes_a_time_limit_as_run_does() {
    let dir = scratch("tradeoff-limit");
    for command in ["run", "tradeoff"] {
        let out = binary::run_args(&[
            OsStr::new(command),
            OsStr::new("--max-seconds=-1"),
            OsStr::new("--out"),
            dir.join(command).as_os_str(),
        ]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(1), "{command}: {err}");
        assert!(
            err.contains("--max-seconds -1: must be a finite number of seconds > 0"),
            "{command}: {err}"
        );
    }
}
