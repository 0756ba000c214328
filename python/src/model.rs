//! Keyword choices → a core [`Muscle`]: the one place where the Python names meet the core's
//! constructors. The names, defaults and rules are those of a scene's `[material]` and
//! `[activation]` tables (scenes/paper.toml): the chapter's values wherever a parameter is left
//! out, every number validated by the core constructor that owns it (whose message is kept).

use activemuscle::active::{
    ActiveCurve, BelowMinimum, ConstantLaw, Coupling, EnergyLaw, ExplicitLaw, FrozenTangent,
    ImplicitLaw, Law,
};
use activemuscle::energy::{EhretBolItskov, Energy, GiantesioMusesti, NeoHookean};
use activemuscle::Muscle;

/// A material as chosen by keywords; `None` means "the chapter's value" (a scene's default).
#[derive(Debug, Clone, Default)]
pub struct ModelSpec {
    /// "giantesio-musesti" | "ehret-bol-itskov" | "neo-hookean".
    pub energy: String,
    /// μ \[kPa\] (required for neo-hookean).
    pub mu: Option<f64>,
    /// α [-] (giantesio-musesti, ehret-bol-itskov).
    pub alpha: Option<f64>,
    /// β [-] (ehret-bol-itskov).
    pub beta: Option<f64>,
    /// w0 [-] (giantesio-musesti, ehret-bol-itskov).
    pub w0: Option<f64>,
    /// "passive" | "constant" | "implicit" | "explicit" | "energy".
    pub law: String,
    /// γ of the constant law.
    pub gamma: Option<f64>,
    /// "frozen" | "consistent".
    pub coupling: String,
    /// "exact" | "symmetric" (frozen coupling only).
    pub frozen_tangent: String,
    /// "zero-work" | "inactive" (energy law only).
    pub below_minimum: String,
    /// Damage d ∈ [0, 1].
    pub damage: f64,
    /// Explicit-law coefficients a, b (eq. D:gamma).
    pub explicit_a: Option<f64>,
    /// See `explicit_a`.
    pub explicit_b: Option<f64>,
    /// Active curve λ_min, λ_opt, k, P_opt (eq. D:pact).
    pub lambda_min: Option<f64>,
    /// See `lambda_min`.
    pub lambda_opt: Option<f64>,
    /// See `lambda_min`.
    pub k: Option<f64>,
    /// See `lambda_min`.
    pub p_opt: Option<f64>,
}

/// Why a choice was refused.
#[derive(Debug, Clone, PartialEq)]
pub enum ModelError {
    /// A keyword has a value outside its choices, or does not apply to the others.
    Choice {
        /// The keyword.
        key: &'static str,
        /// Its value, as given.
        value: String,
        /// The rule it breaks.
        rule: String,
    },
    /// A core constructor refused a number (its own message).
    Core(activemuscle::Error),
}

impl std::fmt::Display for ModelError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ModelError::Choice { key, value, rule } => write!(f, "{key} = {value}: {rule}"),
            ModelError::Core(e) => write!(f, "{e}"),
        }
    }
}

impl From<activemuscle::Error> for ModelError {
    fn from(e: activemuscle::Error) -> Self {
        ModelError::Core(e)
    }
}

fn choice(key: &'static str, value: &str, rule: impl Into<String>) -> ModelError {
    ModelError::Choice {
        key,
        value: format!("{value:?}"),
        rule: rule.into(),
    }
}

fn refuse_given(key: &'static str, v: Option<f64>, rule: String) -> Result<(), ModelError> {
    match v {
        Some(x) => Err(ModelError::Choice {
            key,
            value: x.to_string(),
            rule,
        }),
        None => Ok(()),
    }
}

