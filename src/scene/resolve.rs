//! Validation and resolution of a [`SceneSpec`] into a [`Scene`]: defaults filled in, every rule
//! checked, every model parameter passed once through the core's own constructors (their errors
//! are mapped back to the key that produced them, and the key to its line).

use super::keypath::line_of;
use super::{ActivationSpec, ExplicitSpec, Scene, SceneSpec};
use crate::active::law::LawRepresentation;
use crate::app_error::{SceneError, SpecError};
use crate::models::{EnergySpec, IncompressibilitySpec, LawKind, MaterialSpec, Models};
use crate::studies::spec::{damages, Defaults};
use crate::studies::{slug, tradeoff, Study, StudyKind, StudySpec, MAX_SLUG_BYTES};
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
    let (models, damage) = models(&spec).map_err(error)?;
    let act = &spec.activation;
    let defaults = Defaults {
        models: &models,
        law: act.law.unwrap_or_default(),
        coupling: act.coupling.unwrap_or_default(),
        damage: &damage,
        base,
    };
    let (studies, resolved) = studies(&spec.studies, &defaults).map_err(error)?;
    crate::studies::size::check(&studies).map_err(error)?;
    axial_fibres(models.fibre, &studies).map_err(error)?;
    let resolved = SceneSpec {
        title: spec.title.clone(),
        material: MaterialSpec {
            energy: EnergySpec::written(&models.energy),
            fibre: Some(models.fibre),
        },
        activation: ActivationSpec {
            approach: Some(models.approach),
            curve: Some(ActivationSpec::written_curve(&models.curve).0),
            curve_parameters: ActivationSpec::written_curve(&models.curve).1,
            law: Some(defaults.law),
            coupling: Some(defaults.coupling),
            frozen_tangent: Some(models.frozen_tangent),
            below_minimum: Some(models.below_minimum),
            map: Some(models.map),
            damage: Some(damage.clone()),
            explicit: Some(ExplicitSpec {
                a: Some(models.explicit.0),
                b: Some(models.explicit.1),
            }),
            representation: Some(models.representation_spec().0),
            table_stretches: models.representation_spec().1,
            force_velocity: models.force_velocity,
        },
        // Written out even when left out (`kind = "exact"`): `check` shows every default.
        incompressibility: Some(IncompressibilitySpec::written(models.volumetric.as_ref())),
        studies: resolved,
    };
    Ok(Scene {
        file: file.to_string(),
        source: text.to_string(),
        title: spec.title.unwrap_or_else(|| "activemuscle scene".into()),
        models,
        studies,
        resolved,
    })
}

/// The material and activation of the scene, and its default damage values.
fn models(spec: &SceneSpec) -> Result<(Models, Vec<f64>), SpecError> {
    let mut models = Models::from_spec(&spec.material, &spec.activation)?;
    if let Some(inc) = &spec.incompressibility {
        models.volumetric = inc
            .build(&models.energy)
            .map_err(|e| e.within("incompressibility"))?;
    }
    tables_build(&models)?;
    let damage = spec.activation.damage.as_deref().unwrap_or(&[0.0]);
    Ok((models, damages("activation.damage", damage)?))
}

/// A tabulated law's tables are built here, at d = 0, for the implicit and the energy law: a
/// range the table cannot meet (the exact law fails inside it, e.g. exp overflows at λ ≈ 8.5
/// for the chapter's energy) is refused at `activation.table_stretches` instead of failing
/// every study that uses it. Costs 0.04–0.1 s per law.
fn tables_build(models: &Models) -> Result<(), SpecError> {
    let LawRepresentation::Tabulated(table) = models.representation else {
        return Ok(());
    };
    if !models.approach.has_law() {
        return Ok(());
    }
    for kind in [LawKind::Implicit, LawKind::Energy] {
        // A law this material cannot have is refused where the studies ask for it.
        let Ok(law) = models.law(kind) else {
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

/// The studies, validated in file order, and their resolved specs; trade-off studies take what
/// they leave out from the first cylinder study, wherever it is.
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
        let key = format!("study[{i}]");
        if s.kind() == StudyKind::Tradeoff {
            if let Some(first) = studies.iter().position(|s| matches!(s, Study::Tradeoff(_))) {
                return Err(SpecError::new(
                    format!("{key}.kind"),
                    "\"tradeoff\"",
                    format!(
                        "a scene holds at most one tradeoff study (study[{first}] is one): \
                         its outputs are tradeoff.csv, tradeoff.md and the tradeoff figures"
                    ),
                ));
            }
        }
        let (study, r) = s.resolve(defaults).map_err(|e| e.within(&key))?;
        unique_name(&study, &studies).map_err(|e| e.within(&key))?;
        studies.push(study);
        resolved.push(r);
    }
    let fallback = crate::studies::fallback(&studies);
    for (i, ((study, given), r)) in studies.iter_mut().zip(specs).zip(&mut resolved).enumerate() {
        if let (Study::Tradeoff(t), StudySpec::Tradeoff(given), StudySpec::Tradeoff(r)) =
            (study, given, r)
        {
            tradeoff::complete(t, given, r, &fallback)
                .map_err(|e| e.within(&format!("study[{i}]")))?;
        }
    }
    Ok((studies, resolved))
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

/// The axisymmetric FE cylinder (cylinder and trade-off studies) has its fibres along its axis,
/// e₁ of the material frame: a unit fibre `f` with |f · e₁| < 1 − 1e-12 cannot be represented
/// there and is refused, naming the first study that would have replaced it by the axis.
fn axial_fibres(fibre: [f64; 3], studies: &[Study]) -> Result<(), SpecError> {
    if fibre[0].abs() >= 1.0 - 1e-12 {
        return Ok(());
    }
    match studies
        .iter()
        .position(|s| matches!(s, Study::Cylinder(_) | Study::Tradeoff(_)))
    {
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
