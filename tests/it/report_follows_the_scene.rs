//! The report and its figures follow the scene (issue 11): every curve a run writes to
//! `curves.csv` is drawn in some figure, with a legend entry and part of it inside the frame;
//! headings and captions name what the scene asked for and nothing else; a clipped axis says so;
//! the FE-vs-0D table reports the difference where the activation shows; the γ = 0 at the centre
//! of the clamped cylinder is the laws' γ = 0 below λ_min. Scenes unlike the chapter's:
//! `scenes/examples/*.toml` and a small chapter-like scene.

use activemuscle::active::{ActiveCurve, ExplicitLaw};
use activemuscle::output::figures::figures;
use activemuscle::output::report::{html, RunInfo};
use activemuscle::plot::CurveId;
use activemuscle::plot::{Figure, Panel, Series, Stroke};
use activemuscle::scene::{Results, RunOptions, Scene};
use activemuscle::studies::curves::{cylinder_rows, uniaxial_rows};
use activemuscle::studies::cylinder::CylinderResult;
use activemuscle::studies::fit::correlations;
use activemuscle::studies::uniaxial::UniaxialResult;
use activemuscle::uniaxial::along_fibres;
use std::collections::BTreeSet;
use std::path::Path;

/// A small scene shaped like the chapter's: two energies, both directions, every law ×
/// coupling at two damages, constant γ, a clamped cylinder.
const CHAPTER_LIKE: &str = r#"
title = "chapter-like"
[[study]]
kind = "uniaxial"
stretch = { from = 0.7, to = 1.5, step = 0.1 }
compare = [{ energy = "ehret-bol-itskov" }]
laws = ["implicit", "explicit", "energy"]
couplings = ["frozen", "consistent"]
damage = [0.0, 0.5]
constant_gamma = [0.0, 0.2, 0.4]
[[study]]
kind = "uniaxial"
direction = "across"
stretch = { from = 0.7, to = 1.5, step = 0.1 }
laws = []
[[study]]
kind = "cylinder"
nr = 1
nz = 4
law = "explicit"
coupling = "frozen"
damage = [0.0, 0.5]
stretch = [0.9, 1.0, 1.17]
"#;

fn load(name: &str) -> Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/examples")
        .join(name);
    Scene::load(&path).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn run(scene: &Scene) -> Results {
    scene.run(&RunOptions::default())
}

/// The curves a run writes to curves.csv.
fn written(results: &Results) -> BTreeSet<CurveId> {
    let mut rows = Vec::new();
    for (study, u) in results.of::<UniaxialResult>() {
        rows.extend(uniaxial_rows(study, u));
    }
    for (study, c) in results.of::<CylinderResult>() {
        rows.extend(cylinder_rows(study, c));
    }
    rows.iter().map(|r| r.curve()).collect()
}

/// The curves drawn with a legend entry and at least one point inside their panel's frame.
fn drawn(figures: &[Figure]) -> BTreeSet<CurveId> {
    let mut ids = BTreeSet::new();
    for f in figures {
        for p in &f.panels {
            let frame = p.frame();
            for s in &p.series {
                let visible = s.points.iter().any(|&q| frame.contains(q));
                if let (Some(id), false, true) = (&s.curve, s.label.is_empty(), visible) {
                    ids.insert(id.clone());
                }
            }
        }
    }
    ids
}

/// Every curve written is drawn, and nothing is drawn as a curve that was not written.
fn check_coverage(scene: &Scene) -> (Results, Vec<Figure>) {
    let results = run(scene);
    let figures = figures(scene, &results);
    let (w, d) = (written(&results), drawn(&figures));
    assert!(!w.is_empty());
    assert_eq!(
        w,
        d,
        "{}: written but not drawn: {:?}; drawn but not written: {:?}",
        scene.title,
        w.difference(&d).collect::<Vec<_>>(),
        d.difference(&w).collect::<Vec<_>>()
    );
    let mut stems: Vec<&str> = figures.iter().map(|f| f.stem.as_str()).collect();
    stems.sort();
    stems.dedup();
    assert_eq!(stems.len(), figures.len(), "figure stems are unique");
    (results, figures)
}

