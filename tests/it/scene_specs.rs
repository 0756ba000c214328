//! Each study kind has its own spec: a key of another kind is refused with its line, a study
//! without a known `kind` is named, and the resolved scene that `check` prints reads back to the
//! same scene. The energies a scene may name are the registry's.

use activemuscle::energy::{EhretBolItskov, Energy, GiantesioMusesti, Parametric, SHIPPED};
use activemuscle::models::Models;
use activemuscle::scene::{Scene, SceneError, PAPER_SCENE};
use activemuscle::StrainEnergy;

const FILE: &str = "specs.toml";

fn rejected(text: &str) -> SceneError {
    match Scene::parse(text, FILE) {
        Ok(_) => panic!("accepted a bad scene:\n{text}"),
        Err(e) => e,
    }
}

/// The error names the line, the key and (a word of) the rule.
fn names(e: &SceneError, line: usize, key: &str, rule: &str) {
    let shown = e.to_string();
    assert!(
        shown.starts_with(&format!("{FILE}:{line}: {key}")),
        "expected {FILE}:{line}: {key} …, got: {shown}"
    );
    assert!(shown.contains(rule), "rule {rule:?} missing: {shown}");
}

#[test]
fn each_kind_refuses_the_keys_of_the_others_with_their_line() {
    for (kind, extra, key) in [
        ("uniaxial", "nr = 4", "nr"),
        ("cylinder", "constant_gamma = [0.1]", "constant_gamma"),
        ("stability", "tolerance = 1e-8", "tolerance"),
        ("fit", "normals = 10", "normals"),
        ("tradeoff", "direction = \"along\"", "direction"),
    ] {
        let e = rejected(&format!(
            "title = \"t\"\n\n[[study]]\nkind = \"{kind}\"\nstretch = [1.0, 1.1]\n{extra}\n"
        ));
        names(
            &e,
            6,
            &format!("study[0].{key}"),
            &format!("not a key of a {kind} study"),
        );
        assert_eq!(e.value, "(given)");
    }
    // Inside a table of a study, the table's own keys are named (not the study's).
    let e =
        rejected("[[study]]\nkind = \"uniaxial\"\nstretch = { from = 1, to = 2, stepp = 0.5 }\n");
    names(&e, 3, "study[0].stretch.stepp", "unknown field `stepp`");
    assert!(e.to_string().contains("(did you mean `step`?)"), "{e}");
}

/// A misspelt key is answered with the nearest key the table takes and, in a study, all of them;
/// a word far from every key gets no guess.
#[test]
fn a_misspelt_key_gets_the_nearest_one_and_the_list() {
    let e = rejected("[[study]]\nkind = \"uniaxial\"\nstretches = [1.0, 1.1]\n");
    names(&e, 3, "study[0].stretches", "(did you mean `stretch`?)");
    for key in [
        "name",
        "stretch",
        "damage",
        "laws",
        "couplings",
        "constant_gamma",
    ] {
        assert!(e.rule.contains(key), "{key} not listed: {e}");
    }
    let e = rejected("titel = \"t\"\n[[study]]\nkind = \"uniaxial\"\nstretch = [1.0]\n");
    names(&e, 1, "titel = (given)", "(did you mean `title`?)");
    let e = rejected("[[study]]\nkind = \"uniaxial\"\nstretch = [1.0]\nresolution = 3\n");
    assert!(!e.to_string().contains("did you mean"), "{e}");
}

#[test]
fn a_study_without_a_known_kind_is_named() {
    let e = rejected("[[study]]\nstretch = [1.0]\n");
    names(&e, 1, "study[0].kind", "every study needs kind");
    let e = rejected(
        "[[study]]\nkind = \"uniaxial\"\nstretch = [1.0]\n\n[[study]]\nkind = \"sphere\"\n",
    );
    names(&e, 6, "study[1].kind", "unknown variant `sphere`");
    let e = rejected("study = 3\n");
    names(&e, 1, "study", "array of tables");
}

#[test]
fn the_printed_scene_reads_back_to_the_same_scene() {
    let scene = Scene::paper().expect("paper scene");
    let printed = scene.resolved_toml().expect("printable");
    let again = Scene::parse(&printed, FILE).expect("the printed scene is valid");
    assert_eq!(again.models, scene.models);
    assert_eq!(again.studies, scene.studies);
    // Printing is a fixed point: every default is already written out.
    assert_eq!(again.resolved_toml().expect("printable"), printed);
}

#[test]
fn the_embedded_paper_scene_is_the_chapter_s_models() {
    // The chapter's values (Tables 1 and 2, the explicit law's a and b) as the library states them.
    let scene = Scene::parse(PAPER_SCENE, FILE).expect("paper scene");
    assert_eq!(scene.models, Models::paper());
    assert_eq!(scene.models.explicit, (1.0133, 0.2050));
}

