//! What a user of the CSV files expects (issue 24, item 12): `datapackage.json` beside them
//! gives every column's name, type, unit and meaning, and the data obey it; cylinder rows carry
//! P_0d, dofs, the element and the regions (item 7: d alone no longer hides damaged regions).

use crate::binary;
use crate::scratch::scratch;
use std::collections::HashMap;
use std::path::Path;

/// Every resource of `out/datapackage.json` is a file there whose header is exactly its fields,
/// and every cell obeys its field's type (empty: missing); numbers have a unit and every field a
/// description. Returns the resources' paths.
pub fn the_data_obey_their_package(out: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(out.join("datapackage.json")).expect("datapackage.json");
    let package: serde_json::Value = serde_json::from_str(&text).expect("valid JSON");
    let mut paths = Vec::new();
    for r in package["resources"].as_array().expect("resources") {
        let path = r["path"].as_str().expect("path").to_string();
        let fields = r["schema"]["fields"].as_array().expect("fields");
        let mut reader = csv::Reader::from_path(out.join(&path)).expect("the resource's file");
        let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
        let names: Vec<&str> = fields.iter().map(|f| f["name"].as_str().unwrap()).collect();
        assert_eq!(header, names, "{path}: header against schema");
        for f in fields {
            assert!(
                !f["description"].as_str().unwrap().is_empty(),
                "{path}: {f}"
            );
            if f["type"] == "number" {
                assert!(!f["unit"].as_str().unwrap_or("").is_empty(), "{path}: {f}");
            }
        }
        for record in reader.records() {
            let record = record.unwrap();
            for (cell, f) in record.iter().zip(fields) {
                let ok = cell.is_empty()
                    || match f["type"].as_str().unwrap() {
                        "number" => cell.parse::<f64>().is_ok_and(f64::is_finite),
                        "integer" => cell.parse::<i64>().is_ok(),
                        "boolean" => cell == "true" || cell == "false",
                        "string" => true,
                        other => panic!("{path}: unknown type {other}"),
                    };
                assert!(
                    ok,
                    "{path}: {} = {cell:?} is not a {}",
                    f["name"], f["type"]
                );
            }
        }
        paths.push(path);
    }
    paths
}

/// The rows of a CSV file as maps from column name to cell.
pub fn rows_by_name(path: &Path) -> Vec<HashMap<String, String>> {
    let mut reader = csv::Reader::from_path(path).expect("the file");
    let header: Vec<String> = reader.headers().unwrap().iter().map(String::from).collect();
    reader
        .records()
        .map(|r| {
            header
                .iter()
                .cloned()
                .zip(r.unwrap().iter().map(String::from))
                .collect()
        })
        .collect()
}

#[test]
fn cylinder_rows_carry_their_0d_stress_dofs_element_and_regions() {
    let dir = scratch("datapackage");
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "[[study]]\nkind = \"uniaxial\"\nname = \"tension\"\nstretch = [1.1, 1.2]\n\
         [[study]]\nkind = \"cylinder\"\nname = \"shell\"\nnr = 2\nnz = 4\nstretch = [1.1, 1.2]\n\
         [[study.regions]]\nr = [0.5, 1.0]\ndamage = 0.5\n",
    )
    .unwrap();
    let out = dir.join("out");
    binary::run_quiet(Some(&scene), &out);
    let paths = the_data_obey_their_package(&out);
    assert!(paths.contains(&"curves.csv".to_string()), "{paths:?}");
    let rows = rows_by_name(&out.join("curves.csv"));
    let active_uniaxial = |lambda: &str| {
        rows.iter()
            .find(|r| r["study"] == "tension" && r["law"] == "implicit" && r["lambda"] == lambda)
            .unwrap_or_else(|| panic!("no uniaxial row at {lambda}"))
    };
    let cylinder: Vec<_> = rows.iter().filter(|r| r["model"] == "cylinder").collect();
    assert_eq!(cylinder.len(), 2);
    for r in cylinder {
        // The cylinder's 0D reference is the uniform model's: the uniaxial study of the same
        // model at d = 0 computes the same stress by its own solve.
        let p_0d: f64 = r["P_0d"].parse().unwrap();
        let p_uniaxial: f64 = active_uniaxial(&r["lambda"])["P"].parse().unwrap();
        assert!(
            (p_0d - p_uniaxial).abs() <= 1e-9 * p_uniaxial.abs(),
            "{p_0d} vs {p_uniaxial}"
        );
        assert_eq!(r["element"], "Q2/Q1");
        // Q2/Q1 on 2 × 4 cells: 5 × 9 nodes (u_r fixed on the axis, u_z on both bases) + 3 × 5
        // pressures: far from zero, and not more than 2 × 45 + 15.
        let dofs: usize = r["dofs"].parse().unwrap();
        assert!(dofs > 0 && dofs <= 105, "{dofs}");
        assert!(r["regions"].contains("r/R ∈ [0.5, 1]") && r["regions"].contains("d = 0.5"));
        assert_eq!(r["d"], "0");
    }
}

/// A scene without uniaxial or cylinder studies writes no `curves.csv` (a header alone says
/// nothing), and `datapackage.json` describes exactly the CSV files in the directory.
#[test]
fn a_shear_only_run_writes_no_curves_csv_and_its_package_lists_the_files_written() {
    let dir = scratch("datapackage_shear_only");
    let scene = dir.join("scene.toml");
    std::fs::write(
        &scene,
        "[[study]]\nkind = \"shear\"\nname = \"shear\"\nshear = [0.1, 0.2]\n",
    )
    .unwrap();
    let out = dir.join("out");
    binary::run_quiet(Some(&scene), &out);
    assert!(!out.join("curves.csv").exists());
    let mut written: Vec<String> = std::fs::read_dir(&out)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|name| name.ends_with(".csv"))
        .collect();
    written.sort();
    let mut described = the_data_obey_their_package(&out);
    described.sort();
    assert_eq!(described, written);
    assert_eq!(described, ["shear.csv"]);
    let report = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(!report.contains("curves.csv"));
}
