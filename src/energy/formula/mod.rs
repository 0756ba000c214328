//! An energy written as a formula: W as an expression of the invariants, with named parameters,
//! read at run time (a scene's `energy = "formula"`, Python's `Material(energy="formula", ...)`)
//! and evaluated on `f64` and on every dual number the engine uses, so that stress, tangent,
//! dP/dγ, the activation laws, both couplings, every approach but the structural one, the FE
//! solver, stability and fits follow from it exactly as from a compiled energy.
//!
//! ```text
//! W = "c10*(I1 - 3) + c20*(I1 - 3)^2 + k1/(2*k2)*expm1(k2*(I4 - 1)^2)"
//! ```
//!
//! - **Language** ([`syntax`]): numbers, names, `+ - * / ^` (also `**`), parentheses, the
//!   functions of [`FUNCTIONS`], and definitions before W (`Ip = w0/3*tr_c + (1 - w0)*c_m; ...`).
//! - **Names**: the invariants [`INVARIANTS`] (those every energy sees), the derived ones
//!   [`DERIVED`] (I1, I2, I3, J, I4, λ_f and the isochoric ones), the declared parameters and the
//!   definitions.
//! - **Compiled once** ([`compile`], [`emit`]) into two tapes ([`program`]): the parameter-only
//!   subexpressions, evaluated once per parameter set, and the energy's instructions over the
//!   invariants, evaluated per call with the constants entering as plain numbers.
//! - **Checked** when read ([`compile`]: names, unused parameters and definitions, operations on
//!   parameters that may leave their domain, [`sign`]) and whenever the parameters change ([`check`]:
//!   finite W, ∂W/∂j, ∂²W/∂j² at F = I; W(I) = 0; no stress along the fibres at I; each value in
//!   its range).

mod check;
mod compile;
mod emit;
mod error;
mod program;
mod sign;
mod symbols;
mod syntax;

pub use check::REFERENCE;
pub use error::FormulaError;
pub use symbols::{DERIVED, FUNCTIONS, INVARIANTS};
pub use syntax::{MAX_BYTES, MAX_DEPTH, MAX_NODES};

use super::{Invariants, Parameter, Parametric, StrainEnergy};
use crate::{Error, Result, Scalar};
use program::Program;
use std::sync::Arc;

/// The name of a formula energy that is given none, and the `energy` of its scene table.
pub const FORMULA: &str = "formula";

/// What the formula is, shared by every parameter set of it.
#[derive(Debug)]
struct Definition {
    name: String,
    formula: String,
    parameters: Vec<Parameter>,
    program: Program,
    uses_det_c: bool,
}

/// A strain energy W(C) \[kPa\] written as a formula of the invariants, with named parameters.
///
/// The parameters' values start at their declared values ([`Parameter::default`]); a fit
/// changes them ([`Parametric::rebuilt`]). Cheap to clone: the compiled formula is shared.
#[derive(Debug, Clone)]
pub struct FormulaEnergy {
    definition: Arc<Definition>,
    values: Vec<f64>,
    /// The constant tape's results at `values`.
    constants: Vec<f64>,
    /// The hydrostatic stress at F = I \[kPa\] ([`check`]).
    reference_stress: f64,
    /// The weight of C:M in W's structural invariant, if it has one
    /// ([`check::structural_weight`]).
    structural: Option<f64>,
}

impl PartialEq for FormulaEnergy {
    fn eq(&self, other: &Self) -> bool {
        let (a, b) = (&self.definition, &other.definition);
        (&a.name, &a.formula, &a.parameters, &self.values)
            == (&b.name, &b.formula, &b.parameters, &other.values)
    }
}

impl FormulaEnergy {
    /// W = `formula` with `parameters`, each at its declared value ([`Parameter::default`],
    /// required), admissible in its open range, fitted within its bounds. Every rule of the
    /// module is checked; an error names the key (`W`, `parameters.mu.range`).
    pub fn new(
        formula: &str,
        parameters: Vec<Parameter>,
    ) -> std::result::Result<Self, FormulaError> {
        let mut values = Vec::with_capacity(parameters.len());
        for p in &parameters {
            values.push(declared(p, &parameters)?);
        }
        let ranges: Vec<(String, (f64, f64))> = parameters
            .iter()
            .map(|p| (p.name.to_string(), p.range))
            .collect();
        let (mut graph, root) = compile::compile(formula, &ranges)?;
        let program = emit::program(&mut graph, root);
        let definition = Arc::new(Definition {
            name: FORMULA.to_string(),
            formula: formula.to_string(),
            uses_det_c: program.uses_det_c,
            parameters,
            program,
        });
        Self::at(definition, values)
    }

    /// The same energy called `name` in outputs and labels (default [`FORMULA`]): at most 64
    /// characters, not empty.
    pub fn named(self, name: &str) -> std::result::Result<Self, FormulaError> {
        let name = name.trim();
        if name.is_empty() || name.chars().count() > 64 || name.chars().any(char::is_control) {
            return Err(FormulaError {
                key: "name".into(),
                value: format!("{name:?}"),
                rule: "a formula energy's name is 1 to 64 printable characters".into(),
            });
        }
        let d = &self.definition;
        let definition = Arc::new(Definition {
            name: name.to_string(),
            formula: d.formula.clone(),
            parameters: d.parameters.clone(),
            program: d.program.clone(),
            uses_det_c: d.uses_det_c,
        });
        Ok(Self { definition, ..self })
    }

