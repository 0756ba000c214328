//! Tangent checks for any material: is the tangent A = ∂P/∂F a solver uses the derivative of
//! the stress P, at the states a simulation visits, and where it is not, why.
//!
//! **Taylor remainders.** For a state F, a direction ΔF (scaled to unit Frobenius norm over the
//! entries of F the material varies) and steps h,
//!
//! r₀(h) = ‖P(F + hΔF) − P(F)‖ = O(h),   r₁(h) = ‖P(F + hΔF) − P(F) − h A:ΔF‖ = O(h²)
//!
//! where P is differentiable along the segment and A is its derivative (Frobenius norms over the
//! same entries). With h halving, the observed order of a pair is
//! log(r(h_k)/r(h_{k+1})) / log(h_k/h_{k+1}): 1 for r₀ and 2 for r₁ where the material is
//! smooth. A tangent that is not the stress's derivative gives r₁ order 1 at every h; a kink of
//! P inside the segment [F, F + hΔF] (the slope of the active curve jumping at λ_min) gives
//! order 1 for the h that reach it; a jump of P (the energy law's at λ_min) gives order 0 for
//! both. Remainders below the rounding floor η = 10³ ε (‖P‖ + ‖A‖ ‖F‖) (the rounding of
//! P(F + hΔF) − P(F) is ≈ ε times the size of the terms that make P) are not used for orders.
//!
//! **At the state** ([`StateReport`]): the central-difference tangent
//! A_fd e_j = (P(F + δ_j e_j) − P(F − δ_j e_j))/(2δ_j), δ_j = ε^⅓ max(1, |F_j|) (error
//! O(δ²) + O(ε/δ), ≈ 1e-10 relative), and its error ‖A_fd − A‖/‖A‖; the major-symmetry defect
//! ‖A − Aᵀ‖/‖A‖ of A and of A_fd (a stress that is not a gradient has both; a wrong tangent only
//! A's), with the material's reason where it need not be zero; the error ‖Ã − A‖/‖A‖ of every
//! approximate tangent Ã the solver can use instead (the frozen model's symmetric approximation,
//! the other representation of a tabulated law); strong ellipticity.
//!
//! **Flags** ([`Flag`]): where an observed order leaves its band (a pair of r₁ outside
//! [1.5, 3.5], of r₀ outside [0.5, 2.5]: dropped, or raised by a kink that only the larger step
//! of the pair reaches), the state is flagged with its cause — the segment crosses a fibre stretch where the model is
//! not smooth ([`Edge`]: λ_min, the table ends of a tabulated law, the explicit law's zero
//! crossing, the reversal of the stretch rate under force–velocity), or, with none, the tangent
//! disagreeing with central differences — never averaged away.
//!
//! | module | what |
//! |---|---|
//! | [`material`] | what a check asks of a material ([`TangentMaterial`], any [`crate::fem::AxisymmetricMaterial`] included) and what it may add ([`Known`]) |
//! | [`muscle`] | a [`crate::Muscle`] in 3D with its fibre, volumetric energy and approximate tangents ([`MusclePoint`]) |
//! | [`differences`] | central-difference tangents, at a point and as a material the FE solver can use |
//! | [`taylor`] | [`taylor_test`]: the remainders, the orders, the state's report |
//! | [`flag`] | why an order leaves its band |
//! | [`assembled`] | the Taylor test of the FE solver's assembled residual and tangent |

pub mod assembled;
pub mod differences;
pub mod flag;
pub mod material;
pub mod muscle;
pub mod taylor;

pub use assembled::{assembled_taylor_test, AssembledTaylor};
pub use differences::{central_differences, CentralDifferences};
pub use flag::{Cause, Flag};
pub use material::{Approximation, Edge, Known, TangentMaterial};
pub use muscle::MusclePoint;
pub use taylor::{
    halvings, remainders, state_report, taylor_test, Remainders, StateReport, TaylorReport,
};
