//! The FE fields a ParaView user reads: the nominal and Cauchy stress tensors and the
//! hydrostatic pressure per cell of every VTU file, a `.pvd` series per sweep over the
//! stretches, and the report's statement of how far J is from 1 and where.

use crate::common::vtu_data_array;
use crate::scratch::scratch;
use activemuscle::fem::{AxisymmetricSolver, Bases, Mesh, NeoHookean, SolverOptions, VtkOutput};
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::studies::StudyResult;
use std::path::Path;

/// The 3 × 3 tensors of a VTU cell array, row-major, in the frame (x, y, z) = (r, z, θ).
fn tensors(text: &str, name: &str) -> Vec<[f64; 9]> {
    let v = vtu_data_array(text, name);
    assert_eq!(v.len() % 9, 0, "{name}: nine components a cell");
    v.chunks(9).map(|c| c.try_into().unwrap()).collect()
}

/// Asserts that every tensor is diag(0, zz, 0) (the r–z frame: rr, zz, θθ on the diagonal)
/// within `tol` of |zz|.
fn assert_axial(name: &str, cells: &[[f64; 9]], zz: f64, tol: f64) {
    for (i, t) in cells.iter().enumerate() {
        let mut expected = [0.0; 9];
        expected[4] = zz;
        for (k, (v, e)) in t.iter().zip(expected).enumerate() {
            assert!(
                (v - e).abs() <= tol * zz.abs(),
                "{name}, cell {i}, component {k}: {v} vs {e}"
            );
        }
    }
}

#[test]
fn neo_hookean_sliding_cylinder_writes_the_closed_form_stress_tensors() {
    let (mu, lambda) = (4.0, 1.3);
    let material = NeoHookean::new(mu).unwrap();
    let dir = scratch("fem-fields-neo-hookean");
    let options = SolverOptions {
        vtk: Some(VtkOutput {
            directory: dir.to_path_buf(),
            stretches: vec![lambda],
        }),
        ..SolverOptions::default()
    };
    let mesh = Mesh::structured(1.0, 2.0, 2, 3, 1.0).unwrap();
    let mut solver = AxisymmetricSolver::new(mesh, Bases::Sliding, &material, options).unwrap();
    solver.sweep(&[lambda]).unwrap().into_result().unwrap();
    let text = std::fs::read_to_string(dir.join("lambda_1.3000.vtu")).unwrap();
    // Incompressible uniaxial tension of Ψ = μ/2 (tr C − 3) with free lateral surfaces:
    // p = μ/λ, P_zz = μ(λ − λ⁻²), σ_zz = μ(λ² − λ⁻¹), every other entry 0.
    let p_zz = mu * (lambda - lambda.powi(-2));
    let sigma_zz = mu * (lambda * lambda - 1.0 / lambda);
    assert_axial(
        "nominal_stress",
        &tensors(&text, "nominal_stress"),
        p_zz,
        1e-9,
    );
    assert_axial(
        "cauchy_stress",
        &tensors(&text, "cauchy_stress"),
        sigma_zz,
        1e-9,
    );
    for h in vtu_data_array(&text, "hydrostatic_pressure") {
        assert!((h + sigma_zz / 3.0).abs() < 1e-9 * sigma_zz, "{h}");
    }
    assert!(text.contains(r#"Name="cauchy_stress" NumberOfComponents="9" ComponentName0="rr""#));
}

/// Runs `text` with VTK files into `dir/vtk`; returns the cylinder result of study `i`.
fn run_cylinder(
    text: &str,
    dir: &Path,
    i: usize,
) -> activemuscle::studies::cylinder::CylinderResult {
    let scene = Scene::parse(text, "scene.toml").unwrap();
    let options = RunOptions {
        vtk_dir: Some(dir.join("vtk")),
        ..RunOptions::default()
    };
    let results = scene.run(&options);
    match &results.studies[i].result {
        StudyResult::Cylinder(c) => c.clone(),
        other => panic!("{other:?}"),
    }
}

#[test]
fn sliding_bases_write_the_homogeneous_muscle_stress_of_the_0d_curve() {
    let dir = scratch("fem-fields-muscle");
    let c = run_cylinder(
        "[[study]]\nkind = \"cylinder\"\nbases = \"sliding\"\nnr = 2\nnz = 6\n\
         stretch = [0.8, 1.2]\nvtk = [0.8, 1.2]\n",
        &dir,
        0,
    );
    let sweep = &c.sweeps[0];
    assert_eq!(sweep.points.len(), 2);
    for point in &sweep.points {
        // The homogeneous (0D) nominal stress of the same model, solved without FE.
        let p0 = point.stress_0d.expect("the 0D curve");
        let lambda = point.lambda;
        let file = dir.join("vtk").join(
            sweep
                .vtk_files
                .iter()
                .find(|f| {
                    f.to_string_lossy()
                        .ends_with(&format!("lambda_{lambda:.4}.vtu"))
                })
                .expect("a VTU at the stretch"),
        );
        let text = std::fs::read_to_string(file).unwrap();
        assert_axial(
            "nominal_stress",
            &tensors(&text, "nominal_stress"),
            p0,
            1e-8,
        );
        // J = 1: σ = P Fᵀ, σ_zz = λ P_zz.
        assert_axial(
            "cauchy_stress",
            &tensors(&text, "cauchy_stress"),
            lambda * p0,
            1e-8,
        );
    }
}

#[test]
fn each_sweep_has_a_series_listing_every_vtu_it_wrote_in_stretch_order() {
    let dir = scratch("fem-fields-series");
    let c = run_cylinder(
        "[activation]\ndamage = [0.0, 0.5]\n[[study]]\nkind = \"cylinder\"\nnr = 1\nnz = 4\n\
         stretch = [0.9, 1.0, 1.1, 1.2]\nvtk = [1.2, 0.9, 1.1]\n",
        &dir,
        0,
    );
    assert_eq!(c.sweeps.len(), 2);
    for sweep in &c.sweeps {
        let series = sweep
            .vtk_files
            .iter()
            .find(|f| f.extension().is_some_and(|e| e == "pvd"))
            .expect("a .pvd per sweep");
        let sub = dir.join("vtk").join(series.parent().unwrap());
        let pvd = std::fs::read_to_string(dir.join("vtk").join(series)).unwrap();
        let listed: Vec<(f64, String)> = pvd
            .lines()
            .filter(|l| l.starts_with("<DataSet"))
            .map(|l| {
                let attr = |a: &str| {
                    l.split(&format!("{a}=\""))
                        .nth(1)
                        .unwrap()
                        .split('"')
                        .next()
                        .unwrap()
                        .to_string()
                };
                (attr("timestep").parse().unwrap(), attr("file"))
            })
            .collect();
        // Every VTU in the sweep's directory, by its stretch.
        let mut on_disk: Vec<(f64, String)> = std::fs::read_dir(&sub)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".vtu"))
            .map(|n| (n["lambda_".len()..n.len() - 4].parse().unwrap(), n))
            .collect();
        on_disk.sort_by(|a, b| a.0.total_cmp(&b.0));
        assert_eq!(listed, on_disk);
        assert_eq!(
            listed.iter().map(|l| l.0).collect::<Vec<_>>(),
            [0.9, 1.1, 1.2]
        );
        // The sweep names the series and the three files it lists.
        assert_eq!(sweep.vtk_files.len(), 4);
    }
}