/// The report of a run, without figures.
fn report(scene: &Scene, results: &Results) -> String {
    let info = RunInfo::default();
    html(scene, results, &[], &info).expect("report")
}

/// Headings and captions of every figure, one string.
fn text(figures: &[Figure]) -> String {
    figures
        .iter()
        .map(|f| format!("{}\n{}\n", f.heading, f.caption))
        .collect()
}

#[test]
fn every_curve_of_an_ebi_scene_with_one_damage_is_drawn_and_named_for_what_it_is() {
    let scene = load("ebi_one_damage.toml");
    let (_, figures) = check_coverage(&scene);
    let words = text(&figures);
    for absent in [
        "across",
        "giantesio-musesti",
        "0 … 0.5",
        "d = 0,",
        "Fig. 3",
        "Fig. 9",
    ] {
        assert!(!words.contains(absent), "{absent:?} in\n{words}");
    }
    for present in [
        "ehret-bol-itskov",
        "γ = 0.2, 0.4",
        "d = 0.3",
        "implicit law, frozen coupling; implicit law, consistent coupling; energy law, frozen coupling; energy law, consistent coupling",
        "sliding bases",
        // The chapter's figure for the chapter's energy; here the same plot of another energy.
        "as the chapter's Fig. 5, with the ehret-bol-itskov energy",
    ] {
        assert!(words.contains(present), "{present:?} not in\n{words}");
    }
    // Four law × coupling curves and the target in one stress panel.
    let laws = figures
        .iter()
        .find(|f| f.stem == "fig_laws")
        .expect("fig_laws");
    assert_eq!(laws.panels[1].series.len(), 5);
}

#[test]
fn every_curve_of_an_across_and_clamped_scene_is_drawn() {
    let scene = load("across_and_clamped.toml");
    let (results, figures) = check_coverage(&scene);
    let words = text(&figures);
    // The active models are across the fibres: none of the chapter's figures along them.
    for along_only in ["Fig. 5", "Fig. 7", "Fig. 8", "Fig. 9", "Fig. 10", "Fig. 11"] {
        assert!(!words.contains(along_only), "{along_only} in\n{words}");
    }
    // The material's passive curve along (second study) and across (first): Fig. 2.
    assert!(words.contains("the chapter's Fig. 2"), "{words}");
    assert!(words.contains("neo-hookean") && words.contains("d = 0, 0.5"));
    // d = 1: no stretch where the activation shows; d = 0: the largest difference there is
    // the largest |P_FE − P_0D| over the stretches where (1 − d) P_act > max(P_pas, 0),
    // recomputed here from the curve and the passive material.
    let page = report(&scene, &results);
    let (_, cylinder) = results.of::<CylinderResult>().next().expect("a cylinder");
    let passive = scene.models.passive();
    let curve = ActiveCurve::paper();
    let at_zero = &cylinder.sweeps[0];
    let (mut largest, mut at) = (0.0f64, f64::NAN);
    for p in &at_zero.points {
        let pas = along_fibres(&passive, p.lambda).expect("passive").stress;
        if curve.value(p.lambda) > pas.max(0.0) {
            let d = (p.stress - p.stress_0d.expect("0D")).abs();
            if d > largest {
                (largest, at) = (d, p.lambda);
            }
        }
    }
    assert!(at.is_finite(), "d = 0 has an active range");
    let row = page
        .lines()
        .find(|l| l.contains(&at_zero.label))
        .expect("a row for d = 0");
    let cell = format!("{} kPa at λ = {at} ", activemuscle::plot::short(largest));
    assert!(row.contains(&cell), "{cell:?} not in {row}");
    let one = page
        .lines()
        .find(|l| l.contains(&cylinder.sweeps[1].label))
        .expect("a row for d = 1");
    assert!(one.contains("<td>none</td>"), "{one}");
}

