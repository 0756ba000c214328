//! Time per Newton iteration (assembly, factorisation, solve) against the number of dofs, for
//! the clamped neo-Hookean cylinder (R = 1, L = 4, μ = 5 kPa) stretched to λ = 1.17 in one load
//! step (one factorisation per Newton iteration; see `activemuscle::fem::tangent_solver`): Q2/Q1,
//! and Q1/P0 on the same cells and on cells halved in both directions (the same displacement
//! nodes as Q2/Q1, so similar dofs).
//!
//! Anchor (issue #3): a mature Python/C++ FE framework (generated kernels, UMFPACK LU) needs
//! ≈ 0.13 s per Newton iteration at 9.6k dofs and ≈ 1 s at 37.7k dofs (P2/P1) on this 2-core
//! machine; the column `anchor/x` is that anchor (interpolated through its two points as a power
//! of the dofs) divided by our time.
//!
//! Run: `cargo run --release --example fem_scaling`.

use activemuscle::fem::{
    AxisymmetricSolver, Bases, Element, Mesh, NeoHookean, SolverOptions, Timings,
};
use std::time::Instant;

/// Peak resident memory of the process so far (VmHWM) in MiB, if available.
fn peak_memory_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

/// The anchor's seconds per Newton iteration at `dofs` (through its two measured points).
fn anchor_seconds(dofs: usize) -> f64 {
    let (d0, t0, d1, t1) = (9.6e3f64, 0.13f64, 37.7e3f64, 1.0f64);
    let slope = (t1 / t0).ln() / (d1 / d0).ln();
    t0 * (dofs as f64 / d0).powf(slope)
}

struct Run {
    dofs: usize,
    setup: f64,
    timings: Timings,
    stress: f64,
}

fn run(element: Element, nr: usize, nz: usize) -> Result<Run, Box<dyn std::error::Error>> {
    let material = NeoHookean::new(5.0)?;
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
    Ok(Run {
        dofs: solver.n_free_dofs(),
        setup,
        timings: solver.timings(),
        stress: results[0].nominal_stress,
    })
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    println!(
        "threads: {} (rayon, element loop); factorisations sequential",
        rayon::current_num_threads()
    );
    println!(
        "{:>6} {:>8} {:>7} {:>4} {:>5} {:>5} {:>10} {:>9} {:>8} {:>11} {:>7} {:>6} {:>8} {:>9}",
        "elem",
        "mesh",
        "dofs",
        "its",
        "facts",
        "gmres",
        "assembly/s",
        "factor/s",
        "solve/s",
        "s/iteration",
        "setup/s",
        "MiB",
        "anchor/x",
        "P/kPa"
    );
    for (nr, nz) in [(5, 20), (8, 32), (16, 64), (32, 128), (48, 192), (64, 256)] {
        for (element, nr, nz) in [
            (Element::Q2Q1, nr, nz),
            (Element::Q1P0, nr, nz),
            (Element::Q1P0, 2 * nr, 2 * nz),
        ] {
            let r = run(element, nr, nz)?;
            let t = &r.timings;
            let per = |d: std::time::Duration, n: usize| d.as_secs_f64() / n.max(1) as f64;
            let it = t.per_newton_iteration();
            println!(
                "{:>6} {:>8} {:>7} {:>4} {:>5} {:>5.1} {:>10.4} {:>9.4} {:>8.4} {:>11.4} {:>7.3} {:>6.0} {:>8.1} {:>9.6}",
                element.name(),
                format!("{nr}x{nz}"),
                r.dofs,
                t.newton_iterations,
                t.factorisations,
                t.krylov_iterations as f64 / t.solves.max(1) as f64,
                per(t.assembly, t.assemblies),
                per(t.factorisation, t.factorisations),
                per(t.solve, t.solves),
                it,
                r.setup,
                peak_memory_mib().unwrap_or(f64::NAN),
                anchor_seconds(r.dofs) / it,
                r.stress,
            );
        }
    }
    Ok(())
}
