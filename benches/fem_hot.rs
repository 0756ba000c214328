//! FE hot paths on fixed meshes, for before/after comparisons of a change to `src/fem`:
//! element assembly (residual only, residual + tangent), sparse LU factorisation and solve, and
//! one whole load step (λ = 1 → 1.05: reference state, predictor, Newton with the default
//! linear solver). Material: the chapter's muscle with the explicit law, frozen exact tangent
//! (the paper's FE model); the neo-Hookean verification material isolates the FE machinery.
//! State: the converged clamped cylinder at λ = 1.17 (R = 1, L = 4, grading 3).
//!
//! `cargo bench --bench fem_hot`; medians land in target/criterion/<group>/<id>/new/estimates.json.
//! See BENCHMARKS.md for the figures.

use activemuscle::active::{Coupling, ExplicitLaw, FrozenTangent, Law};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::fem::assembly::Assembler;
use activemuscle::fem::dofs::DofMap;
use activemuscle::fem::linear::SparseLu;
use activemuscle::fem::{
    AxisymmetricMaterial, AxisymmetricSolver, Bases, Mesh, NeoHookean, SolverOptions,
};
use activemuscle::Muscle;
use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use std::hint::black_box;
use std::time::Duration;

fn muscle() -> Muscle<GiantesioMusesti> {
    Muscle::new(
        GiantesioMusesti::paper(),
        Law::Explicit(ExplicitLaw::paper()),
        0.0,
        Coupling::Frozen(FrozenTangent::Exact),
    )
    .expect("the chapter's parameters are valid")
}

fn mesh(nr: usize, nz: usize) -> Mesh {
    Mesh::structured(1.0, 4.0, nr, nz, 3.0).expect("valid mesh")
}

/// The converged clamped state at λ = 1.17 on an nr × nz mesh, with the assembler at that state.
fn state<M: AxisymmetricMaterial>(material: &M, nr: usize, nz: usize) -> (Assembler, Vec<f64>) {
    let mut solver = AxisymmetricSolver::new(
        mesh(nr, nz),
        Bases::Clamped,
        material,
        SolverOptions::default(),
    )
    .expect("solver");
    let r = solver
        .sweep(&[1.17])
        .expect("sweep")
        .into_result()
        .expect("converges");
    let m = mesh(nr, nz);
    let dofs = DofMap::new(&m, Bases::Clamped);
    let mut asm = Assembler::new(&m, &dofs).expect("assembler");
    let x = r[0].state.x.clone();
    asm.assemble(&x, material, true).expect("assembles");
    (asm, x)
}

const MESHES: [(usize, usize); 2] = [(8, 32), (16, 64)];

fn bench(c: &mut Criterion) {
    let m = muscle();
    let nh = NeoHookean::new(5.0).expect("valid");
    let mut g = c.benchmark_group("fem_assembly");
    for (nr, nz) in MESHES {
        let (mut asm, x) = state(&m, nr, nz);
        let id = format!("{nr}x{nz}_{}dofs", asm.pattern.n);
        g.bench_function(BenchmarkId::new("muscle_tangent", &id), |b| {
            b.iter(|| asm.assemble(black_box(&x), &m, true).expect("ok"))
        });
        g.bench_function(BenchmarkId::new("muscle_residual", &id), |b| {
            b.iter(|| asm.assemble(black_box(&x), &m, false).expect("ok"))
        });
        g.bench_function(BenchmarkId::new("neo_hookean_tangent", &id), |b| {
            b.iter(|| asm.assemble(black_box(&x), &nh, true).expect("ok"))
        });
    }
    g.finish();

    let mut g = c.benchmark_group("fem_linear");
    for (nr, nz) in MESHES {
        let (asm, _) = state(&m, nr, nz);
        let id = format!("{nr}x{nz}_{}dofs", asm.pattern.n);
        let mut lu = SparseLu::new(&asm.pattern).expect("symbolic");
        g.bench_function(BenchmarkId::new("lu_factorise", &id), |b| {
            b.iter(|| {
                lu.factorise(&asm.pattern, black_box(&asm.values))
                    .expect("ok")
            })
        });
        lu.factorise(&asm.pattern, &asm.values).expect("ok");
        let rhs: Vec<f64> = asm.residual[..asm.pattern.n].to_vec();
        let mut y = rhs.clone();
        g.bench_function(BenchmarkId::new("lu_solve", &id), |b| {
            b.iter(|| {
                y.copy_from_slice(&rhs);
                lu.solve_in_place(black_box(&mut y)).expect("ok")
            })
        });
    }
    g.finish();

    let mut g = c.benchmark_group("fem_step");
    g.sample_size(10);
    for (nr, nz) in [(4, 16), (8, 32)] {
        let id = format!("{nr}x{nz}");
        g.bench_function(BenchmarkId::new("muscle_clamped_1_to_1.05", &id), |b| {
            b.iter(|| {
                let mut s = AxisymmetricSolver::new(
                    mesh(nr, nz),
                    Bases::Clamped,
                    &m,
                    SolverOptions::default(),
                )
                .expect("solver");
                s.sweep(black_box(&[1.05])).expect("sweep")
            })
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default()
        .sample_size(20)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_millis(2000));
    targets = bench
}
criterion_main!(benches);
