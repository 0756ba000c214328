//! The active-strain map chosen per model (chapter: F_a = I − γ M; volume-preserving:
//! F_a = (1 − γ) M + (1 − γ)^(−½) (I − M)): the fast invariant route against the 9-entry oracle
//! that builds F_a as a 3×3 matrix, the γ-derivatives of the map against dual numbers, the laws
//! and couplings along the fibres against their targets, and closed forms derived by hand.

use activemuscle::active::{
    ActivationLaw, ActivationMap, ActiveCurve, ConstantLaw, Coupling, EnergyLaw, FrozenTangent,
    ImplicitLaw, Law, SolvedLaw, TableSpec, TabulatedLaw,
};
use activemuscle::energy::{EhretBolItskov, GiantesioMusesti, NeoHookean, StrainEnergy};
use activemuscle::invariants::{axial_fibre, axisymmetric_f, Kinematics, AXISYMMETRIC, FULL};
use activemuscle::oracle::full_response_with;
use activemuscle::response::{invariant_derivatives_with, Order};
use activemuscle::testing::Sampler;
use activemuscle::uniaxial::along_fibres;
use activemuscle::{Error, Muscle};
use nalgebra::{SMatrix, SVector};
use num_dual::{hessian, Dual2SVec64, HyperDual64};

const MAPS: [ActivationMap; 2] = [ActivationMap::Chapter, ActivationMap::VolumePreserving];
const GAMMAS: [f64; 4] = [0.0, 0.1, 0.3, 0.5];
const TOL: f64 = 1e-12;

fn rel<const R: usize, const C: usize>(a: &SMatrix<f64, R, C>, b: &SMatrix<f64, R, C>) -> f64 {
    (a - b).amax() / b.amax()
}

/// A muscle at constant γ with the map: its stress, tangent and dP/dγ are those of Ŵ at γ held.
fn held<E: StrainEnergy>(energy: E, map: ActivationMap, gamma: f64) -> Muscle<E> {
    Muscle::new(
        energy,
        Law::Constant(ConstantLaw::new(gamma).unwrap()),
        0.0,
        Coupling::Consistent,
    )
    .unwrap()
    .with_map(map)
    .unwrap()
}

/// The fast route (invariants of C, the map applied to them) against the oracle (dual numbers
/// over F's nine entries and γ, F_a a 3×3 matrix) for one energy: energy, stress, tangent and
/// dP/dγ in 3D and over the five axisymmetric entries, both maps, several γ.
fn fast_route_matches_oracle<E: StrainEnergy + Copy>(energy: E, seed: u64) {
    let mut rng = Sampler::new(seed);
    let mut worst = [0.0f64; 4];
    for map in MAPS {
        for gamma in GAMMAS {
            let muscle = held(energy, map, gamma);
            for n in 0..10 {
                let (f, m) = (rng.deformation(0.25), rng.unit_vector());
                let kin = Kinematics::new(&f, &m).unwrap();
                let fast = muscle.respond(&kin, Order::Tangent, &FULL).unwrap();
                let or = full_response_with(&energy, map, &f, &m, gamma).unwrap();
                let errors = [
                    ((fast.energy - or.energy) / or.energy.abs().max(1e-3)).abs(),
                    rel(&fast.stress.unwrap(), &or.stress),
                    rel(&fast.tangent.unwrap(), &or.tangent),
                    if gamma == 0.0 && or.dstress_dgamma.amax() == 0.0 {
                        fast.dstress_dgamma.unwrap().amax()
                    } else {
                        rel(&fast.dstress_dgamma.unwrap(), &or.dstress_dgamma)
                    },
                ];
                for (k, e) in errors.iter().enumerate() {
                    assert!(
                        *e <= TOL,
                        "{} map, gamma {gamma}, sample {n}: quantity {k} differs by {e:e}",
                        map.name()
                    );
                    worst[k] = worst[k].max(*e);
                }

                // Axisymmetric: fibres along the axis, F from five entries.
                let f5 = SVector::<f64, 5>::from_fn(|i, _| {
                    let one = if matches!(i, 0 | 3 | 4) { 1.0 } else { 0.0 };
                    one + rng.range(-0.2, 0.2)
                });
                let (fa, ma) = (axisymmetric_f(&f5), axial_fibre());
                let kin = Kinematics::new(&fa, &ma).unwrap();
                let fast = muscle.respond(&kin, Order::Tangent, &AXISYMMETRIC).unwrap();
                let or = full_response_with(&energy, map, &fa, &ma, gamma).unwrap();
                let pos = AXISYMMETRIC.index.map(|(k, l)| 3 * k + l);
                let or_p = SVector::<f64, 5>::from_fn(|a, _| or.stress[pos[a]]);
                let or_g = SVector::<f64, 5>::from_fn(|a, _| or.dstress_dgamma[pos[a]]);
                let or_t = SMatrix::<f64, 5, 5>::from_fn(|a, b| or.tangent[(pos[a], pos[b])]);
                assert!(rel(&fast.stress.unwrap(), &or_p) <= TOL);
                assert!(rel(&fast.tangent.unwrap(), &or_t) <= TOL);
                if gamma > 0.0 {
                    assert!(rel(&fast.dstress_dgamma.unwrap(), &or_g) <= TOL);
                }
            }
        }
    }
    eprintln!("worst relative difference [W, P, dP/dF, dP/dgamma]: {worst:?}");
}

