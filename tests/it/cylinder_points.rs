//! Named boundary points of a cylinder study (`[study.points]`): validated against the mesh at
//! load time, reported per stretch and model (typed results, `points_<study>.csv`, report), and
//! on the sliding cylinder equal to the homogeneous displacement u_z = (λ − 1) z,
//! u_r = (λ^(−1/2) − 1) r.

use activemuscle::output::csv::files;
use activemuscle::output::report::{html, RunInfo};
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::studies::StudyResult;

const FILE: &str = "points.toml";

fn scene(points: &str, element: &str) -> String {
    format!(
        r#"
[[study]]
kind = "cylinder"
name = "sliding tip"
bases = "sliding"
radius = 1.0
length = 4.0
nr = 2
nz = 4
element = "{element}"
law = "explicit"
coupling = "frozen"
damage = [0.0, 0.3]
stretch = [0.8, 1.0, 1.2]

[study.points]
{points}
"#
    )
}

#[test]
fn sliding_cylinder_end_nodes_move_as_the_homogeneous_state() {
    for element in ["Q2/Q1", "Q1/P0"] {
        let text = scene(
            "tip_axis = [0.0, 4.0]\ntip_rim = [1.0, 4.0]\nbase_rim = [1.0, 0.0]\nmid_rim = [1.0, 2.0]",
            element,
        );
        let scene = Scene::parse(&text, FILE).unwrap();
        let results = scene.run(&RunOptions::default());
        assert!(results.failures().next().is_none());
        let StudyResult::Cylinder(c) = &results.studies[0].result else {
            panic!("a cylinder result");
        };
        let names: Vec<&str> = c.points.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["base_rim", "mid_rim", "tip_axis", "tip_rim"]);
        assert_eq!(c.sweeps.len(), 2);
        for sweep in &c.sweeps {
            assert_eq!(sweep.displacements.len(), 3);
            for (p, u) in sweep.points.iter().zip(&sweep.displacements) {
                let l = p.lambda;
                for ((name, at), u) in c.points.iter().zip(u) {
                    let (ur, uz) = ((l.powf(-0.5) - 1.0) * at[0], (l - 1.0) * at[1]);
                    assert!(
                        (u[0] - ur).abs() < 1e-10 && (u[1] - uz).abs() < 1e-12,
                        "{element} {name} at λ = {l}: {u:?} vs ({ur}, {uz})"
                    );
                }
            }
        }
        let files = files(&results);
        let points = files
            .iter()
            .find(|f| f.file.starts_with("points_"))
            .expect("a points CSV");
        assert_eq!(points.file, "points_sliding_tip.csv");
        let csv = String::from_utf8(points.bytes().unwrap()).unwrap();
        let lines: Vec<&str> = csv.lines().collect();
        assert_eq!(
            lines[0],
            "study,point,r,z,law,coupling,d,lambda,u_r,u_z,approach"
        );
        assert_eq!(lines.len(), 1 + 2 * 3 * 4, "per model, stretch and point");
        assert!(lines[1].starts_with("sliding tip,base_rim,1,0,explicit,frozen,0,0.8,"));
        let info = RunInfo::default();
        let report = html(&scene, &results, &[], &info).unwrap();
        assert!(report.contains("<h2>Named points</h2>"));
        assert!(
            report.contains("<td>tip_axis</td><td>(0, 4)</td>"),
            "the report table lists the points"
        );
    }
}

#[test]
fn a_point_that_is_not_a_boundary_node_is_refused_with_the_nearest_one() {
    // Q2/Q1 2 × 4: nodes every 0.25 in r and 0.5 in z.
    for (points, nearest) in [
        ("tip = [0.3, 4.0]", "[0.25, 4]"),
        ("inside = [0.5, 2.0]", "[0, 2]"),
        ("outside = [1.5, 4.0]", "[1, 4]"),
    ] {
        let e = Scene::parse(&scene(points, "Q2/Q1"), FILE).unwrap_err();
        let shown = e.to_string();
        println!("{shown}");
        let key = points.split(' ').next().unwrap();
        assert!(
            shown.starts_with(&format!("{FILE}:17: study[0].points.{key}")),
            "{shown}"
        );
        assert!(shown.contains("mesh node on the boundary"), "{shown}");
        assert!(shown.contains(nearest), "{nearest}: {shown}");
    }
    // Q1/P0 keeps the corners only (r = 0, 0.5, 1): the nearest to 0.3 is 0.5, not Q2/Q1's 0.25.
    let e = Scene::parse(&scene("tip = [0.3, 4.0]", "Q1/P0"), FILE).unwrap_err();
    assert!(e.to_string().contains("[0.5, 4]"), "{e}");
}
