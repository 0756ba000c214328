//! Validation and resolution of a [`SceneFile`] into a [`Scene`]: defaults filled in, every rule
//! checked, every model parameter passed once through the core's own constructors (their errors
//! are mapped back to the key that produced them).

use super::fit::{resolve_fit, FitStudy};
use super::schema::{
    ActivationSpec, BasesKind, BelowMinimumKind, CouplingKind, DirectionKind, ElementKind,
    EnergyKind, EnergySpec, ExplicitSpec, LawKind, MaterialSpec, SceneFile, StretchSpec, StudyKind,
    StudySpec, TangentKind,
};
use super::stability::{resolve_stability, StabilityStudy};
use super::tradeoff::{resolve_tradeoff, TradeoffStudy};
use super::SceneError;
use crate::active::{
    ActiveCurve, BelowMinimum, ConstantLaw, Coupling, EnergyLaw, ExplicitLaw, FrozenTangent,
    ImplicitLaw, Law,
};
use crate::energy::{EhretBolItskov, Energy, GiantesioMusesti, NeoHookean};
use crate::fit::Parametric;
use crate::tradeoff::study::scene_cylinder;
use crate::Muscle;

/// A validated scene with every default resolved.
#[derive(Debug, Clone)]
pub struct Scene {
    /// File name (or the embedded scene's name).
    pub file: String,
    /// The scene text as read.
    pub source: String,
    /// Title.
    pub title: String,
    /// The passive energy.
    pub material: Energy,
    /// Fibre direction (unit). The tests are defined relative to it, so any direction gives the
    /// same curves; the cylinder's axis is aligned with it.
    pub fibre: [f64; 3],
    /// Active curve.
    pub curve: ActiveCurve,
    /// Explicit-law coefficients (a, b).
    pub explicit: (f64, f64),
    /// Tangent used by the frozen model.
    pub frozen_tangent: TangentKind,
    /// What the energy law does below λ_min.
    pub below_minimum: BelowMinimum,
    /// Studies in file order.
    pub studies: Vec<Study>,
    /// The resolved scene as a TOML document (every default written out).
    pub resolved: SceneFile,
}

/// A study to run.
#[derive(Debug, Clone)]
pub enum Study {
    /// Homogeneous uniaxial tension.
    Uniaxial(UniaxialStudy),
    /// The FE cylinder.
    Cylinder(CylinderStudy),
    /// A least-squares fit.
    Fit(FitStudy),
    /// Material stability along the fibres.
    Stability(StabilityStudy),
    /// Speed versus accuracy.
    Tradeoff(TradeoffStudy),
}

/// One activation model: law, coupling, damage.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelChoice {
    /// Activation law.
    pub law: LawKind,
    /// Coupling.
    pub coupling: CouplingKind,
    /// Damage d ∈ [0, 1].
    pub damage: f64,
}

/// A validated uniaxial study.
#[derive(Debug, Clone)]
pub struct UniaxialStudy {
    /// Label.
    pub name: String,
    /// Loading direction relative to the fibres.
    pub direction: DirectionKind,
    /// Stretches, ascending, without duplicates.
    pub stretches: Vec<f64>,
    /// Whether to include the material's passive curve.
    pub passive: bool,
    /// Extra passive energies.
    pub compare: Vec<Energy>,
    /// Active models: laws × couplings × damages.
    pub models: Vec<ModelChoice>,
    /// Constant activations.
    pub constant_gamma: Vec<f64>,
}

/// A validated cylinder study.
#[derive(Debug, Clone)]
pub struct CylinderStudy {
    /// Label.
    pub name: String,
    /// Radius R.
    pub radius: f64,
    /// Length L.
    pub length: f64,
    /// Cells in r.
    pub nr: usize,
    /// Cells in z.
    pub nz: usize,
    /// Middle/base cell-height ratio.
    pub grading: f64,
    /// Base conditions.
    pub bases: BasesKind,
    /// Finite element.
    pub element: ElementKind,
    /// Target stretches, ascending.
    pub stretches: Vec<f64>,
    /// Activation law.
    pub law: LawKind,
    /// Coupling.
    pub coupling: CouplingKind,
    /// Damage values, one FE sweep each.
    pub damages: Vec<f64>,
    /// Stretches with VTK output.
    pub vtk: Vec<f64>,
    /// Newton tolerance.
    pub tolerance: f64,
}

