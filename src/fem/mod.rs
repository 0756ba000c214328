//! Axisymmetric mixed displacement–pressure finite elements for the muscle cylinder.
//!
//! A cylinder of radius R and length L, fibres along z, is meshed in its meridian half plane
//! (r, z) ∈ [0, R] × [0, L] with quadrilaterals of the user's [`Element`]: Taylor–Hood Q2/Q1
//! (default, inf–sup stable) or the cheaper Q1/P0 (incompressibility in the mean per cell),
//! chosen in [`SolverOptions::element`]. The solver minimises
//! (finds the saddle point of) Π(u, p) = ∫ [Ψ(F) − p (J − 1)] dV with
//!
//! F = [[1 + ∂u_r/∂r, 0, ∂u_r/∂z], [0, 1 + u_r/r, 0], [∂u_z/∂r, 0, 1 + ∂u_z/∂z]],
//! J = F_θθ (F_rr F_zz − F_rz F_zr),  dV = 2π r dr dz,
//!
//! for any constitutive model behind [`AxisymmetricMaterial`]. Boundary conditions: u_r = 0 on
//! the axis, u_z = 0 at z = 0, u_z = (λ − 1) L at z = L, lateral surface traction free, bases
//! [`Bases::Sliding`] or [`Bases::Clamped`]. See [`solver::AxisymmetricSolver`].
//!
//! The modules, from the bottom up (imports run one way, none in a circle):
//!
//! | module | what |
//! |---|---|
//! | [`error`], [`finite`], [`material`], [`kinematics`], [`timings`], [`linear_solver`] | leaves: errors, the finiteness test of long slices, the material interface, J and its derivatives, time per phase, the choice of linear solver |
//! | [`element`] | the elements, one file each ([`element::MixedElement`]) plus a line of its registry, and their shared reference element and weak form |
//! | [`memory`] | the memory a solve needs, from counts, and its limit |
//! | [`mesh`] | the meridian mesh (structured, bounded by [`memory`]; the cells of any element) |
//! | [`dofs`], [`condensation`], [`assembly`] | the dof numbering, the static condensation of a condensed node, the parallel assembly into a pattern built once |
//! | [`ordering`], [`ldlt`], [`pattern_lu`], [`linear`], [`gmres`] | the elimination order, LDLᵀ of the symmetric part, LU on its pattern, faer's LU, GMRES |
//! | [`tangent_solver`] | which factorisation preconditions the Newton system |
//! | [`relaxation`] | the local relaxation of a predictor that overshoots in a few cells |
//! | [`continuation`], [`problem`] | load stepping with Newton for any [`NonlinearSystem`], and the mixed problem as one |
//! | [`vtk`], [`solver`] | VTK output; the solver that drives a mesh through the stretches |

pub mod assembly;
pub mod condensation;
pub mod continuation;
pub mod dissection;
pub mod dofs;
pub mod element;
pub mod error;
pub mod finite;
pub mod gmres;
pub mod kinematics;
pub mod ldlt;
pub mod linear;
pub mod linear_solver;
pub mod material;
pub mod memory;
pub mod mesh;
pub mod ordering;
pub mod pattern_lu;
pub mod problem;
pub mod relaxation;
pub mod solver;
pub mod tangent_solver;
pub mod timings;
pub mod vtk;

pub use assembly::QuadraturePoint;
pub use continuation::{Cancel, NonlinearSystem};
pub use dofs::Bases;
pub use element::Element;
pub use error::{FemError, FemResult, StepFailure};
pub use material::{AxiF, AxisymmetricMaterial, NeoHookean, Region, Regions};
pub use memory::MemoryEstimate;
pub use mesh::{Boundary, Mesh};
pub use solver::{
    AxisymmetricSolver, IterationRecord, LinearSolver, Progress, SolverOptions, State, StepRecord,
    Stepping, StretchResult, Sweep, Timings, VtkOutput,
};
