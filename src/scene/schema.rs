//! The scene file as written: serde structures mirroring the TOML, every key optional except
//! where a study cannot do without it. Defaults and rules live in `scene::resolve`.

use crate::tradeoff::study::OptionGroup;
use serde::de::{self, MapAccess, SeqAccess, Visitor};
use serde::{Deserialize, Deserializer, Serialize};
use std::collections::BTreeMap;
use std::fmt;

/// The whole file.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct SceneFile {
    /// Free text shown in the report.
    pub title: Option<String>,
    /// The passive material and the fibre direction.
    #[serde(default)]
    pub material: MaterialSpec,
    /// Active curve, activation law, coupling and damage values shared by the studies.
    #[serde(default)]
    pub activation: ActivationSpec,
    /// The studies, in order (`[[study]]`).
    #[serde(default, rename = "study")]
    pub studies: Vec<StudySpec>,
}

/// Energy kinds (`energy = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum EnergyKind {
    /// The chapter's energy, eq. D:Wpassiva.
    #[default]
    GiantesioMusesti,
    /// Ehret–Böl–Itskov, eq. D:Webi.
    EhretBolItskov,
    /// Incompressible neo-Hookean reference.
    NeoHookean,
}

/// `[material]`: an energy, its parameters (chapter values by default) and the fibre direction.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// Energy kind.
    #[serde(default)]
    pub energy: EnergyKind,
    /// μ \[kPa\].
    pub mu: Option<f64>,
    /// α [-] (giantesio-musesti, ehret-bol-itskov).
    pub alpha: Option<f64>,
    /// β [-] (ehret-bol-itskov).
    pub beta: Option<f64>,
    /// w0 [-] (giantesio-musesti, ehret-bol-itskov).
    pub w0: Option<f64>,
    /// Fibre direction m in the reference configuration (normalised).
    pub fibre: Option<[f64; 3]>,
}

/// An extra passive energy to compare with (`compare = [{ energy = "ehret-bol-itskov" }]`).
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct EnergySpec {
    /// Energy kind.
    #[serde(default)]
    pub energy: EnergyKind,
    /// μ \[kPa\].
    pub mu: Option<f64>,
    /// α [-].
    pub alpha: Option<f64>,
    /// β [-].
    pub beta: Option<f64>,
    /// w0 [-].
    pub w0: Option<f64>,
}

/// Activation laws (`law = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum LawKind {
    /// eq. D:eqgammaesplicita solved numerically.
    #[default]
    Implicit,
    /// eq. D:gamma (closed form, a and b).
    Explicit,
    /// The energy-consistent fit.
    Energy,
}

/// Couplings (`coupling = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum CouplingKind {
    /// The chapter's model: γ held in the stress.
    #[default]
    Frozen,
    /// Truly hyperelastic: Ψ(F) = Ŵ(F, g(λ_f(F))).
    Consistent,
}

/// Linearisation of the frozen model (`frozen_tangent = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum TangentKind {
    /// Exact, non-symmetric.
    #[default]
    Exact,
    /// Symmetric, inexact.
    Symmetric,
}

/// What the energy law does below λ_min (`below_minimum = "..."`), see
/// [`crate::active::BelowMinimum`].
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BelowMinimumKind {
    /// γ continues on the zero-work root branch: γ and Ψ continuous across λ_min.
    #[default]
    ZeroWork,
    /// γ = 0 below λ_min (the chapter's literal reading): γ jumps at λ_min.
    Inactive,
}

/// `[activation]`.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ActivationSpec {
    /// λ_min [-] (Table D:paratt).
    pub lambda_min: Option<f64>,
    /// λ_opt [-].
    pub lambda_opt: Option<f64>,
    /// k [-].
    pub k: Option<f64>,
    /// P_opt \[kPa\].
    pub p_opt: Option<f64>,
    /// Default law of the studies.
    pub law: Option<LawKind>,
    /// Default coupling of the studies.
    pub coupling: Option<CouplingKind>,
    /// Tangent of the frozen model.
    pub frozen_tangent: Option<TangentKind>,
    /// What the energy law does below λ_min.
    pub below_minimum: Option<BelowMinimumKind>,
    /// Default damage values d ∈ [0, 1].
    pub damage: Option<Vec<f64>>,
    /// Coefficients of the explicit law (eq. D:gamma).
    pub explicit: Option<ExplicitSpec>,
}

/// `explicit = { a = 1.0133, b = 0.2050 }`.
#[derive(Debug, Clone, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ExplicitSpec {
    /// a [-].
    pub a: Option<f64>,
    /// b [-].
    pub b: Option<f64>,
}

