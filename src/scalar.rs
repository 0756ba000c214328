//! The scalar type every generic model function is written for.

use num_dual::DualNum;

/// A real number or a dual number over `f64` (value plus exact derivatives).
///
/// Write a model once as `fn f<T: Scalar>(x: T) -> T`; `f64` evaluates it, num-dual's types
/// (`Dual64`, `Dual2SVec64<N>`, `HyperDual64`, …) differentiate it. Comparisons of dual numbers
/// look at the real part only, so a branch such as `λ > λ_min` follows the same path in both.
pub trait Scalar: DualNum<Primitive = f64> + Copy + Send + Sync {}

impl<T: DualNum<Primitive = f64> + Copy + Send + Sync> Scalar for T {}
