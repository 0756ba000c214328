//! The Q1/P0 element (bilinear displacement, one constant pressure per cell, 2 × 2 Gauss) next to
//! Taylor–Hood Q2/Q1: exact on the homogeneous solution, exact tangent, incompressibility in the
//! mean per cell, and convergence of the clamped reaction towards a fine Q2/Q1 solution.

use activemuscle::fem::assembly::Assembler;
use activemuscle::fem::dofs::DofMap;
use activemuscle::fem::element::jacobian;
use activemuscle::fem::{
    AxisymmetricSolver, Bases, Element, FemError, Mesh, NeoHookean, SolverOptions, StepRecord,
    VtkOutput,
};

use crate::common;
use crate::scratch;
use common::NonSymmetric;
use scratch::scratch;

fn q1p0() -> SolverOptions {
    SolverOptions {
        element: Element::Q1P0,
        ..SolverOptions::default()
    }
}

#[test]
fn q1p0_sliding_bases_reproduce_the_homogeneous_neo_hookean_curve() {
    let (mu, radius, length) = (2.5, 1.5, 4.0);
    let material = NeoHookean::new(mu).unwrap();
    // A graded, non-uniform mesh: the homogeneous solution (linear in r and z) must not care.
    let mesh = Mesh::structured(radius, length, 3, 5, 2.0).unwrap();
    let mut solver = AxisymmetricSolver::new(mesh, Bases::Sliding, &material, q1p0()).unwrap();
    assert_eq!(solver.element(), Element::Q1P0);
    assert_eq!(
        solver.mesh().n_nodes(),
        4 * 6,
        "the corners of the 3 × 5 cells"
    );
    let targets = [0.7, 0.85, 1.0, 1.15, 1.3, 1.6];
    let results = solver.sweep(&targets).unwrap().into_result().unwrap();
    assert_eq!(results.len(), targets.len());
    let mesh = solver.mesh().clone();
    let dofs = solver.dofs().clone();
    for res in &results {
        let lambda = res.stretch;
        // Independent closed form of the incompressible neo-Hookean bar: P = μ (λ − λ⁻²).
        let exact = mu * (lambda - lambda.powi(-2));
        let error = (res.nominal_stress - exact).abs();
        println!(
            "λ = {lambda:.2}: P_FE = {:.12e}, P_exact = {exact:.12e}, |error| / μ = {:.2e}",
            res.nominal_stress,
            error / mu
        );
        assert!(
            error <= 1e-9 * mu.max(exact.abs()),
            "λ = {lambda}: {error:e}"
        );
        // Homogeneous displacement at every node: u_r = (λ^{-1/2} − 1) r, u_z = (λ − 1) z.
        let worst = mesh
            .nodes
            .iter()
            .zip(&dofs.node_u)
            .map(|(x, d)| {
                let (ur, uz) = (res.state.x[d[0] as usize], res.state.x[d[1] as usize]);
                (ur - (lambda.powf(-0.5) - 1.0) * x[0])
                    .abs()
                    .max((uz - (lambda - 1.0) * x[1]).abs())
            })
            .fold(0.0, f64::max);
        assert!(
            worst < 1e-10 * length,
            "λ = {lambda}: nodal error {worst:e}"
        );
        // J = 1 at every quadrature point and the cell pressures are the uniaxial p = μ/λ.
        assert!(res.max_volume_error < 1e-10);
        for &p in &dofs.element_p {
            let p = res.state.x[p as usize];
            assert!((p - mu / lambda).abs() < 1e-9 * mu, "λ = {lambda}: p = {p}");
        }
        assert!((res.fibre_stretch_centre - lambda).abs() < 1e-10);
    }
}

/// One large load step 1 → 1.3 on a clamped cylinder of 6 × 12 Q1/P0 cells.
fn one_step(material: &NonSymmetric) -> StepRecord {
    common::one_step(material, Element::Q1P0, 6, 12)
}

#[test]
fn q1p0_newton_with_the_exact_nonsymmetric_tangent_converges_quadratically() {
    let step = one_step(&NonSymmetric {
        mu: 10.0,
        c: 1.5,
        approximate: false,
    });
    common::assert_quadratic(&step, "Q1/P0, exact tangent");
}

/// A deterministic pseudo-random number in [−1, 1].
fn wiggle(k: usize) -> f64 {
    ((k as f64 + 1.0) * 12.9898).sin() * 0.5 + ((k as f64 + 3.0) * 78.233).sin() * 0.5
}

