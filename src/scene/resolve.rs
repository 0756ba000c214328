//! Validation and resolution of a [`SceneSpec`] into a [`Scene`]: defaults filled in, every rule
//! checked, every model parameter passed once through the core's own constructors (their errors
//! are mapped back to the key that produced them, and the key to its line).

use super::keypath::line_of;
use super::{ActivationSpec, Scene, SceneSpec};
use crate::active::law::LawRepresentation;
use crate::active::Approach;
use crate::app_error::{SceneError, SpecError};
use crate::models::{EnergySpec, IncompressibilitySpec, MaterialSpec, ModelDefaults, Models};
use crate::studies::spec::{damages, Defaults};
use crate::studies::{slug, Study, StudyKind, StudySpec, MAX_SLUG_BYTES};
use crate::text::shortest;
use std::path::Path;

pub(super) fn resolve(
    spec: SceneSpec,
    text: &str,
    file: &str,
    base: &Path,
) -> Result<Scene, SceneError> {
    let error = |e: SpecError| SceneError {
        file: file.to_string(),
        line: line_of(text, &e.key),
        key: e.key,
        value: e.value,
        rule: e.rule,
    };
    let (models, choices) = models(&spec).map_err(error)?;
    let defaults = Defaults {
        models: &models,
        approach: choices.approach,
        law: choices.law,
        coupling: choices.coupling,
        damage: &choices.damage,
        base,
    };
    let (studies, resolved) = studies(&spec.studies, &defaults).map_err(error)?;
    crate::studies::size::check(&studies).map_err(error)?;
    axial_fibres(models.fibre, &studies).map_err(error)?;
    let approaches = approaches(choices.approach, &studies);
    activation_applies(&spec.activation, &approaches, &studies).map_err(error)?;
    let resolved = SceneSpec {
        title: spec.title.clone(),
        material: MaterialSpec {
            energy: EnergySpec::written(&models.energy),
            fibre: Some(models.fibre),
        },
        activation: ActivationSpec::written(&models, &choices, &approaches),
        // Written out even when left out (`kind = "exact"`): `check` shows every default.
        incompressibility: Some(IncompressibilitySpec::written(models.volumetric.as_ref())),
        studies: resolved,
    };
    Ok(Scene {
        file: file.to_string(),
        source: text.to_string(),
        title: spec.title.unwrap_or_else(|| "activemuscle scene".into()),
        models,
        defaults: choices,
        studies,
        resolved,
    })
}

/// The material, activation and incompressibility of the scene, and its studies' defaults (the
/// damage values validated, the approach possible on the material and calibrated to its curve).
fn models(spec: &SceneSpec) -> Result<(Models, ModelDefaults), SpecError> {
    let models = Models::from_spec(
        &spec.material,
        &spec.activation,
        spec.incompressibility.as_ref(),
    )?;
    let mut choices = spec.activation.defaults();
    choices.damage = damages("activation.damage", &choices.damage)?;
    let approach = choices.approach;
    let given = || format!("{:?}", approach.name());
    models
        .activation_map(approach)
        .map_err(|rule| SpecError::new("activation.approach", given(), rule))?;
    if let Some(curves) = approach
        .curves()
        .filter(|c| !c.contains(&models.curve.name()))
    {
        return Err(SpecError::new(
            "activation.curve",
            format!("{:?}", models.curve.name()),
            format!(
                "approach = {} is calibrated to the curves {}",
                given(),
                curves.join(", ")
            ),
        ));
    }
    tables_build(&models, approach)?;
    Ok((models, choices))
}

/// The approaches the scene's models use: its own and its studies' (each once, in order).
fn approaches(scene: Approach, studies: &[Study]) -> Vec<Approach> {
    let mut v = vec![scene];
    for a in studies.iter().flat_map(Study::approaches) {
        if !v.contains(&a) {
            v.push(a);
        }
    }
    v
}

/// Refuses an `[activation]` key that applies to none of the scene's `approaches`, and
/// `force_velocity` without a study driven in time (quasi-static studies have λ̇ = 0, f_v = 1).
fn activation_applies(
    activation: &ActivationSpec,
    approaches: &[Approach],
    studies: &[Study],
) -> Result<(), SpecError> {
    activation.refuse_inapplicable(approaches)?;
    if activation.force_velocity.is_some() && !studies.iter().any(Study::in_time) {
        let in_time: Vec<&str> = StudyKind::ALL
            .iter()
            .filter(|k| k.in_time())
            .map(|k| k.name())
            .collect();
        return Err(SpecError::new(
            "activation.force_velocity",
            "(given)",
            format!(
                "force–velocity scales the active stress by the stretch rate of a study driven in \
                 time (kind = {}); this scene has none, and its quasi-static studies have \
                 λ̇ = 0, f_v = 1",
                in_time.join(" | ")
            ),
        ));
    }
    Ok(())
}

/// A tabulated law's tables are built here, at d = 0, for the laws of `approach` that solve for
/// its variable (implicit, energy): a range the table cannot meet (the exact law fails inside it,
/// e.g. exp overflows at λ ≈ 8.5 for the chapter's energy) is refused at
/// `activation.table_stretches` instead of failing every study that uses it. Costs 0.04–0.1 s per
/// law.
fn tables_build(models: &Models, approach: Approach) -> Result<(), SpecError> {
    let LawRepresentation::Tabulated(table) = models.representation else {
        return Ok(());
    };
    let Ok(map) = models.activation_map(approach) else {
        return Ok(());
    };
    for &kind in approach.laws().iter().filter(|l| l.solves()) {
        // A law this material cannot have is refused where the studies ask for it.
        let Ok(law) = models.law(kind, map) else {
            continue;
        };
        if let Err(e) = law.represented(models.representation, &[0.0]) {
            return Err(SpecError::new(
                "activation.table_stretches",
                format!(
                    "[{}, {}]",
                    shortest(table.lambda_lo),
                    shortest(table.lambda_hi)
                ),
                format!(
                    "the {} law's table cannot be built on this range at d = 0: {e}; narrow the range",
                    kind.name()
                ),
            ));
        }
    }
    Ok(())
}