#[test]
fn a_chapter_like_scene_draws_the_chapters_figures_and_every_curve() {
    let scene = Scene::parse(CHAPTER_LIKE, "chapter-like.toml").expect("valid");
    let (_, figures) = check_coverage(&scene);
    let words = text(&figures);
    for fig in [2, 3, 5, 7, 8, 9, 10, 11, 12] {
        assert!(
            words.contains(&format!("the chapter's Fig. {fig}")),
            "Fig. {fig} missing:\n{words}"
        );
    }
    // Constant γ = 0.4 is drawn (on the log axis) and its legend entry is there.
    let constant = figures
        .iter()
        .find(|f| f.stem == "fig_constant_gamma")
        .expect("constant γ");
    let top = &constant.panels[0];
    let frame = top.frame();
    let g = top
        .series
        .iter()
        .find(|s| s.label == "γ = 0.4")
        .expect("γ = 0.4 in the legend");
    assert!(g.points.iter().any(|&p| frame.contains(p)));
}

#[test]
fn gamma_at_the_centre_of_the_clamped_cylinder_is_zero_where_the_fibres_are_below_lambda_min() {
    const SCENE: &str = r#"
[[study]]
kind = "cylinder"
nr = 2
nz = 8
law = "explicit"
coupling = "frozen"
damage = [0.0, 0.5]
stretch = [0.7, 1.0]
[[study]]
kind = "cylinder"
nr = 2
nz = 8
bases = "sliding"
law = "explicit"
coupling = "frozen"
stretch = [0.7, 1.0]
"#;
    let scene = Scene::parse(SCENE, "centre.toml").expect("valid");
    let results = run(&scene);
    let lmin = ActiveCurve::paper().lambda_min();
    let law = ExplicitLaw::paper();
    let mut cylinders = results.of::<CylinderResult>();
    let (_, clamped) = cylinders.next().expect("clamped");
    for s in &clamped.sweeps {
        let p = &s.points[0];
        assert_eq!(p.lambda, 0.7);
        // The clamped ends shorten less, the middle more than the applied stretch.
        assert!(
            p.fibre_stretch_centre < 0.64 && p.fibre_stretch_centre <= lmin,
            "{p:?}"
        );
        assert_eq!(
            law.gamma(p.fibre_stretch_centre, s.model.damage)
                .expect("γ"),
            0.0
        );
        assert_eq!(p.gamma_centre, 0.0);
    }
    // Sliding bases: homogeneous, λ_f = λ = 0.7 > λ_min, γ = the law's γ(0.7) ≈ 0.28.
    let (_, sliding) = cylinders.next().expect("sliding");
    let p = &sliding.sweeps[0].points[0];
    assert!((p.fibre_stretch_centre - 0.7).abs() < 1e-9);
    let expected = law.gamma(0.7, 0.0).expect("γ");
    assert!((p.gamma_centre - expected).abs() < 1e-9 && expected > 0.2);
    let page = report(&scene, &results);
    assert!(page.contains("<h2>γ at the centre of the cylinder</h2>"));
    let clamped_p = &clamped.sweeps[0].points[0];
    assert!(page.contains(&format!(
        "λ = 0.7: λ_f = {}, γ = 0",
        activemuscle::plot::short(clamped_p.fibre_stretch_centre)
    )));
}

/// A curve that blows up beside a moderate one.
fn blow_up_panel() -> Panel {
    let lambdas: Vec<f64> = (0..=95).map(|i| 0.65 + 0.01 * f64::from(i)).collect();
    let moderate = lambdas.iter().map(|&l| (l, 70.0 * (l - 0.6))).collect();
    let exponential = lambdas
        .iter()
        .map(|&l| (l, (20.0 * (l - 1.0)).exp()))
        .collect();
    Panel::new(
        "test",
        "stretch λ [-]",
        "P [kPa]",
        vec![
            Series::new("moderate", moderate, Stroke::Solid, 0),
            Series::new("exponential", exponential, Stroke::Solid, 1),
        ],
    )
}

