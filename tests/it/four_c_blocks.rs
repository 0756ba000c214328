//! 4C's active muscle cubes as scenes (issue 23, item 4): `scenes/examples/4c_*_block.toml` run
//! through the binary's scene path, against references derived here, independently of the
//! crate's laws, maps and solvers: the homogeneous block F = diag(b, b, λ) with the fibre along
//! e₃, 4C's stress formulas written out (src/mat/4C_mat_muscle_weickenmeier.cpp and
//! 4C_mat_muscle_giantesio.cpp, as transcribed), ω of the structural approach by 4C's Lambert W
//! closed form, γ of the volume-preserving map from the energy condition by bisection, the
//! twitch train summed by hand, and the equilibrium S = 0 solved by Newton on dual-number
//! gradients of the energy written here.

use activemuscle::scene::{RunOptions, Scene};
use activemuscle::studies::history::HistoryResult;
use activemuscle::studies::StudyResult;
use activemuscle::Scalar;
use num_dual::first_derivative;

/// 4C's active-cube parameters (mat_muscle_weickenmeier_hex, MAT 2).
const MU: f64 = 0.1599;
const ALPHA: f64 = 19.69;
const BETA: f64 = 1.19;
const W0: f64 = 0.7388;
const KAPPA: f64 = 100.0;
const N_A: f64 = 0.005207;
const LAMBDA_MIN: f64 = 0.682;
const LAMBDA_OPT: f64 = 1.192;
const DT: f64 = 1e-4;
const STEPS: usize = 150;

/// 4C's twitch superposition at t (stimuli at 0, 0.004, …, before t; schedule value 1).
fn twitch_level(t: f64) -> f64 {
    let units = [
        (0.05, 25.0, 0.02),
        (0.29, 44.0, 0.011),
        (0.66, 768.0, 0.011),
    ];
    let interstimulus = 0.004;
    let mut a = 0.0;
    for (rho, force, time) in units {
        let ratio: f64 = time / interstimulus;
        let gain = (1.0 - (-2.0 * ratio * ratio * ratio).exp()) / ratio;
        let mut sum = 0.0;
        let mut j = 0.0;
        while j * interstimulus < t {
            let x = (t - j * interstimulus) / time;
            sum += force * x * (1.0 - x).exp();
            j += 1.0;
        }
        a += rho * gain * sum;
    }
    a
}

/// Ehret's force–stretch curve as 4C writes it, and its integral.
fn f_xi(l: f64) -> (f64, f64) {
    if l <= LAMBDA_MIN {
        return (0.0, 0.0);
    }
    let d = LAMBDA_MIN - LAMBDA_OPT;
    let e = ((2.0 * LAMBDA_MIN - l - LAMBDA_OPT) * (l - LAMBDA_OPT) / (2.0 * d * d)).exp();
    (
        (l - LAMBDA_MIN) / (LAMBDA_OPT - LAMBDA_MIN) * e,
        d * (e - 0.5_f64.exp()),
    )
}

/// Böl & Reese's force–velocity factor as 4C writes it (λ̇_min = −17, k_e = k_c = 5).
fn f_v(rate: f64, de: f64, dc: f64) -> f64 {
    let (min, ke, kc) = (-17.0, 5.0, 5.0);
    let r = rate / min;
    if rate > 0.0 {
        (1.0 + de) - de * (1.0 + r) / (1.0 - ke * kc * r)
    } else {
        (1.0 - dc) + dc * (1.0 - r) / (1.0 + kc * r)
    }
}

/// The principal branch of Lambert's W by Newton from 1 (x > 0).
fn lambert_w(x: f64) -> f64 {
    let mut w: f64 = x.ln_1p().max(1e-3);
    for _ in 0..100 {
        let step = (w * w.exp() - x) / (w.exp() * (w + 1.0));
        w -= step;
        if step.abs() < 1e-16 * w.abs() {
            break;
        }
    }
    w
}

