//! Time of one assembly of the clamped neo-Hookean cylinder (R = 1, L = 4, μ = 5 kPa, Q2/Q1,
//! a stretched and perturbed state), tangent and residual only: the minimum over `REPEATS`
//! assemblies, the figure least disturbed by a shared machine. Run on one thread to time the
//! element loop and the gather alone:
//!
//!     RAYON_NUM_THREADS=1 cargo run --release --example fem_assembly -- 16 64 400
//!
//! A fourth argument `muscle` assembles the chapter's muscle instead (frozen explicit law,
//! exact tangent, d = 0) at its converged clamped state at λ = 1.17.
//!
//! prints `<nr>x<nz> tangent <ms> residual <ms> checksum <Σ values + Σ residual>` (the checksum
//! tells whether a change to the assembly changed its numbers), then the pattern LU's
//! factorisation of that tangent, the minimum and the median over `REPEATS` (on rayon's threads,
//! two cores if it has them, as in the sweep): `pattern LU factorise <ms> median <ms>`.

use activemuscle::active::{Coupling, ExplicitLaw, FrozenTangent, Law};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::fem::assembly::Assembler;
use activemuscle::fem::dofs::DofMap;
use activemuscle::fem::ldlt::SymmetricPartLdlt;
use activemuscle::fem::pattern_lu::PatternLu;
use activemuscle::fem::{
    AxisymmetricMaterial, AxisymmetricSolver, Bases, Mesh, NeoHookean, SolverOptions,
};
use activemuscle::Muscle;
use std::time::Instant;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |i: usize, default: usize| -> Result<usize, String> {
        args.get(i).map_or(Ok(default), |s| {
            s.parse().map_err(|_| {
                format!("argument {s:?}: usage fem_assembly [NR NZ REPEATS [neo-hookean|muscle]]")
            })
        })
    };
    let (nr, nz, repeats) = (arg(0, 16)?, arg(1, 64)?, arg(2, 100)?.max(1));
    let mesh = Mesh::structured(1.0, 4.0, nr, nz, 1.0)?;
    let dofs = DofMap::new(&mesh, Bases::Clamped);
    let mut assembler = Assembler::new(&mesh, &dofs)?;
    let material: Box<dyn AxisymmetricMaterial> = match args.get(3).map(String::as_str) {
        None | Some("neo-hookean") => Box::new(NeoHookean::new(5.0)?),
        Some("muscle") => Box::new(Muscle::new(
            GiantesioMusesti::paper(),
            Law::Explicit(ExplicitLaw::paper()),
            0.0,
            Coupling::Frozen(FrozenTangent::Exact),
        )?),
        Some(other) => return Err(format!("material {other:?}: neo-hookean or muscle").into()),
    };
    let x = match args.get(3).map(String::as_str) {
        Some("muscle") => {
            let mut solver = AxisymmetricSolver::new(
                mesh.clone(),
                Bases::Clamped,
                material.as_ref(),
                SolverOptions::default(),
            )?;
            let solved = solver.sweep(&[1.17])?.into_result()?;
            solved[0].state.x.clone()
        }
        _ => {
            let mut x = vec![0.0; dofs.n_total];
            dofs.apply_stretch(&mut x, 1.17);
            for (i, v) in x.iter_mut().enumerate().take(dofs.n_free) {
                *v = 1e-3 * ((i % 7) as f64 - 3.0);
            }
            x
        }
    };
    let mut fastest = |tangent: bool| -> Result<f64, activemuscle::Error> {
        let mut best = f64::INFINITY;
        for _ in 0..repeats {
            let t = Instant::now();
            assembler.assemble(&x, material.as_ref(), tangent)?;
            best = best.min(t.elapsed().as_secs_f64());
        }
        Ok(best)
    };
    let (tangent, residual) = (fastest(true)?, fastest(false)?);
    let checksum: f64 =
        assembler.values.iter().sum::<f64>() + assembler.residual.iter().sum::<f64>();
    println!(
        "{nr}x{nz} tangent {:.3} ms residual {:.3} ms checksum {checksum:.15e}",
        tangent * 1e3,
        residual * 1e3
    );
    assembler.assemble(&x, material.as_ref(), true)?;
    let pattern = &assembler.pattern;
    let ldlt = SymmetricPartLdlt::for_mesh(pattern, &mesh, &dofs, assembler.system_index())?;
    let mut lu = PatternLu::new(pattern, ldlt.symbolic(), ldlt.perm())?;
    let mut times = Vec::with_capacity(repeats);
    for _ in 0..repeats {
        let t = Instant::now();
        lu.factorise(&assembler.values)?;
        times.push(t.elapsed().as_secs_f64());
    }
    times.sort_by(f64::total_cmp);
    println!(
        "pattern LU factorise {:.3} ms median {:.3} ms",
        times[0] * 1e3,
        times[repeats / 2] * 1e3
    );
    Ok(())
}
