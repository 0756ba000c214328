//! Damage and activation varying in space in the FE cylinder (`[[study.regions]]`): regions
//! that change nothing reproduce the uniform cylinder, a region covering the sliding cylinder
//! at activation a reproduces the 0D curve at d_eff = d + (1 − d)(1 − a), a damaged outer layer
//! lies between the undamaged and the uniformly damaged cylinder, VTK carries the fields, and
//! the scene's errors name file:line and key.

use activemuscle::active::{Coupling, Drive, ExplicitLaw, FrozenTangent, Law};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::studies::cylinder::CylinderResult;
use activemuscle::studies::StudyResult;
use activemuscle::uniaxial::along_fibres;
use activemuscle::Muscle;

use crate::scratch;
use scratch::scratch;

const FILE: &str = "regions.toml";

/// A cylinder study (explicit law, frozen) with `regions` appended (TOML) after line 14.
fn scene(bases: &str, damage: &str, stretch: &str, regions: &str) -> String {
    format!(
        r#"[[study]]
kind = "cylinder"
name = "regions"
bases = "{bases}"
radius = 1.0
length = 4.0
nr = 5
nz = 4
law = "explicit"
coupling = "frozen"
damage = {damage}
stretch = {stretch}
tolerance = 1e-11

{regions}"#
    )
}

fn run(text: &str, options: &RunOptions) -> CylinderResult {
    let scene = Scene::parse(text, FILE).unwrap();
    let results = scene.run(options);
    assert!(
        results.failures().next().is_none(),
        "{:?}",
        results.failures().collect::<Vec<_>>()
    );
    match &results.studies[0].result {
        StudyResult::Cylinder(c) => c.clone(),
        other => panic!("a cylinder result, got {other:?}"),
    }
}

fn stresses(c: &CylinderResult) -> Vec<Vec<f64>> {
    c.sweeps
        .iter()
        .map(|s| s.points.iter().map(|p| p.stress).collect())
        .collect()
}

#[test]
fn regions_with_the_models_own_damage_give_the_uniform_cylinder() {
    let (damage, stretch) = ("[0.3]", "[0.9, 1.1]");
    let uniform = run(
        &scene("clamped", damage, stretch, ""),
        &RunOptions::default(),
    );
    // Overlapping regions at the sweep's own damage, written out or through a = 1.
    let regions = "[[study.regions]]\nr = [0.0, 0.5]\ndamage = 0.3\n\n[[study.regions]]\nz = [0.5, 1.0]\nactivation = 1.0\n\n[[study.regions]]\nr = [0.2, 0.9]\nz = [0.1, 0.7]\ndamage = 0.3\nactivation = 1.0\n";
    let same = run(
        &scene("clamped", damage, stretch, regions),
        &RunOptions::default(),
    );
    let (a, b) = (stresses(&uniform), stresses(&same));
    assert_eq!(a.len(), 1);
    for (sa, sb) in a.iter().zip(&b) {
        assert_eq!(sa.len(), 2);
        for (x, y) in sa.iter().zip(sb) {
            assert!((x - y).abs() <= 1e-12 * x.abs().max(1.0), "{x} vs {y}");
        }
    }
}

#[test]
fn one_region_over_the_sliding_cylinder_is_the_0d_curve_at_the_effective_damage() {
    // d_eff = 0.2 + 0.8 · 0.25 = 0.4: inside the explicit law's domain (d_eff ≤ 0.5).
    let (d, a) = (0.2, 0.75);
    let d_eff = Drive::new(d, a).unwrap().effective_damage();
    let regions = format!("[[study.regions]]\nactivation = {a}\n");
    let c = run(
        &scene(
            "sliding",
            &format!("[{d}]"),
            "[0.8, 1.0, 1.2, 1.4]",
            &regions,
        ),
        &RunOptions::default(),
    );
    // The 0D reference: a muscle built at damage d_eff (no activation level involved).
    let muscle = Muscle::new(
        GiantesioMusesti::paper(),
        Law::Explicit(ExplicitLaw::paper()),
        d_eff,
        Coupling::Frozen(FrozenTangent::Exact),
    )
    .unwrap();
    let undamaged = Muscle::new(
        GiantesioMusesti::paper(),
        Law::Explicit(ExplicitLaw::paper()),
        d,
        Coupling::Frozen(FrozenTangent::Exact),
    )
    .unwrap();
    let points = &c.sweeps[0].points;
    assert_eq!(points.len(), 4);
    for p in points {
        let exact = along_fibres(&muscle, p.lambda).unwrap().stress;
        let rel = (p.stress - exact).abs() / exact.abs().max(1e-3);
        assert!(
            rel < 1e-9,
            "λ = {}: FE {} vs 0D {exact}",
            p.lambda,
            p.stress
        );
        // And it is not the model's own d (the region changed something).
        let own = along_fibres(&undamaged, p.lambda).unwrap().stress;
        assert!((own - exact).abs() > 1e-3 * own.abs(), "λ = {}", p.lambda);
    }
}