/// 4C's MAT_Muscle_Weickenmeier ω (evaluate_activation_level) for the active stress `pa`.
fn weickenmeier_omega(l: f64, pa: f64) -> f64 {
    if pa == 0.0 {
        return 0.0;
    }
    let ip1 = W0 / 3.0 * (2.0 * l - 2.0 / (l * l)) + 2.0 * (1.0 - W0) * l;
    let ip = W0 / 3.0 * (l * l + 2.0 / l) + (1.0 - W0) * l * l;
    let xi = pa * (2.0 * ALPHA * l / MU) * (0.5 * ALPHA * (2.0 - 2.0 * ip + l * ip1)).exp()
        + 0.5 * ALPHA * l * ip1 * (0.5 * ALPHA * l * ip1).exp();
    lambert_w(xi) / (ALPHA * l * l) - ip1 / (2.0 * l)
}

/// The diagonal of 4C's Weickenmeier second Piola–Kirchhoff stress at F = diag(b, b, λ) and ω
/// held (S_xx, S_zz), with 4C's coupled volumetric term.
fn weickenmeier_stress(b: f64, l: f64, omega: f64) -> [f64; 2] {
    let c = [b * b, l * l];
    let det = c[0] * c[0] * c[1];
    let lw = [W0 / 3.0, W0 / 3.0 + 1.0 - W0];
    let i = 2.0 * c[0] * lw[0] + c[1] * (lw[1] + omega);
    let j = det * (2.0 * lw[0] / c[0] + lw[1] / c[1]);
    let (ea, eb) = ((ALPHA * (i - 1.0)).exp(), (BETA * (j - 1.0)).exp());
    let s = |k: usize, lk: f64| {
        0.5 * MU
            * (ea * lk + eb * (j / c[k] - det * lw[k] / (c[k] * c[k])) - det.powf(-KAPPA) / c[k])
    };
    [s(0, lw[0]), s(1, lw[1] + omega)]
}

/// Newton on (b, λ) for `residual` = 0 with a central-difference Jacobian, from (1, 1).
fn solve(residual: impl Fn(f64, f64) -> [f64; 2], start: [f64; 2]) -> [f64; 2] {
    let mut x = start;
    for _ in 0..60 {
        let r = residual(x[0], x[1]);
        let h = 1e-7;
        let col = |k: usize| {
            let (mut p, mut m) = (x, x);
            p[k] += h;
            m[k] -= h;
            let (rp, rm) = (residual(p[0], p[1]), residual(m[0], m[1]));
            [(rp[0] - rm[0]) / (2.0 * h), (rp[1] - rm[1]) / (2.0 * h)]
        };
        let (a, c) = (col(0), col(1));
        let det = a[0] * c[1] - c[0] * a[1];
        let dx = [
            -(r[0] * c[1] - c[0] * r[1]) / det,
            -(a[0] * r[1] - r[0] * a[1]) / det,
        ];
        x = [x[0] + dx[0], x[1] + dx[1]];
        if dx[0].abs().max(dx[1].abs()) < 1e-15 {
            break;
        }
    }
    x
}

/// The block of 4C's Weickenmeier material at the end of the twitch train: (b, λ) at every
/// step, with the velocity dependence (d_e, d_c) (0, 0: none) by backward Euler.
fn weickenmeier_history(de: f64, dc: f64) -> Vec<f64> {
    let mut previous = 1.0;
    let mut stretches = vec![1.0];
    let mut x = [1.0, 1.0];
    for n in 1..=STEPS {
        let t = n as f64 * DT;
        let poptft = N_A * twitch_level(t);
        x = solve(
            |b, l| {
                let pa = poptft * f_xi(l).0 * f_v((l - previous) / DT, de, dc);
                weickenmeier_stress(b, l, weickenmeier_omega(l, pa))
            },
            x,
        );
        previous = x[1];
        stretches.push(x[1]);
    }
    stretches
}

/// 4C's MAT_Muscle_Giantesio energy at F = diag(b, b, λ) with the volume-preserving map at γ
/// and 4C's volumetric term, generic (dual numbers give its gradient).
fn giantesio_energy<T: Scalar>(b: T, l: T, gamma: T) -> T {
    let c = -gamma + 1.0;
    let ce = [b * b * c, l * l / (c * c)];
    let det = ce[0] * ce[0] * ce[1];
    let lw = [W0 / 3.0, W0 / 3.0 + 1.0 - W0];
    let ie = ce[0] * (2.0 * lw[0]) + ce[1] * lw[1];
    let je = det * (ce[0].recip() * (2.0 * lw[0]) + ce[1].recip() * lw[1]);
    let w = ((ie - 1.0) * ALPHA).exp() / ALPHA + ((je - 1.0) * BETA).exp() / BETA;
    let det_c = b.powi(4) * l * l;
    w * (MU / 4.0) + det_c.powf(-KAPPA) * (MU / (4.0 * KAPPA))
}