#[test]
fn fast_route_matches_the_oracle_for_both_maps_chapter_energy() {
    fast_route_matches_oracle(GiantesioMusesti::paper(), 0x3a9_0001);
}

#[test]
fn fast_route_matches_the_oracle_for_both_maps_ehret_bol_itskov() {
    fast_route_matches_oracle(EhretBolItskov::paper(), 0x3a9_0002);
}

#[test]
fn fast_route_matches_the_oracle_for_both_maps_neo_hookean() {
    fast_route_matches_oracle(NeoHookean::new(2.0).unwrap(), 0x3a9_0003);
}

/// ∂Ŵ/∂γ, ∂²Ŵ/∂γ², ∂Ŵ/∂j and ∂²Ŵ/∂j∂γ of the invariant route against a dual-number Hessian of
/// the generic Ŵ(j, γ) = φ W(A(γ) j) (the map's hand-written γ-derivatives against the map's
/// own formulas, differentiated by num-dual), for an energy that uses all five invariants.
#[test]
fn gamma_derivatives_of_the_map_match_dual_numbers() {
    #[derive(Clone, Copy)]
    struct AllFive;
    impl StrainEnergy for AllFive {
        fn energy<T: activemuscle::Scalar>(&self, c: &activemuscle::energy::Invariants<T>) -> T {
            (c.tr_c - 3.0) * 0.7
                + (c.c_m - 1.0).powi(2) * 0.4
                + (c.tr_c_inv - 3.0) * 0.3
                + (c.c_inv_m - 1.0).powi(2) * 0.2
                + c.det_c.ln().powi(2) * 0.5
        }
    }
    let mut rng = Sampler::new(0x3a9_0004);
    for map in MAPS {
        for gamma in [0.05, 0.2, 0.45] {
            let kin = Kinematics::new(&rng.deformation(0.25), &rng.unit_vector()).unwrap();
            let j = SVector::from(kin.invariants);
            let d = invariant_derivatives_with(&AllFive, map, &j, gamma, Order::Tangent).unwrap();
            let s = d.second.unwrap();
            let x = SVector::<f64, 6>::from_fn(|i, _| if i < 5 { j[i] } else { gamma });
            let (w, g, h) = hessian(
                |v: SVector<Dual2SVec64<6>, 6>| {
                    map.active_energy(&AllFive, &[v[0], v[1], v[2], v[3], v[4]], v[5])
                },
                &x,
            );
            let close = |a: f64, b: f64, what: &str| {
                assert!(
                    (a - b).abs() <= 1e-12 * b.abs().max(1.0),
                    "{} map, gamma {gamma}: {what} {a} vs {b}",
                    map.name()
                )
            };
            close(d.energy, w, "energy");
            close(d.d_gamma, g[5], "dW/dgamma");
            close(s.d_gammagamma, h[(5, 5)], "d2W/dgamma2");
            let d_jj = d.d_jj().unwrap();
            for a in 0..5 {
                close(d.d_j[a], g[a], "dW/dj");
                close(s.d_jgamma[a], h[(a, 5)], "d2W/dj dgamma");
                for b in 0..5 {
                    close(d_jj[(a, b)], h[(a, b)], "d2W/dj2");
                }
            }
        }
    }
}