/// The studies, validated in file order, and their resolved specs; then each completed from the
/// others where its kind takes what it leaves out from them ([`StudySpec::completed`]).
fn studies(
    specs: &[StudySpec],
    defaults: &Defaults,
) -> Result<(Vec<Study>, Vec<StudySpec>), SpecError> {
    if specs.is_empty() {
        return Err(SpecError::new(
            "study",
            "(none)",
            format!(
                "a scene needs at least one [[study]] (kind = {})",
                StudyKind::names()
            ),
        ));
    }
    let mut studies: Vec<Study> = Vec::with_capacity(specs.len());
    let mut resolved: Vec<StudySpec> = Vec::with_capacity(specs.len());
    for (i, s) in specs.iter().enumerate() {
        one_per_scene(s.kind(), &studies).map_err(|e| e.within(&format!("study[{i}]")))?;
        let (study, r) = s
            .resolve(defaults)
            .map_err(|e| e.within(&format!("study[{i}]")))?;
        unique_name(&study, &studies).map_err(|e| e.within(&format!("study[{i}]")))?;
        studies.push(study);
        resolved.push(r);
    }
    // What a study takes from the others, once all are resolved.
    for (i, s) in specs.iter().enumerate() {
        if let Some((study, r)) = s
            .completed(&resolved[i], i, &studies, defaults)
            .map_err(|e| e.within(&format!("study[{i}]")))?
        {
            studies[i] = study;
            resolved[i] = r;
        }
    }
    Ok((studies, resolved))
}

/// Refuses a second study of a `kind` a scene holds at most one of, `before` holding the
/// studies resolved so far.
fn one_per_scene(kind: StudyKind, before: &[Study]) -> Result<(), SpecError> {
    let (Some(why), Some(first)) = (
        kind.one_per_scene(),
        before.iter().position(|s| s.kind() == kind),
    ) else {
        return Ok(());
    };
    Err(SpecError::new(
        "kind",
        format!("{:?}", kind.name()),
        format!(
            "a scene holds at most one {} study (study[{first}] is one): {why}",
            kind.name()
        ),
    ))
}

/// Output files and directories are named by [`slug`] of a study's name: it must have a letter
/// or a digit (of any script), be at most [`MAX_SLUG_BYTES`] long as a file name (a longer one
/// would make the run fail when it writes, after computing) and differ from every earlier
/// study's (`"cyl A"` and `"cyl-a"` are both `cyl_a`).
fn unique_name(study: &Study, before: &[Study]) -> Result<(), SpecError> {
    let name = study.name();
    let file = slug(name);
    if file.is_empty() {
        return Err(SpecError::new(
            "name",
            format!("{name:?}"),
            "a study's name names its output files: it needs at least one letter or digit",
        ));
    }
    if file.len() > MAX_SLUG_BYTES {
        let shown: String = name.chars().take(40).collect();
        return Err(SpecError::new(
            "name",
            format!("{shown:?}… ({} characters)", name.chars().count()),
            format!(
                "a study's name names its output files (fig_…_<name>.png, points_<name>.csv), and \
                 a file name has at most 255 bytes: as a file name this one has {} bytes, at most \
                 {MAX_SLUG_BYTES} (about {MAX_SLUG_BYTES} ASCII letters or digits) are allowed; \
                 give it a shorter name",
                file.len()
            ),
        ));
    }
    match before.iter().position(|s| slug(s.name()) == file) {
        None => Ok(()),
        Some(j) => Err(SpecError::new(
            "name",
            format!("{name:?}"),
            format!(
                "study[{j}] is named {:?}: both give the output name {file:?} (names are compared by \
                 their letters and digits, case ignored); give each study a name of its own",
                before[j].name()
            ),
        )),
    }
}

/// The axisymmetric FE cylinder (the studies of a kind that solves it,
/// [`StudyKind::axial_fibres`]) has its fibres along its axis, e₁ of the material frame: a unit
/// fibre `f` with |f · e₁| < 1 − 1e-12 cannot be represented there and is refused, naming the
/// first study that would have replaced it by the axis.
fn axial_fibres(fibre: [f64; 3], studies: &[Study]) -> Result<(), SpecError> {
    if fibre[0].abs() >= 1.0 - 1e-12 {
        return Ok(());
    }
    match studies.iter().position(|s| s.kind().axial_fibres()) {
        None => Ok(()),
        Some(i) => {
            let shown: Vec<String> = fibre.iter().map(|x| format!("{x:.4}")).collect();
            Err(SpecError::new(
                "material.fibre",
                format!("[{}] (normalised)", shown.join(", ")),
                format!(
                    "study[{i}] ({}) solves the axisymmetric FE cylinder, whose fibres run along its \
                     axis e₁ = [1, 0, 0]; a fibre across or oblique to the axis breaks the axial symmetry: \
                     use fibre = [1, 0, 0] (homogeneous studies are the same for any fibre direction)",
                    studies[i].name()
                ),
            ))
        }
    }
}