#[test]
fn q1p0_tangent_matches_central_differences_of_the_residual() {
    let material = NonSymmetric {
        mu: 10.0,
        c: 1.5,
        approximate: false,
    };
    let mesh = Mesh::structured(1.0, 2.0, 3, 4, 2.0)
        .unwrap()
        .with_element(Element::Q1P0);
    let dofs = DofMap::new(&mesh, Bases::Clamped);
    let mut asm = Assembler::new(&mesh, &dofs).unwrap();
    // A general state: stretched, with perturbed displacements and pressures.
    let mut x = vec![0.0; dofs.n_total];
    dofs.apply_stretch(&mut x, 1.2);
    for (k, xi) in x[..dofs.n_free].iter_mut().enumerate() {
        *xi = if k < dofs.n_free_u {
            0.03 * wiggle(k)
        } else {
            10.0 * (1.0 + 0.3 * wiggle(k))
        };
    }
    let v: Vec<f64> = (0..dofs.n_free).map(|k| wiggle(k + 1000)).collect();
    asm.assemble(&x, &material, true).unwrap();
    let n = dofs.n_free;
    let mut kv = vec![0.0; n];
    for (j, vj) in v.iter().enumerate() {
        let p = &asm.pattern;
        for k in p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize {
            kv[p.row_idx[k] as usize] += asm.values[k] * vj;
        }
    }
    let h = 1e-6;
    let residual_at = |asm: &mut Assembler, s: f64| {
        let mut y = x.clone();
        for (yi, vi) in y[..n].iter_mut().zip(&v) {
            *yi += s * vi;
        }
        asm.assemble(&y, &material, false).unwrap();
        asm.residual[..n].to_vec()
    };
    let plus = residual_at(&mut asm, h);
    let minus = residual_at(&mut asm, -h);
    let scale = kv.iter().fold(0.0f64, |m, a| m.max(a.abs()));
    let error = kv
        .iter()
        .zip(plus.iter().zip(&minus))
        .map(|(k, (p, m))| (k - (p - m) / (2.0 * h)).abs())
        .fold(0.0f64, f64::max);
    println!("max |K v − ΔR/Δx| / max |K v| = {:.2e}", error / scale);
    assert!(error < 1e-7 * scale, "{error:e} vs {scale:e}");
}

#[test]
fn q1p0_holds_incompressibility_in_the_mean_of_every_cell() {
    let material = NeoHookean::new(5.0).unwrap();
    let mesh = Mesh::structured(1.0, 4.0, 4, 16, 4.0).unwrap();
    let mut solver = AxisymmetricSolver::new(mesh, Bases::Clamped, &material, q1p0()).unwrap();
    let res = solver.sweep(&[1.17]).unwrap().into_result().unwrap();
    let qps = solver.quadrature_points(&res[0].state);
    assert_eq!(qps.len(), 4 * 4 * 16);
    let n_el = solver.mesh().n_elements();
    let mut mean = vec![(0.0f64, 0.0f64); n_el]; // ∫_e (J − 1) dV, ∫_e dV
    for q in &qps {
        mean[q.element].0 += (jacobian(&q.f) - 1.0) * q.dv;
        mean[q.element].1 += q.dv;
    }
    let worst_mean = mean.iter().map(|(dj, v)| dj.abs() / v).fold(0.0, f64::max);
    let worst_point = res[0].max_volume_error;
    println!(
        "max over cells |∫_e (J − 1) dV| / V_e = {worst_mean:.2e}; max |J − 1| at a point = {worst_point:.2e}"
    );
    assert!(worst_mean < 1e-10, "mean volume error {worst_mean:e}");
    // Only the mean is constrained: the clamped state is not pointwise isochoric.
    assert!(worst_point > 1e3 * worst_mean.max(1e-14));
}

