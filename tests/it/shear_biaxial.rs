//! Simple shear and planar biaxial stretch (issue 25) against derivations written here: the
//! neo-Hookean closed forms, central differences of the energy along the shear path, the
//! approaches agreeing along the fibres and differing in shear by exactly the derivative of their
//! energies' difference, objectivity, and the study kinds through a scene.

use activemuscle::active::{ActiveCurve, Coupling, FrozenTangent, ImplicitLaw, Law};
use activemuscle::energy::{GiantesioMusesti, NeoHookean};
use activemuscle::homogeneous::{in_plane_fibre, planar_biaxial, simple_shear};
use activemuscle::invariants::{Kinematics, FULL};
use activemuscle::output::csv::files;
use activemuscle::response::Order;
use activemuscle::scene::{RunOptions, Scene};
use activemuscle::uniaxial::along_fibres;
use activemuscle::{Muscle, StrainEnergy};
use nalgebra::{Matrix3, Rotation3, Vector3};

const MU: f64 = 2.0;

#[test]
fn neo_hookean_simple_shear_is_the_closed_form() {
    let muscle = Muscle::passive(NeoHookean::new(MU).unwrap());
    for k in [-0.3, 0.0, 0.1, 0.5, 1.2] {
        for angle in [0.0, 30.0, 90.0] {
            let s = simple_shear(&muscle, None, k, angle).unwrap();
            let c = s.cauchy;
            // σ = μ B − p I with B = F Fᵀ and σ₃₃ = 0: σ₁₂ = μk, σ₁₁ = μk², σ₂₂ = 0.
            assert!((c[(0, 1)] - MU * k).abs() < 1e-12, "k = {k}");
            assert!((c[(1, 0)] - MU * k).abs() < 1e-12);
            assert!((c[(0, 0)] - MU * k * k).abs() < 1e-12);
            assert!(c[(1, 1)].abs() < 1e-12 && c[(2, 2)].abs() < 1e-12);
            assert_eq!(s.gamma, 0.0);
        }
    }
}