/// The muscle `spec` chooses, with the scene's defaults and rules.
pub fn muscle(spec: &ModelSpec) -> Result<Muscle<Energy>, ModelError> {
    let not_for = |key: &'static str, v: Option<f64>| {
        refuse_given(
            key,
            v,
            format!("the {} energy has no parameter {key}", spec.energy),
        )
    };
    let energy = match spec.energy.as_str() {
        "giantesio-musesti" => {
            not_for("beta", spec.beta)?;
            let p = GiantesioMusesti::paper();
            Energy::GiantesioMusesti(GiantesioMusesti::new(
                spec.mu.unwrap_or(p.mu()),
                spec.alpha.unwrap_or(p.alpha()),
                spec.w0.unwrap_or(p.w0()),
            )?)
        }
        "ehret-bol-itskov" => {
            let p = EhretBolItskov::paper();
            Energy::EhretBolItskov(EhretBolItskov::new(
                spec.mu.unwrap_or(p.mu()),
                spec.alpha.unwrap_or(p.alpha()),
                spec.beta.unwrap_or(p.beta()),
                spec.w0.unwrap_or(p.w0()),
            )?)
        }
        "neo-hookean" => {
            not_for("alpha", spec.alpha)?;
            not_for("beta", spec.beta)?;
            not_for("w0", spec.w0)?;
            let mu = spec.mu.ok_or_else(|| ModelError::Choice {
                key: "mu",
                value: "(missing)".into(),
                rule: "the neo-hookean energy has no chapter value: give mu [kPa]".into(),
            })?;
            Energy::NeoHookean(NeoHookean::new(mu)?)
        }
        other => {
            return Err(choice(
                "energy",
                other,
                "must be \"giantesio-musesti\", \"ehret-bol-itskov\" or \"neo-hookean\"",
            ))
        }
    };
    let p = ActiveCurve::paper();
    let curve = ActiveCurve::new(
        spec.lambda_min.unwrap_or(p.lambda_min()),
        spec.lambda_opt.unwrap_or(p.lambda_opt()),
        spec.k.unwrap_or(p.k()),
        spec.p_opt.unwrap_or(p.p_opt()),
    )?;
    let below_minimum = match spec.below_minimum.as_str() {
        "zero-work" => BelowMinimum::ZeroWork,
        "inactive" => BelowMinimum::Inactive,
        other => {
            return Err(choice(
                "below_minimum",
                other,
                "must be \"zero-work\" or \"inactive\"",
            ))
        }
    };
    let only_for = |key: &'static str, v: Option<f64>, law: &str| {
        refuse_given(key, v, format!("applies to law = \"{law}\" only"))
    };
    if spec.law != "constant" {
        only_for("gamma", spec.gamma, "constant")?;
    }
    if spec.law != "explicit" {
        only_for("explicit.a", spec.explicit_a, "explicit")?;
        only_for("explicit.b", spec.explicit_b, "explicit")?;
    }
    let law = match spec.law.as_str() {
        "passive" => Law::Passive,
        "constant" => {
            let gamma = spec.gamma.ok_or_else(|| ModelError::Choice {
                key: "gamma",
                value: "(missing)".into(),
                rule: "law = \"constant\" needs gamma in [0, 1)".into(),
            })?;
            Law::Constant(ConstantLaw::new(gamma)?)
        }
        "implicit" => Law::Implicit(ImplicitLaw::new(energy.clone(), curve)),
        "energy" => Law::Energy(EnergyLaw::new(energy.clone(), curve).below_minimum(below_minimum)),
        "explicit" => {
            let Energy::GiantesioMusesti(gm) = energy else {
                return Err(choice(
                    "law",
                    "explicit",
                    format!(
                        "eq. D:gamma is derived for the giantesio-musesti energy; energy is {:?}",
                        spec.energy
                    ),
                ));
            };
            let (a, b) = ExplicitLaw::paper().coefficients();
            Law::Explicit(ExplicitLaw::new(
                spec.explicit_a.unwrap_or(a),
                spec.explicit_b.unwrap_or(b),
                gm,
                curve,
            )?)
        }
        other => {
            return Err(choice(
                "law",
                other,
                "must be \"passive\", \"constant\", \"implicit\", \"explicit\" or \"energy\"",
            ))
        }
    };
    let coupling = match (spec.coupling.as_str(), spec.frozen_tangent.as_str()) {
        ("consistent", _) => Coupling::Consistent,
        ("frozen", "exact") => Coupling::Frozen(FrozenTangent::Exact),
        ("frozen", "symmetric") => Coupling::Frozen(FrozenTangent::Symmetric),
        ("frozen", other) => {
            return Err(choice(
                "frozen_tangent",
                other,
                "must be \"exact\" or \"symmetric\"",
            ))
        }
        (other, _) => {
            return Err(choice(
                "coupling",
                other,
                "must be \"frozen\" or \"consistent\"",
            ))
        }
    };
    Ok(Muscle::new(energy, law, spec.damage, coupling)?)
}
