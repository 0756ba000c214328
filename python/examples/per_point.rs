//! The Rust yardstick of the Python bench (python/bench/bench.py): the same material points,
//! evaluated by `Muscle::respond` in a plain Rust loop with P, A and dP/dγ stored per point, serial
//! and on rayon's threads. Prints `rust_serial_ns N` and `rust_parallel_ns N` per point.
//!
//! `cargo run --release --manifest-path python/Cargo.toml --example per_point -- N LAW`

use _native::model::named;
use activemuscle::invariants::{Kinematics, FULL};
use activemuscle::models::{CouplingKind, ModelChoice, Models};
use activemuscle::response::Order;
use nalgebra::{Matrix3, Vector3};
use rayon::prelude::*;
use std::time::Instant;

/// Point p of n: a stretch λ ∈ [0.8, 1.4] along e₁, isochoric (the bench's F).
fn deformation(p: usize, n: usize) -> Matrix3<f64> {
    let lambda = 0.8 + 0.6 * p as f64 / (n.max(2) - 1) as f64;
    Matrix3::from_diagonal(&Vector3::new(lambda, lambda.powf(-0.5), lambda.powf(-0.5)))
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().collect();
    let n: usize = args
        .get(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(100_000);
    let law = named("law", args.get(2).map_or("explicit", String::as_str))?;
    let material = Models::paper().muscle(ModelChoice {
        approach: activemuscle::active::Approach::ActiveStrain,
        law,
        coupling: CouplingKind::Frozen,
        damage: 0.0,
    })?;
    let m = Vector3::new(1.0, 0.0, 0.0);
    let f: Vec<Matrix3<f64>> = (0..n).map(|p| deformation(p, n)).collect();
    let run = |out: &mut [f64], p: usize| -> Result<(), activemuscle::Error> {
        let r = material.respond(&Kinematics::new(&f[p], &m)?, Order::Tangent, &FULL)?;
        let (s, t, d) = (
            r.stress.unwrap_or_default(),
            r.tangent.unwrap_or_default(),
            r.dstress_dgamma.unwrap_or_default(),
        );
        out[..9].copy_from_slice(s.as_slice());
        out[9..90].copy_from_slice(t.as_slice());
        out[90..99].copy_from_slice(d.as_slice());
        out[99] = r.gamma;
        Ok(())
    };
    // Output buffers allocated once: from the second round on, Rust writes into warm memory
    // (the Python call allocates fresh numpy arrays every time: a strict yardstick).
    let (mut serial, mut parallel) = (vec![0.0; 100 * n], vec![0.0; 100 * n]);
    for _ in 0..3 {
        let out = &mut serial;
        let start = Instant::now();
        for (p, o) in out.chunks_mut(100).enumerate() {
            run(o, p)?;
        }
        println!(
            "rust_serial_ns {:.1}",
            start.elapsed().as_secs_f64() * 1e9 / n as f64
        );
        let start = Instant::now();
        parallel
            .par_chunks_mut(100)
            .enumerate()
            .try_for_each(|(p, o)| run(o, p))?;
        println!(
            "rust_parallel_ns {:.1}",
            start.elapsed().as_secs_f64() * 1e9 / n as f64
        );
    }
    Ok(())
}