/// Study kinds (`kind = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StudyKind {
    /// Homogeneous uniaxial tension (0D).
    Uniaxial,
    /// The axisymmetric FE cylinder.
    Cylinder,
    /// A least-squares fit of model parameters (issue 5).
    Fit,
    /// Material stability along the uniaxial path along the fibres (issue 7).
    Stability,
    /// Speed versus accuracy of every option that trades one for the other (issue 6).
    Tradeoff,
}

/// What a fit study fits (`fit = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum FitKind {
    /// Passive parameters of the material's energy to (λ, P) data (eq. D:Ppas).
    Passive,
    /// (λ_min, λ_opt, k, P_opt) of the active curve (eq. D:pact).
    ActiveCurve,
    /// (a, b) of the explicit law (eq. D:gamma) against the implicit law.
    ExplicitLaw,
    /// The damage d of a weakened total curve.
    Damage,
}

/// What the stresses of active-curve data are (`stress = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StressKind {
    /// Active stress P_act.
    Active,
    /// Total stress of a tetanised muscle; the model's passive stress is subtracted.
    Total,
}

/// Residual of the explicit-law fit (`residual = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum ResidualKind {
    /// Total stress it produces against P_pas + (1 − d) P_act \[kPa\] (the chapter's choice).
    Stress,
    /// Activation γ against the implicit γ [-].
    Activation,
}

/// Search strategy of a fit (`method = "..."`).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum MethodKind {
    /// Gauss–Newton with line search.
    GaussNewton,
    /// Nelder–Mead, then Gauss–Newton (for poor starting values).
    NelderMead,
}

/// Uniaxial loading direction relative to the fibres.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum DirectionKind {
    /// Along the fibres.
    Along,
    /// Across the fibres.
    Across,
}

/// Base conditions of the cylinder.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum BasesKind {
    /// u_r free on the bases (homogeneous solution).
    Sliding,
    /// u_r = 0 on the bases.
    Clamped,
}

/// Finite element of a cylinder study.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize, Serialize)]
pub enum ElementKind {
    /// Taylor–Hood: biquadratic displacement, continuous bilinear pressure (default).
    #[serde(rename = "Q2/Q1")]
    Q2Q1,
    /// Bilinear displacement, one pressure per cell (cheaper, less accurate).
    #[serde(rename = "Q1/P0")]
    Q1P0,
}

