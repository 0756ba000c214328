//! Mesh study of the clamped neo-Hookean cylinder at λ = 1.17 (nominal stress and max |J − 1|).
//! Run: `cargo run --profile test --example fem_clamped_study`.

use activemuscle::fem::{AxisymmetricSolver, Bases, Mesh, NeoHookean, SolverOptions};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let material = NeoHookean::new(5.0)?;
    for grading in [1.0, 4.0] {
        for (nr, nz) in [(2, 8), (4, 16), (8, 32), (16, 64), (32, 128)] {
            let mesh = Mesh::structured(1.0, 4.0, nr, nz, grading)?;
            let mut solver =
                AxisymmetricSolver::new(mesh, Bases::Clamped, &material, SolverOptions::default())?;
            let res = solver.sweep(&[1.17])?.into_result()?;
            println!(
                "grading {grading}: {nr:>3} × {nz:<4} P = {:.10} kPa, max |J − 1| = {:.2e}",
                res[0].nominal_stress, res[0].max_volume_error
            );
        }
    }
    Ok(())
}