#[test]
fn q1p0_clamped_reaction_converges_to_the_fine_taylor_hood_solution() {
    let (mu, radius, length, lambda, grading) = (5.0, 1.0, 4.0, 1.17, 4.0);
    let material = NeoHookean::new(mu).unwrap();
    let solve = |element: Element, nr: usize, nz: usize| {
        let mesh = Mesh::structured(radius, length, nr, nz, grading).unwrap();
        let options = SolverOptions {
            element,
            ..SolverOptions::default()
        };
        let mut solver = AxisymmetricSolver::new(mesh, Bases::Clamped, &material, options).unwrap();
        let r = solver.sweep(&[lambda]).unwrap().into_result().unwrap();
        (solver.n_free_dofs(), r[0].nominal_stress)
    };
    // An independent discretisation as reference: Taylor–Hood on a fine mesh.
    let (ref_dofs, reference) = solve(Element::Q2Q1, 24, 96);
    println!("reference Q2/Q1 24 × 96 ({ref_dofs} dofs): P = {reference:.8} kPa");
    println!(
        "{:>7} {:>8} {:>8} {:>14} {:>10}",
        "element", "mesh", "dofs", "P/kPa", "rel.error"
    );
    let mut errors = Vec::new();
    for (nr, nz) in [(2, 8), (4, 16), (8, 32), (16, 64)] {
        for element in Element::ALL {
            let (dofs, p) = solve(element, nr, nz);
            let e = (p - reference).abs() / reference;
            println!(
                "{element:>7} {:>8} {dofs:>8} {p:>14.8} {e:>10.2e}",
                format!("{nr}×{nz}")
            );
            if element == Element::Q1P0 {
                errors.push(e);
            }
        }
    }
    let orders: Vec<f64> = errors.windows(2).map(|w| (w[0] / w[1]).log2()).collect();
    println!("Q1/P0 observed orders (h halved): {orders:.2?}");
    assert!(
        errors.windows(2).all(|w| w[1] < w[0]),
        "Q1/P0 errors {errors:?} do not decrease"
    );
    assert!(errors[errors.len() - 1] < 1e-2, "{errors:?}");
}

#[test]
fn q1p0_vtu_output_has_bilinear_cells_with_the_homogeneous_values() {
    let (mu, lambda) = (4.0, 1.3);
    let material = NeoHookean::new(mu).unwrap();
    let tmp = scratch("fem-q1p0-vtu");
    let directory = tmp.join("vtk");
    let options = SolverOptions {
        vtk: Some(VtkOutput {
            directory: directory.clone(),
            stretches: vec![lambda],
        }),
        ..q1p0()
    };
    let mesh = Mesh::structured(1.0, 2.0, 2, 3, 1.0).unwrap();
    let mut solver = AxisymmetricSolver::new(mesh, Bases::Sliding, &material, options).unwrap();
    solver.sweep(&[lambda]).unwrap().into_result().unwrap();
    let text = std::fs::read_to_string(directory.join("lambda_1.3000.vtu")).unwrap();
    assert!(text.contains(r#"NumberOfPoints="12" NumberOfCells="6""#));
    let block = |name: &str| common::vtu_data_array(&text, name);
    assert!(block("types").iter().all(|&t| t == 9.0), "VTK_QUAD cells");
    assert_eq!(block("offsets").last(), Some(&24.0));
    common::assert_uniaxial_neo_hookean_cells(&text, mu, lambda);
}

#[test]
fn q2q1_on_a_mesh_rebuilt_from_its_corners_gives_the_same_solution() {
    let material = NeoHookean::new(5.0).unwrap();
    let original = Mesh::structured(1.0, 4.0, 3, 6, 2.0).unwrap();
    let rebuilt = original
        .clone()
        .with_element(Element::Q1P0)
        .with_element(Element::Q2Q1);
    assert_eq!(rebuilt.n_nodes(), original.n_nodes());
    assert_eq!(rebuilt.n_elements(), original.n_elements());
    let stress = |mesh: Mesh| {
        let mut solver =
            AxisymmetricSolver::new(mesh, Bases::Clamped, &material, SolverOptions::default())
                .unwrap();
        solver.sweep(&[1.17]).unwrap().into_result().unwrap()[0].nominal_stress
    };
    let (a, b) = (stress(original), stress(rebuilt));
    assert!((a - b).abs() < 1e-10 * a, "{a} vs {b}");
}

#[test]
fn a_q1p0_cell_without_free_displacement_is_an_input_error() {
    // One clamped cell: its 4 corners are all held, so its pressure couples to nothing.
    let material = NeoHookean::new(5.0).unwrap();
    let mesh = Mesh::structured(1.0, 1.0, 1, 1, 1.0).unwrap();
    let e = AxisymmetricSolver::new(mesh, Bases::Clamped, &material, q1p0()).unwrap_err();
    assert!(matches!(e, FemError::InvalidInput { .. }), "{e}");
}

#[test]
fn elements_are_named_and_parsed_both_ways() {
    for element in Element::ALL {
        assert_eq!(element.name().parse::<Element>(), Ok(element));
        assert_eq!(
            element
                .to_string()
                .replace('/', "")
                .to_lowercase()
                .parse::<Element>(),
            Ok(element)
        );
    }
    assert!("Q2P1".parse::<Element>().is_err());
    assert_eq!(SolverOptions::default().element, Element::Q2Q1);
}