impl Study {
    /// The study's label.
    pub fn name(&self) -> &str {
        match self {
            Study::Uniaxial(s) => &s.name,
            Study::Cylinder(s) => &s.name,
            Study::Fit(s) => &s.name,
            Study::Stability(s) => &s.name,
            Study::Tradeoff(s) => &s.name,
        }
    }
}

impl Scene {
    /// The activation law `kind` built for this scene's material and curve.
    pub fn law(&self, kind: LawKind) -> crate::Result<Law<Energy>> {
        Ok(match kind {
            LawKind::Implicit => Law::Implicit(ImplicitLaw::new(self.material.clone(), self.curve)),
            LawKind::Energy => Law::Energy(
                EnergyLaw::new(self.material.clone(), self.curve).below_minimum(self.below_minimum),
            ),
            LawKind::Explicit => {
                let gm = match &self.material {
                    Energy::GiantesioMusesti(gm) => *gm,
                    _ => GiantesioMusesti::paper(),
                };
                Law::Explicit(ExplicitLaw::new(
                    self.explicit.0,
                    self.explicit.1,
                    gm,
                    self.curve,
                )?)
            }
        })
    }

    /// The coupling `kind` with this scene's frozen tangent.
    pub fn coupling(&self, kind: CouplingKind) -> Coupling {
        match (kind, self.frozen_tangent) {
            (CouplingKind::Consistent, _) => Coupling::Consistent,
            (CouplingKind::Frozen, TangentKind::Exact) => Coupling::Frozen(FrozenTangent::Exact),
            (CouplingKind::Frozen, TangentKind::Symmetric) => {
                Coupling::Frozen(FrozenTangent::Symmetric)
            }
        }
    }

    /// The active muscle of `model`.
    pub fn muscle(&self, model: ModelChoice) -> crate::Result<Muscle<Energy>> {
        Muscle::new(
            self.material.clone(),
            self.law(model.law)?,
            model.damage,
            self.coupling(model.coupling),
        )
    }

    /// A muscle with constant activation γ (coupling irrelevant: g′ = 0).
    pub fn constant(&self, gamma: f64) -> crate::Result<Muscle<Energy>> {
        Muscle::new(
            self.material.clone(),
            Law::Constant(ConstantLaw::new(gamma)?),
            0.0,
            Coupling::Consistent,
        )
    }
}

pub(super) struct Ctx<'a> {
    pub file: &'a str,
}

impl Ctx<'_> {
    pub fn err(
        &self,
        key: impl Into<String>,
        value: impl fmt::Display,
        rule: impl Into<String>,
    ) -> SceneError {
        SceneError {
            file: self.file.to_string(),
            key: key.into(),
            value: value.to_string(),
            rule: rule.into(),
            line: None,
        }
    }

    /// Maps a core error to the key `prefix.<parameter>`.
    pub fn core(&self, prefix: &str, e: crate::Error) -> SceneError {
        match e {
            crate::Error::InvalidParameter { name, value, rule } => {
                self.err(format!("{prefix}.{name}"), value, rule)
            }
            crate::Error::ActivationOutOfRange { gamma } => {
                self.err(prefix, gamma, "activation gamma must lie in [0, 1)")
            }
            other => self.err(prefix, "", other.to_string()),
        }
    }
}

use std::fmt;

pub(super) fn fmt_list(v: &[f64]) -> String {
    let items: Vec<String> = v.iter().map(|x| x.to_string()).collect();
    format!("[{}]", items.join(", "))
}