/// Along the fibres the volume-preserving map leaves an incompressible uniaxial elastic state:
/// C = diag(λ², 1/λ, 1/λ), F_a⁻¹ = diag(1/c, √c, √c) (c = 1 − γ), so
/// C_e = diag(λ²/c², c/λ, c/λ) and, with det F_a = 1, for W = μ/2 (tr C − 3):
///
/// Ŵ(λ, γ) = μ/2 (λ²/c² + 2c/λ − 3),  P = dŴ/dλ = μ (λ/c² − c/λ²)
///
/// (the nominal stress along the incompressible path, lateral faces traction free). Compared
/// with the map's generic energy and with the muscle's nominal stress.
#[test]
fn volume_preserving_map_along_the_fibres_matches_the_hand_written_neo_hookean_energy() {
    let mu = 2.0;
    let nh = NeoHookean::new(mu).unwrap();
    let map = ActivationMap::VolumePreserving;
    for gamma in [0.0, 0.15, 0.4] {
        let c = 1.0 - gamma;
        let muscle = held(nh, map, gamma);
        for lambda in [0.7, 0.9, 1.0, 1.2, 1.5] {
            let w = mu / 2.0 * (lambda * lambda / (c * c) + 2.0 * c / lambda - 3.0);
            let p = mu * (lambda / (c * c) - c / (lambda * lambda));
            let generic = map.fibre_path_energy(&nh, lambda, gamma);
            let stress = along_fibres(&muscle, lambda).unwrap().stress;
            assert!(
                (generic - w).abs() <= 1e-14 * w.abs().max(1.0),
                "{generic} vs {w}"
            );
            assert!(
                (stress - p).abs() <= 1e-13 * p.abs().max(1.0),
                "{stress} vs {p}"
            );
        }
    }
}

/// For any energy, the volume-preserving fibre-path energy is the passive one at the elastic
/// stretch λ/(1 − γ): Ŵ(λ, γ) = W_pas(λ/(1 − γ)) (the elastic state is incompressible uniaxial).
#[test]
fn volume_preserving_fibre_path_is_the_passive_path_at_the_elastic_stretch() {
    let gm = GiantesioMusesti::paper();
    let map = ActivationMap::VolumePreserving;
    for gamma in [0.1, 0.3] {
        for lambda in [0.8, 1.0, 1.3] {
            let a: f64 = map.fibre_path_energy(&gm, lambda, gamma);
            let b: f64 = ActivationMap::Chapter.fibre_path_energy(&gm, lambda / (1.0 - gamma), 0.0);
            assert!((a - b).abs() <= 1e-14 * b.abs().max(1e-3), "{a} vs {b}");
        }
    }
}

fn gm() -> GiantesioMusesti {
    GiantesioMusesti::paper()
}

/// P_pas + (1 − d) P_act [kPa] (the passive curve does not depend on the map: γ = 0).
fn target(l: f64, d: f64) -> f64 {
    along_fibres(&Muscle::passive(gm()), l).unwrap().stress
        + (1.0 - d) * ActiveCurve::paper().value(l)
}

/// Largest |P − target| / max(|target|, 1) over 200 stretches in (λ_min, 1.6].
fn worst_gap(muscle: &Muscle<GiantesioMusesti>, d: f64) -> f64 {
    let lmin = ActiveCurve::paper().lambda_min();
    (1..=200)
        .map(|i| lmin + (1.6 - lmin) * i as f64 / 200.0)
        .map(|l| {
            let (p, t) = (along_fibres(muscle, l).unwrap().stress, target(l, d));
            (p - t).abs() / t.abs().max(1.0)
        })
        .fold(0.0, f64::max)
}