/// One `[[study]]`. Keys that do not belong to the study's kind are rejected by validation.
#[derive(Debug, Clone, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct StudySpec {
    /// `uniaxial`, `cylinder`, `fit`, `stability` or `tradeoff`.
    pub kind: StudyKind,
    /// Label in logs and the report.
    pub name: Option<String>,
    /// Stretches λ: a list or `{ from, to, step, extra = [...] }`.
    pub stretch: Option<StretchSpec>,
    /// Damage values (default: `activation.damage`).
    pub damage: Option<Vec<f64>>,
    // --- uniaxial ---
    /// `along` or `across` (uniaxial).
    pub direction: Option<DirectionKind>,
    /// Include the passive curve of the material (uniaxial; default true).
    pub passive: Option<bool>,
    /// Extra passive energies (uniaxial).
    pub compare: Option<Vec<EnergySpec>>,
    /// Activation laws (uniaxial; default `[activation.law]`; `[]` for none).
    pub laws: Option<Vec<LawKind>>,
    /// Couplings (uniaxial; default `[activation.coupling]`).
    pub couplings: Option<Vec<CouplingKind>>,
    /// Constant activations γ ∈ [0, 1) (uniaxial).
    pub constant_gamma: Option<Vec<f64>>,
    // --- cylinder ---
    /// Radius R (cylinder).
    pub radius: Option<f64>,
    /// Length L (cylinder).
    pub length: Option<f64>,
    /// Cells in r (cylinder).
    pub nr: Option<i64>,
    /// Cells in z (cylinder).
    pub nz: Option<i64>,
    /// Middle/base cell-height ratio ≥ 1 (cylinder).
    pub grading: Option<f64>,
    /// `clamped` or `sliding` (cylinder).
    pub bases: Option<BasesKind>,
    /// `"Q2/Q1"` (default) or `"Q1/P0"` (cylinder).
    pub element: Option<ElementKind>,
    /// Activation law (cylinder; default `activation.law`).
    pub law: Option<LawKind>,
    /// Coupling (cylinder; default `activation.coupling`).
    pub coupling: Option<CouplingKind>,
    /// Stretches at which VTK fields are written (cylinder; must be among the stretches).
    pub vtk: Option<Vec<f64>>,
    /// Newton tolerance (cylinder).
    pub tolerance: Option<f64>,
    // --- fit ---
    /// What to fit (fit, required): `passive` | `active-curve` | `explicit-law` | `damage`.
    pub fit: Option<FitKind>,
    /// CSV data file with header `lambda,P` (λ [-], P \[kPa\]), relative to the scene file (fit).
    pub data: Option<String>,
    /// Passive energy whose curve is the data (fit passive; instead of `data`).
    pub reference: Option<EnergySpec>,
    /// Stresses of active-curve data: `active` or `total` (fit active-curve).
    pub stress: Option<StressKind>,
    /// Damage values of synthetic weakened curves, one fit each (fit damage; instead of `data`).
    pub true_damage: Option<Vec<f64>>,
    /// Standard deviation of Gaussian noise added to synthetic data \[kPa\] (fit).
    pub noise: Option<f64>,
    /// Seed of the noise (fit).
    pub seed: Option<i64>,
    /// `stress` or `activation` (fit explicit-law).
    pub residual: Option<ResidualKind>,
    /// Free parameters (fit; default: the fit's own choice).
    pub free: Option<Vec<String>>,
    /// Starting values by parameter name (fit).
    pub start: Option<BTreeMap<String, f64>>,
    /// Bounds [lower, upper] by parameter name (fit).
    pub bounds: Option<BTreeMap<String, [f64; 2]>>,
    /// `gauss-newton` or `nelder-mead` (fit).
    pub method: Option<MethodKind>,
    /// Maximum Gauss–Newton iterations (fit).
    pub max_iterations: Option<i64>,
    // --- stability ---
    /// Sampled reference normals of the strong-ellipticity check (stability).
    pub normals: Option<i64>,
    // --- tradeoff ---
    /// Option groups to measure (tradeoff; default all).
    pub options: Option<Vec<OptionGroup>>,
    /// Meshes `[nr, nz]` of the mesh option, coarse to fine (tradeoff; the last is the reference).
    pub meshes: Option<Vec<[i64; 2]>>,
    /// Newton tolerances of the tolerance option, loose to tight (tradeoff; the last is the
    /// reference).
    pub tolerances: Option<Vec<f64>>,
}

/// Stretches: `[0.8, 1.0, 1.2]` or `{ from = 0.7, to = 1.6, step = 0.05, extra = [1.17] }`.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum StretchSpec {
    /// Explicit list.
    List(Vec<f64>),
    /// Evenly spaced, plus extra points.
    Range {
        /// First stretch.
        from: f64,
        /// Last stretch (must be reached by whole steps).
        to: f64,
        /// Step > 0.
        step: f64,
        /// Extra stretches merged in.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        extra: Vec<f64>,
    },
}

// Hand-written so that errors inside keep their position in the file (an untagged derive
// buffers the value and loses it).
impl<'de> Deserialize<'de> for StretchSpec {
    fn deserialize<D: Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct V;
        impl<'de> Visitor<'de> for V {
            type Value = StretchSpec;
            fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
                f.write_str("a list of stretches or a table { from, to, step, extra }")
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<Self::Value, A::Error> {
                let mut v = Vec::new();
                while let Some(x) = seq.next_element::<f64>()? {
                    v.push(x);
                }
                Ok(StretchSpec::List(v))
            }
            fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<Self::Value, A::Error> {
                const FIELDS: &[&str] = &["from", "to", "step", "extra"];
                let (mut from, mut to, mut step, mut extra) = (None, None, None, Vec::new());
                while let Some(key) = map.next_key::<String>()? {
                    match key.as_str() {
                        "from" => from = Some(map.next_value::<f64>()?),
                        "to" => to = Some(map.next_value::<f64>()?),
                        "step" => step = Some(map.next_value::<f64>()?),
                        "extra" => extra = map.next_value::<Vec<f64>>()?,
                        other => return Err(de::Error::unknown_field(other, FIELDS)),
                    }
                }
                Ok(StretchSpec::Range {
                    from: from.ok_or_else(|| de::Error::missing_field("from"))?,
                    to: to.ok_or_else(|| de::Error::missing_field("to"))?,
                    step: step.ok_or_else(|| de::Error::missing_field("step"))?,
                    extra,
                })
            }
        }
        deserializer.deserialize_any(V)
    }
}
