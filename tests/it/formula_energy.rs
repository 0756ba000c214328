//! Energies written as formulas: each shipped energy written as a formula responds exactly as
//! the compiled one (stress, tangent, dP/dγ, ∂Ŵ/∂γ, ∂²Ŵ/∂γ² at random states; every approach,
//! law and coupling; the FE cylinder); the neo-Hookean formula against its closed forms in
//! uniaxial tension and simple shear; a hydrostatic reference stress gets the volumetric forms'
//! linear term, a stress along the fibres at F = I is refused; and the scene's refusals, each at
//! its key and line.

use activemuscle::active::{ActivationMap, Approach};
use activemuscle::energy::{FormulaEnergy, NeoHookean, Parameter, Parametric, SHIPPED};
use activemuscle::fem::{AxisymmetricSolver, Bases, Mesh, SolverOptions};
use activemuscle::homogeneous::simple_shear;
use activemuscle::invariants::{Kinematics, FULL};
use activemuscle::models::{CouplingKind, LawKind, ModelChoice, Models};
use activemuscle::response::{active_response, Order};
use activemuscle::scene::Scene;
use activemuscle::testing::Sampler;
use activemuscle::uniaxial::{along_fibres, nearly_incompressible, Direction};
use activemuscle::volumetric::{Volumetric, VolumetricForm};
use activemuscle::{Energy, Muscle, StrainEnergy};
use nalgebra::{DMatrix, Matrix3};

const POSITIVE: (f64, f64) = (0.0, f64::INFINITY);

fn formula(text: &str, parameters: &[(&str, &str, f64, (f64, f64))]) -> FormulaEnergy {
    let declared = parameters
        .iter()
        .map(|&(name, unit, value, range)| Parameter::declared(name, unit, value, range))
        .collect();
    FormulaEnergy::new(text, declared).unwrap_or_else(|e| panic!("{text}: {e}"))
}

/// Each shipped energy and the same energy written as a formula (its registry entry's formula,
/// [`Energy::as_formula`]), at other parameters than the chapter's where a formula could hide a
/// default.
fn twins() -> Vec<(Energy, Energy)> {
    let values = |name: &str| match name {
        "mu" => 0.21,
        "alpha" => 14.5,
        "beta" => 1.7,
        "w0" => 0.66,
        other => panic!("a value for {other}"),
    };
    let twins: Vec<(Energy, Energy)> = SHIPPED
        .iter()
        .filter(|e| e.w.is_some())
        .map(|e| {
            let v: Vec<f64> = e.parameters.iter().map(|p| values(&p.name)).collect();
            let shipped = e.build(&v).unwrap();
            let written = Energy::Formula(shipped.as_formula().unwrap());
            (shipped, written)
        })
        .collect();
    assert!(twins.len() >= 4);
    twins
}

fn relative(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, x| m.max(x.abs())).max(1e-3);
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

#[test]
fn a_formula_identical_to_each_shipped_energy_gives_the_same_derivatives_to_1e_12() {
    let mut s = Sampler::new(44);
    for (shipped, written) in twins() {
        assert_eq!(
            shipped.uses_det_c(),
            written.uses_det_c(),
            "{}",
            shipped.name()
        );
        let mut worst: f64 = 0.0;
        for _ in 0..40 {
            let (f, m, gamma) = (s.deformation(0.25), s.unit_vector(), s.range(0.0, 0.45));
            let kin = Kinematics::new(&f, &m).unwrap();
            let at = |e: &Energy| active_response(e, &kin, gamma, Order::Tangent, &FULL).unwrap();
            let (a, b) = (at(&written), at(&shipped));
            let pairs = [
                relative(&[a.energy], &[b.energy]),
                relative(a.stress.unwrap().as_slice(), b.stress.unwrap().as_slice()),
                relative(a.tangent.unwrap().as_slice(), b.tangent.unwrap().as_slice()),
                relative(
                    a.dstress_dgamma.unwrap().as_slice(),
                    b.dstress_dgamma.unwrap().as_slice(),
                ),
                relative(&[a.denergy_dgamma.unwrap()], &[b.denergy_dgamma.unwrap()]),
                relative(
                    &[a.d2energy_dgamma2.unwrap()],
                    &[b.d2energy_dgamma2.unwrap()],
                ),
            ];
            worst = pairs.iter().fold(worst, |w, x| w.max(*x));
        }
        println!("{}: worst relative difference {worst:.1e}", shipped.name());
        assert!(worst <= 1e-12, "{}: {worst:e}", shipped.name());
    }
}

