//! The figures of a run, built from what each study computed: every curve of `curves.csv` is
//! drawn in some figure with a legend entry (the series carry its
//! [`CurveId`](crate::plot::CurveId)), headings and captions name the scene's energy, laws,
//! couplings and damages, axes follow the data (clipped where a curve blows up, and the caption
//! says so: [`crate::plot::Panel::frame`]). Where a figure shows what one of the chapter's figures shows, its
//! heading says which.
//!
//! | figure | drawn when | shows |
//! |---|---|---|
//! | `fig_passive_<direction>` | a uniaxial study has passive curves (not only the material's, already in `fig_transverse_isotropy`) | each passive energy |
//! | `fig_transverse_isotropy` | the material's passive curve is computed along and across the fibres | both |
//! | `fig_constant_gamma` | constant γ | each γ; a zoom on the zero crossings |
//! | `fig_active_curve`, `fig_damage_active` | active models along the fibres (two damages or more for the second) | P_act, (1 − d) P_act |
//! | `fig_gamma_and_stresses` | the implicit law, frozen, along the fibres | γ; P_tot, P_pas, (1 − d) P_act at the smallest damage |
//! | `fig_explicit_vs_implicit_gamma`, `fig_explicit_ptot` | the explicit (and implicit) law, frozen, along the fibres | γ of both; P_tot against its target |
//! | `fig_laws` | active models | γ and P of every law × coupling at the smallest damage, with the target |
//! | `fig_loss_of_activation` | two damages or more | P per law × coupling, a curve per damage |
//! | `fig_cylinder` | a cylinder study | γ and λ_f at the centre, P (FE and 0D) per damage |
//! | `fig_fe_vs_0d` | cylinder studies | P_FE − P_0D per damage, a panel per study |
//! | `fig_fit_*`, `fig_stability_*` | fit and stability studies | data and fits; stability along the fibres |
//! | `fig_history_*` | activation-in-time studies | a(t); P(t) or λ(t) and γ(t) per damage |
//!
//! A stem that two studies would share gets the study's name appended.

use crate::plot::Figure;
use crate::scene::{Results, Scene};
use crate::studies::outputs::Context;
use crate::studies::{slug, StudyResult};
use crate::StrainEnergy;

/// What the kinds' figures and report sections take from `scene`.
pub fn context(scene: &Scene) -> Context {
    let paper = crate::models::Models::paper();
    Context {
        material: scene.models.energy.name().to_string(),
        curve: scene.models.curve,
        chapter_material: scene.models.energy == paper.energy && scene.models.curve == paper.curve,
    }
}

/// Every figure the results support, kind by kind in the order of the registry
/// ([`StudyResult::figures`]), each kind's studies in scene order; stems made unique, and γ
/// written as the approach's variable.
pub fn figures(scene: &Scene, results: &Results) -> Vec<Figure> {
    let mut out = StudyResult::figures(&results.studies, &context(scene));
    unique_stems(&mut out, results);
    // The figures are written with the active-strain γ; the scene's approach may name its
    // variable otherwise (the structural ω).
    if let Some(v) = scene.defaults.approach.variable().filter(|v| *v != "γ") {
        for f in &mut out {
            f.rename_symbol("γ", v);
        }
    }
    out
}

/// Appends the study's name to a stem that another figure already has (and a number if that
/// is taken too).
fn unique_stems(figures: &mut [Figure], results: &Results) {
    let studies: Vec<&str> = results.studies.iter().map(|s| s.name.as_str()).collect();
    for i in 1..figures.len() {
        if figures[..i].iter().any(|f| f.stem == figures[i].stem) {
            let own = studies
                .iter()
                .find(|s| figures[i].heading.contains(&format!("\"{s}\"")))
                .map_or(i.to_string(), |s| slug(s));
            let kind = figures[i].stem.trim_start_matches("fig_").to_string();
            let stem = if own.starts_with(&kind) {
                format!("fig_{own}")
            } else {
                format!("fig_{kind}_{own}")
            };
            // Two study names may give one slug ("cyl A", "cyl-a"): then a number as well.
            let taken = |t: &str| figures[..i].iter().any(|f| f.stem == t);
            figures[i].stem = (1..)
                .map(|n| {
                    if n == 1 {
                        stem.clone()
                    } else {
                        format!("{stem}_{n}")
                    }
                })
                .find(|t| !taken(t))
                .unwrap_or(stem);
        }
    }
}