/// The energy `spec` describes, the chapter's values where it leaves a parameter out; errors
/// name `key.<parameter>`.
pub(super) fn energy(ctx: &Ctx, key: &str, spec: &EnergySpec) -> Result<Energy, SceneError> {
    let EnergySpec {
        energy: kind,
        mu,
        alpha,
        beta,
        w0,
    } = *spec;
    let not_for = |name: &str, v: Option<f64>| -> Result<(), SceneError> {
        match v {
            Some(x) => Err(ctx.err(
                format!("{key}.{name}"),
                x,
                format!("the {} energy has no parameter {name}", kind_name(kind)),
            )),
            None => Ok(()),
        }
    };
    let e = match kind {
        EnergyKind::GiantesioMusesti => {
            not_for("beta", beta)?;
            let p = GiantesioMusesti::paper();
            GiantesioMusesti::new(
                mu.unwrap_or(p.mu()),
                alpha.unwrap_or(p.alpha()),
                w0.unwrap_or(p.w0()),
            )
            .map(Energy::GiantesioMusesti)
        }
        EnergyKind::EhretBolItskov => {
            let p = EhretBolItskov::paper();
            EhretBolItskov::new(
                mu.unwrap_or(p.mu()),
                alpha.unwrap_or(p.alpha()),
                beta.unwrap_or(p.beta()),
                w0.unwrap_or(p.w0()),
            )
            .map(Energy::EhretBolItskov)
        }
        EnergyKind::NeoHookean => {
            not_for("alpha", alpha)?;
            not_for("beta", beta)?;
            not_for("w0", w0)?;
            let Some(mu) = mu else {
                return Err(ctx.err(
                    format!("{key}.mu"),
                    "(missing)",
                    "the neo-hookean energy has no chapter value: give mu [kPa]",
                ));
            };
            NeoHookean::new(mu).map(Energy::NeoHookean)
        }
    };
    e.map_err(|e| ctx.core(key, e))
}

pub(super) fn kind_name(kind: EnergyKind) -> &'static str {
    match kind {
        EnergyKind::GiantesioMusesti => "giantesio-musesti",
        EnergyKind::EhretBolItskov => "ehret-bol-itskov",
        EnergyKind::NeoHookean => "neo-hookean",
    }
}

/// The spec of a built energy: its kind and every parameter it holds, given or default (what
/// the printed scene shows, so that it is the energy that runs).
pub(super) fn written(e: &Energy) -> EnergySpec {
    let mut spec = EnergySpec {
        energy: match e {
            Energy::GiantesioMusesti(_) => EnergyKind::GiantesioMusesti,
            Energy::EhretBolItskov(_) => EnergyKind::EhretBolItskov,
            Energy::NeoHookean(_) => EnergyKind::NeoHookean,
        },
        ..EnergySpec::default()
    };
    for (name, value) in e.parameter_names().iter().zip(e.parameter_values()) {
        let slot = match *name {
            "mu" => &mut spec.mu,
            "alpha" => &mut spec.alpha,
            "beta" => &mut spec.beta,
            _ => &mut spec.w0,
        };
        *slot = Some(value);
    }
    spec
}

/// Stretch lists: finite, > 0, ascending without duplicates, reasonably short.
pub(super) fn stretches(ctx: &Ctx, key: &str, spec: &StretchSpec) -> Result<Vec<f64>, SceneError> {
    const MAX: usize = 100_000;
    let mut v = match spec {
        StretchSpec::List(v) => v.clone(),
        StretchSpec::Range {
            from,
            to,
            step,
            extra,
        } => {
            if !(step.is_finite() && *step > 0.0) {
                return Err(ctx.err(format!("{key}.step"), step, "must be finite and > 0"));
            }
            if !(from.is_finite() && to.is_finite() && to >= from) {
                return Err(ctx.err(
                    format!("{key}.to"),
                    to,
                    format!("must be finite and ≥ from = {from}"),
                ));
            }
            let n = ((to - from) / step).round();
            if ((from + n * step) - to).abs() > 1e-9 * step.max(1.0) {
                return Err(ctx.err(
                    format!("{key}.step"),
                    step,
                    format!("from = {from} must reach to = {to} in whole steps"),
                ));
            }
            if n >= MAX as f64 {
                return Err(ctx.err(
                    format!("{key}.step"),
                    step,
                    format!("gives more than {MAX} stretches"),
                ));
            }
            // Rounded to 10 decimals so that 0.65 + 0.01 i prints as the decimal it means.
            let mut v: Vec<f64> = (0..=n as usize)
                .map(|i| ((from + i as f64 * step) * 1e10).round() / 1e10)
                .collect();
            v.extend_from_slice(extra);
            v
        }
    };
    non_empty(
        ctx,
        key,
        &v,
        "the stretch list is empty: give at least one stretch",
    )?;
    if let Some(bad) = v.iter().find(|x| !(x.is_finite() && **x > 0.0)) {
        return Err(ctx.err(key, bad, "every stretch must be finite and > 0"));
    }
    v.sort_by(f64::total_cmp);
    v.dedup();
    Ok(v)
}

