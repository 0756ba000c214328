//! The nearly incompressible cylinder (Ψ + U(J) by the perturbed Lagrangian): exact tangent with
//! the pressure block (Taylor test), quadratic Newton, sliding bases = the 0D compressible curve,
//! and convergence to the exactly incompressible solution as κ grows, for both elements.

use activemuscle::fem::assembly::Assembler;
use activemuscle::fem::dofs::DofMap;
use activemuscle::fem::{AxisymmetricSolver, Bases, Element, Mesh, NeoHookean, SolverOptions};
use activemuscle::models::{CouplingKind, LawKind, ModelChoice, Models};
use activemuscle::uniaxial::{nearly_incompressible, reference_stress, Direction};
use activemuscle::volumetric::{Volumetric, VolumetricForm};

use crate::common;
use common::NonSymmetric;

const MU: f64 = 2.5; // kPa

fn wiggle(k: usize) -> f64 {
    ((k as f64 + 1.0) * 12.9898).sin() * 0.5 + ((k as f64 + 3.0) * 78.233).sin() * 0.5
}

fn forms(kappa: f64) -> [VolumetricForm; 3] {
    [
        VolumetricForm::Quadratic { kappa },
        VolumetricForm::Logarithmic { kappa },
        VolumetricForm::Giantesio4C {
            kappa: (2.0 * kappa / MU - 1.0) / 2.0,
            mu: MU,
        },
    ]
}

/// Taylor test of the assembled residual and tangent, pressure–pressure block included, on a
/// general (non-equilibrium) state of a Q1/P0 clamped cylinder (no condensation, so the system
/// matrix is K itself): ‖R(x + h v) − R(x) − h K v‖ falls as h² (ratio 100 per decade of h).
#[test]
fn penalised_tangent_passes_the_taylor_test() {
    let material = NonSymmetric {
        mu: MU,
        c: 1.5,
        approximate: false,
    };
    for form in forms(4.0 * MU) {
        let vol = Volumetric::new(form, MU).unwrap();
        let mesh = Mesh::structured(1.0, 2.0, 3, 4, 2.0)
            .unwrap()
            .with_element(Element::Q1P0);
        let dofs = DofMap::new(&mesh, Bases::Clamped);
        let mut asm = Assembler::with_volumetric(&mesh, &dofs, Some(vol)).unwrap();
        assert!(!asm.is_condensed());
        let mut x = vec![0.0; dofs.n_total];
        dofs.apply_stretch(&mut x, 1.2);
        for (k, xi) in x[..dofs.n_free].iter_mut().enumerate() {
            *xi = if k < dofs.n_free_u {
                0.03 * wiggle(k)
            } else {
                2.0 * (1.0 + 0.3 * wiggle(k))
            };
        }
        let n = dofs.n_free;
        let v: Vec<f64> = (0..n).map(|k| wiggle(k + 1000)).collect();
        asm.assemble(&x, &material, true).unwrap();
        let r0 = asm.residual[..n].to_vec();
        let mut kv = vec![0.0; n];
        let p = asm.pattern.clone();
        for (j, vj) in v.iter().enumerate() {
            for k in p.col_ptr[j] as usize..p.col_ptr[j + 1] as usize {
                kv[p.row_idx[k] as usize] += asm.values[k] * vj;
            }
        }
        let remainder = |asm: &mut Assembler, h: f64| {
            let mut y = x.clone();
            for (yi, vi) in y[..n].iter_mut().zip(&v) {
                *yi += h * vi;
            }
            asm.assemble(&y, &material, false).unwrap();
            let worst = |rows: std::ops::Range<usize>| {
                rows.map(|i| (asm.residual[i] - r0[i] - h * kv[i]).abs())
                    .fold(0.0f64, f64::max)
            };
            [worst(0..dofs.n_free_u), worst(dofs.n_free_u..n)]
        };
        let e: Vec<[f64; 2]> = [1e-2, 1e-3, 1e-4]
            .iter()
            .map(|&h| remainder(&mut asm, h))
            .collect();
        println!("{}: Taylor remainders (u rows, p rows) {e:?}", form.name());
        // Both the displacement rows and the pressure rows (J − J̃(p), K_pp) are second order.
        for block in 0..2 {
            for w in e.windows(2) {
                let ratio = w[0][block] / w[1][block];
                assert!((70.0..140.0).contains(&ratio), "{form:?}: {e:?}");
            }
        }
    }
}

/// One large load step 1 → 1.15 of a clamped cylinder of the chapter's active muscle (explicit
/// law, frozen: non-symmetric exact tangent) with a stiff volumetric energy (U″(1) = 10⁴ kPa):
/// Newton converges quadratically with the assembled tangent, both elements, every form.
#[test]
fn newton_converges_quadratically_with_the_penalty() {
    let muscle = chapter_muscle();
    let mu = 0.1599;
    let bulk = 1e4;
    let chapter_forms = [
        VolumetricForm::Quadratic { kappa: bulk },
        VolumetricForm::Logarithmic { kappa: bulk },
        VolumetricForm::Giantesio4C {
            kappa: (2.0 * bulk / mu - 1.0) / 2.0,
            mu,
        },
    ];
    for element in Element::ALL {
        for form in chapter_forms {
            let options = SolverOptions {
                stepping: common::large_steps(0.15),
                element,
                volumetric: Some(Volumetric::new(form, 0.0).unwrap()),
                ..SolverOptions::default()
            };
            let mesh = Mesh::structured(1.0, 4.0, 3, 8, 1.0).unwrap();
            let mut solver =
                AxisymmetricSolver::new(mesh, Bases::Clamped, &muscle, options).unwrap();
            let sweep = solver.sweep(&[1.15]).unwrap();
            assert!(sweep.failures.is_empty(), "{:?}", sweep.failures);
            let steps = &sweep.results[0].steps;
            assert_eq!(steps.len(), 1, "the step must not be cut");
            let r = common::residuals(&steps[0]);
            let orders = common::observed_orders(&r);
            println!(
                "{element} {}: residuals {r:?}, orders {orders:?}",
                form.name()
            );
            let last = *orders.last().expect("three iterates above the floor");
            assert!(last >= 1.8, "{element} {form:?}: order {last} ({r:?})");
        }
    }
}