/// The reference coordinates of the nodes of cell `cell` of a VTU file's text (9-node cells).
fn cell_nodes(text: &str, cell: usize) -> Vec<[f64; 2]> {
    let points = {
        let start = text.find("<Points>").unwrap();
        let body = &text[start..];
        let body = &body[body.find("ascii\">").unwrap() + 7..body.find("</DataArray>").unwrap()];
        let v: Vec<f64> = body
            .split_whitespace()
            .map(|x| x.parse().unwrap())
            .collect();
        v.chunks(3).map(|c| [c[0], c[1]]).collect::<Vec<_>>()
    };
    let connectivity = vtu_data_array(text, "connectivity");
    connectivity[9 * cell..9 * cell + 9]
        .iter()
        .map(|&n| points[n as usize])
        .collect()
}

#[test]
fn the_report_says_how_far_j_is_from_1_and_where() {
    let dir = scratch("fem-fields-volume");
    let scene = dir.join("scene.toml");
    // R = 1, L = 4.
    std::fs::write(
        &scene,
        "[[study]]\nkind = \"cylinder\"\nnr = 4\nnz = 16\nstretch = [0.7]\nvtk = [0.7]\n\
         law = \"explicit\"\n",
    )
    .unwrap();
    let out = dir.join("out");
    crate::binary::run_quiet(Some(&scene), &out);
    let vtu = std::fs::read_dir(out.join("vtk"))
        .unwrap()
        .flat_map(|d| std::fs::read_dir(d.unwrap().path()).unwrap())
        .map(|e| e.unwrap().path())
        .find(|p| p.extension().is_some_and(|e| e == "vtu"))
        .unwrap();
    let text = std::fs::read_to_string(vtu).unwrap();
    // The largest |J̄ − 1| of the cells and its cell, read from the VTU file's cell means.
    let (worst_cell, worst) = vtu_data_array(&text, "J")
        .iter()
        .map(|j| (j - 1.0).abs())
        .enumerate()
        .fold((0, 0.0), |m, (i, e)| if e > m.1 { (i, e) } else { m });
    assert!(worst > 1e-3, "a clamped cylinder at λ = 0.7: {worst}");
    let report = std::fs::read_to_string(out.join("report.html")).unwrap();
    let section = &report[report
        .find("How far J = det F is from 1")
        .expect("the section")..];
    let row = &section[section.find("<tr><td>").unwrap()..section.find("</table>").unwrap()];
    let cells = row.split("<td>").last().unwrap();
    let shown = format!("{} %", activemuscle::text::significant(100.0 * worst, 3));
    assert!(
        cells.starts_with(&format!("{shown} at λ = 0.7")),
        "{shown}: {row}"
    );
    // Where: the reported centroid lies in that cell's box.
    let number = |key: &str| -> f64 {
        let at = cells.find(key).unwrap() + key.len();
        cells[at..]
            .split([',', ')'])
            .next()
            .unwrap()
            .trim()
            .parse()
            .unwrap()
    };
    let (r, z) = (number("r/R = "), 4.0 * number("z/L = "));
    let nodes = cell_nodes(&text, worst_cell);
    let (lo, hi) = nodes
        .iter()
        .fold(([f64::MAX; 2], [f64::MIN; 2]), |(lo, hi), n| {
            (
                [lo[0].min(n[0]), lo[1].min(n[1])],
                [hi[0].max(n[0]), hi[1].max(n[1])],
            )
        });
    assert!(
        (lo[0]..=hi[0]).contains(&r) && (lo[1] - 1e-3..=hi[1] + 1e-3).contains(&z),
        "({r}, {z}) outside the cell {lo:?}–{hi:?}: {row}"
    );
}