/// The models of the scene's other choices with `energy` and the active-strain `map`.
fn models(energy: &Energy, map: ActivationMap) -> Models {
    Models {
        energy: energy.clone(),
        map,
        ..Models::paper()
    }
}

#[test]
fn every_approach_law_and_coupling_follows_the_formula_as_the_compiled_energy() {
    let mut s = Sampler::new(45);
    let states: Vec<(Matrix3<f64>, nalgebra::Vector3<f64>)> = (0..6)
        .map(|_| (s.deformation(0.2), s.unit_vector()))
        .collect();
    let mut checked = 0;
    for (shipped, written) in twins() {
        let structural = shipped.structural_fibre_weight();
        assert_eq!(
            written.structural_fibre_weight().is_some(),
            structural.is_some()
        );
        if let (Some(a), Some(b)) = (written.structural_fibre_weight(), structural) {
            assert!((a - b).abs() < 1e-14, "{}: f {a} vs {b}", shipped.name());
        }
        let mut approaches = vec![
            (Approach::ActiveStrain, ActivationMap::Chapter),
            (Approach::ActiveStrain, ActivationMap::VolumePreserving),
            (Approach::ActiveStress, ActivationMap::Chapter),
        ];
        if structural.is_some() {
            approaches.push((Approach::Structural, ActivationMap::Chapter));
        }
        for (approach, map) in approaches {
            for law in [LawKind::Implicit, LawKind::Energy] {
                for coupling in [CouplingKind::Frozen, CouplingKind::Consistent] {
                    let choice = ModelChoice {
                        approach,
                        law,
                        coupling,
                        damage: 0.2,
                    };
                    let muscle = |e: &Energy| models(e, map).muscle(choice).unwrap();
                    let (a, b) = (muscle(&written), muscle(&shipped));
                    for (f, m) in &states {
                        let kin = Kinematics::new(f, m).unwrap();
                        let (ra, rb) = (
                            a.respond(&kin, Order::Tangent, &FULL).unwrap(),
                            b.respond(&kin, Order::Tangent, &FULL).unwrap(),
                        );
                        let what = format!(
                            "{} {approach:?} {map:?} {law:?} {coupling:?}",
                            shipped.name()
                        );
                        assert!((ra.gamma - rb.gamma).abs() <= 1e-12, "{what}: γ");
                        let p =
                            relative(ra.stress.unwrap().as_slice(), rb.stress.unwrap().as_slice());
                        let k = relative(
                            ra.tangent.unwrap().as_slice(),
                            rb.tangent.unwrap().as_slice(),
                        );
                        let dg = relative(
                            ra.dstress_dgamma.unwrap().as_slice(),
                            rb.dstress_dgamma.unwrap().as_slice(),
                        );
                        assert!(
                            p.max(k).max(dg) <= 1e-11,
                            "{what}: P {p:e}, K {k:e}, dP/dγ {dg:e}"
                        );
                        checked += 1;
                    }
                }
            }
        }
    }
    assert_eq!(checked, 6 * 4 * (4 * 3 + 3));
}