#[test]
fn a_damaged_outer_layer_lowers_the_force_monotonically_between_the_uniform_cylinders() {
    let stretch = "[0.9, 1.1]";
    let uniform = stresses(&run(
        &scene("clamped", "[0.0, 1.0]", stretch, ""),
        &RunOptions::default(),
    ));
    let layer = |damage: f64| {
        let regions = format!("[[study.regions]]\nr = [0.8, 1.0]\ndamage = {damage}\n");
        stresses(&run(
            &scene("clamped", "[0.0]", stretch, &regions),
            &RunOptions::default(),
        ))
        .remove(0)
    };
    let layers: Vec<Vec<f64>> = [0.0, 0.5, 1.0].into_iter().map(layer).collect();
    for k in 0..2 {
        let (intact, damaged) = (uniform[0][k], uniform[1][k]);
        // A layer with d = 0 is the undamaged cylinder.
        assert!((layers[0][k] - intact).abs() <= 1e-12 * intact.abs(), "{k}");
        assert!(
            layers[0][k] > layers[1][k] && layers[1][k] > layers[2][k],
            "{layers:?}"
        );
        assert!(layers[2][k] > damaged, "{layers:?} vs {damaged}");
    }
}

#[test]
fn vtk_carries_damage_and_activation_cell_fields_with_regions_only() {
    let tmp = scratch("regions-vtk");
    let dir = tmp.join("vtk");
    let options = RunOptions {
        vtk_dir: Some(dir.clone()),
        ..RunOptions::default()
    };
    let read = |regions: &str| -> String {
        let c = run(&scene("clamped", "[0.0]", "[1.1]", regions), &options);
        let file = dir.join(&c.sweeps[0].vtk_files[0]);
        std::fs::read_to_string(&file).unwrap()
    };
    let vtu =
        read("vtk = [1.1]\n[[study.regions]]\nr = [0.8, 1.0]\ndamage = 0.2\nactivation = 0.7\n");
    let field = |name: &str| -> Vec<f64> {
        let start = vtu
            .find(&format!("Name=\"{name}\""))
            .unwrap_or_else(|| panic!("no {name} field"));
        let body = &vtu[start..];
        let body = &body[body.find('>').unwrap() + 1..body.find("</DataArray>").unwrap()];
        body.split_whitespace()
            .map(|v| v.parse().unwrap())
            .collect()
    };
    // 5 × 4 cells; the outer column (r ∈ [0.8, 1], a cell boundary) is the region.
    let (damage, activation) = (field("damage"), field("activation"));
    assert_eq!(damage.len(), 20);
    let pairs: Vec<(f64, f64)> = damage.into_iter().zip(activation).collect();
    // Volume-weighted cell averages of a constant: the constant to rounding.
    let near =
        |p: &(f64, f64), q: (f64, f64)| (p.0 - q.0).abs() < 1e-14 && (p.1 - q.1).abs() < 1e-14;
    assert_eq!(
        pairs.iter().filter(|p| near(p, (0.2, 0.7))).count(),
        4,
        "{pairs:?}"
    );
    assert_eq!(
        pairs.iter().filter(|p| near(p, (0.0, 1.0))).count(),
        16,
        "{pairs:?}"
    );
    // Without regions: no such fields.
    let _ = std::fs::remove_dir_all(&dir);
    let vtu = read("vtk = [1.1]\n");
    assert!(!vtu.contains("Name=\"damage\"") && vtu.contains("Name=\"gamma\""));
}

