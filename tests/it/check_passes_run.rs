//! What `activemuscle check` passes must run (issue 24, item 8): each scene below passed the
//! check and failed, or silently meant something else, only when it ran. Now the scene is
//! refused when it is read, with the key, the value and why. The library's parser is what
//! `check` runs.

use activemuscle::scene::Scene;

/// The error of reading `text` as a scene, in words; fails the test if the scene is accepted.
fn refused(text: &str) -> String {
    match Scene::parse(text, "scene.toml") {
        Ok(_) => panic!("the scene was accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

fn accepted(text: &str) {
    if let Err(e) = Scene::parse(text, "scene.toml") {
        panic!("the scene was refused: {e}\n{text}");
    }
}

fn assert_has(text: &str, needles: &[&str]) {
    for n in needles {
        assert!(text.contains(n), "{n:?} not in: {text}");
    }
}

#[test]
fn a_tradeoff_tolerance_below_round_off_is_refused_and_written_short() {
    let scene = |t: &str| {
        format!(
            "[[study]]\nkind = \"tradeoff\"\noptions = [\"newton-tolerance\"]\n\
             stretch = [1.1]\nnr = 1\nnz = 4\ntolerances = [1e-6, {t}]\n"
        )
    };
    let e = refused(&scene("1e-300"));
    assert_has(&e, &["tolerances[1]", "1e-300", "4 ε"]);
    // Numbers in messages are short (item 10): no 300-digit decimal.
    assert!(!e.contains("0000000000"), "{e}");
    // The smallest tolerance the solver accepts (4 ε) is accepted here too.
    accepted(&scene(&format!("{:e}", 4.0 * f64::EPSILON)));
    refused(&scene(&format!("{:e}", 3.9 * f64::EPSILON)));
}

#[test]
fn a_tradeoff_mesh_beyond_the_memory_limit_is_refused_before_anything_runs() {
    let e = refused(
        "[[study]]\nkind = \"tradeoff\"\noptions = [\"mesh\"]\nstretch = [1.1]\n\
         meshes = [[2, 4], [3000, 3000]]\n",
    );
    assert_has(&e, &["meshes", "3000 × 3000", "memory"]);
    // The FE mesh of the groups that solve only it is checked too.
    let e = refused(
        "[[study]]\nkind = \"tradeoff\"\noptions = [\"newton-tolerance\"]\nstretch = [1.1]\n\
         nr = 3000\nnz = 3000\n",
    );
    assert_has(&e, &["nr", "memory"]);
    // The mesh option's meshes do not count when the mesh option is not chosen.
    accepted(
        "[[study]]\nkind = \"tradeoff\"\noptions = [\"newton-tolerance\"]\nstretch = [1.1]\n\
         nr = 1\nnz = 4\nmeshes = [[2, 4], [3000, 3000]]\n",
    );
}

#[test]
fn bounds_that_exclude_the_default_start_are_refused() {
    let scene = |bounds: &str| {
        format!(
            "[[study]]\nkind = \"fit\"\nfit = \"damage\"\ntrue_damage = [0.3]\n\
             stretch = {{ from = 0.8, to = 1.4, step = 0.05 }}\n{bounds}"
        )
    };
    // The damage fit starts at the model's d = 0.
    let e = refused(&scene("bounds = { d = [0.1, 1.0] }\n"));
    assert_has(&e, &["bounds.d", "[0.1, 1]", "start", "0"]);
    accepted(&scene("bounds = { d = [0.0, 1.0] }\n"));
    accepted(&scene("bounds = { d = [0.1, 1.0] }\nstart = { d = 0.5 }\n"));
    // A start given outside its bounds was refused before; it still is.
    let e = refused(&scene(
        "bounds = { d = [0.1, 1.0] }\nstart = { d = 0.05 }\n",
    ));
    assert_has(&e, &["start.d", "0.05"]);
}

#[test]
fn a_schedule_that_starts_after_the_first_time_is_refused() {
    let scene = |schedule: &str| {
        format!(
            "[[study]]\nkind = \"activation-in-time\"\n\
             time = {{ from = 0, to = 10, step = 1 }}\n{schedule}"
        )
    };
    // Before: a(t) = 1 from t = 0, the "late" start silently ignored.
    let e = refused(&scene("schedule = [[5, 1]]\n"));
    assert_has(&e, &["schedule[0]", "t = 5 s", "0 s"]);
    accepted(&scene("schedule = [[0, 0], [5, 1]]\n"));
    // A stretch schedule holds its first stretch before its first point too.
    let e = refused(&scene(
        "schedule = [[0, 1]]\nstretch = [[2, 1.0], [5, 1.1]]\n",
    ));
    assert_has(&e, &["stretch[0]", "t = 2 s"]);
}

#[test]
fn a_region_that_governs_no_quadrature_point_is_refused() {
    let scene = |regions: &str| {
        format!("[[study]]\nkind = \"cylinder\"\nstretch = [1.1]\nnr = 2\nnz = 4\n{regions}")
    };
    // nr = 2: the first column of cells is r ∈ [0, 0.5] R, its first Gauss points at
    // r = 0.25 (1 − √0.6) R = 0.056 R; a shell r ∈ [0, 0.05] R holds none of them.
    let e = refused(&scene("[[study.regions]]\nr = [0.0, 0.05]\ndamage = 0.5\n"));
    assert_has(&e, &["regions[0]", "no quadrature point", "2 × 4"]);
    accepted(&scene("[[study.regions]]\nr = [0.0, 0.06]\ndamage = 0.5\n"));
    // A region every point of which a later region takes over has no effect either.
    let e = refused(&scene(
        "[[study.regions]]\nr = [0.5, 1.0]\ndamage = 0.5\n\
         [[study.regions]]\nr = [0.4, 1.0]\ndamage = 0.2\n",
    ));
    assert_has(&e, &["regions[0]", "later regions"]);
}

#[test]
fn a_table_range_the_exact_law_cannot_meet_is_refused() {
    let scene = |range: &str| {
        format!(
            "[activation]\nrepresentation = \"tabulated\"\ntable_stretches = {range}\n\
             [[study]]\nkind = \"uniaxial\"\nstretch = [0.8, 1.2]\n"
        )
    };
    // The chapter's exp(α(I₄ − 1)²) overflows near λ = 8.5: a table up to 10 cannot be built,
    // and every study using it failed at run time.
    let e = refused(&scene("[0.3, 10.0]"));
    assert_has(
        &e,
        &[
            "activation.table_stretches",
            "[0.3, 10]",
            "narrow the range",
        ],
    );
    assert!(!e.contains("0000000000"), "{e}");
    accepted(&scene("[0.3, 3.0]"));
}

#[test]
fn a_fit_start_outside_the_default_bounds_is_refused_at_its_key() {
    let scene = |start: &str| {
        format!(
            "[[study]]\nkind = \"fit\"\nfit = \"damage\"\ntrue_damage = [0.3]\n\
             stretch = {{ from = 0.8, to = 1.4, step = 0.05 }}\n{start}"
        )
    };
    // No bounds given: the damage's admissible range [0, 1] bounds the fit.
    let e = refused(&scene("start = { d = 1.5 }\n"));
    assert_has(&e, &["start.d", "1.5", "[0, 1]"]);
    accepted(&scene("start = { d = 0.9 }\n"));
    // Given bounds widen it (the fit runs within them).
    accepted(&scene("start = { d = 0.9 }\nbounds = { d = [0.0, 1.0] }\n"));
    // A passive fit's default bounds are the energy's parameter ranges (w0 ∈ (0, 1)).
    let e = refused(
        "[[study]]\nkind = \"fit\"\nfit = \"passive\"\nreference = { energy = \"ehret-bol-itskov\" }\n\
         free = [\"w0\"]\nstart = { w0 = 1.5 }\n",
    );
    assert_has(&e, &["start.w0", "1.5"]);
}

#[test]
fn a_volumetric_energy_stiffer_than_f64_resolves_is_refused_when_read() {
    let scene = |kind: &str, kappa: &str| {
        format!(
            "[incompressibility]\nkind = \"{kind}\"\nkappa = {kappa}\n\
             [[study]]\nkind = \"uniaxial\"\nstretch = [0.8, 1.0, 1.2]\n"
        )
    };
    // The chapter's energy has E₀ = dP/dλ(1) ≈ 0.42 kPa along the fibres: at most 1e10 E₀.
    for kappa in ["1e300", "1e16", "1e10"] {
        let e = refused(&scene("quadratic", kappa));
        assert_has(
            &e,
            &["incompressibility.kappa", "1e10 times", "E₀ = 0.4223 kPa"],
        );
        assert!(!e.contains("0000000000000"), "{e}");
    }
    let e = refused(&scene("4c-giantesio", "1e300"));
    assert_has(&e, &["incompressibility.kappa", "1e300"]);
    // Just below the bound the scene is accepted and every stretch runs.
    let text = scene("quadratic", "4e9");
    let results = Scene::parse(&text, "scene.toml")
        .unwrap()
        .run(&activemuscle::scene::RunOptions::default());
    assert!(results.complete(), "{:?}", results.studies[0].failures);
}