#[test]
fn the_fe_cylinder_of_the_chapters_formula_is_the_chapters() {
    let (shipped, written) = twins().swap_remove(0);
    let sweep = |e: &Energy| {
        let m = models(e, ActivationMap::Chapter)
            .muscle(ModelChoice {
                approach: Approach::ActiveStrain,
                law: LawKind::Implicit,
                coupling: CouplingKind::Frozen,
                damage: 0.0,
            })
            .unwrap();
        let mesh = Mesh::structured(1.0, 3.0, 2, 4, 1.0).unwrap();
        let mut solver =
            AxisymmetricSolver::new(mesh, Bases::Clamped, &m, SolverOptions::default()).unwrap();
        let out = solver.sweep(&[1.1, 0.9]).unwrap();
        assert!(out.failures.is_empty());
        out.results
            .iter()
            .map(|r| r.nominal_stress)
            .collect::<Vec<f64>>()
    };
    let (a, b) = (sweep(&written), sweep(&shipped));
    println!("formula {a:?}\ncompiled {b:?}");
    assert!(relative(&a, &b) < 1e-9, "{a:?} vs {b:?}");
}

#[test]
fn the_neo_hookean_formula_has_its_closed_forms_in_uniaxial_tension_and_simple_shear() {
    let mu = 0.37;
    let nh = formula("mu/2*(I1 - 3)", &[("mu", "kPa", mu, POSITIVE)]);
    let muscle = Muscle::passive(nh);
    for lambda in [0.7, 0.95, 1.0, 1.2, 1.6] {
        let p = along_fibres(&muscle, lambda).unwrap().stress;
        let closed = mu * (lambda - lambda.powi(-2));
        assert!(
            (p - closed).abs() <= 1e-13 * (1.0 + closed.abs()),
            "λ = {lambda}: {p} vs {closed}"
        );
    }
    for k in [0.05, 0.3, 0.8] {
        let state = simple_shear(&muscle, None, k, 30.0).unwrap();
        let (p, sigma) = (state.nominal, state.cauchy);
        assert!(
            (p[(0, 1)] - mu * k).abs() < 1e-12,
            "P₁₂ = {} vs μk = {}",
            p[(0, 1)],
            mu * k
        );
        assert!((sigma[(0, 1)] - mu * k).abs() < 1e-12);
        assert!(
            (sigma[(0, 0)] - sigma[(1, 1)] - mu * k * k).abs() < 1e-12,
            "normal stress difference"
        );
    }
}

#[test]
fn a_hydrostatic_reference_stress_gets_the_linear_term_a_fibre_stress_is_refused() {
    let mu = 0.37;
    let nh = formula("mu/2*(I1 - 3)", &[("mu", "kPa", mu, POSITIVE)]);
    // P(I) = μ I, as the closed form 2 ∂W/∂I₁ I says; the engine's own reading agrees.
    assert!((nh.reference_stress() - mu).abs() < 1e-15);
    let s0 = activemuscle::uniaxial::reference_stress(&nh).unwrap();
    assert!((s0 - mu).abs() < 1e-14);
    // With a volumetric energy the linear term cancels it: no stress and no volume change at λ = 1.
    let v = Volumetric::new(VolumetricForm::Quadratic { kappa: 1e3 }, s0).unwrap();
    let at_rest =
        nearly_incompressible(&Muscle::passive(nh.clone()), &v, Direction::Along, 1.0).unwrap();
    assert!(
        at_rest.stress.abs() < 1e-12 && (at_rest.lateral[0] - 1.0).abs() < 1e-12,
        "{at_rest:?}"
    );
    // The same as the compiled neo-Hookean energy, away from rest.
    let compiled = Muscle::passive(NeoHookean::new(mu).unwrap());
    for lambda in [0.9, 1.3] {
        let a = nearly_incompressible(&Muscle::passive(nh.clone()), &v, Direction::Along, lambda)
            .unwrap();
        let b = nearly_incompressible(&compiled, &v, Direction::Along, lambda).unwrap();
        assert!((a.stress - b.stress).abs() < 1e-12 * (1.0 + b.stress.abs()));
    }
    // A stress along the fibres at F = I is not a pressure: refused, saying why.
    let declared = vec![Parameter::declared("k", "kPa", 1.0, POSITIVE)];
    let e = FormulaEnergy::new("k*(I4 - 1) + k*(I1 - 3)^2", declared).unwrap_err();
    assert_eq!(e.key, "W");
    assert!(e.rule.contains("along the fibres"), "{e}");
    // A constant in W is refused too.
    let declared = vec![Parameter::declared("mu", "kPa", 1.0, POSITIVE)];
    let e = FormulaEnergy::new("mu/2*(I1 - 3) + mu", declared).unwrap_err();
    assert!(e.rule.contains("store no energy"), "{e}");
}