#[test]
fn invalid_regions_are_refused_with_file_line_and_key() {
    let first = "[[study.regions]]\nr = [0.0, 0.5]\ndamage = 0.1\n\n";
    // The second region's header is line 19 of the scene.
    for (second, line, key, rule) in [
        (
            "r = [0.9, 0.8]\ndamage = 0.5",
            20,
            "study[0].regions[1].r",
            "0 ≤ r0 < r1 ≤ 1",
        ),
        (
            "z = [0.0, 1.5]\ndamage = 0.5",
            20,
            "study[0].regions[1].z",
            "0 ≤ z0 < z1 ≤ 1",
        ),
        ("damage = 1.5", 20, "study[0].regions[1].damage", "[0, 1]"),
        (
            "r = [0.2, 0.4]\nactivation = -0.1",
            21,
            "study[0].regions[1].activation",
            "[0, 1]",
        ),
        (
            "r = [0.2, 0.4]",
            19,
            "study[0].regions[1]",
            "damage and/or activation",
        ),
        (
            "dmage = 0.5",
            20,
            "study[0].regions[1].dmage",
            "unknown field",
        ),
    ] {
        let text = scene(
            "clamped",
            "[0.0]",
            "[1.1]",
            &format!("{first}[[study.regions]]\n{second}\n"),
        );
        let e = Scene::parse(&text, FILE).unwrap_err().to_string();
        assert!(e.starts_with(&format!("{FILE}:{line}: {key}")), "{e}");
        assert!(e.contains(rule), "{rule}: {e}");
    }
}

#[test]
fn the_example_scene_loads_and_runs_to_the_end() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/examples/damaged_outer_layer.toml");
    let scene = Scene::load(&path).unwrap();
    let results = scene.run(&RunOptions::default());
    assert!(
        results.complete(),
        "{:?}",
        results.failures().collect::<Vec<_>>()
    );
    // The report's study table says where each region is and what it holds, as the file wrote it.
    let details = &results.studies[0].details;
    for line in [
        "region 1: r/R ∈ [0.8, 1], z/L ∈ [0, 1], d = 0.5, a = 1",
        "region 2: r/R ∈ [0, 0.5], z/L ∈ [0.3333, 0.6667], d = the sweep's, a = 0.5",
    ] {
        assert!(
            details.iter().any(|d| d == line),
            "{line} not in {details:?}"
        );
    }
}

/// A muscle of the chapter with the explicit law at damage `d` (frozen, exact tangent).
fn explicit_muscle(d: f64) -> Muscle<GiantesioMusesti> {
    Muscle::new(
        GiantesioMusesti::paper(),
        Law::Explicit(ExplicitLaw::paper()),
        d,
        Coupling::Frozen(FrozenTangent::Exact),
    )
    .unwrap()
}

#[test]
fn newton_with_regions_converges_quadratically_so_the_tangent_is_exact() {
    use activemuscle::fem::{AxisymmetricSolver, Bases, Mesh, Region, Regions, SolverOptions};
    // The example's layout on R = 1, L = 4: an outer layer at d = 0.5, a core at d_eff = 0.5.
    let material = Regions::new(
        explicit_muscle(0.0),
        (0.0, 1.0),
        vec![
            Region {
                r: [0.8, 1.0],
                z: [0.0, 4.0],
                material: explicit_muscle(0.5),
                fields: (0.5, 1.0),
            },
            Region {
                r: [0.0, 0.5],
                z: [4.0 / 3.0, 8.0 / 3.0],
                material: explicit_muscle(0.5),
                fields: (0.0, 0.5),
            },
        ],
    );
    let mesh = Mesh::structured(1.0, 4.0, 10, 24, 1.0).unwrap();
    let mut solver =
        AxisymmetricSolver::new(mesh, Bases::Clamped, &material, SolverOptions::default()).unwrap();
    let sweep = solver.sweep(&[1.0, 1.1, 1.2]).unwrap();
    assert!(sweep.failures.is_empty(), "{:?}", sweep.failures);
    // Quadratic convergence near the solution, r_{k+1} ≤ C r_k², with C = 1e3 (measured ≤ 100);
    // a tangent that missed the regions' materials converges linearly, r_{k+1} ≈ ρ r_k, and fails
    // it by orders of magnitude once r_k < 1e-4. (The step 1.05 → 1.1 fails its line search and
    // is halved: the extra iterations against the uniform cylinder are that, not the tangent.)
    let mut checked = 0;
    for step in sweep.results.iter().flat_map(|r| &r.steps) {
        if step.failure.is_some() {
            continue;
        }
        let r: Vec<f64> = std::iter::once(step.initial_residual)
            .chain(step.iterations.iter().map(|i| i.residual))
            .collect();
        for w in r.windows(2).filter(|w| w[0] < 1e-3 && w[1] > 1e-13) {
            assert!(
                w[1] <= 1e3 * w[0] * w[0],
                "step {} → {}: residuals {r:?}",
                step.from,
                step.to
            );
            checked += 1;
        }
    }
    assert!(checked >= 8, "only {checked} iterations near the solution");
}