/// W(F(k)) of `muscle` along the shear path with the fibre at `angle`.
fn energy_along_shear<E: StrainEnergy>(muscle: &Muscle<E>, k: f64, angle: f64) -> f64 {
    let f = Matrix3::new(1.0, k, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    let kin = Kinematics::new(&f, &in_plane_fibre(angle)).unwrap();
    muscle.respond(&kin, Order::Energy, &FULL).unwrap().energy
}

#[test]
fn chapter_energy_in_shear_is_the_derivative_of_its_energy() {
    let muscle = Muscle::passive(GiantesioMusesti::paper());
    for angle in [0.0, 45.0, 90.0] {
        for k in [0.0, 0.1, 0.3, 0.6] {
            let s = simple_shear(&muscle, None, k, angle).unwrap();
            let h = 1e-5;
            let fd = (energy_along_shear(&muscle, k + h, angle)
                - energy_along_shear(&muscle, k - h, angle))
                / (2.0 * h);
            let sigma = s.cauchy[(0, 1)];
            assert!(
                (sigma - fd).abs() < 1e-7 * (1.0 + fd.abs()),
                "θ = {angle}, k = {k}: σ₁₂ = {sigma} vs dW/dk = {fd}"
            );
        }
    }
}

/// Active stress and active strain reproduce the same target along the fibres (to 1e-10) and
/// differ in shear along the fibres: with θ = 0 the fibre stretch stays 1, so γ = g(1) is
/// constant on the path and the difference of σ₁₂ is d/dk [Ŵ(F(k), g(1)) − W(F(k))] (central
/// differences here); active stress only adds σ₁₁ = (1 − d) P_act(1).
#[test]
fn active_stress_and_active_strain_agree_along_the_fibres_and_differ_in_shear() {
    let gm = GiantesioMusesti::paper();
    let curve = ActiveCurve::paper();
    let d = 0.1;
    let strain = Muscle::new(
        gm,
        Law::Implicit(ImplicitLaw::new(gm, curve)),
        d,
        Coupling::Frozen(FrozenTangent::Exact),
    )
    .unwrap();
    let stress = Muscle::active_stress(gm, curve, d).unwrap();
    let passive = Muscle::passive(gm);
    for lambda in [0.8, 1.0, 1.17, 1.3] {
        let a = along_fibres(&strain, lambda).unwrap().stress;
        let b = along_fibres(&stress, lambda).unwrap().stress;
        assert!(
            (a - b).abs() < 1e-10 * (1.0 + a.abs()),
            "λ = {lambda}: {a} vs {b}"
        );
    }
    let g1 = strain.activation(1.0).unwrap().gamma;
    let frozen = Muscle::new(
        gm,
        Law::Constant(activemuscle::active::ConstantLaw::new(g1).unwrap()),
        0.0,
        Coupling::Consistent,
    )
    .unwrap();
    let t1 = (1.0 - d) * curve.value(1.0);
    for k in [0.1, 0.3, 0.5] {
        let s_strain = simple_shear(&strain, None, k, 0.0).unwrap();
        let s_stress = simple_shear(&stress, None, k, 0.0).unwrap();
        let s_passive = simple_shear(&passive, None, k, 0.0).unwrap();
        assert!((s_strain.fibre_stretch - 1.0).abs() < 1e-14);
        assert!((s_strain.gamma - g1).abs() < 1e-14);
        let h = 1e-5;
        let diff =
            |k: f64| energy_along_shear(&frozen, k, 0.0) - energy_along_shear(&passive, k, 0.0);
        let expected = (diff(k + h) - diff(k - h)) / (2.0 * h);
        let got = s_strain.cauchy[(0, 1)] - s_stress.cauchy[(0, 1)];
        assert!(
            (got - expected).abs() < 1e-7 * (1.0 + expected.abs()),
            "k = {k}: {got} vs {expected}"
        );
        // Not a rounding effect: the shear stresses differ by more than 10 %.
        assert!(
            got.abs() > 0.1 * s_stress.cauchy[(0, 1)].abs(),
            "k = {k}: Δσ₁₂ = {got}"
        );
        // Active stress: the passive shear stress, plus T(1) along e₁ only.
        assert!((s_stress.cauchy[(0, 1)] - s_passive.cauchy[(0, 1)]).abs() < 1e-10);
        assert!(
            (s_stress.cauchy[(0, 0)] - s_passive.cauchy[(0, 0)] - t1).abs() < 1e-9 * (1.0 + t1)
        );
    }
}

/// The same state rotated, F′ = Q F with the reference fibre unchanged: the same invariants,
/// P′ = Q P.
#[test]
fn rotated_shear_states_have_the_same_invariants_and_rotated_stresses() {
    let gm = GiantesioMusesti::paper();
    let curve = ActiveCurve::paper();
    let muscle = Muscle::new(
        gm,
        Law::Implicit(ImplicitLaw::new(gm, curve)),
        0.0,
        Coupling::Consistent,
    )
    .unwrap();
    let f = Matrix3::new(1.0, 0.4, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0);
    let m = in_plane_fibre(30.0);
    let q = Rotation3::from_axis_angle(
        &nalgebra::Unit::new_normalize(Vector3::new(1.0, 2.0, -0.5)),
        0.7,
    )
    .into_inner();
    let r = |f: &Matrix3<f64>| {
        let kin = Kinematics::new(f, &m).unwrap();
        (
            kin.invariants,
            muscle.respond(&kin, Order::Stress, &FULL).unwrap(),
        )
    };
    let (j0, r0) = r(&f);
    let (j1, r1) = r(&(q * f));
    for i in 0..5 {
        assert!((j0[i] - j1[i]).abs() < 1e-13 * (1.0 + j0[i].abs()));
    }
    let p0 = Matrix3::from_row_slice(r0.stress.unwrap().as_slice());
    let p1 = Matrix3::from_row_slice(r1.stress.unwrap().as_slice());
    assert!((q * p0 - p1).abs().max() < 1e-12 * p0.abs().max());
    assert!((r0.gamma - r1.gamma).abs() < 1e-14);
}

#[test]
fn equibiaxial_isotropic_block_has_equal_stresses_and_the_closed_form() {
    let muscle = Muscle::passive(NeoHookean::new(MU).unwrap());
    for l in [0.9, 1.1, 1.3] {
        let s = planar_biaxial(&muscle, None, l, l).unwrap();
        let (p11, p22) = (s.nominal[(0, 0)], s.nominal[(1, 1)]);
        assert!((p11 - p22).abs() < 1e-12 * (1.0 + p11.abs()));
        // P₁₁ = μ (λ − λ₃²/λ), λ₃ = λ⁻².
        let expected = MU * (l - l.powi(-4) / l);
        assert!(
            (p11 - expected).abs() < 1e-12 * (1.0 + expected.abs()),
            "{p11} vs {expected}"
        );
        assert!((s.f[(2, 2)] - l.powi(-2)).abs() < 1e-15);
        assert!(s.cauchy[(2, 2)].abs() < 1e-12);
    }
    // A strip: the chapter's anisotropic energy is stiffer along its fibres.
    let gm = Muscle::passive(GiantesioMusesti::paper());
    let along = planar_biaxial(&gm, None, 1.2, 1.0).unwrap().nominal[(0, 0)];
    let across = planar_biaxial(&gm, None, 1.0, 1.2).unwrap().nominal[(1, 1)];
    assert!(along > across, "{along} vs {across}");
}

#[test]
fn nearly_incompressible_biaxial_block_tends_to_the_exact_one() {
    let gm = Muscle::passive(GiantesioMusesti::paper());
    let exact = planar_biaxial(&gm, None, 1.15, 1.05).unwrap();
    let mut last = f64::INFINITY;
    for kappa in [1e2, 1e4, 1e6] {
        let v = activemuscle::volumetric::Volumetric::new(
            activemuscle::volumetric::VolumetricForm::Quadratic { kappa },
            0.0,
        )
        .unwrap();
        let s = planar_biaxial(&gm, Some(&v), 1.15, 1.05).unwrap();
        assert!(s.cauchy[(2, 2)].abs() < 1e-9, "σ₃₃ = {}", s.cauchy[(2, 2)]);
        let gap = (s.nominal[(0, 0)] - exact.nominal[(0, 0)]).abs();
        assert!(gap < last, "κ = {kappa}: {gap}");
        last = gap;
    }
    assert!(last < 1e-4 * exact.nominal[(0, 0)].abs(), "{last}");
}

#[test]
fn shear_and_biaxial_studies_run_from_a_scene_and_write_their_tables() {
    let scene_text = r#"
[[study]]
kind = "shear"
shear = { from = 0.0, to = 0.4, step = 0.1 }
fibre_angles = [0.0, 90.0]
approaches = ["active-strain", "active-stress"]
damage = [0.0]

[[study]]
kind = "biaxial"
path = "strip"
stretch = [1.0, 1.1, 1.2]
approaches = ["active-strain", "active-stress"]
"#;
    let scene = Scene::parse(scene_text, "planar.toml").unwrap();
    let results = scene.run(&RunOptions::default());
    let failures: Vec<_> = results.failures().collect();
    assert!(failures.is_empty(), "{failures:?}");
    let files = files(&results);
    let shear = files
        .iter()
        .find(|f| f.file == "shear.csv")
        .expect("shear.csv");
    let text = String::from_utf8(shear.bytes().unwrap()).unwrap();
    let header = text.lines().next().unwrap();
    for column in [
        "approach",
        "fibre_angle",
        "shear",
        "sigma_12",
        "sigma_11",
        "sigma_22",
        "sigma_33",
    ] {
        assert!(header.split(',').any(|c| c == column), "{header}");
    }
    // (passive + 2 approaches) × 2 angles × 5 amounts of shear.
    assert_eq!(text.lines().count(), 1 + 3 * 2 * 5);
    let biaxial = files
        .iter()
        .find(|f| f.file == "biaxial.csv")
        .expect("biaxial.csv");
    assert_eq!(
        String::from_utf8(biaxial.bytes().unwrap())
            .unwrap()
            .lines()
            .count(),
        1 + 3 * 3
    );
    // A nearly incompressible scene is refused for shear, with the reason.
    let e = Scene::parse(
        &format!("[incompressibility]\nkind = \"quadratic\"\nkappa = 1e3\n{scene_text}"),
        "planar.toml",
    );
    assert!(e.is_err_and(|e| e.to_string().contains("exactly incompressible")));
}
