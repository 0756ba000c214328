//! Lists of a fixed length in a scene: one value too many is refused at the list's own key and
//! line, as one too few always was (the TOML reader used to drop the extra values silently:
//! `pairs = [[1.0, 1.1, 1.2]]` ran the pair (1.0, 1.1)). Each case is written with the right
//! length too, which the scene accepts.

use activemuscle::scene::Scene;

/// A scene with `with`, then the same scene with `without`: the first is refused naming `key`,
/// the given and the expected count and line `line`; the second is accepted.
fn refused_at(with: &str, without: &str, key: &str, given: usize, expected: usize, line: usize) {
    let e = match Scene::parse(with, "scene.toml") {
        Ok(_) => panic!("accepted:\n{with}"),
        Err(e) => e,
    };
    let text = e.to_string();
    assert_eq!(e.key, key, "{text}");
    assert_eq!(e.line, Some(line), "{text}");
    assert!(
        text.contains(&format!("a list of {given} values"))
            && text.contains(&format!("exactly {expected}")),
        "{text}"
    );
    if let Err(e) = Scene::parse(without, "scene.toml") {
        panic!("refused: {e}\n{without}");
    }
}

/// `[[study]]` of `kind` with `lines`.
fn study(kind: &str, lines: &str) -> String {
    format!("[[study]]\nkind = \"{kind}\"\n{lines}")
}

#[test]
fn a_biaxial_pair_of_three_stretches_is_refused() {
    refused_at(
        &study("biaxial", "pairs = [[1.0, 1.1], [1.0, 1.1, 1.2]]\n"),
        &study("biaxial", "pairs = [[1.0, 1.1], [1.0, 1.2]]\n"),
        "study[0].pairs",
        3,
        2,
        3,
    );
}

#[test]
fn a_fibre_of_four_components_is_refused() {
    let tail = "[[study]]\nkind = \"uniaxial\"\nstretch = [1.1]\n";
    refused_at(
        &format!("[material]\nfibre = [1, 0, 0, 5]\n{tail}"),
        &format!("[material]\nfibre = [1, 0, 0]\n{tail}"),
        "material.fibre",
        4,
        3,
        2,
    );
}

#[test]
fn a_region_range_and_a_named_point_of_three_values_are_refused() {
    let cylinder = |region: &str, point: &str| {
        study(
            "cylinder",
            &format!(
                "stretch = [1.1]\nnr = 1\nnz = 4\n[study.points]\ncorner = {point}\n\
                 [[study.regions]]\n{region}\ndamage = 0.5\n"
            ),
        )
    };
    let (good_point, good_r) = ("[1.0, 4.0]", "r = [0.5, 1.0]");
    refused_at(
        &cylinder("r = [0.5, 1.0, 2.0]", good_point),
        &cylinder(good_r, good_point),
        "study[0].regions[0].r",
        3,
        2,
        9,
    );
    refused_at(
        &cylinder("z = [0.0, 0.5, 1.0]", good_point),
        &cylinder("z = [0.0, 0.5]", good_point),
        "study[0].regions[0].z",
        3,
        2,
        9,
    );
    refused_at(
        &cylinder(good_r, "[1.0, 4.0, 0.0]"),
        &cylinder(good_r, good_point),
        "study[0].points.corner",
        3,
        2,
        7,
    );
}

#[test]
fn a_tradeoff_mesh_of_three_counts_is_refused() {
    let tradeoff = |meshes: &str| {
        study(
            "tradeoff",
            &format!("options = [\"mesh\"]\nstretch = [1.1]\nmeshes = {meshes}\n"),
        )
    };
    refused_at(
        &tradeoff("[[1, 4], [2, 8, 16]]"),
        &tradeoff("[[1, 4], [2, 8]]"),
        "study[0].meshes",
        3,
        2,
        5,
    );
}

#[test]
fn a_table_range_of_three_stretches_is_refused() {
    let scene = |range: &str| {
        format!(
            "[activation]\nrepresentation = \"tabulated\"\ntable_stretches = {range}\n{}",
            study("uniaxial", "stretch = [1.1]\n")
        )
    };
    refused_at(
        &scene("[0.6, 1.5, 2.0]"),
        &scene("[0.6, 1.5]"),
        "activation.table_stretches",
        3,
        2,
        3,
    );
}

#[test]
fn fit_bounds_of_three_values_are_refused() {
    let fit = |bounds: &str| {
        study(
            "fit",
            &format!(
                "fit = \"damage\"\ntrue_damage = [0.3]\nstretch = {{ from = 0.8, to = 1.4, step = 0.05 }}\n\
                 bounds = {{ d = {bounds} }}\n"
            ),
        )
    };
    refused_at(
        &fit("[0.0, 0.5, 1.0]"),
        &fit("[0.0, 1.0]"),
        "study[0].bounds.d",
        3,
        2,
        6,
    );
}

#[test]
fn a_schedule_point_and_a_stretch_row_of_three_values_are_refused() {
    let history = |schedule: &str, stretch: &str| {
        study(
            "activation-in-time",
            &format!("time = [0, 1, 2]\nschedule = {schedule}\nstretch = {stretch}\n"),
        )
    };
    let (good_schedule, good_stretch) = ("[[0, 0.5], [1, 1]]", "[[0, 1.0], [2, 1.2]]");
    refused_at(
        &history("[[0, 0.5], [1, 1, 7]]", good_stretch),
        &history(good_schedule, good_stretch),
        "study[0].schedule",
        3,
        2,
        4,
    );
    refused_at(
        &history(good_schedule, "[[0, 1.0], [2, 1.2, 1.4]]"),
        &history(good_schedule, good_stretch),
        "study[0].stretch",
        3,
        2,
        5,
    );
}
