//! Strain-energy densities, written once as generic scalar functions of the invariants of C.
//!
//! A model implements [`StrainEnergy::energy`] for any scalar `T: DualNum<Primitive = f64> + Copy`;
//! `f64` gives the value, dual numbers give exact derivatives. The framework owns the invariants
//! and their derivatives with respect to F (see [`crate::invariants`]), so a model never writes a
//! derivative by hand.

pub mod formula;

pub(crate) use crate::parameter::{open_unit, positive};
pub use crate::parameter::{Parameter, ScalarWith};
use crate::Scalar;
use crate::{Error, Result};
pub use formula::{FormulaEnergy, FormulaError, FORMULA};

/// e^x − 1 \[-\] for any scalar, with one exponential where that is accurate: a dual number's
/// derivatives need e^x₀ (x₀ the real part) anyway, and for |x₀| ≥ 1/2 the subtraction e^x₀ − 1
/// amplifies e^x₀'s rounding by e^x₀/|e^x₀ − 1| ≤ 2.6, so the value stays within 3 ulp; below,
/// where e^x − 1 cancels, num-dual's `exp_m1` (which evaluates both exp_m1 and exp). glibc's
/// expm1 costs several times its exp: this halves the cost of an exponential energy's term.
pub fn exp_m1<T: Scalar>(x: T) -> T {
    if x.re().abs() >= 0.5 {
        x.exp() - 1.0
    } else {
        x.exp_m1()
    }
}

/// The invariants of a right Cauchy–Green tensor C with respect to the fibre direction m
/// (M = m ⊗ m) that energies may use.
///
/// | field | definition | at C = I |
/// |---|---|---|
/// | `tr_c` | tr C | 3 |
/// | `c_m` | C : M = λ_f² | 1 |
/// | `tr_c_inv` | tr C⁻¹ | 3 |
/// | `c_inv_m` | C⁻¹ : M | 1 |
/// | `det_c` | det C = J² | 1 |
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Invariants<T> {
    /// tr C.
    pub tr_c: T,
    /// C : M, the squared fibre stretch.
    pub c_m: T,
    /// tr C⁻¹.
    pub tr_c_inv: T,
    /// C⁻¹ : M.
    pub c_inv_m: T,
    /// det C.
    pub det_c: T,
}

impl<T: Copy> Invariants<T> {
    /// Number of invariants.
    pub const COUNT: usize = 5;

    /// From `[tr C, C:M, tr C⁻¹, C⁻¹:M, det C]`.
    pub fn from_array(v: [T; 5]) -> Self {
        Self {
            tr_c: v[0],
            c_m: v[1],
            tr_c_inv: v[2],
            c_inv_m: v[3],
            det_c: v[4],
        }
    }

    /// As `[tr C, C:M, tr C⁻¹, C⁻¹:M, det C]`.
    pub fn to_array(self) -> [T; 5] {
        [self.tr_c, self.c_m, self.tr_c_inv, self.c_inv_m, self.det_c]
    }
}

/// A hyperelastic strain-energy density W(C) \[kPa\], transversely isotropic about the fibre direction.
///
/// Implement [`energy`](Self::energy) once, generically; every response (stress, tangent, dP/dγ,
/// activation, both couplings, the FE solver) follows from it. Under the incompressibility
/// constraint det C = 1 the energy need not vanish with det C; with active strain the *elastic*
/// C_e has det C_e = (1 − γ)⁻², so an energy that uses `det_c` sees it.
pub trait StrainEnergy: Clone + Send + Sync {
    /// W(C) in kPa from the invariants of C. Must be 0 at C = I for a stress-free reference.
    fn energy<T: Scalar>(&self, invariants: &Invariants<T>) -> T;

    /// Short name for logs and output files.
    fn name(&self) -> &str {
        "user-defined"
    }

