//! Time per Newton iteration (assembly, factorisation, solve) against the number of dofs, for
//! the clamped neo-Hookean cylinder (R = 1, L = 4, μ = 5 kPa) stretched to λ = 1.17 in one load
//! step (one factorisation per Newton iteration; see `activemuscle::fem::tangent_solver`): Q2/Q1,
//! and Q1/P0 on the same cells and on cells halved in both directions (the same displacement
//! nodes as Q2/Q1, so similar dofs).
//!
//! The reference, legacy FEniCS on the same problem and the same dofs, is measured by
//! `python/bench/fe_per_iteration.py`, which alternates its runs with this example's one-case mode
//! (BENCHMARKS.md, "Against legacy FEniCS").
//!
//! Run: `cargo run --release --example fem_scaling`. One case, for a driver that alternates with
//! another code (`python/bench/fe_per_iteration.py`): `fem_scaling Q2Q1 16 64` prints one line
//! `ours <element> <nr>x<nz> dofs <free> its <n> assembly <s> factor <s> solve <s> iteration <s>
//! P <kPa>`, every time the phase's total divided by the Newton iterations (assembly includes the
//! line search's residual-only assemblies), P to 12 digits.

use activemuscle::fem::{
    AxisymmetricSolver, Bases, Element, Mesh, NeoHookean, SolverOptions, Stepping, Timings,
};
use std::time::Instant;

/// Peak resident memory of the process so far (VmHWM) in MiB, if available.
fn peak_memory_mib() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
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
        stepping: Stepping {
            initial_step: 0.17,
            max_step: 0.17,
            ..Stepping::default()
        },
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

/// `fem_scaling ELEMENT NR NZ`: one case, one machine-readable line (see the module doc).
fn single(args: &[String]) -> Result<(), Box<dyn std::error::Error>> {
    let usage = "usage: fem_scaling [Q2Q1|Q1P0 NR NZ]";
    let [element, nr, nz] = args else {
        return Err(usage.into());
    };
    let element = match element.as_str() {
        "Q2Q1" => Element::Q2Q1,
        "Q1P0" => Element::Q1P0,
        other => return Err(format!("element {other:?}: {usage}").into()),
    };
    let cells = |s: &String| -> Result<usize, String> {
        s.parse()
            .map_err(|_| format!("cell count {s:?} is not a positive integer: {usage}"))
    };
    let (nr, nz) = (cells(nr)?, cells(nz)?);
    let r = run(element, nr, nz)?;
    let t = &r.timings;
    let per = |d: std::time::Duration| d.as_secs_f64() / t.newton_iterations.max(1) as f64;
    println!(
        "ours {} {nr}x{nz} dofs {} its {} assembly {:.6} factor {:.6} solve {:.6} iteration {:.6} P {:.12}",
        element.name().replace('/', ""),
        r.dofs,
        t.newton_iterations,
        per(t.assembly + t.residual_assembly),
        per(t.factorisation),
        per(t.solve),
        t.per_newton_iteration(),
        r.stress,
    );
    Ok(())
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    if !args.is_empty() {
        return single(&args);
    }
    println!(
        "threads: {} (rayon, element loop); factorisations sequential",
        rayon::current_num_threads()
    );
    println!(
        "{:>6} {:>8} {:>7} {:>4} {:>5} {:>5} {:>10} {:>9} {:>8} {:>11} {:>7} {:>6} {:>9}",
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
                "{:>6} {:>8} {:>7} {:>4} {:>5} {:>5.1} {:>10.4} {:>9.4} {:>8.4} {:>11.4} {:>7.3} {:>6.0} {:>9.6}",
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
                r.stress,
            );
        }
    }
    Ok(())
}