#[test]
fn an_axis_is_clipped_where_a_curve_blows_up_and_the_caption_says_how_far_it_goes() {
    let panel = blow_up_panel();
    let f = panel.frame();
    // e^{20 · 0.6} = 1.6e5 at λ = 1.6: the frame stops far below, above the moderate curve.
    assert!(f.clipped_above && !f.clipped_below, "{f:?}");
    assert!(f.y.1 > 70.0 * 1.0 && f.y.1 < 1e3, "{f:?}");
    for s in &panel.series {
        assert!(
            s.points.iter().any(|&p| f.contains(p)),
            "{} visible",
            s.label
        );
    }
    let figure = Figure::new("x", "x", "Caption.", vec![panel]);
    assert!(
        figure.caption.contains("y axis cut at")
            && figure.caption.contains("1.628e5 kPa at λ = 1.6"),
        "{}",
        figure.caption
    );
    // Without the blow-up nothing is cut and the frame holds every point.
    let mut calm = blow_up_panel();
    calm.series.pop();
    let f = calm.frame();
    assert!(!f.clipped_above && !f.clipped_below);
    assert!(calm.series[0].points.iter().all(|&p| f.contains(p)));
    assert_eq!(
        Figure::new("x", "x", "Caption.", vec![calm]).caption,
        "Caption."
    );
}

#[test]
fn a_fits_correlations_read_as_the_other_parameters_names_and_values() {
    let names = ["alpha".to_string(), "beta".into(), "w0".into()];
    let row = [Some(0.5), Some(1.0), None];
    let text = correlations(&row, &names, 1, |c| Ok(format!("{c:.5}"))).expect("text");
    assert_eq!(text, "alpha: 0.50000; w0: n/a");
}

#[test]
fn figures_of_studies_whose_names_give_one_stem_get_different_files() {
    // "cylinder x" and "x" both name a second cylinder figure fig_cylinder_x.
    let study = |name: &str| {
        format!(
            "[[study]]\nkind = \"cylinder\"\nname = \"{name}\"\nnr = 1\nnz = 2\nbases = \"sliding\"\nstretch = [1.1]\n"
        )
    };
    let text = [study("a"), study("cylinder x"), study("x")].concat();
    let scene = Scene::parse(&text, "stems.toml").expect("valid");
    let (_, figures) = check_coverage(&scene);
    let stems: Vec<&str> = figures
        .iter()
        .map(|f| f.stem.as_str())
        .filter(|s| s.starts_with("fig_cylinder"))
        .collect();
    assert_eq!(
        stems,
        ["fig_cylinder", "fig_cylinder_x", "fig_cylinder_x_2"]
    );
}

/// A constant series (an activation level held at 1) gets a frame around it wide enough for
/// distinct tick labels: ±10 % of the value (±1 around 0), not a relative 1e-9.
#[test]
fn a_constant_series_gets_a_readable_axis() {
    for value in [1.0, -250.0, 0.0] {
        let points = (0..=10).map(|i| (f64::from(i), value)).collect();
        let panel = Panel::new(
            "test",
            "time t [s]",
            "a [-]",
            vec![Series::new("level", points, Stroke::Solid, 0)],
        );
        let f = panel.frame();
        let width = f.y.1 - f.y.0;
        assert!(f.contains((5.0, value)), "{f:?}");
        let expected = if value == 0.0 { 2.0 } else { 0.2 * value.abs() };
        assert!(width >= expected * (1.0 - 1e-12), "{value}: {f:?}");
    }
}

