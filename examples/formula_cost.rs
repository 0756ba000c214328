//! What writing an energy as a formula costs: the chapter's (or EBI's) energy compiled against the
//! same energy written as a formula ([`Energy::as_formula`]), per material point and per sweep of
//! the clamped cylinder, `n` times. Made to be counted by callgrind, whose instruction counts do
//! not depend on the machine's load (BENCHMARKS.md has the figures and the commands):
//!
//! ```text
//! cargo build --release --example formula_cost
//! valgrind --tool=callgrind --callgrind-out-file=/dev/null \
//!     target/release/examples/formula_cost point formula giantesio-musesti 20000
//! ```
//!
//! Arguments: `point | muscle | fe`, `compiled | formula`, an energy name, `n`.
//! - `point`: P, ∂P/∂F and ∂P/∂γ of the active-strain response at a fixed γ (axisymmetric).
//! - `muscle`: `Muscle::respond` with the implicit law (γ solved through the energy), frozen
//!   coupling, exact tangent (axisymmetric).
//! - `fe`: a sweep of the clamped cylinder (4 × 16 Q2/Q1 cells, λ = 1.0, 1.1), implicit law.
//!
//! The cost per unit is the difference of two counts over the difference of their `n` (the set-up
//! — parsing the formula, building the mesh — cancels).

use activemuscle::active::Approach;
use activemuscle::energy::{EhretBolItskov, Energy, GiantesioMusesti};
use activemuscle::fem::{AxisymmetricSolver, Bases, Mesh, SolverOptions};
use activemuscle::invariants::{axial_fibre, axisymmetric_f, Kinematics, AXISYMMETRIC};
use activemuscle::models::{CouplingKind, LawKind, ModelChoice, Models};
use activemuscle::response::{active_response, Order};
use nalgebra::SVector;
use std::hint::black_box;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let [what, form, energy, n] = args.as_slice() else {
        return Err("arguments: point|muscle|fe compiled|formula ENERGY N".into());
    };
    let compiled = match energy.as_str() {
        "giantesio-musesti" => Energy::GiantesioMusesti(GiantesioMusesti::paper()),
        "ehret-bol-itskov" => Energy::EhretBolItskov(EhretBolItskov::paper()),
        _ => {
            return Err(format!("energy {energy:?}: giantesio-musesti or ehret-bol-itskov").into())
        }
    };
    let energy = match form.as_str() {
        "compiled" => compiled,
        "formula" => Energy::Formula(compiled.as_formula()?),
        _ => return Err(format!("{form:?}: compiled or formula").into()),
    };
    let n: usize = n.parse()?;
    let models = Models {
        energy: energy.clone(),
        ..Models::paper()
    };
    let muscle = models.muscle(ModelChoice {
        approach: Approach::ActiveStrain,
        law: LawKind::Implicit,
        coupling: CouplingKind::Frozen,
        damage: 0.0,
    })?;
    let l = 1.0 / 1.1_f64.sqrt();
    let entries = SVector::<f64, 5>::from([l, 0.05, 0.02, 1.1, l]);
    let m = axial_fibre();
    for _ in 0..n {
        match what.as_str() {
            "point" => {
                let kin = Kinematics::new(&axisymmetric_f(black_box(&entries)), &m)?;
                let r = active_response(
                    &energy,
                    &kin,
                    black_box(0.15),
                    Order::Tangent,
                    &AXISYMMETRIC,
                );
                black_box(r?);
            }
            "muscle" => {
                let kin = Kinematics::new(&axisymmetric_f(black_box(&entries)), &m)?;
                black_box(muscle.respond(&kin, Order::Tangent, &AXISYMMETRIC)?);
            }
            "fe" => {
                let mesh = Mesh::structured(1.0, 4.0, 4, 16, 3.0)?;
                let options = SolverOptions::default();
                let mut solver = AxisymmetricSolver::new(mesh, Bases::Clamped, &muscle, options)?;
                black_box(solver.sweep(&[1.0, 1.1])?);
            }
            _ => return Err(format!("{what:?}: point, muscle or fe").into()),
        }
    }
    Ok(())
}