    /// The energy of `definition` at parameter `values`, checked at the reference.
    fn at(
        definition: Arc<Definition>,
        values: Vec<f64>,
    ) -> std::result::Result<Self, FormulaError> {
        let constants = definition.program.constants(&values);
        let shown = values_text(&definition.parameters, &values);
        if let Some(k) = constants.iter().position(|c| !c.is_finite()) {
            return Err(FormulaError::formula(
                format!("{}", constants[k]),
                format!(
                    "a part of W that depends on the parameters only is not finite with {shown}"
                ),
            ));
        }
        let reference_stress = check::reference(&definition.program, &constants, &shown)?;
        let structural = check::structural_weight(&definition.program, &constants);
        Ok(Self {
            definition,
            values,
            constants,
            reference_stress,
            structural,
        })
    }

    /// The formula as given.
    pub fn formula(&self) -> &str {
        &self.definition.formula
    }

    /// The formula on one line, its comments left out (for tables and legends).
    pub fn formula_line(&self) -> String {
        self.definition
            .formula
            .lines()
            .map(|l| l.split('#').next().unwrap_or(""))
            .flat_map(str::split_whitespace)
            .collect::<Vec<_>>()
            .join(" ")
    }

    /// The hydrostatic stress s₀ at F = I \[kPa\]: P(I) = s₀ I (0 for a stress-free reference).
    pub fn reference_stress(&self) -> f64 {
        self.reference_stress
    }
}

/// The value of parameter `p` (one of `all`), checked: a name of the language, unique, a finite
/// value inside its open range, bounds within the range.
fn declared(p: &Parameter, all: &[Parameter]) -> std::result::Result<f64, FormulaError> {
    let name = p.name.as_ref();
    let bad = |field: &str, value: String, rule: String| {
        Err(FormulaError::parameter(name, field, value, rule))
    };
    if !symbols::is_name(name) {
        return bad(
            "",
            format!("{name:?}"),
            "a parameter's name is letters, digits and _, not starting with a digit".into(),
        );
    }
    if symbols::reserved(name) {
        return bad("", name.into(), "a word of the formula language (an invariant or a function): give the parameter another name".into());
    }
    if all.iter().filter(|q| q.name == p.name).count() > 1 {
        return bad("", name.into(), "declared twice".into());
    }
    let (lo, hi) = p.range;
    if lo.is_nan() || hi.is_nan() || lo >= hi {
        return bad(
            "range",
            interval(p.range),
            "range = [lower, upper] needs lower < upper (± inf allowed)".into(),
        );
    }
    let Some(value) = p.default else {
        return bad(
            "value",
            "(missing)".into(),
            "a formula parameter needs its value".into(),
        );
    };
    if !(value.is_finite() && lo < value && value < hi) {
        return bad(
            "value",
            crate::text::shortest(value),
            format!("must lie in the range ({lo}, {hi}) (lower < value < upper)"),
        );
    }
    let (blo, bhi) = p.bounds;
    if blo.is_nan() || bhi.is_nan() || blo >= bhi || blo < lo || bhi > hi {
        return bad(
            "bounds",
            interval(p.bounds),
            format!("fit bounds [lower, upper] need lower < upper within the range [{lo}, {hi}]"),
        );
    }
    Ok(value)
}

fn interval((a, b): (f64, f64)) -> String {
    format!(
        "[{}, {}]",
        crate::text::shortest(a),
        crate::text::shortest(b)
    )
}

/// `mu = 0.16, alpha = 19` of the parameters at `values`.
fn values_text(parameters: &[Parameter], values: &[f64]) -> String {
    if parameters.is_empty() {
        return "no parameters".into();
    }
    let v: Vec<String> = parameters
        .iter()
        .zip(values)
        .map(|(p, v)| format!("{} = {}", p.name, crate::text::shortest(*v)))
        .collect();
    v.join(", ")
}

impl StrainEnergy for FormulaEnergy {
    #[inline(always)]
    fn energy<T: Scalar>(&self, invariants: &Invariants<T>) -> T {
        self.definition.program.energy(&self.constants, invariants)
    }

    fn name(&self) -> &str {
        &self.definition.name
    }

    fn uses_det_c(&self) -> bool {
        self.definition.uses_det_c
    }

    /// Read off W's gradient ([`check::structural_weight`]): f = 1 − w0 for a formula written
    /// in I_p = (w0/3) tr C + (1 − w0) C:M, none for one with a fibre term of its own.
    fn structural_fibre_weight(&self) -> Option<f64> {
        self.structural
    }
}

impl Parametric for FormulaEnergy {
    fn parameters(&self) -> &[Parameter] {
        &self.definition.parameters
    }

    fn parameter_values(&self) -> Vec<f64> {
        self.values.clone()
    }

    /// The same formula at `values`, each inside its range and checked at the reference
    /// ([`Error::Formula`] otherwise).
    fn rebuilt(&self, values: &[f64]) -> Result<Self> {
        let parameters = &self.definition.parameters;
        if values.len() != parameters.len() {
            return Err(Error::InvalidParameter {
                name: "parameters",
                value: values.len() as f64,
                rule: "give one value per parameter of the formula",
            });
        }
        for (p, &v) in parameters.iter().zip(values) {
            let (lo, hi) = p.range;
            if !(v.is_finite() && lo < v && v < hi) {
                return Err(Error::Formula(FormulaError::parameter(
                    &p.name,
                    "",
                    crate::text::shortest(v),
                    format!("must lie in the range ({lo}, {hi})"),
                )));
            }
        }
        Self::at(self.definition.clone(), values.to_vec()).map_err(Error::Formula)
    }

    fn energy_with<T: Scalar>(&self, parameters: &[T], invariants: &Invariants<T>) -> T {
        let c = self.definition.program.constants(parameters);
        self.definition.program.energy(&c, invariants)
    }
}