    /// Whether W depends on `det_c`. An energy that does not may return `false`: the responses
    /// then differentiate over four invariants instead of five (about 1.5× faster tangents).
    /// Returning `false` for an energy that does use `det_c` gives wrong derivatives.
    fn uses_det_c(&self) -> bool {
        true
    }

    /// The weight f of C:M in a structural invariant I = C:L = ((1 − f)/3) tr C + f C:M, if W
    /// depends on C:M only through I (the chapter's, Ehret–Böl–Itskov's and 4C's energies:
    /// f = 1 − w0). Lets the structural activation I = C:(L + ωM) of Ehret, Böl & Itskov (2011)
    /// act on the energy ([`crate::active::ActivationMap::Structural`]); `None` (the default):
    /// the energy has no such invariant and the structural approach is refused.
    fn structural_fibre_weight(&self) -> Option<f64> {
        None
    }
}

/// An energy with named parameters that can be read, rebuilt from numbers (validated) and passed
/// to the energy's one formula as dual numbers (derivatives in the parameters, for fitting).
/// Every [`Shipped`] energy, [`FormulaEnergy`] and [`Energy`] implement it.
pub trait Parametric: StrainEnergy + Sized {
    /// The parameters, in order.
    fn parameters(&self) -> &[Parameter];

    /// Current values, in the order of [`parameters`](Self::parameters).
    fn parameter_values(&self) -> Vec<f64>;

    /// The same model with new parameter values, validated by its constructor.
    fn rebuilt(&self, values: &[f64]) -> Result<Self>;

    /// W(C) \[kPa\] with the parameters given as scalars (dual numbers differentiate in them).
    fn energy_with<T: Scalar>(&self, parameters: &[T], invariants: &Invariants<T>) -> T;

    /// Names of the parameters, in order.
    fn parameter_names(&self) -> Vec<&str> {
        self.parameters().iter().map(|p| p.name.as_ref()).collect()
    }
}

/// A shipped energy: its name, its parameter table and its formula over those parameters. Its
/// file in `src/energy/` implements this (and [`StrainEnergy`]); one line in
/// `shipped_energies!` below makes it a choice of [`Energy`], of scene files (`energy = "name"`
/// with its parameters by name), of `check`'s printout, of passive fits and of the report.
pub trait Shipped: StrainEnergy + Sized {
    /// Name in scene files and outputs (`giantesio-musesti`).
    const NAME: &'static str;
    /// What it is, with its formula, for the report's table of models.
    const FORMULA: &'static str;
    /// Where the chapter has it (`eq. (1); parameters Table 1`), or `not in the chapter`.
    const CHAPTER: &'static str;
    /// The parameters, in the order of [`values`](Self::values).
    const PARAMETERS: &'static [Parameter];
    /// The same energy in the formula language ([`formula`]), over the parameters' names, if
    /// it can be written there: what [`Energy::as_formula`] builds (the trade-off study's
    /// convenience-against-speed group times the two; a test checks that they agree to
    /// rounding).
    const W: Option<&'static str> = None;
    /// The parameter values.
    fn values(&self) -> Vec<f64>;
    /// The energy with these parameter values (in the order of [`PARAMETERS`](Self::PARAMETERS)),
    /// validated.
    fn from_values(values: &[f64]) -> Result<Self>;
    /// W(C) \[kPa\] with the parameters given as scalars, in the same order.
    fn energy_of<T: Scalar>(parameters: &[T], invariants: &Invariants<T>) -> T;
}

impl<E: Shipped> Parametric for E {
    fn parameters(&self) -> &[Parameter] {
        E::PARAMETERS
    }
    fn parameter_values(&self) -> Vec<f64> {
        self.values()
    }
    fn rebuilt(&self, values: &[f64]) -> Result<Self> {
        E::from_values(values)
    }
    fn energy_with<T: Scalar>(&self, parameters: &[T], invariants: &Invariants<T>) -> T {
        E::energy_of(parameters, invariants)
    }
}

