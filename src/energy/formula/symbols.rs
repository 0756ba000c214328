//! The vocabulary of a formula: the five invariants the framework supplies, the usual invariants
//! derived from them (written in the formula language itself), and the functions.
//!
//! The invariants are those every energy sees ([`crate::energy::Invariants`]); the framework owns
//! their derivatives with respect to F, so a formula differentiates only in them. C²:M (I₅) is
//! not among them: an energy that needs it is a compiled one (one file in `src/energy/`).

use crate::Scalar;

/// The invariants of C (of C_e under active strain), in the order of
/// [`crate::energy::Invariants::to_array`]: name and meaning.
pub const INVARIANTS: [(&str, &str); 5] = [
    ("tr_c", "tr C"),
    ("c_m", "C:M = λ_f², M = m ⊗ m"),
    ("tr_c_inv", "tr C⁻¹"),
    ("c_inv_m", "C⁻¹:M"),
    ("det_c", "det C = J²"),
];

/// The derived invariants: name, definition in the formula language, meaning.
pub const DERIVED: [(&str, &str, &str); 9] = [
    ("I1", "tr_c", "I₁ = tr C"),
    (
        "I2",
        "det_c*tr_c_inv",
        "I₂ = ½[(tr C)² − tr C²] = det C · tr C⁻¹",
    ),
    ("I3", "det_c", "I₃ = det C"),
    ("J", "sqrt(det_c)", "J = det F = √(det C)"),
    ("I4", "c_m", "I₄ = C:M = λ_f²"),
    ("lambda_f", "sqrt(c_m)", "λ_f = √(C:M), the fibre stretch"),
    ("I1_bar", "det_c^(-1/3)*tr_c", "Ī₁ = J^(−2/3) I₁"),
    ("I2_bar", "det_c^(1/3)*tr_c_inv", "Ī₂ = J^(−4/3) I₂"),
    ("I4_bar", "det_c^(-1/3)*c_m", "Ī₄ = J^(−2/3) I₄"),
];

/// A function of one argument.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Function {
    /// −x (the sign, not a name of the language).
    Neg,
    /// eˣ.
    Exp,
    /// eˣ − 1, accurate near 0 ([`crate::energy::exp_m1`]).
    ExpM1,
    /// ln x.
    Ln,
    /// ln(1 + x), accurate near 0.
    Ln1p,
    /// √x.
    Sqrt,
    /// ∛x.
    Cbrt,
    /// sinh x.
    Sinh,
    /// cosh x.
    Cosh,
    /// tanh x.
    Tanh,
    /// arctan x.
    Atan,
}

/// The functions a formula may call: name, function, meaning.
pub const FUNCTIONS: [(&str, Function, &str); 10] = [
    ("exp", Function::Exp, "eˣ"),
    ("expm1", Function::ExpM1, "eˣ − 1 (accurate for small x)"),
    ("ln", Function::Ln, "natural logarithm"),
    ("ln1p", Function::Ln1p, "ln(1 + x) (accurate for small x)"),
    ("sqrt", Function::Sqrt, "√x"),
    ("cbrt", Function::Cbrt, "∛x"),
    ("sinh", Function::Sinh, "hyperbolic sine"),
    ("cosh", Function::Cosh, "hyperbolic cosine"),
    ("tanh", Function::Tanh, "hyperbolic tangent"),
    ("atan", Function::Atan, "arctangent"),
];

/// Names a modeller may expect that the language writes otherwise, and what to write.
const HINTS: [(&str, &str); 12] = [
    ("I5", "I₅ = C²:M is not among the invariants the framework supplies (tr C, C:M, tr C⁻¹, C⁻¹:M, det C); an energy that needs it is a compiled one"),
    ("log", "the natural logarithm is written ln(x)"),
    ("log1p", "ln(1 + x) is written ln1p(x)"),
    ("exp_m1", "eˣ − 1 is written expm1(x)"),
    ("pow", "a power is written x^y (or x**y)"),
    ("abs", "|x| is not differentiable at 0: write the smooth form (e.g. x^2)"),
    ("max", "max is not differentiable where its arguments meet: write a smooth form"),
    ("min", "min is not differentiable where its arguments meet: write a smooth form"),
    ("pi", "write π as a number, 3.141592653589793"),
    ("e", "write e as exp(1) or a number, 2.718281828459045"),
    ("lambda", "the fibre stretch is lambda_f"),
    ("gamma", "γ is the activation's, not the energy's: W is the passive energy, evaluated at C_e under active strain"),
];

/// The function called `name`.
pub fn function(name: &str) -> Option<Function> {
    FUNCTIONS.iter().find(|f| f.0 == name).map(|f| f.1)
}

/// The invariant called `name` (its index in [`INVARIANTS`]).
pub fn invariant(name: &str) -> Option<usize> {
    INVARIANTS.iter().position(|i| i.0 == name)
}

/// The definition of the derived invariant called `name`.
pub fn derived(name: &str) -> Option<&'static str> {
    DERIVED.iter().find(|d| d.0 == name).map(|d| d.1)
}

/// Whether `name` is a word of the language (an invariant, a derived invariant, a function),
/// which a parameter or a definition may not take.
pub fn reserved(name: &str) -> bool {
    invariant(name).is_some() || derived(name).is_some() || function(name).is_some()
}

/// What to say about an unknown name: a hint for a name a modeller may expect, else the nearest
/// of `known` (within two edits), else nothing.
pub fn suggestion(name: &str, known: &[&str]) -> String {
    if let Some((_, hint)) = HINTS.iter().find(|h| h.0 == name) {
        return format!(" ({hint})");
    }
    crate::text::closest(name, known).map_or(String::new(), |k| format!(" (did you mean `{k}`?)"))
}

/// Whether `name` is a name of the language: ASCII letters, digits and `_`, not starting with a
/// digit.
pub fn is_name(name: &str) -> bool {
    let mut chars = name.chars();
    chars
        .next()
        .is_some_and(|c| c.is_ascii_alphabetic() || c == '_')
        && chars.all(|c| c.is_ascii_alphanumeric() || c == '_')
}

impl Function {
    /// f(x) for any scalar.
    #[inline(always)]
    pub fn apply<T: Scalar>(self, x: T) -> T {
        match self {
            Function::Neg => -x,
            Function::Exp => x.exp(),
            Function::ExpM1 => crate::energy::exp_m1(x),
            Function::Ln => x.ln(),
            Function::Ln1p => x.ln_1p(),
            Function::Sqrt => x.sqrt(),
            Function::Cbrt => x.cbrt(),
            Function::Sinh => x.sinh(),
            Function::Cosh => x.cosh(),
            Function::Tanh => x.tanh(),
            Function::Atan => x.atan(),
        }
    }
}