/// 4C's energy condition for γ (solve_activation_level_equation): the activated uniaxial
/// energy minus the passive one minus 4 ∫Pa/μ, on the incompressible uniaxial path.
fn giantesio_condition(l: f64, gamma: f64, work: f64) -> f64 {
    let x = 1.0 - 2.0 * W0 / 3.0;
    let y = 2.0 * W0 / 3.0;
    let c = 1.0 - gamma;
    let ie = x * l * l / (c * c) + y * c / l;
    let je = x * c * c / (l * l) + y * l / c;
    let ip = x * l * l + y / l;
    let jp = x / (l * l) + y * l;
    let lhs = (ALPHA * (ie - 1.0)).exp() / ALPHA + (BETA * (je - 1.0)).exp() / BETA;
    let rhs =
        4.0 * work / MU + (ALPHA * (ip - 1.0)).exp() / ALPHA + (BETA * (jp - 1.0)).exp() / BETA;
    lhs - rhs
}

/// γ(λ) of the energy condition: the first sign change above 0 by steps, then bisection.
fn giantesio_gamma(l: f64, poptft: f64) -> f64 {
    let work = poptft * f_xi(l).1;
    if work <= 0.0 {
        return 0.0;
    }
    let f = |g: f64| giantesio_condition(l, g, work);
    let (mut lo, mut hi) = (0.0, 0.0);
    for k in 1..1000 {
        hi = k as f64 * 1e-3;
        if f(hi) > 0.0 {
            break;
        }
        lo = hi;
    }
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if f(mid) > 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The Giantesio block at t = 0.015 s: the stationary point of Ψ(b, λ) = Ŵ(b, λ, γ(λ)) + U,
/// ∂Ψ/∂b = 0 and ∂Ψ/∂λ + ∂Ψ/∂γ γ′(λ) = 0, γ′ by central differences of the bisection
/// (h = 1e-6 λ, as 4C).
fn giantesio_final_stretch() -> f64 {
    let poptft = N_A * twitch_level(STEPS as f64 * DT);
    let x = solve(
        |b, l| {
            let g = giantesio_gamma(l, poptft);
            let h = 1e-6 * l;
            let slope =
                (giantesio_gamma(l + h, poptft) - giantesio_gamma(l - h, poptft)) / (2.0 * h);
            let db = first_derivative(|b| giantesio_energy(b, l.into(), g.into()), b).1;
            let dl = first_derivative(|l| giantesio_energy(b.into(), l, g.into()), l).1;
            let dg = first_derivative(|g| giantesio_energy(b.into(), l.into(), g), g).1;
            [db, dl + dg * slope]
        },
        [1.0, 1.0],
    );
    x[1]
}

/// The stretch history of a `scenes/examples/` scene's only activation-in-time study.
fn scene_stretches(file: &str) -> Vec<(f64, f64)> {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenes/examples")
        .join(file);
    let scene = Scene::load(&path).unwrap();
    let results = scene.run(&RunOptions::default());
    let failures: Vec<_> = results.failures().collect();
    assert!(failures.is_empty(), "{failures:?}");
    let history: Vec<&HistoryResult> = results
        .studies
        .iter()
        .filter_map(|o| match &o.result {
            StudyResult::ActivationInTime(h) => Some(h),
            _ => None,
        })
        .collect();
    history[0].histories[0]
        .points
        .iter()
        .map(|p| (p.t, p.lambda))
        .collect()
}

#[test]
fn the_twitch_train_reaches_4c_s_optimal_stress_at_the_end() {
    // Stimuli at 0, 4, 8 and 12 ms; the level is 4C's P_opt(t)/N_a.
    assert_eq!(twitch_level(0.0), 0.0);
    let a = twitch_level(0.015);
    assert!(a > 600.0 && a < 700.0, "{a}");
}

#[test]
fn weickenmeier_block_is_the_structural_approach_with_the_implicit_law() {
    let ours = scene_stretches("4c_weickenmeier_block.toml");
    assert_eq!(ours.len(), STEPS + 1);
    let reference = weickenmeier_history(0.0, 0.0);
    for (n, ((t, l), r)) in ours.iter().zip(&reference).enumerate() {
        assert!((t - n as f64 * DT).abs() < 1e-12);
        assert!((l - r).abs() < 1e-9, "step {n}: λ = {l} vs {r}");
    }
    println!(
        "final stretch {} (4C's dispz + 1: 0.697612490315673)",
        ours[STEPS].1
    );
}

#[test]
fn weickenmeier_block_with_force_velocity_follows_the_backward_euler_rate() {
    let ours = scene_stretches("4c_weickenmeier_velocity_block.toml");
    let reference = weickenmeier_history(0.5, 1.0);
    let without = weickenmeier_history(0.0, 0.0);
    for (n, ((_, l), r)) in ours.iter().zip(&reference).enumerate() {
        assert!((l - r).abs() < 1e-9, "step {n}: λ = {l} vs {r}");
    }
    // Shortening lowers the active stress: the block contracts less than without the factor.
    assert!(ours[STEPS].1 > without[STEPS] + 0.05);
    println!(
        "final stretch {} (4C's dispz + 1: 0.796149955720945)",
        ours[STEPS].1
    );
}

#[test]
fn giantesio_block_is_the_volume_preserving_energy_law_with_the_consistent_coupling() {
    let ours = scene_stretches("4c_giantesio_block.toml");
    let reference = giantesio_final_stretch();
    let last = ours[STEPS].1;
    // The reference's γ′ is a central difference (as 4C's): ≈ 1e-9 in λ.
    assert!((last - reference).abs() < 1e-8, "λ = {last} vs {reference}");
    println!("final stretch {last} (4C's dispz + 1: 0.697006759757)");
}

/// 4C's formulation in the FE cylinder (issue 23, item 5): 4C's passive energy with its coupled
/// volumetric term on a sliding cylinder is the homogeneous nearly incompressible block to
/// 1e-9, passive and with the structural activation, and the reference state starts from the
/// pressure that balances 4C's energy at F = I (μ/2; p = 0 has no volume ratio for J^(−2κ)).
#[test]
fn four_c_formulation_runs_in_the_fe_cylinder_and_sliding_bases_equal_0d() {
    let text = r#"
[material]
energy = "4c-passive"
mu = 5.0
alpha = 15.0
beta = 1.0
w0 = 0.8

[incompressibility]
kind = "4c-giantesio"
kappa = 100.0

[activation]
approach = "structural"
curve = "ehret-bol-itskov"
p_opt = 2.0

[[study]]
kind = "cylinder"
name = "passive"
nr = 2
nz = 4
bases = "sliding"
law = "implicit"
coupling = "frozen"
damage = [1.0]
stretch = [0.9, 1.0, 1.2, 1.4]

[[study]]
kind = "cylinder"
name = "structural"
nr = 2
nz = 4
bases = "sliding"
law = "implicit"
coupling = "consistent"
damage = [0.0]
stretch = [0.9, 1.1, 1.25]
"#;
    let scene = Scene::parse(text, "4c_cylinder.toml").unwrap();
    let results = scene.run(&RunOptions::default());
    let failures: Vec<_> = results.failures().collect();
    assert!(failures.is_empty(), "{failures:?}");
    let cylinders: Vec<_> = results
        .of::<activemuscle::studies::cylinder::CylinderResult>()
        .collect();
    assert_eq!(cylinders.len(), 2);
    for (name, c) in cylinders {
        for s in &c.sweeps {
            assert!(!s.points.is_empty(), "{name}: no points");
            for p in &s.points {
                let p0 = p.stress_0d.unwrap();
                let rel = (p.stress - p0).abs() / p0.abs().max(1e-6);
                println!(
                    "{name}: λ = {}: P_FE = {:.12e}, P_0D = {p0:.12e} ({rel:.1e})",
                    p.lambda, p.stress
                );
                assert!(
                    rel < 1e-9,
                    "{name} at λ = {}: {} vs {p0}",
                    p.lambda,
                    p.stress
                );
            }
        }
    }
}