fn volume_preserving() -> ActivationMap {
    ActivationMap::VolumePreserving
}

#[test]
fn implicit_law_with_the_volume_preserving_map_reproduces_the_target_curve() {
    let law = ImplicitLaw::new(gm(), ActiveCurve::paper()).with_map(volume_preserving());
    for d in [0.0, 0.25, 0.5] {
        let muscle = Muscle::new(
            gm(),
            Law::Implicit(law.clone()),
            d,
            Coupling::Frozen(FrozenTangent::Exact),
        )
        .unwrap();
        assert_eq!(muscle.map(), volume_preserving());
        let gap = worst_gap(&muscle, d);
        assert!(gap < 1e-10, "d = {d}: {gap:e}");
    }
    // The map changes γ: the same stress needs a different activation.
    let chapter = ImplicitLaw::new(gm(), ActiveCurve::paper());
    let (a, b) = (
        law.activation(1.0, 0.0).unwrap(),
        chapter.activation(1.0, 0.0).unwrap(),
    );
    println!("gamma(1.0): volume-preserving {a:.5}, chapter {b:.5}");
    assert!((a - b).abs() > 1e-3);
}

#[test]
fn energy_law_with_the_volume_preserving_map_and_consistent_coupling_reproduces_the_target() {
    let law = EnergyLaw::new(gm(), ActiveCurve::paper()).with_map(volume_preserving());
    for d in [0.0, 0.25, 0.5] {
        let muscle = Muscle::new(gm(), Law::Energy(law.clone()), d, Coupling::Consistent).unwrap();
        let gap = worst_gap(&muscle, d);
        assert!(gap < 1e-10, "d = {d}: {gap:e}");
        // dΨ/dλ by the chain rule on the fibre path: the residual's own λ-derivative is zero.
        let l = 1.1;
        let v = law.evaluate(l, d).unwrap();
        let w = volume_preserving().fibre_path_energy(
            &gm(),
            HyperDual64::from_re(l).derivative1(),
            HyperDual64::from_re(v.gamma).derivative2(),
        );
        let consistent = w.eps1 + w.eps2 * v.slope;
        assert!((consistent - target(l, d)).abs() <= 1e-10 * target(l, d).abs());
    }
}

/// A table built from the volume-preserving implicit law follows the map: γ and the frozen
/// fibre stress match the exact law's at stretches the build never saw.
#[test]
fn tabulated_implicit_law_follows_the_volume_preserving_map() {
    let exact = ImplicitLaw::new(gm(), ActiveCurve::paper()).with_map(volume_preserving());
    let spec = TableSpec {
        lambda_lo: 0.7,
        lambda_hi: 1.4,
        ..TableSpec::default()
    };
    let table = TabulatedLaw::new(SolvedLaw::Implicit(exact.clone()), &[0.0], spec).unwrap();
    let law = Law::Tabulated(table);
    assert_eq!(law.map(), Some(volume_preserving()));
    let muscle = Muscle::new(
        gm(),
        law.clone(),
        0.0,
        Coupling::Frozen(FrozenTangent::Exact),
    )
    .unwrap();
    assert_eq!(muscle.map(), volume_preserving());
    for i in 0..50 {
        let l = 0.7137 + 0.6731 * i as f64 / 50.0;
        let (t, e) = (
            law.activation(l, 0.0).unwrap(),
            exact.activation(l, 0.0).unwrap(),
        );
        assert!(
            (t - e).abs() <= spec.gamma_tolerance,
            "lambda {l}: {t} vs {e}"
        );
        let gap = (along_fibres(&muscle, l).unwrap().stress - target(l, 0.0)).abs();
        assert!(
            gap <= 1e-9 + 1e-10 * target(l, 0.0).abs(),
            "lambda {l}: {gap:e} kPa"
        );
    }
}