pub(super) fn damages(ctx: &Ctx, key: &str, v: &[f64]) -> Result<Vec<f64>, SceneError> {
    non_empty(
        ctx,
        key,
        v,
        "the damage list is empty: give at least one d ∈ [0, 1]",
    )?;
    for (i, d) in v.iter().enumerate() {
        if !(0.0..=1.0).contains(d) {
            return Err(ctx.err(format!("{key}[{i}]"), d, "damage d must lie in [0, 1]"));
        }
    }
    Ok(v.to_vec())
}

/// Every law × coupling × damage, in that order of nesting.
pub(super) fn models(
    laws: &[LawKind],
    couplings: &[CouplingKind],
    damages: &[f64],
) -> Vec<ModelChoice> {
    let mut models = Vec::with_capacity(laws.len() * couplings.len() * damages.len());
    for &law in laws {
        for &coupling in couplings {
            for &damage in damages {
                models.push(ModelChoice {
                    law,
                    coupling,
                    damage,
                });
            }
        }
    }
    models
}

/// A list that must not be empty; `rule` says what to give.
pub(super) fn non_empty<T>(ctx: &Ctx, key: &str, v: &[T], rule: &str) -> Result<(), SceneError> {
    if v.is_empty() {
        Err(ctx.err(key, "[]", rule))
    } else {
        Ok(())
    }
}

/// A length or tolerance: finite and > 0.
pub(super) fn positive(ctx: &Ctx, key: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() && v > 0.0 {
        Ok(v)
    } else {
        Err(ctx.err(key, v, "must be finite and > 0"))
    }
}

/// A number of cells along one direction: an integer in [1, 10000].
pub(super) fn cell_count(ctx: &Ctx, key: &str, v: i64) -> Result<usize, SceneError> {
    if (1..=10_000).contains(&v) {
        Ok(v as usize)
    } else {
        Err(ctx.err(
            key,
            v,
            "the number of cells must be an integer in [1, 10000]",
        ))
    }
}

/// The middle/base cell-height ratio of a cylinder mesh: finite and ≥ 1.
pub(super) fn grading(ctx: &Ctx, key: &str, v: f64) -> Result<f64, SceneError> {
    if v.is_finite() && v >= 1.0 {
        Ok(v)
    } else {
        Err(ctx.err(key, v, "must be finite and ≥ 1 (1 = uniform)"))
    }
}

/// Every key of a study besides `kind`, `name`, `stretch` and `damage`, and whether it is given.
fn given_keys(s: &StudySpec) -> Vec<(&'static str, bool)> {
    vec![
        ("direction", s.direction.is_some()),
        ("passive", s.passive.is_some()),
        ("compare", s.compare.is_some()),
        ("laws", s.laws.is_some()),
        ("couplings", s.couplings.is_some()),
        ("constant_gamma", s.constant_gamma.is_some()),
        ("radius", s.radius.is_some()),
        ("length", s.length.is_some()),
        ("nr", s.nr.is_some()),
        ("nz", s.nz.is_some()),
        ("grading", s.grading.is_some()),
        ("bases", s.bases.is_some()),
        ("law", s.law.is_some()),
        ("coupling", s.coupling.is_some()),
        ("vtk", s.vtk.is_some()),
        ("tolerance", s.tolerance.is_some()),
        ("fit", s.fit.is_some()),
        ("data", s.data.is_some()),
        ("reference", s.reference.is_some()),
        ("stress", s.stress.is_some()),
        ("true_damage", s.true_damage.is_some()),
        ("noise", s.noise.is_some()),
        ("seed", s.seed.is_some()),
        ("residual", s.residual.is_some()),
        ("free", s.free.is_some()),
        ("start", s.start.is_some()),
        ("bounds", s.bounds.is_some()),
        ("method", s.method.is_some()),
        ("max_iterations", s.max_iterations.is_some()),
        ("normals", s.normals.is_some()),
        ("options", s.options.is_some()),
        ("meshes", s.meshes.is_some()),
        ("tolerances", s.tolerances.is_some()),
    ]
}