/// An isotropic energy's curves along and across the fibres coincide: the figure says so and
/// does not call the material transversely isotropic; a γ close to 1 is noted.
#[test]
fn an_isotropic_energy_is_not_called_transversely_isotropic() {
    let scene = Scene::parse(
        r#"
[material]
energy = "neo-hookean"
mu = 2.0
[[study]]
kind = "uniaxial"
name = "along"
stretch = { from = 0.8, to = 1.4, step = 0.05 }
laws = ["implicit"]
couplings = ["frozen"]
[[study]]
kind = "uniaxial"
name = "across"
direction = "across"
stretch = { from = 0.8, to = 1.4, step = 0.05 }
laws = []
"#,
        "isotropic.toml",
    )
    .unwrap();
    let (results, figures) = check_coverage(&scene);
    let all = text(&figures);
    assert!(all.contains("neo-hookean is isotropic"), "{all}");
    assert!(!all.contains("Transversely isotropic behaviour"), "{all}");
    // The chapter's active curve on a neo-Hookean block of μ = 2 kPa drives γ to ≈ 0.97.
    let page = report(&scene, &results);
    assert!(page.contains("γ reaches 0.9"), "no note on γ close to 1");
}

/// The same studies on the chapter's energy with another μ: the figures that depend on the energy
/// are "as the chapter's", with this scene's parameters; those of the active curve alone (Figs. 7
/// and 9) are still the chapter's, since the curve is.
#[test]
fn a_scene_with_other_parameters_does_not_claim_the_chapter_s_figures() {
    let text_of = |material: &str| {
        let scene =
            Scene::parse(&format!("{CHAPTER_LIKE}{material}"), "other-mu.toml").expect("valid");
        let (_, figures) = check_coverage(&scene);
        text(&figures)
    };
    let words = text_of("[material]\nmu = 0.5\n");
    for fig in [2, 5, 8, 10, 11, 12] {
        assert!(
            words.contains(&format!(
                "as the chapter's Fig. {fig}, with this scene's parameters"
            )),
            "Fig. {fig}:\n{words}"
        );
        assert!(
            !words.contains(&format!("— the chapter's Fig. {fig}")),
            "Fig. {fig}"
        );
    }
    assert!(!words.contains("Fig. 3"), "{words}");
    for fig in [7, 9] {
        assert!(
            words.contains(&format!("— the chapter's Fig. {fig}")),
            "Fig. {fig}"
        );
    }
    // Another active curve: Figs. 7 and 9 are no longer the chapter's either.
    let words = text_of("[activation]\np_opt = 50.0\n");
    for fig in [7, 9] {
        assert!(
            words.contains(&format!(
                "as the chapter's Fig. {fig}, with this scene's parameters"
            )),
            "Fig. {fig}:\n{words}"
        );
    }
}

/// Every shipped energy's row in the report's table of models says what it is, with its formula,
/// as the energy registry declares it (4c-passive was "a shipped energy" when the report kept its
/// own list).
#[test]
fn every_shipped_energy_has_its_formula_in_the_table_of_models() {
    for energy in activemuscle::energy::SHIPPED {
        // Parameters without a chapter value must be given.
        let given: String = energy
            .parameters
            .iter()
            .filter(|p| p.default.is_none())
            .map(|p| format!("{} = 1.0\n", p.name))
            .collect();
        let text = format!(
            "[material]\nenergy = \"{}\"\n{given}[[study]]\nkind = \"uniaxial\"\nstretch = [1.1]\nlaws = []\n",
            energy.name
        );
        let scene = Scene::parse(&text, "energy.toml").expect("valid scene");
        let page = report(&scene, &scene.run(&RunOptions::default()));
        let row = format!(
            "<td>{} (energy)</td><td>{}; the material, with ",
            energy.name,
            activemuscle::text::escape_html(energy.formula)
        );
        assert!(page.contains(&row), "{}: no row {row}", energy.name);
        assert!(
            page.contains(&format!(
                "</td><td>{}</td></tr>",
                activemuscle::text::escape_html(energy.chapter)
            )),
            "{}",
            energy.name
        );
    }
}