#[test]
fn the_shipped_energies_are_the_registry_s_with_their_chapter_values() {
    // Chapter values typed from the chapter (Table 1; the values quoted after the EBI energy).
    let chapter: [(&str, &[(&str, f64)]); 2] = [
        (
            "giantesio-musesti",
            &[("mu", 0.1599), ("alpha", 19.35), ("w0", 0.7335)],
        ),
        (
            "ehret-bol-itskov",
            &[
                ("mu", 0.1599),
                ("alpha", 19.69),
                ("beta", 1.190),
                ("w0", 0.7388),
            ],
        ),
    ];
    for (name, values) in chapter {
        let shipped = SHIPPED.iter().find(|e| e.name == name).expect("shipped");
        let defaults: Vec<(&str, f64)> = shipped
            .parameters
            .iter()
            .map(|p| (p.name.as_ref(), p.default.expect("a chapter value")))
            .collect();
        assert_eq!(defaults, values, "{name}");
    }
    assert_eq!(
        Energy::GiantesioMusesti(GiantesioMusesti::paper()).parameter_values(),
        vec![0.1599, 19.35, 0.7335]
    );
    assert_eq!(
        Energy::EhretBolItskov(EhretBolItskov::paper()).parameter_values(),
        vec![0.1599, 19.69, 1.190, 0.7388]
    );
    // Every shipped energy is a scene's material by its name, with its parameters by name; one
    // without a chapter value for a parameter needs it given.
    for shipped in SHIPPED {
        let given: Vec<String> = shipped
            .parameters
            .iter()
            .filter(|p| p.default.is_none())
            .map(|p| format!("{} = 2.5\n", p.name))
            .collect();
        let text = format!(
            "[material]\nenergy = \"{}\"\n{}[[study]]\nkind = \"uniaxial\"\nstretch = [1.1]\nlaws = []\n",
            shipped.name,
            given.concat()
        );
        let scene = Scene::parse(&text, FILE).unwrap_or_else(|e| panic!("{}: {e}", shipped.name));
        assert_eq!(scene.models.energy.name(), shipped.name);
        for (p, v) in shipped
            .parameters
            .iter()
            .zip(scene.models.energy.parameter_values())
        {
            assert_eq!(v, p.default.unwrap_or(2.5), "{} {}", shipped.name, p.name);
        }
        if !given.is_empty() {
            let e = rejected(&text.replace(&given.concat(), ""));
            assert!(e.rule.contains("no chapter value"), "{e}");
        }
    }
    let e = rejected(
        "[material]\nenergy = \"mooney\"\n[[study]]\nkind = \"uniaxial\"\nstretch = [1.0]\n",
    );
    names(
        &e,
        2,
        "material.energy",
        "giantesio-musesti, ehret-bol-itskov, neo-hookean",
    );
}

#[test]
fn bad_schedules_and_motor_units_are_named_with_their_line() {
    let head = "[[study]]\nkind = \"activation-in-time\"\ntime = [0.0, 1.0]\n";
    let e = rejected(&format!("{head}schedule = [[0.0, 1.0], [0.0, 0.5]]\n"));
    names(&e, 4, "study[0].schedule[1]", "increase strictly");
    let e = rejected(&format!("{head}schedule = [[0.0, 1.0], [0.5, -0.5]]\n"));
    names(&e, 4, "study[0].schedule[1]", "[0, 1]");
    assert_eq!(e.value, "-0.5");
    let e = rejected(&format!(
        "{head}motor_units = [\n  {{ fraction = 0.5, twitch_force = 0.3, contraction_time = 0.1, interstimulus = 0.02 }},\n  {{ fraction = 0.4, twitch_force = 0.3, contraction_time = 0.05, interstimulus = 0.01 }},\n]\n"
    ));
    names(&e, 4, "study[0].motor_units", "sum to 1");
    let e = rejected(&format!(
        "{head}motor_units = [{{ fraction = 1.0, twitch_force = 0.3, contraction_time = -0.1, interstimulus = 0.02 }}]\n"
    ));
    names(&e, 4, "study[0].motor_units[0].contraction_time", "> 0");
    // F = 1 overshoots a = 1 (a fused tetanus tends to e F G ≈ 2.7): accepted, as 4C's twitch
    // forces with P_opt = N_a give a ≫ 1 (scenes/examples/4c_*_block.toml).
    Scene::parse(
        &format!(
            "{head}motor_units = [{{ fraction = 1.0, twitch_force = 1.0, contraction_time = 0.1, interstimulus = 0.01 }}]\n"
        ),
        FILE,
    )
    .expect("a level above 1 is a stronger drive, not an error");
    let e = rejected(&format!("{head}stretch = [[0.0, 1.0], [1.0, 0.0]]\n"));
    names(&e, 4, "study[0].stretch[1]", "> 0");
    let e = rejected(&format!("{head}stretch = \"loose\"\n"));
    names(&e, 4, "study[0].stretch", "free");
    let e = rejected("[[study]]\nkind = \"activation-in-time\"\ntime = [-1.0, 1.0]\n");
    names(&e, 3, "study[0].time", "≥ 0");
    let e = rejected("[[study]]\nkind = \"activation-in-time\"\nschedule = [[0.0, 1.0]]\n");
    names(&e, 1, "study[0].time", "time steps");
    let e = rejected(&format!("{head}laws = [\"implicit\"]\n"));
    names(&e, 4, "study[0].laws", "one law");
}

