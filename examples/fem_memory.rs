//! The memory estimate of a solve against what the solve really uses: prints the estimate
//! before and after the symbolic factorisation, then runs a sweep; measure the peak resident
//! memory with `/usr/bin/time -v` (or read VmHWM, printed at the end). The last line, `cost …`,
//! sums it up for `python/bench/cost_curve.py`: free dofs, the two estimates and the peak
//! (MiB), the sweep's wall time (s), its Newton iterations (those of curves.csv: summed over
//! the stretches' load steps) and the time per iteration (ms).
//!
//! `cargo run --release --example fem_memory -- NR NZ [neo-hookean|muscle] [Q2Q1|Q1P0]
//! [--stretches L1,L2,…]` (muscle: the chapter's explicit law, frozen exact tangent, clamped;
//! neo-Hookean: μ = 5 kPa; the 20 stretches 0.70, 0.75, …, 1.60 and 1.17 unless `--stretches`
//! names fewer: a truncated sweep, for the time per iteration and the peak on a large mesh).

use activemuscle::active::{Coupling, ExplicitLaw, FrozenTangent, Law};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::fem::{
    AxisymmetricMaterial, AxisymmetricSolver, Bases, Element, LinearSolver, MemoryEstimate, Mesh,
    NeoHookean, SolverOptions,
};
use activemuscle::Muscle;

const MIB: f64 = 1024.0 * 1024.0;

/// Peak resident memory of the process so far (VmHWM) in MiB, if available.
fn peak_memory_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

fn run<M: AxisymmetricMaterial>(
    material: &M,
    nr: usize,
    nz: usize,
    element: Element,
    targets: &[f64],
) -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "resident at start: {:.1} MiB",
        peak_memory_mib().unwrap_or(f64::NAN)
    );
    let before = MemoryEstimate::structured(nr, nz, element, LinearSolver::SymmetricPartGmres);
    println!(
        "estimate from the counts: {:.1} MiB ({:.0} dofs, {:.0} nonzeros, {:.0} factor values)",
        before.bytes / MIB,
        before.dofs,
        before.nonzeros,
        before.factor_values
    );
    let mesh = Mesh::structured(1.0, 4.0, nr, nz, 1.0)?;
    let options = SolverOptions {
        element,
        ..SolverOptions::default()
    };
    let mut solver = AxisymmetricSolver::new(mesh, Bases::Clamped, material, options)?;
    println!(
        "resident after the set-up: {:.1} MiB",
        peak_memory_mib().unwrap_or(f64::NAN)
    );
    let exact = solver.memory_estimate().clone();
    println!(
        "estimate after the symbolic factorisation: {:.1} MiB ({:.0} dofs, {:.0} nonzeros, {:.0} factor values)",
        exact.bytes / MIB,
        exact.dofs,
        exact.nonzeros,
        exact.factor_values
    );
    let start = std::time::Instant::now();
    let sweep = solver.sweep(targets)?;
    let seconds = start.elapsed().as_secs_f64();
    let peak = peak_memory_mib().unwrap_or(f64::NAN);
    println!(
        "{} of {} stretches; peak resident memory (VmHWM) {peak:.1} MiB",
        sweep.results.len(),
        targets.len(),
    );
    // One line for a driver (python/bench/cost_curve.py).
    let its: usize = sweep
        .results
        .iter()
        .flat_map(|r| &r.steps)
        .map(|s| s.iterations.len())
        .sum();
    println!(
        "cost {nr}x{nz} dofs {} estimate_counts {:.1} estimate {:.1} sweep {seconds:.3} its {its} \
         iteration {:.2} peak {peak:.1} stretches {}/{}",
        exact.dofs,
        before.bytes / MIB,
        exact.bytes / MIB,
        1e3 * seconds / its.max(1) as f64,
        sweep.results.len(),
        targets.len()
    );
    Ok(())
}

/// The stretches after `--stretches` (comma-separated), else the chapter's 20; the other
/// arguments in their order.
fn stretches(mut args: Vec<String>) -> Result<(Vec<f64>, Vec<String>), String> {
    let Some(at) = args.iter().position(|a| a == "--stretches") else {
        let mut all: Vec<f64> = (0..=18).map(|k| 0.70 + 0.05 * k as f64).collect();
        all.push(1.17);
        return Ok((all, args));
    };
    let list = args
        .get(at + 1)
        .ok_or("--stretches needs a list, e.g. 1.05,1.1")?;
    let targets = list
        .split(',')
        .map(|l| match l.trim().parse::<f64>() {
            Ok(v) if v.is_finite() && v > 0.0 => Ok(v),
            _ => Err(format!(
                "--stretches {list}: {l:?} is not a positive stretch"
            )),
        })
        .collect::<Result<Vec<f64>, String>>()?;
    args.drain(at..at + 2);
    Ok((targets, args))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let (targets, args) = stretches(std::env::args().collect())?;
    let usage = "usage: fem_memory NR NZ [neo-hookean|muscle] [Q2Q1|Q1P0] [--stretches L1,L2,…]";
    let (nr, nz): (usize, usize) = (
        args.get(1).ok_or(usage)?.parse()?,
        args.get(2).ok_or(usage)?.parse()?,
    );
    let element: Element = args.get(4).map_or(Ok(Element::Q2Q1), |e| e.parse())?;
    match args.get(3).map(String::as_str) {
        None | Some("muscle") => {
            let muscle = Muscle::new(
                GiantesioMusesti::paper(),
                Law::Explicit(ExplicitLaw::paper()),
                0.0,
                Coupling::Frozen(FrozenTangent::Exact),
            )?;
            run(&muscle, nr, nz, element, &targets)
        }
        Some("neo-hookean") => run(&NeoHookean::new(5.0)?, nr, nz, element, &targets),
        Some(_) => Err(usage.into()),
    }
}
