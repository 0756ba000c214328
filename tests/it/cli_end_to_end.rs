//! A small scene runs end to end through the binary; its CSV agrees with the library's own
//! homogeneous results, the sliding cylinder with the 0D curve, and no output contains NaN.

use activemuscle::active::{ActiveCurve, Coupling, ExplicitLaw, FrozenTangent, ImplicitLaw, Law};
use activemuscle::energy::{Energy, GiantesioMusesti};
use activemuscle::uniaxial::along_fibres;
use activemuscle::Muscle;
use std::collections::HashMap;

use crate::binary;
use crate::scratch;
use scratch::scratch;

const SCENE: &str = r#"
title = "end-to-end test"
[[study]]
kind = "uniaxial"
stretch = [0.8, 1.0, 1.17, 1.4]
laws = ["implicit", "explicit"]
couplings = ["frozen"]
damage = [0.0, 0.3]
[[study]]
kind = "cylinder"
nr = 1
nz = 2
bases = "sliding"
law = "explicit"
coupling = "frozen"
damage = [0.0]
stretch = [0.9, 1.0, 1.1]
vtk = [1.1]
"#;

fn relative(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs().max(1e-300)
}

#[test]
fn small_scene_matches_the_library_and_writes_every_output() {
    let dir = scratch("cli-e2e");
    let scene = dir.join("small.toml");
    std::fs::write(&scene, SCENE).expect("write scene");
    let out_dir = dir.join("out");
    binary::run_quiet(Some(&scene), &out_dir);

    let csv = std::fs::read_to_string(out_dir.join("curves.csv")).expect("curves.csv");
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("study,model,direction,bases,energy,law,coupling,d,lambda,gamma,P,P_pas,P_act,newton_iterations,cauchy,J,P_0d,dofs,element,regions,approach,in_domain")
    );
    let gm = GiantesioMusesti::paper();
    let energy = Energy::GiantesioMusesti(gm);
    let frozen = Coupling::Frozen(FrozenTangent::Exact);
    let passive = Muscle::passive(energy.clone());
    let mut muscles: HashMap<(String, String), Muscle<Energy>> = HashMap::new();
    let (mut uniaxial, mut cylinder) = (0, 0);
    for line in lines {
        // The study's name first (the scene's defaults); the other columns as they were.
        let study = line.split(',').next().unwrap_or_default();
        let c: Vec<&str> = line.split(',').skip(1).collect();
        assert_eq!(c.len(), 21, "{line}");
        let expected_study = match c[0] {
            "uniaxial" => "uniaxial along fibres",
            _ => "cylinder sliding explicit frozen",
        };
        assert_eq!(study, expected_study, "{line}");
        let lambda: f64 = c[7].parse().expect("lambda");
        let p: f64 = c[9].parse().expect("P");
        let (law, d) = (c[4].to_string(), c[6].to_string());
        // The scene's default approach names every active row, none of the passive ones.
        let approach = if law == "passive" {
            ""
        } else {
            "active-strain"
        };
        assert_eq!(c[19], approach, "{line}");
        let muscle = muscles.entry((law.clone(), d.clone())).or_insert_with(|| {
            let d: f64 = if d.is_empty() {
                0.0
            } else {
                d.parse().expect("d")
            };
            match law.as_str() {
                "passive" => Muscle::passive(energy.clone()),
                "implicit" => Muscle::new(
                    energy.clone(),
                    Law::Implicit(ImplicitLaw::new(energy.clone(), ActiveCurve::paper())),
                    d,
                    frozen,
                )
                .expect("muscle"),
                "explicit" => Muscle::new(
                    energy.clone(),
                    Law::Explicit(ExplicitLaw::paper()),
                    d,
                    frozen,
                )
                .expect("muscle"),
                other => panic!("unexpected law {other}"),
            }
        });
        let expected = along_fibres(muscle, lambda).expect("0D point");
        match c[0] {
            "uniaxial" => {
                uniaxial += 1;
                assert!(
                    relative(p, expected.stress) < 1e-12,
                    "{line}: P = {p}, library {}",
                    expected.stress
                );
                let sigma: f64 = c[13].parse().expect("cauchy");
                assert!(relative(sigma, expected.cauchy) < 1e-12, "{line}");
                let g: f64 = c[8].parse().expect("gamma");
                assert!(
                    (g - expected.gamma).abs() <= 1e-12 * expected.gamma.abs().max(1e-3),
                    "{line}"
                );
                if law != "passive" {
                    let pas: f64 = c[10].parse().expect("P_pas");
                    assert!(
                        relative(pas, along_fibres(&passive, lambda).expect("passive").stress)
                            < 1e-12
                    );
                    let act: f64 = c[11].parse().expect("P_act");
                    let dd: f64 = d.parse().expect("d");
                    assert!(
                        relative(act, (1.0 - dd) * ActiveCurve::paper().value(lambda)) < 1e-12
                            || act == 0.0
                    );
                } else {
                    assert!(
                        c[10].is_empty() && c[11].is_empty() && c[12].is_empty(),
                        "{line}"
                    );
                }
            }
            "cylinder" => {
                cylinder += 1;
                assert_eq!(c[2], "sliding");
                // Sliding bases: homogeneous tension, FE = 0D to solver tolerance.
                assert!(
                    (p - expected.stress).abs() < 1e-6 * expected.stress.abs().max(1.0),
                    "{line}: 0D {}",
                    expected.stress
                );
                assert!(c[12].parse::<usize>().is_ok(), "{line}");
            }
            other => panic!("unexpected model {other}"),
        }
    }
    // 1 passive + 2 laws × 2 damages, 4 stretches each; 3 cylinder stretches.
    assert_eq!(uniaxial, 5 * 4);
    assert_eq!(cylinder, 3);

    for f in [
        "report.html",
        "scene.toml",
        "fig_fe_vs_0d.png",
        "fig_fe_vs_0d.svg",
        "fig_explicit_vs_implicit_gamma.png",
        "fig_active_curve.svg",
        "vtk",
    ] {
        assert!(out_dir.join(f).exists(), "missing {f}");
    }
    let vtk = std::fs::read_dir(out_dir.join("vtk"))
        .expect("vtk dir")
        .count();
    assert_eq!(vtk, 1);
    for entry in std::fs::read_dir(&out_dir).expect("out dir") {
        let path = entry.expect("entry").path();
        assert!(
            !path
                .file_name()
                .is_some_and(|n| n.to_string_lossy().starts_with(".activemuscle-partial")),
            "staging left behind"
        );
        if path
            .extension()
            .is_some_and(|e| e == "csv" || e == "html" || e == "svg")
        {
            let text = std::fs::read_to_string(&path).expect("read output");
            assert!(!text.contains("NaN"), "NaN in {}", path.display());
        }
    }
    let report = std::fs::read_to_string(out_dir.join("report.html")).expect("report");
    assert!(report.contains("data:image/png;base64,") && report.contains("end-to-end test"));
}
