//! Time per Newton iteration (assembly, factorisation, solve) against the number of dofs, for
//! the clamped neo-Hookean cylinder stretched to λ = 1.17 in one load step, for both elements:
//! Q2/Q1 and Q1/P0 on the same cells, and Q1/P0 on cells halved in both directions (the same
//! displacement nodes as Q2/Q1, so similar dofs).
//!
//! Run: `cargo run --release --example fem_scaling`.

use activemuscle::fem::{AxisymmetricSolver, Bases, Element, Mesh, NeoHookean, SolverOptions};
use std::time::Instant;

/// Peak resident memory of the process so far (VmHWM) in MiB, if available.
fn peak_memory_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let material = NeoHookean::new(5.0)?;
    println!(
        "threads: {} (rayon), faer parallelism: {:?}",
        rayon::current_num_threads(),
        faer::get_global_parallelism()
    );
    println!(
        "{:>7} {:>9} {:>9} {:>6} {:>11} {:>11} {:>11} {:>11} {:>9} {:>10} {:>12} {:>12} {:>11}",
        "element",
        "mesh",
        "dofs",
        "iters",
        "assembly/s",
        "factor/s",
        "solve/s",
        "iter/s",
        "setup/s",
        "VmHWM/MiB",
        "gmres/solve",
        "LU fallback",
        "P/kPa"
    );
    for (nr, nz) in [(5, 20), (8, 32), (16, 64), (32, 128), (48, 192), (64, 256)] {
        for (element, nr, nz) in [
            (Element::Q2Q1, nr, nz),
            (Element::Q1P0, nr, nz),
            (Element::Q1P0, 2 * nr, 2 * nz),
        ] {
            let t0 = Instant::now();
            let mesh = Mesh::structured(1.0, 4.0, nr, nz, 1.0)?;
            let options = SolverOptions {
                initial_step: 0.17,
                max_step: 0.17,
                element,
                ..SolverOptions::default()
            };
            let mut solver = AxisymmetricSolver::new(mesh, Bases::Clamped, &material, options)?;
            let setup = t0.elapsed().as_secs_f64();
            let results = solver.sweep(&[1.17])?.into_result()?;
            let t = solver.timings();
            let per = |d: std::time::Duration, n: usize| d.as_secs_f64() / n.max(1) as f64;
            let (a, f, s) = (
                per(t.assembly, t.assemblies),
                per(t.factorisation, t.factorisations),
                per(t.solve, t.solves),
            );
            println!(
                "{:>7} {:>9} {:>9} {:>6} {:>11.4} {:>11.4} {:>11.4} {:>11.4} {:>9.3} {:>10.0} {:>12.1} {:>12} {:>11.6}",
                element.name(),
                format!("{nr}x{nz}"),
                solver.n_free_dofs(),
                t.factorisations,
                a,
                f,
                s,
                a + f + s,
                setup,
                peak_memory_mib().unwrap_or(f64::NAN),
                t.krylov_iterations as f64 / t.solves.max(1) as f64,
                t.lu_fallbacks,
                results[0].nominal_stress
            );
        }
    }
    Ok(())
}