fn chapter_muscle() -> activemuscle::Muscle<activemuscle::Energy> {
    Models::paper()
        .muscle(ModelChoice {
            approach: activemuscle::active::Approach::ActiveStrain,
            law: LawKind::Explicit,
            coupling: CouplingKind::Frozen,
            damage: 0.0,
        })
        .unwrap()
}

/// Sliding bases: the FE solution is the homogeneous nearly incompressible state, so its
/// nominal stress equals the 0D curve of [`nearly_incompressible`] and every node moves as
/// u_r = (t − 1) r, u_z = (λ − 1) z with the 0D lateral stretch t, for the chapter's active
/// muscle (explicit law, frozen), both elements, every form.
#[test]
fn sliding_cylinder_equals_the_0d_compressible_curve() {
    let muscle = chapter_muscle();
    let s0 = reference_stress(muscle.energy()).unwrap();
    let mu = 0.1599;
    let targets = [0.9, 1.0, 1.1, 1.2];
    for element in Element::ALL {
        let chapter_forms = [
            VolumetricForm::Quadratic { kappa: 500.0 },
            VolumetricForm::Logarithmic { kappa: 500.0 },
            VolumetricForm::Giantesio4C { kappa: 200.0, mu },
        ];
        for form in chapter_forms {
            let vol = Volumetric::new(form, s0).unwrap();
            let options = SolverOptions {
                element,
                volumetric: Some(vol),
                ..SolverOptions::default()
            };
            let mesh = Mesh::structured(1.0, 4.0, 2, 4, 1.0).unwrap();
            let mut solver =
                AxisymmetricSolver::new(mesh, Bases::Sliding, &muscle, options).unwrap();
            let results = solver.sweep(&targets).unwrap().into_result().unwrap();
            let (mesh, dofs) = (solver.mesh().clone(), solver.dofs().clone());
            for res in &results {
                let l = res.stretch;
                let zero_d = nearly_incompressible(&muscle, &vol, Direction::Along, l).unwrap();
                let scale = zero_d.stress.abs().max(1.0);
                let err = (res.nominal_stress - zero_d.stress).abs();
                println!(
                    "{element} {} λ = {l}: P_FE = {:.10e}, P_0D = {:.10e}",
                    form.name(),
                    res.nominal_stress,
                    zero_d.stress
                );
                assert!(err < 1e-8 * scale, "{element} {form:?} λ = {l}: {err:e}");
                let t = zero_d.lateral[0];
                let mut worst = 0.0f64;
                for (node, x) in mesh.nodes.iter().enumerate() {
                    let d = dofs.node_u[node];
                    let ur = res.state.x[d[0] as usize];
                    let uz = res.state.x[d[1] as usize];
                    worst = worst
                        .max((ur - (t - 1.0) * x[0]).abs())
                        .max((uz - (l - 1.0) * x[1]).abs());
                }
                assert!(worst < 1e-9, "{element} λ = {l}: nodal error {worst:e}");
            }
        }
    }
}

/// Clamped bases (non-homogeneous): the nearly incompressible reaction tends to the exactly
/// incompressible one on the same mesh as O(1/κ), tenfold per decade of κ (±25 %), over three
/// decades, both elements: the mixed form stays well posed as κ grows.
#[test]
fn clamped_cylinder_converges_to_the_incompressible_one() {
    let material = NeoHookean::new(MU).unwrap();
    let l = 1.25;
    for element in Element::ALL {
        let solve = |volumetric: Option<Volumetric>| {
            let options = SolverOptions {
                element,
                volumetric,
                ..SolverOptions::default()
            };
            let mesh = Mesh::structured(1.0, 3.0, 3, 8, 1.0).unwrap();
            let mut solver =
                AxisymmetricSolver::new(mesh, Bases::Clamped, &material, options).unwrap();
            solver.sweep(&[l]).unwrap().into_result().unwrap()[0].nominal_stress
        };
        let exact = solve(None);
        let distance: Vec<f64> = [1e2, 1e3, 1e4, 1e5]
            .iter()
            .map(|&k| {
                let vol = Volumetric::new(VolumetricForm::Quadratic { kappa: k * MU }, MU).unwrap();
                (solve(Some(vol)) - exact).abs()
            })
            .collect();
        println!("{element}: |P_κ − P| = {distance:?} (P = {exact})");
        for w in distance.windows(2) {
            let ratio = w[0] / w[1];
            assert!((8.0..12.5).contains(&ratio), "{element}: {distance:?}");
        }
    }
}