/// Rejects every given key of study `key` that is not in `allowed` for a study of `kind`.
pub(super) fn only_keys(
    ctx: &Ctx,
    key: &str,
    s: &StudySpec,
    kind: &str,
    allowed: &[&str],
) -> Result<(), SceneError> {
    for (name, present) in given_keys(s) {
        if present && !allowed.contains(&name) {
            let hint = match (kind, name) {
                ("uniaxial" | "stability", "law") => " (it takes a list: laws = [...])",
                ("uniaxial" | "stability", "coupling") => " (it takes a list: couplings = [...])",
                ("cylinder", "laws") => " (a cylinder study takes one law: law = \"...\")",
                ("cylinder", "couplings") => {
                    " (a cylinder study takes one coupling: coupling = \"...\")"
                }
                _ => "",
            };
            return Err(ctx.err(
                format!("{key}.{name}"),
                "(given)",
                format!("not a key of a {kind} study{hint}"),
            ));
        }
    }
    Ok(())
}

pub(super) fn resolve(raw: SceneFile, text: &str, file: &str) -> Result<Scene, SceneError> {
    let ctx = Ctx { file };
    let MaterialSpec {
        energy: kind,
        mu,
        alpha,
        beta,
        w0,
        fibre,
    } = raw.material.clone();
    let material = energy(
        &ctx,
        "material",
        &EnergySpec {
            energy: kind,
            mu,
            alpha,
            beta,
            w0,
        },
    )?;
    let fibre = fibre.unwrap_or([1.0, 0.0, 0.0]);
    let norm = fibre.iter().map(|x| x * x).sum::<f64>().sqrt();
    if !(norm.is_finite() && norm > 1e-12) {
        return Err(ctx.err(
            "material.fibre",
            fmt_list(&fibre),
            "the fibre direction must be a finite, non-zero vector",
        ));
    }
    let fibre = fibre.map(|x| x / norm);

    let act = raw.activation.clone();
    let p = ActiveCurve::paper();
    let curve = ActiveCurve::new(
        act.lambda_min.unwrap_or(p.lambda_min()),
        act.lambda_opt.unwrap_or(p.lambda_opt()),
        act.k.unwrap_or(p.k()),
        act.p_opt.unwrap_or(p.p_opt()),
    )
    .map_err(|e| ctx.core("activation", e))?;
    let ex = act.explicit.clone().unwrap_or_default();
    let explicit = (ex.a.unwrap_or(1.0133), ex.b.unwrap_or(0.2050));
    ExplicitLaw::new(explicit.0, explicit.1, GiantesioMusesti::paper(), curve)
        .map_err(|e| ctx.core("activation.explicit", e))?;
    let default_law = act.law.unwrap_or_default();
    let default_coupling = act.coupling.unwrap_or_default();
    let frozen_tangent = act.frozen_tangent.unwrap_or_default();
    let below_minimum_kind = act.below_minimum.unwrap_or_default();
    let below_minimum = match below_minimum_kind {
        BelowMinimumKind::ZeroWork => BelowMinimum::ZeroWork,
        BelowMinimumKind::Inactive => BelowMinimum::Inactive,
    };
    let default_damage = damages(
        &ctx,
        "activation.damage",
        act.damage.as_deref().unwrap_or(&[0.0]),
    )?;
    let explicit_ok = |key: String, law: LawKind| -> Result<(), SceneError> {
        if law == LawKind::Explicit && kind != EnergyKind::GiantesioMusesti {
            Err(ctx.err(
                key,
                "\"explicit\"",
                format!(
                    "eq. D:gamma is derived for the giantesio-musesti energy; material.energy is {}",
                    kind_name(kind)
                ),
            ))
        } else {
            Ok(())
        }
    };

    if raw.studies.is_empty() {
        return Err(ctx.err(
            "study",
            "(none)",
            "a scene needs at least one [[study]] (kind = \"uniaxial\", \"cylinder\", \"fit\", \"stability\" or \"tradeoff\")",
        ));
    }
    let mut studies = Vec::new();
    let mut resolved_studies = Vec::new();
    // Trade-off studies take what they leave out from the first cylinder study, wherever it is.
    let mut pending = Vec::new();
    for (i, s) in raw.studies.iter().enumerate() {
        let key = format!("study[{i}]");
        let k = |name: &str| format!("{key}.{name}");
        let lambdas = match &s.stretch {
            Some(spec) => Some(stretches(&ctx, &k("stretch"), spec)?),
            None => None,
        };
        let required = |l: Option<Vec<f64>>| -> Result<Vec<f64>, SceneError> {
            l.ok_or_else(|| ctx.err(k("stretch"), "(missing)", "every study needs its stretches"))
        };
        let damage = match &s.damage {
            Some(d) => damages(&ctx, &k("damage"), d)?,
            None => default_damage.clone(),
        };
        let mut r = s.clone();
        r.damage = Some(damage.clone());
        match s.kind {
            StudyKind::Fit => {
                let (study, resolved) = resolve_fit(&ctx, &key, s, &material, curve, lambdas)?;
                studies.push(Study::Fit(study));
                resolved_studies.push(resolved);
                continue;
            }
            StudyKind::Stability => {
                let (study, resolved) = resolve_stability(&ctx, &key, s, kind, lambdas)?;
                studies.push(Study::Stability(study));
                resolved_studies.push(resolved);
                continue;
            }
            StudyKind::Tradeoff => {
                if let Some(first) = studies.iter().position(|s| matches!(s, Study::Tradeoff(_))) {
                    return Err(ctx.err(
                        k("kind"),
                        "\"tradeoff\"",
                        format!(
                            "a scene holds at most one tradeoff study (study[{first}] is one): \
                             its outputs are tradeoff.csv, tradeoff.md and the tradeoff figures"
                        ),
                    ));
                }
                let (study, resolved, rest) = resolve_tradeoff(&ctx, &key, s, lambdas)?;
                pending.push((studies.len(), rest));
                studies.push(Study::Tradeoff(study));
                resolved_studies.push(resolved);
                continue;
            }
            StudyKind::Uniaxial => {
                let lambdas = required(lambdas)?;
                only_keys(
                    &ctx,
                    &key,
                    s,
                    "uniaxial",
                    &[
                        "direction",
                        "passive",
                        "compare",
                        "laws",
                        "couplings",
                        "constant_gamma",
                    ],
                )?;
                let direction = s.direction.unwrap_or(DirectionKind::Along);
                let laws = s.laws.clone().unwrap_or_else(|| vec![default_law]);
                for (j, l) in laws.iter().enumerate() {
                    explicit_ok(format!("{key}.laws[{j}]"), *l)?;
                }
                let couplings = s
                    .couplings
                    .clone()
                    .unwrap_or_else(|| vec![default_coupling]);
                if !laws.is_empty() && couplings.is_empty() {
                    return Err(ctx.err(
                        k("couplings"),
                        "[]",
                        "active laws need at least one coupling",
                    ));
                }
                let mut compare = Vec::new();
                for (j, c) in s.compare.iter().flatten().enumerate() {
                    compare.push(energy(&ctx, &format!("{key}.compare[{j}]"), c)?);
                }
                let constant_gamma = s.constant_gamma.clone().unwrap_or_default();
                for (j, g) in constant_gamma.iter().enumerate() {
                    ConstantLaw::new(*g).map_err(|_| {
                        ctx.err(
                            format!("{key}.constant_gamma[{j}]"),
                            g,
                            "activation gamma must lie in [0, 1) (γ = 1 is infinite contraction)",
                        )
                    })?;
                }
                let models = models(&laws, &couplings, &damage);
                let passive = s.passive.unwrap_or(true);
                if !passive && compare.is_empty() && models.is_empty() && constant_gamma.is_empty()
                {
                    return Err(ctx.err(
                        &key,
                        "(nothing to compute)",
                        "a uniaxial study needs passive = true, compare, laws or constant_gamma",
                    ));
                }
                r.direction = Some(direction);
                r.passive = Some(passive);
                r.laws = Some(laws);
                r.couplings = Some(couplings);
                r.constant_gamma = Some(constant_gamma.clone());
                r.compare = Some(compare.iter().map(written).collect());
                let name = s.name.clone().unwrap_or_else(|| match direction {
                    DirectionKind::Along => "uniaxial along fibres".into(),
                    DirectionKind::Across => "uniaxial across fibres".into(),
                });
                r.name = Some(name.clone());
                studies.push(Study::Uniaxial(UniaxialStudy {
                    name,
                    direction,
                    stretches: lambdas,
                    passive,
                    compare,
                    models,
                    constant_gamma,
                }));
            }
            StudyKind::Cylinder => {
                let lambdas = required(lambdas)?;
                only_keys(
                    &ctx,
                    &key,
                    s,
                    "cylinder",
                    &[
                        "radius",
                        "length",
                        "nr",
                        "nz",
                        "grading",
                        "bases",
                        "element",
                        "law",
                        "coupling",
                        "vtk",
                        "tolerance",
                    ],
                )?;
                let radius = positive(&ctx, &k("radius"), s.radius.unwrap_or(1.0))?;
                let length = positive(&ctx, &k("length"), s.length.unwrap_or(4.0))?;
                let nr = cell_count(&ctx, &k("nr"), s.nr.unwrap_or(6))?;
                let nz = cell_count(&ctx, &k("nz"), s.nz.unwrap_or(24))?;
                let grading = grading(&ctx, &k("grading"), s.grading.unwrap_or(1.0))?;
                let tolerance = positive(&ctx, &k("tolerance"), s.tolerance.unwrap_or(1e-10))?;
                let law = s.law.unwrap_or(default_law);
                explicit_ok(k("law"), law)?;
                let coupling = s.coupling.unwrap_or(default_coupling);
                let vtk = s.vtk.clone().unwrap_or_default();
                for (j, v) in vtk.iter().enumerate() {
                    if !lambdas.iter().any(|l| (l - v).abs() < 1e-12) {
                        return Err(ctx.err(
                            format!("{key}.vtk[{j}]"),
                            v,
                            "VTK output is written only at computed stretches: add it to stretch",
                        ));
                    }
                }
                let bases = s.bases.unwrap_or(BasesKind::Clamped);
                let element = s.element.unwrap_or(ElementKind::Q2Q1);
                let name = s.name.clone().unwrap_or_else(|| {
                    format!(
                        "cylinder {} {} {}",
                        match bases {
                            BasesKind::Clamped => "clamped",
                            BasesKind::Sliding => "sliding",
                        },
                        law_name(law),
                        coupling_name(coupling)
                    )
                });
                r.name = Some(name.clone());
                r.radius = Some(radius);
                r.length = Some(length);
                r.nr = Some(nr as i64);
                r.nz = Some(nz as i64);
                r.grading = Some(grading);
                r.bases = Some(bases);
                r.element = Some(element);
                r.law = Some(law);
                r.coupling = Some(coupling);
                r.vtk = Some(vtk.clone());
                r.tolerance = Some(tolerance);
                studies.push(Study::Cylinder(CylinderStudy {
                    name,
                    radius,
                    length,
                    nr,
                    nz,
                    grading,
                    bases,
                    element,
                    stretches: lambdas,
                    law,
                    coupling,
                    damages: damage,
                    vtk,
                    tolerance,
                }));
            }
        }
        resolved_studies.push(r);
    }

    let cylinder = scene_cylinder(&studies);
    for (i, rest) in pending {
        if let Study::Tradeoff(t) = &mut studies[i] {
            rest.complete(t, &mut resolved_studies[i], cylinder);
        }
    }

    let material_spec = written(&material);
    let resolved = SceneFile {
        title: raw.title.clone(),
        material: MaterialSpec {
            energy: material_spec.energy,
            mu: material_spec.mu,
            alpha: material_spec.alpha,
            beta: material_spec.beta,
            w0: material_spec.w0,
            fibre: Some(fibre),
        },
        activation: ActivationSpec {
            lambda_min: Some(curve.lambda_min()),
            lambda_opt: Some(curve.lambda_opt()),
            k: Some(curve.k()),
            p_opt: Some(curve.p_opt()),
            law: Some(default_law),
            coupling: Some(default_coupling),
            frozen_tangent: Some(frozen_tangent),
            below_minimum: Some(below_minimum_kind),
            damage: Some(default_damage),
            explicit: Some(ExplicitSpec {
                a: Some(explicit.0),
                b: Some(explicit.1),
            }),
        },
        studies: resolved_studies,
    };
    Ok(Scene {
        file: file.to_string(),
        source: text.to_string(),
        title: raw.title.unwrap_or_else(|| "activemuscle scene".into()),
        material,
        fibre,
        curve,
        explicit,
        frozen_tangent,
        below_minimum,
        studies,
        resolved,
    })
}

/// Name of a law in logs and files.
pub fn law_name(l: LawKind) -> &'static str {
    match l {
        LawKind::Implicit => "implicit",
        LawKind::Explicit => "explicit",
        LawKind::Energy => "energy",
    }
}

/// Name of a coupling in logs and files.
pub fn coupling_name(c: CouplingKind) -> &'static str {
    match c {
        CouplingKind::Frozen => "frozen",
        CouplingKind::Consistent => "consistent",
    }
}
