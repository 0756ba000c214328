//! The chapter's cylinder (R = 1, L = 4, clamped bases) swept over λ ∈ [0.70, 1.60] step 0.05
//! plus 1.17, for every damage, on a chosen mesh; where a direction stops, the material is
//! diagnosed at the quadrature points of the failed trial state (strong ellipticity, law jumps).
//!
//! `cargo run --release --example cylinder_sweep -- NR NZ explicit|implicit|tabulated|energy [sliding]`
//! (explicit, implicit and tabulated: the implicit law tabulated over λ ∈ [0.5, 1.6], frozen
//! coupling; energy: consistent coupling)
//! (environment: `DAMAGE=0.2,0.3` to restrict the damages, `LINEAR=lu` for the LU-only solver)
//! prints `d lambda P gamma_centre newton_iterations` rows and the diagnoses.

use activemuscle::active::{
    ActiveCurve, Coupling, EnergyLaw, ExplicitLaw, FrozenTangent, ImplicitLaw, Law, SolvedLaw,
    TableSpec, TabulatedLaw,
};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::fem::{AxisymmetricSolver, Bases, FemError, Mesh, SolverOptions, StepRecord};
use activemuscle::stability::diagnose_axisymmetric;
use activemuscle::Muscle;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let usage = "usage: cylinder_sweep NR NZ explicit|implicit|tabulated|energy [sliding]";
    let (nr, nz): (usize, usize) = (
        args.get(1).ok_or(usage)?.parse()?,
        args.get(2).ok_or(usage)?.parse()?,
    );
    let gm = GiantesioMusesti::paper();
    let (law, coupling, damages) = match args.get(3).map(String::as_str) {
        Some("explicit") => (
            Law::Explicit(ExplicitLaw::paper()),
            Coupling::Frozen(FrozenTangent::Exact),
            vec![0.0, 0.1, 0.2, 0.3, 0.4, 0.5],
        ),
        Some("implicit") => (
            Law::Implicit(ImplicitLaw::new(gm, ActiveCurve::paper())),
            Coupling::Frozen(FrozenTangent::Exact),
            vec![0.0, 0.1, 0.2, 0.3, 0.4, 0.5],
        ),
        Some("tabulated") => {
            let damages = vec![0.0, 0.1, 0.2, 0.3, 0.4, 0.5];
            let exact = SolvedLaw::Implicit(ImplicitLaw::new(gm, ActiveCurve::paper()));
            let table = TabulatedLaw::new(exact, &damages, TableSpec::default())?;
            (
                Law::Tabulated(table),
                Coupling::Frozen(FrozenTangent::Exact),
                damages,
            )
        }
        Some("energy") => (
            Law::Energy(EnergyLaw::new(gm, ActiveCurve::paper())),
            Coupling::Consistent,
            vec![0.0, 0.5],
        ),
        _ => return Err(usage.into()),
    };
    let bases = if args.get(4).map(String::as_str) == Some("sliding") {
        Bases::Sliding
    } else {
        Bases::Clamped
    };
    let mut targets: Vec<f64> = (0..=18).map(|k| 0.70 + 0.05 * k as f64).collect();
    targets.push(1.17);
    // DAMAGE=0.2,0.3 restricts the damages.
    let damages: Vec<f64> = match std::env::var("DAMAGE") {
        Ok(list) => list.split(',').map(str::parse).collect::<Result<_, _>>()?,
        Err(_) => damages,
    };
    let mut options = SolverOptions::default();
    if std::env::var("LINEAR").as_deref() == Ok("lu") {
        options.linear_solver = activemuscle::fem::LinearSolver::Lu;
    }
    println!(
        "# {nr}x{nz} {bases:?} {} law, {} coupling",
        law.name(),
        coupling.name()
    );
    println!("d lambda P_kPa gamma_centre newton_iterations");
    for d in damages {
        let muscle = Muscle::new(gm, law.clone(), d, coupling)?;
        let start = Instant::now();
        let mut solver = AxisymmetricSolver::new(
            Mesh::structured(1.0, 4.0, nr, nz, 1.0)?,
            bases,
            &muscle,
            options.clone(),
        )?;
        let sweep = solver.sweep(&targets)?;
        for r in &sweep.results {
            if std::env::var("TRACE").is_ok() {
                trace(&r.steps);
            }
            let its: usize = r.steps.iter().map(|s| s.iterations.len()).sum();
            println!(
                "{d} {:.2} {:.15e} {:.6} {its}",
                r.stretch, r.nominal_stress, r.gamma_centre
            );
        }
        let t = solver.timings();
        eprintln!(
            "d = {d}: {} of {} targets in {:.1} s ({} dofs): assembly {:.2} s / {}, residuals {:.2} s / {}, factorisation {:.2} s / {}, solve {:.2} s / {} ({} Krylov iterations, {} LU fallbacks)",
            sweep.results.len(),
            targets.len(),
            start.elapsed().as_secs_f64(),
            solver.n_free_dofs(),
            t.assembly.as_secs_f64(),
            t.assemblies,
            t.residual_assembly.as_secs_f64(),
            t.residual_assemblies,
            t.factorisation.as_secs_f64(),
            t.factorisations,
            t.solve.as_secs_f64(),
            t.solves,
            t.krylov_iterations,
            t.lu_fallbacks
        );
        for (failure, trial) in sweep.failures.iter().zip(&sweep.failed_trials) {
            eprintln!("  stopped: {failure}");
            if let (FemError::TargetNotReached { .. }, Some(points)) = (failure, trial) {
                let f: Vec<_> = points.iter().map(|q| q.f).collect();
                eprintln!("  diagnosis: {}", diagnose_axisymmetric(&muscle, &f, 200));
            }
        }
    }
    Ok(())
}

/// `TRACE=1`: each load step's Newton history, scaled residual / increment per iteration.
fn trace(steps: &[StepRecord]) {
    for s in steps {
        let h: Vec<String> = s
            .iterations
            .iter()
            .map(|i| {
                let step = if i.step_length == 1.0 {
                    String::new()
                } else {
                    format!("@{}", i.step_length)
                };
                format!("{:.1e}/{:.1e}{step}", i.residual, i.increment)
            })
            .collect();
        println!(
            "#   {:.4} -> {:.4}: predictor {:.1e}; {}",
            s.from,
            s.to,
            s.initial_residual,
            h.join(" ")
        );
    }
}