/// One entry of [`SHIPPED`]: a shipped energy's name, parameters and constructor.
#[derive(Debug, Clone, Copy)]
pub struct ShippedEnergy {
    /// Name in scene files (`energy = "..."`).
    pub name: &'static str,
    /// What it is, with its formula ([`Shipped::FORMULA`]).
    pub formula: &'static str,
    /// Where the chapter has it ([`Shipped::CHAPTER`]).
    pub chapter: &'static str,
    /// Its parameters.
    pub parameters: &'static [Parameter],
    /// The energy in the formula language, if it has one ([`Shipped::W`]).
    pub w: Option<&'static str>,
    build: fn(&[f64]) -> Result<Energy>,
}

impl ShippedEnergy {
    /// The shipped energy called `name`.
    pub fn find(name: &str) -> Option<&'static ShippedEnergy> {
        SHIPPED.iter().find(|e| e.name == name)
    }

    /// The energy with parameter `values`, one per parameter, in order; validated.
    pub fn build(&self, values: &[f64]) -> Result<Energy> {
        if values.len() != self.parameters.len() {
            return Err(Error::InvalidParameter {
                name: "parameters",
                value: values.len() as f64,
                rule: "give one value per parameter of the energy",
            });
        }
        (self.build)(values)
    }
}

/// The shipped energies: `shipped_energies! { file::Type, ... }` declares each energy's module
/// (`src/energy/file.rs`) and re-exports its type, and generates [`Energy`] (one variant per type,
/// named as the type, and [`Energy::Formula`]), its [`StrainEnergy`] and [`Parametric`]
/// implementations and [`SHIPPED`].
macro_rules! shipped_energies {
    ($($(#[$doc:meta])* $file:ident::$energy:ident),* $(,)?) => {
        $(mod $file;
        pub use $file::$energy;)*

        /// Any of the shipped energies or a formula, chosen at run time (e.g. from a scene
        /// file).
        #[derive(Debug, Clone, PartialEq)]
        pub enum Energy {
            $($(#[$doc])* $energy($energy),)*
            /// An energy written as a formula ([`formula`]).
            Formula(FormulaEnergy),
        }

        impl StrainEnergy for Energy {
            fn energy<T: Scalar>(&self, invariants: &Invariants<T>) -> T {
                match self {
                    $(Energy::$energy(w) => w.energy(invariants),)*
                    Energy::Formula(w) => w.energy(invariants),
                }
            }

            fn name(&self) -> &str {
                match self {
                    $(Energy::$energy(w) => w.name(),)*
                    Energy::Formula(w) => w.name(),
                }
            }

            fn uses_det_c(&self) -> bool {
                match self {
                    $(Energy::$energy(w) => w.uses_det_c(),)*
                    Energy::Formula(w) => w.uses_det_c(),
                }
            }

            fn structural_fibre_weight(&self) -> Option<f64> {
                match self {
                    $(Energy::$energy(w) => w.structural_fibre_weight(),)*
                    Energy::Formula(w) => w.structural_fibre_weight(),
                }
            }
        }

        impl Parametric for Energy {
            fn parameters(&self) -> &[Parameter] {
                match self {
                    $(Energy::$energy(_) => $energy::PARAMETERS,)*
                    Energy::Formula(w) => w.parameters(),
                }
            }
            fn parameter_values(&self) -> Vec<f64> {
                match self {
                    $(Energy::$energy(w) => w.values(),)*
                    Energy::Formula(w) => w.parameter_values(),
                }
            }
            fn rebuilt(&self, values: &[f64]) -> Result<Self> {
                Ok(match self {
                    $(Energy::$energy(_) => Energy::$energy($energy::from_values(values)?),)*
                    Energy::Formula(w) => Energy::Formula(w.rebuilt(values)?),
                })
            }
            fn energy_with<T: Scalar>(&self, parameters: &[T], invariants: &Invariants<T>) -> T {
                match self {
                    $(Energy::$energy(_) => $energy::energy_of(parameters, invariants),)*
                    Energy::Formula(w) => w.energy_with(parameters, invariants),
                }
            }
        }

        impl Energy {
            /// This energy written as a formula: a shipped energy's [`Shipped::W`] with
            /// its parameters at their values (named `<name> (formula)`); a formula energy is
            /// itself. An error for a shipped energy without a formula.
            pub fn as_formula(&self) -> std::result::Result<FormulaEnergy, FormulaError> {
                let (text, parameters, name) = match self {
                    $(Energy::$energy(_) => ($energy::W, $energy::PARAMETERS, $energy::NAME),)*
                    Energy::Formula(f) => return Ok(f.clone()),
                };
                let Some(text) = text else {
                    return Err(FormulaError {
                        key: "energy".into(),
                        value: name.into(),
                        rule: "this energy is not written in the formula language (Shipped::W)".into(),
                    });
                };
                let declared = parameters
                    .iter()
                    .zip(self.parameter_values())
                    .map(|(p, v)| Parameter {
                        default: Some(v),
                        ..p.clone()
                    })
                    .collect();
                FormulaEnergy::new(text, declared)?.named(&format!("{name} (formula)"))
            }
        }

        /// The shipped energies, in the order of [`Energy`]'s variants (the first is the
        /// chapter's, the default of scene files).
        pub const SHIPPED: &[ShippedEnergy] = &[$(ShippedEnergy {
            name: $energy::NAME,
            formula: $energy::FORMULA,
            chapter: $energy::CHAPTER,
            parameters: $energy::PARAMETERS,
            w: $energy::W,
            build: |v| Ok(Energy::$energy($energy::from_values(v)?)),
        },)*];
    };
}

// A new shipped energy: its file in this directory (`impl StrainEnergy` and `impl Shipped`) and
// one line here.
shipped_energies! {
    /// The chapter's passive energy, eq. (1).
    giantesio_musesti::GiantesioMusesti,
    /// The Ehret–Böl–Itskov energy, eq. (4).
    ehret_bol_itskov::EhretBolItskov,
    /// Incompressible neo-Hookean reference.
    neo_hookean::NeoHookean,
    /// 4C's muscle passive energy (Weickenmeier et al. 2014).
    four_c_passive::FourCPassive,
}

#[cfg(test)]
mod tests {
    use super::exp_m1;
    use num_dual::Dual2_64;

    /// |a − b| in units in the last place of b.
    fn ulps(a: f64, b: f64) -> f64 {
        (a - b).abs() / (b.abs() * f64::EPSILON).max(f64::MIN_POSITIVE)
    }

    #[test]
    fn exp_m1_stays_within_3_ulp_of_libm_and_its_derivatives_are_exp() {
        let mut worst: f64 = 0.0;
        for k in -4000i32..=4000 {
            // Dense around the switch at |x| = 1/2, and out to |x| = 40.
            let x = if k.abs() <= 2000 {
                k as f64 * 5e-4
            } else {
                k.signum() as f64 * (1.0 + (k.abs() - 2000) as f64 * 0.0195)
            };
            worst = worst.max(ulps(exp_m1(x), x.exp_m1()));
            // Value, first and second derivative of a second-order dual.
            let d = exp_m1(Dual2_64::from_re(x).derivative());
            assert!(ulps(d.re, x.exp_m1()) <= 3.0, "x = {x}");
            assert_eq!(d.v1, x.exp(), "x = {x}: first derivative");
            assert_eq!(d.v2, x.exp(), "x = {x}: second derivative");
        }
        println!("worst {worst} ulp");
        assert!(worst <= 3.0, "worst {worst} ulp");
        // Below the switch it is libm's expm1 itself (no cancellation of e^x − 1).
        assert_eq!(exp_m1(1e-10), 1e-10_f64.exp_m1());
    }
}