/// A Yeoh-type matrix with a Holzapfel-type fibre term.
pub fn yeoh_fibres() -> FormulaEnergy {
    formula(
        "c10*(I1 - 3) + c20*(I1 - 3)^2 + k1/(2*k2)*expm1(k2*(I4 - 1)^2)",
        &[
            ("c10", "kPa", 0.12, POSITIVE),
            ("c20", "kPa", 0.05, POSITIVE),
            ("k1", "kPa", 0.4, POSITIVE),
            ("k2", "-", 6.0, POSITIVE),
        ],
    )
}

/// The scene of `material` (the lines of a `[material]` table) with one uniaxial study.
fn scene(material: &str) -> String {
    format!("[material]\n{material}\n\n[[study]]\nkind = \"uniaxial\"\nstretch = [1.0, 1.1]\n")
}

/// The scene's error: key, line, rule.
fn refused(material: &str) -> (String, Option<usize>, String) {
    let e = Scene::parse(&scene(material), "formula.toml").expect_err("refused");
    println!("{e}");
    (e.key, e.line, e.rule)
}

#[test]
fn bad_formulas_are_refused_at_their_key_and_line() {
    let mu = "[material.parameters]\nmu = { value = 0.2, unit = \"kPa\", range = [0, inf] }";
    // Unknown names, with the nearest known one.
    let (key, line, rule) = refused(&format!(
        "energy = \"formula\"\nW = \"mu/2*(I_1 - 3)\"\n{mu}"
    ));
    assert_eq!((key.as_str(), line), ("material.W", Some(3)));
    assert!(
        rule.contains("unknown name `I_1`") && rule.contains("did you mean `I1`"),
        "{rule}"
    );
    let (_, _, rule) = refused(&format!(
        "energy = \"formula\"\nW = \"mu2/2*(I1 - 3)\"\n{mu}"
    ));
    assert!(rule.contains("did you mean `mu`"), "{rule}");
    let (_, _, rule) = refused(&format!(
        "energy = \"formula\"\nW = \"mu*log(I1/3)^2\"\n{mu}"
    ));
    assert!(rule.contains("written ln(x)"), "{rule}");
    // A division by a parameter whose range includes 0.
    let (key, _, rule) = refused(&format!(
        "energy = \"formula\"\nW = \"mu*(I1 - 3) + expm1(k*(I4 - 1)^2)/k\"\n{mu}\nk = 2.0"
    ));
    assert_eq!(key, "material.W");
    assert!(
        rule.contains("a division by `k`") && rule.contains("k ∈ (-inf, inf)"),
        "{rule}"
    );
    // Not finite at F = I: (I1 − 3)^1.5 has an infinite second derivative there.
    let (key, _, rule) = refused(&format!(
        "energy = \"formula\"\nW = \"mu*(I1 - 3)^1.5\"\n{mu}"
    ));
    assert_eq!(key, "material.W");
    assert!(rule.contains("not finite at F = I"), "{rule}");
    // Declarations: a value outside its range, an unused parameter, a flat parameter.
    let (key, line, rule) = refused(
        "energy = \"formula\"\nW = \"mu/2*(I1 - 3)\"\n[material.parameters]\nmu = { value = -1, range = [0, inf] }",
    );
    assert_eq!(
        (key.as_str(), line),
        ("material.parameters.mu.value", Some(5))
    );
    assert!(rule.contains("must lie in the range (0, inf)"), "{rule}");
    // A range or fit bounds of three values: refused at their own key, not cut to two.
    for key in ["range", "bounds"] {
        let (at, _, rule) = refused(&format!(
            "energy = \"formula\"\nW = \"mu/2*(I1 - 3)\"\n[material.parameters]\nmu = {{ value = 1, {key} = [0, 5, 10] }}"
        ));
        assert!(
            at.ends_with(&format!("mu.{key}")) || at.ends_with("mu"),
            "{at}: {rule}"
        );
        assert!(rule.contains("exactly 2"), "{rule}");
    }
    let (key, _, rule) = refused(&format!(
        "energy = \"formula\"\nW = \"mu/2*(I1 - 3)\"\n{mu}\nk = 2.0"
    ));
    assert_eq!(key, "material.parameters.k");
    assert!(rule.contains("does not use parameter k"), "{rule}");
    let (key, _, rule) = refused("energy = \"formula\"\nW = \"2*(I1 - 3)\"\nmu = 0.2");
    assert_eq!(key, "material.mu");
    assert!(rule.contains("parameters = {"), "{rule}");
    // W belongs to a formula.
    let (key, _, _) = refused("energy = \"neo-hookean\"\nmu = 1.0\nW = \"mu*(I1 - 3)\"");
    assert_eq!(key, "material.W");
    // A syntax error names the column.
    let (_, _, rule) = refused(&format!("energy = \"formula\"\nW = \"mu/2*(I1 - 3\"\n{mu}"));
    assert!(
        rule.contains("expected `)`") && rule.contains("column 13"),
        "{rule}"
    );
}