#[test]
fn the_printed_scene_reads_back_to_the_same_study() {
    let scene = Scene::parse(
        r#"
[[study]]
kind = "activation-in-time"
time = { from = 0.0, to = 0.1, step = 0.05 }
schedule = [[0.0, 0.5], [0.05, 1.0]]
interpolation = "linear"
stretch = "free"
motor_units = [{ fraction = 1.0, twitch_force = 0.3, contraction_time = 0.04, interstimulus = 0.02 }]
"#,
        FILE,
    )
    .unwrap();
    let printed = scene.resolved_toml().unwrap();
    let again = Scene::parse(&printed, FILE).unwrap_or_else(|e| panic!("{e}\n{printed}"));
    assert_eq!(again.studies, scene.studies);
    assert_eq!(again.resolved_toml().unwrap(), printed);
}

/// Every study without its own `damage` takes `activation.damage`: a stability study beside a
/// uniaxial one shows the same damages.
#[test]
fn studies_without_their_own_damage_take_the_activation_s() {
    let scene = Scene::parse(
        r#"
[activation]
damage = [0.0, 0.3, 0.5]

[[study]]
kind = "uniaxial"
name = "u"
stretch = [0.9, 1.1]

[[study]]
kind = "stability"
name = "s"
stretch = [0.9, 1.1]
normals = 4
"#,
        FILE,
    )
    .unwrap();
    let resolved: toml::Value = toml::from_str(&scene.resolved_toml().unwrap()).unwrap();
    let studies = resolved["study"].as_array().unwrap();
    assert_eq!(studies.len(), 2);
    for study in studies {
        let damage: Vec<f64> = study["damage"]
            .as_array()
            .unwrap()
            .iter()
            .map(|v| v.as_float().unwrap())
            .collect();
        assert_eq!(damage, [0.0, 0.3, 0.5], "{study}");
    }
}

/// A misspelt key of `[material]` (taken for an energy parameter, whose values are numbers) is
/// named as such, not as a type error.
#[test]
fn a_misspelt_material_key_is_named() {
    let e = rejected("[material]\nengery = \"neo-hookean\"\n");
    assert!(e.to_string().contains("engery is not a number"), "{e}");
    assert!(e.to_string().contains("misspelt"), "{e}");
}

/// Values far out of range are written back short in the message, as the scene gives them
/// (issue 24, item 10: `1e300` was printed as its 301 digits).
#[test]
fn extreme_values_are_written_short_in_messages() {
    const STUDY: &str = "[[study]]\nkind = \"uniaxial\"\nstretch = [1.0, 1.1]\n";
    for (text, key, shown) in [
        (
            "[[study]]\nkind = \"uniaxial\"\nstretch = [1.0, -1e300]\n".to_string(),
            "study[0].stretch",
            "-1e300",
        ),
        (
            format!("[activation]\ndamage = [1e300]\n{STUDY}"),
            "activation.damage[0]",
            "1e300",
        ),
        (
            format!("[material]\nmu = -1e300\n{STUDY}"),
            "material.mu",
            "-1e300",
        ),
        (
            format!("[material]\nmu = 1e-300\nalpha = -2.5e-300\n{STUDY}"),
            "material.alpha",
            "-2.5e-300",
        ),
        (
            "[[study]]\nkind = \"cylinder\"\nnr = 1\nnz = 2\nstretch = [1.1]\n\
             regions = [{ r = [0.0, 1e300], damage = 0.5 }]\n"
                .to_string(),
            "study[0].regions[0].r",
            "[0, 1e300]",
        ),
    ] {
        let e = rejected(&text);
        let message = e.to_string();
        assert!(
            message.contains(&format!("{key} = {shown}")),
            "{key} = {shown}: {message}"
        );
        assert!(
            message.len() < 200,
            "{} characters: {message}",
            message.len()
        );
    }
}
