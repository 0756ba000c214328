//! Every CSV file that names a law also names the activation approach (issue 42, item 5): the
//! rows of an activation model say the scene's `[activation] approach`; an approach without a
//! law (active stress) leaves the law and coupling cells empty instead of naming the law it does
//! not have; passive rows have no approach.

use crate::binary;
use crate::datapackage::rows_by_name as rows;
use crate::scratch::scratch;
use std::collections::HashMap;

/// A uniaxial, a stability, an activation-in-time and a cylinder study (with a named point)
/// under `approach`.
fn scene(approach: &str) -> String {
    format!(
        "[activation]\napproach = \"{approach}\"\n\
         [[study]]\nkind = \"uniaxial\"\nname = \"along\"\nstretch = [0.9, 1.1]\ndamage = [0.0, 0.5]\n\
         [[study]]\nkind = \"stability\"\nname = \"stab\"\nstretch = [0.9, 1.1]\nnormals = 8\n\
         [[study]]\nkind = \"activation-in-time\"\nname = \"twitch\"\n\
         time = {{ from = 0.0, to = 0.1, step = 0.05 }}\nschedule = [[0.0, 1.0]]\nstretch = 1.1\n\
         [[study]]\nkind = \"cylinder\"\nname = \"cyl\"\nnr = 1\nnz = 2\nbases = \"sliding\"\n\
         damage = [0.3]\nstretch = [1.0, 1.1]\n[study.points]\ntip = [1.0, 4.0]\n"
    )
}

/// Runs the scene of `approach` and checks every file with a `law` column; returns the active
/// rows of curves.csv.
fn check(approach: &str, has_law: bool) -> Vec<HashMap<String, String>> {
    let dir = scratch(&format!("approach-{approach}"));
    let path = dir.join("scene.toml");
    std::fs::write(&path, scene(approach)).unwrap();
    let out = dir.join("out");
    binary::run_quiet(Some(&path), &out);
    let files = [
        "curves.csv",
        "stability.csv",
        "history.csv",
        "points_cyl.csv",
    ];
    for file in files {
        let rows = rows(&out.join(file));
        let active: Vec<_> = rows.iter().filter(|r| r["law"] != "passive").collect();
        assert!(!active.is_empty(), "{file}: no active row");
        for r in &active {
            assert_eq!(r["approach"], approach, "{file}: {r:?}");
            assert_eq!(!r["law"].is_empty(), has_law, "{file}: {r:?}");
            assert_eq!(!r["coupling"].is_empty(), has_law, "{file}: {r:?}");
            assert!(!r["d"].is_empty(), "{file}: {r:?}");
        }
        for r in rows.iter().filter(|r| r["law"] == "passive") {
            assert_eq!(r["approach"], "", "{file}: {r:?}");
        }
    }
    // Every one of them is described, its approach column too.
    let described = crate::datapackage::the_data_obey_their_package(&out);
    assert!(files.iter().all(|f| described.iter().any(|d| d == f)));
    rows(&out.join("curves.csv"))
        .into_iter()
        .filter(|r| r["law"] != "passive" && r["model"] == "uniaxial")
        .collect()
}

#[test]
fn active_stress_rows_name_their_approach_and_no_law() {
    let active = check("active-stress", false);
    assert_eq!(active.len(), 2 * 2);
    // Along the fibres active stress is its target: P = P_pas + (1 − d) P_act, γ ≡ 0.
    for r in active {
        let [p, pas, act, gamma] = ["P", "P_pas", "P_act", "gamma"].map(|c| {
            r[c].parse::<f64>()
                .unwrap_or_else(|_| panic!("{c} in {r:?}"))
        });
        assert!((p - pas - act).abs() <= 1e-12 * p.abs().max(1.0), "{r:?}");
        assert_eq!(gamma, 0.0);
    }
}

#[test]
fn active_strain_and_structural_rows_name_their_approach_and_law() {
    for approach in ["active-strain", "structural"] {
        let active = check(approach, true);
        assert!(active
            .iter()
            .all(|r| r["law"] == "implicit" && r["coupling"] == "frozen"));
    }
}