#[test]
fn check_prints_the_formula_back_and_the_printout_reads_as_the_same_energy() {
    let text = scene(
        "energy = \"formula\"\nname = \"yeoh-fibres\"\nW = \"\"\"\n  c10*(I1 - 3)  # matrix\n  + k1/(2*k2)*expm1(k2*(I4 - 1)^2)\"\"\"\n\
         [material.parameters]\nc10 = { value = 0.12, unit = \"kPa\", range = [0, inf], symbol = \"c₁₀\" }\n\
         k1 = { value = 0.4, unit = \"kPa\", range = [0, inf], bounds = [0, 10] }\nk2 = { value = 6, range = [0, 100] }",
    );
    let scene = Scene::parse(&text, "yeoh.toml").unwrap();
    let Energy::Formula(f) = &scene.models.energy else {
        panic!("a formula energy")
    };
    assert_eq!(f.name(), "yeoh-fibres");
    assert!(f.formula().contains("# matrix"), "the formula as given");
    let printed = scene.resolved_toml().unwrap();
    println!("{printed}");
    let again = Scene::parse(&printed, "printed.toml").unwrap();
    assert_eq!(again.models.energy, scene.models.energy);
    let bounds: Vec<(f64, f64)> = f.parameters().iter().map(|p| p.bounds).collect();
    assert_eq!(bounds, [(0.0, f64::INFINITY), (0.0, 10.0), (0.0, 100.0)]);
}

#[test]
fn the_fit_jacobian_of_a_formula_is_its_parameter_derivative() {
    // energy_with on dual parameters against central differences of W in each parameter.
    use activemuscle::energy::Invariants;
    use num_dual::Dual64;
    let w = yeoh_fibres();
    let j = Invariants::from_array([3.3, 1.2, 3.1, 0.85, 1.0]);
    let values = w.parameter_values();
    let mut jac = DMatrix::zeros(1, values.len());
    for k in 0..values.len() {
        let seeded: Vec<Dual64> = values
            .iter()
            .enumerate()
            .map(|(i, &v)| {
                if i == k {
                    Dual64::from_re(v).derivative()
                } else {
                    Dual64::from_re(v)
                }
            })
            .collect();
        let lifted = Invariants::from_array(j.to_array().map(Dual64::from_re));
        jac[(0, k)] = w.energy_with(&seeded, &lifted).eps;
        let h = 1e-6 * values[k];
        let at = |x: f64| {
            let mut v = values.clone();
            v[k] = x;
            w.rebuilt(&v).unwrap().energy(&j)
        };
        let fd = (at(values[k] + h) - at(values[k] - h)) / (2.0 * h);
        assert!(
            (fd - jac[(0, k)]).abs() < 1e-7 * (1.0 + fd.abs()),
            "∂W/∂θ_{k}: {fd} vs {}",
            jac[(0, k)]
        );
    }
}
