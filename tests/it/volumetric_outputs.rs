//! Nearly incompressible scenes in the outputs (issue 24, item 2): a compared energy is stress
//! free at λ = 1 with its own reference stress, curves.csv carries the volume ratio J, and the
//! captions that say a law reproduces its target say by how much it misses it here, measured
//! from the curves themselves.

use activemuscle::output::csv::files;
use activemuscle::output::figures::figures;
use activemuscle::scene::{RunOptions, Scene};

/// curves.csv of `scene` as (header, rows of cells), and its figures.
fn curves(
    scene: &Scene,
) -> (
    Vec<String>,
    Vec<Vec<String>>,
    Vec<activemuscle::plot::Figure>,
) {
    let results = scene.run(&RunOptions::default());
    let failures: Vec<_> = results.failures().collect();
    assert!(failures.is_empty(), "{failures:?}");
    let csv = files(&results)[0].bytes().unwrap();
    let mut r = csv::Reader::from_reader(csv.as_slice());
    let header = r.headers().unwrap().iter().map(String::from).collect();
    let cells = r
        .records()
        .map(|x| x.unwrap().iter().map(String::from).collect())
        .collect();
    (header, cells, figures(scene, &results))
}

fn column(header: &[String], name: &str) -> usize {
    header
        .iter()
        .position(|h| h == name)
        .unwrap_or_else(|| panic!("no column {name}"))
}

const VOLUMETRIC: &str = "[incompressibility]\nkind = \"4c-giantesio\"\nkappa = 1.0\nmu = 0.1599\n";

#[test]
fn a_compared_energy_is_stress_free_and_equals_it_as_the_material() {
    let stretches = "stretch = [1.0, 1.1, 1.3]\n";
    let compared = Scene::parse(
        &format!("{VOLUMETRIC}[[study]]\nkind = \"uniaxial\"\nname = \"u\"\n{stretches}compare = [{{ energy = \"4c-passive\" }}]\n"),
        "compare.toml",
    )
    .unwrap();
    let alone = Scene::parse(
        &format!("[material]\nenergy = \"4c-passive\"\n{VOLUMETRIC}[[study]]\nkind = \"uniaxial\"\nname = \"u\"\n{stretches}laws = []\n"),
        "alone.toml",
    )
    .unwrap();
    let (h, rows, _) = curves(&compared);
    let (ha, alone_rows, _) = curves(&alone);
    let (energy, lambda, p) = (column(&h, "energy"), column(&h, "lambda"), column(&h, "P"));
    let four_c: Vec<&Vec<String>> = rows.iter().filter(|r| r[energy] == "4c-passive").collect();
    let reference: Vec<&Vec<String>> = alone_rows
        .iter()
        .filter(|r| r[column(&ha, "energy")] == "4c-passive")
        .collect();
    assert_eq!(four_c.len(), 3);
    assert_eq!(reference.len(), 3);
    for (c, a) in four_c.iter().zip(&reference) {
        let (pc, pa): (f64, f64) = (c[p].parse().unwrap(), a[column(&ha, "P")].parse().unwrap());
        if c[lambda] == "1" {
            assert!(pc.abs() < 1e-12, "P(1) = {pc}");
        }
        assert!(
            (pc - pa).abs() <= 1e-12 * (1.0 + pa.abs()),
            "λ = {}: {pc} vs {pa}",
            c[lambda]
        );
    }
}

#[test]
fn nearly_incompressible_rows_carry_j_and_exact_rows_leave_it_empty() {
    let study = "[[study]]\nkind = \"uniaxial\"\nname = \"u\"\nstretch = [0.9, 1.2]\nlaws = [\"implicit\"]\ncouplings = [\"frozen\"]\n";
    let (h, rows, _) = curves(&Scene::parse(&format!("{VOLUMETRIC}{study}"), "near.toml").unwrap());
    let (j, cauchy, p, lambda) = (
        column(&h, "J"),
        column(&h, "cauchy"),
        column(&h, "P"),
        column(&h, "lambda"),
    );
    for r in &rows {
        let x = |i: usize| r[i].parse::<f64>().unwrap();
        // σ = J⁻¹ P Fᵀ along the stretch: σ J = P λ.
        assert!(
            (x(cauchy) * x(j) - x(p) * x(lambda)).abs() < 1e-10 * (1.0 + x(p).abs()),
            "{r:?}"
        );
        assert!(x(j) > 0.0 && (x(j) - 1.0).abs() > 1e-6, "{r:?}");
    }
    let (h, rows, _) = curves(&Scene::parse(study, "exact.toml").unwrap());
    assert!(rows.iter().all(|r| r[column(&h, "J")].is_empty()));
}

/// The largest |P − (P_pas + P_act)| of the implicit/frozen rows of `rows`.
fn largest_gap(h: &[String], rows: &[Vec<String>]) -> f64 {
    let (law, p, pas, act) = (
        column(h, "law"),
        column(h, "P"),
        column(h, "P_pas"),
        column(h, "P_act"),
    );
    rows.iter()
        .filter(|r| r[law] == "implicit")
        .map(|r| {
            let x = |i: usize| r[i].parse::<f64>().unwrap();
            (x(p) - x(pas) - x(act)).abs()
        })
        .fold(0.0, f64::max)
}

#[test]
fn the_laws_caption_says_how_far_a_nearly_incompressible_curve_is_from_its_target() {
    let study = "[[study]]\nkind = \"uniaxial\"\nname = \"u\"\nstretch = [0.9, 1.0, 1.2]\nlaws = [\"implicit\"]\ncouplings = [\"frozen\"]\n";
    let caption = |figures: &[activemuscle::plot::Figure]| {
        figures
            .iter()
            .find(|f| f.stem.starts_with("fig_laws"))
            .map(|f| f.caption.clone())
            .expect("fig_laws")
    };
    let (h, rows, figs) =
        curves(&Scene::parse(&format!("{VOLUMETRIC}{study}"), "near.toml").unwrap());
    let gap = largest_gap(&h, &rows);
    assert!(
        gap > 1.0,
        "the volumetric energy moves the curve off its target: {gap}"
    );
    let text = caption(&figs);
    let said = text
        .split("misses it by up to ")
        .nth(1)
        .and_then(|rest| rest.split(" kPa").next())
        .unwrap_or_else(|| panic!("no gap in the caption: {text}"));
    let said: f64 = said.parse().unwrap();
    assert!(
        (said - gap).abs() <= 0.01 * gap,
        "caption {said} vs the curves' {gap}"
    );
    let (h, rows, figs) = curves(&Scene::parse(study, "exact.toml").unwrap());
    assert!(largest_gap(&h, &rows) < 1e-9);
    assert!(!caption(&figs).contains("misses"), "{}", caption(&figs));
}