#[test]
fn a_muscle_refuses_a_map_other_than_its_laws() {
    let law = Law::Implicit(ImplicitLaw::new(gm(), ActiveCurve::paper()));
    let muscle = Muscle::new(gm(), law, 0.0, Coupling::Consistent).unwrap();
    match muscle.with_map(volume_preserving()) {
        Err(Error::MapMismatch { law, law_map, map }) => {
            assert_eq!(
                (law, law_map, map),
                ("implicit", "chapter", "volume-preserving")
            )
        }
        other => panic!("expected a map mismatch, got {other:?}"),
    }
}

const FILE: &str = "map_scene.toml";

/// The scene's implicit law, frozen, d = 0.
fn implicit_frozen(scene: &activemuscle::scene::Scene) -> Muscle<activemuscle::Energy> {
    use activemuscle::models::{CouplingKind, LawKind, ModelChoice};
    let choice = ModelChoice {
        approach: activemuscle::active::Approach::ActiveStrain,
        law: LawKind::Implicit,
        coupling: CouplingKind::Frozen,
        damage: 0.0,
    };
    scene.models.muscle(choice).unwrap()
}

fn rejected(text: &str) -> String {
    match activemuscle::scene::Scene::parse(text, FILE) {
        Ok(_) => panic!("accepted a bad scene:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn scenes_choose_the_active_strain_map() {
    use activemuscle::scene::Scene;
    let study = "[[study]]\nkind = \"uniaxial\"\nstretch = [1.0]\nlaws = [\"implicit\"]\n";
    let text = format!("[activation]\nmap = \"volume-preserving\"\n{study}");
    let scene = Scene::parse(&text, FILE).unwrap();
    assert_eq!(scene.models.map, volume_preserving());
    let muscle = implicit_frozen(&scene);
    assert_eq!(muscle.map(), volume_preserving());
    assert_eq!(
        muscle.activation(1.0).unwrap().gamma,
        ImplicitLaw::new(gm(), ActiveCurve::paper())
            .with_map(volume_preserving())
            .activation(1.0, 0.0)
            .unwrap()
    );
    // A constant activation follows the scene's map too.
    assert_eq!(
        scene
            .models
            .constant(scene.defaults.approach, 0.2)
            .unwrap()
            .map(),
        volume_preserving()
    );
    // The default is the chapter's, and the printed scene says which map runs.
    let default = Scene::parse(study, FILE).unwrap();
    assert_eq!(default.models.map, ActivationMap::Chapter);
    let printed = toml::to_string_pretty(&default.resolved).unwrap();
    assert!(printed.contains("map = \"chapter\""), "{printed}");

    let e = rejected(&format!("[activation]\nmap = \"isochoric\"\n{study}"));
    assert!(
        e.starts_with(&format!("{FILE}:2: activation.map")) && e.contains("\"isochoric\""),
        "{e}"
    );
    // The explicit law is fitted for the chapter's map.
    let e = rejected(
        "[activation]\nmap = \"volume-preserving\"\n[[study]]\nkind = \"uniaxial\"\nstretch = [1.0]\nlaws = [\"explicit\"]\n",
    );
    assert!(
        e.contains("explicit law") && e.contains("volume-preserving"),
        "{e}"
    );
}

/// A scene's tabulated law follows the scene's map: the table is built from the exact law solved
/// with it.
#[test]
fn a_scene_tabulates_the_law_of_its_map() {
    use activemuscle::scene::Scene;
    let text = "[activation]\nmap = \"volume-preserving\"\nrepresentation = \"tabulated\"\n\
                table_stretches = [0.8, 1.3]\n[[study]]\nkind = \"uniaxial\"\nstretch = [1.0]\n\
                laws = [\"implicit\"]\n";
    let scene = Scene::parse(text, FILE).unwrap();
    let muscle = implicit_frozen(&scene);
    assert_eq!(muscle.law().name(), "implicit-tabulated");
    assert_eq!(muscle.map(), volume_preserving());
    let exact = ImplicitLaw::new(gm(), ActiveCurve::paper()).with_map(volume_preserving());
    for l in [0.85, 1.0, 1.21] {
        let (t, e) = (
            muscle.activation(l).unwrap().gamma,
            exact.activation(l, 0.0).unwrap(),
        );
        assert!((t - e).abs() <= 1e-12, "lambda {l}: {t} vs {e}");
    }
}
