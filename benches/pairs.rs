//! Ratios of per-point costs on a shared machine: each pair of routines is run alternately, in
//! blocks of `BLOCK` calls, `ROUNDS` times, and each keeps its fastest block (a block that other
//! processes interrupted is slower, never faster, so the minimum estimates the uncontended cost
//! and both sides of a ratio are taken at the same moments).
//!
//! `cargo bench --bench pairs` prints `A ns, B ns, B/A` per pair; `ROUNDS=400 cargo bench --bench
//! pairs` for more rounds. Same inputs as `benches/constitutive.rs` (see BENCHMARKS.md). The last
//! pairs are the chapter's and EBI's energies compiled against the same written as formulas.

mod closed_form;
mod point;

use activemuscle::active::{
    ActivationMap, ActiveCurve, ConstantLaw, Coupling, EnergyLaw, ExplicitLaw, FrozenTangent,
    ImplicitLaw, Law, LawRepresentation, TableSpec,
};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::invariants::{axial_fibre, axisymmetric_f, Kinematics, AXISYMMETRIC, FULL};
use activemuscle::response::{active_response, Order};
use activemuscle::Muscle;
use closed_form::ClosedForm;
use point::{axi_entries, full_f, GAMMA};
use std::hint::black_box;
use std::time::Instant;

const BLOCK: usize = 20_000;

/// `BLOCK` calls of `f` [ns per call] (generic, so that `f` is inlined into the loop as in
/// criterion's `iter`).
fn block(f: &mut impl FnMut()) -> f64 {
    let start = Instant::now();
    for _ in 0..BLOCK {
        f();
    }
    start.elapsed().as_secs_f64() * 1e9 / BLOCK as f64
}

/// The fastest of `rounds` blocks of each routine, run alternately [ns per call].
fn pair(rounds: usize, mut a: impl FnMut(), mut b: impl FnMut()) -> (f64, f64) {
    let mut best = (f64::INFINITY, f64::INFINITY);
    for _ in 0..rounds {
        best.0 = best.0.min(block(&mut a));
        best.1 = best.1.min(block(&mut b));
    }
    best
}

fn main() {
    let rounds: usize = std::env::var("ROUNDS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(200);
    let energy = GiantesioMusesti::paper();
    let cf = ClosedForm::new(energy.mu(), energy.alpha(), energy.w0());
    let (m, f5, f3) = (axial_fibre(), axi_entries(), full_f());
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!("load average before: {}", load.trim());
    let report = |name: &str, (a, b): (f64, f64)| {
        println!("{name}: {a:.1} ns, {b:.1} ns, ratio {:.3}", b / a);
    };

    report(
        "P + dP/dF + dP/dgamma, axisym: closed form, fast AD",
        pair(
            rounds,
            || {
                black_box(cf.axisymmetric(black_box(&f5), black_box(GAMMA)).unwrap());
            },
            || {
                let kin = Kinematics::new(&axisymmetric_f(black_box(&f5)), &m).unwrap();
                let r = active_response(
                    &energy,
                    &kin,
                    black_box(GAMMA),
                    Order::Tangent,
                    &AXISYMMETRIC,
                );
                black_box(r.unwrap());
            },
        ),
    );
    report(
        "P + dP/dF + dP/dgamma, 3D: closed form, fast AD",
        pair(
            rounds,
            || {
                black_box(
                    cf.full(black_box(&f3), black_box(&m), black_box(GAMMA))
                        .unwrap(),
                );
            },
            || {
                let kin = Kinematics::new(black_box(&f3), black_box(&m)).unwrap();
                let r = active_response(&energy, &kin, black_box(GAMMA), Order::Tangent, &FULL);
                black_box(r.unwrap());
            },
        ),
    );

    let curve = ActiveCurve::paper();
    let frozen = Coupling::Frozen(FrozenTangent::Exact);
    let tabulated = |law: Law<GiantesioMusesti>| {
        law.represented(LawRepresentation::Tabulated(TableSpec::default()), &[0.0])
            .unwrap()
    };
    let muscle = |law, coupling| Muscle::new(energy, law, 0.0, coupling).unwrap();
    let explicit = muscle(Law::Explicit(ExplicitLaw::paper()), frozen);
    let implicit = Law::Implicit(ImplicitLaw::new(energy, curve));
    let energy_law = Law::Energy(EnergyLaw::new(energy, curve));
    let respond = |mu: &Muscle<GiantesioMusesti>| {
        let kin = Kinematics::new(&axisymmetric_f(black_box(&f5)), &m).unwrap();
        black_box(mu.respond(&kin, Order::Tangent, &AXISYMMETRIC).unwrap());
    };
    for (name, mu) in [
        (
            "Muscle::respond tangent, axisym: explicit law (frozen), implicit tabulated (frozen)",
            muscle(tabulated(implicit.clone()), frozen),
        ),
        (
            "Muscle::respond tangent, axisym: explicit law (frozen), energy tabulated (consistent)",
            muscle(tabulated(energy_law.clone()), Coupling::Consistent),
        ),
        (
            "Muscle::respond tangent, axisym: explicit law (frozen), implicit exact (frozen)",
            muscle(implicit.clone(), frozen),
        ),
        (
            "Muscle::respond tangent, axisym: explicit law (frozen), energy exact (consistent)",
            muscle(energy_law.clone(), Coupling::Consistent),
        ),
    ] {
        let r = if name.contains("exact") {
            rounds / 10 + 1
        } else {
            rounds
        };
        report(
            name,
            pair(r, &mut || respond(&explicit), &mut || respond(&mu)),
        );
    }
    // The active-strain map at constant γ (as benches/constitutive.rs's group "map").
    let mapped = |map| {
        muscle(
            Law::Constant(ConstantLaw::new(GAMMA).unwrap()),
            Coupling::Consistent,
        )
        .with_map(map)
        .unwrap()
    };
    let (chapter, volume_preserving) = (
        mapped(ActivationMap::Chapter),
        mapped(ActivationMap::VolumePreserving),
    );
    report(
        "Muscle::respond tangent, axisym, constant gamma: chapter map, volume-preserving map",
        pair(rounds, &mut || respond(&chapter), &mut || {
            respond(&volume_preserving)
        }),
    );
    // The activation approaches at the chapter's material (issue 23): each against the
    // chapter's active strain with the explicit law, frozen.
    let active_stress = Muscle::active_stress(energy, curve, 0.0).unwrap();
    report(
        "Muscle::respond tangent, axisym: explicit law (frozen), active stress",
        pair(rounds, &mut || respond(&explicit), &mut || {
            respond(&active_stress)
        }),
    );
    let structural_map = activemuscle::active::ActivationMap::structural(&energy).unwrap();
    let structural = |law: Law<GiantesioMusesti>, coupling| {
        muscle(law, coupling).with_map(structural_map).unwrap()
    };
    let structural_implicit =
        Law::Implicit(ImplicitLaw::new(energy, curve).with_map(structural_map));
    for (name, mu) in [
        (
            "Muscle::respond tangent, axisym: explicit law (frozen), structural implicit tabulated (frozen)",
            structural(tabulated(structural_implicit.clone()), frozen),
        ),
        (
            "Muscle::respond tangent, axisym: explicit law (frozen), structural implicit exact (frozen)",
            structural(structural_implicit.clone(), frozen),
        ),
    ] {
        let r = if name.contains("exact") {
            rounds / 10 + 1
        } else {
            rounds
        };
        report(
            name,
            pair(r, &mut || respond(&explicit), &mut || respond(&mu)),
        );
    }
    formula_pairs(rounds);
    let load = std::fs::read_to_string("/proc/loadavg").unwrap_or_default();
    println!("load average after: {}", load.trim());
}

/// Convenience against speed (issue 44): each of the chapter's and EBI's energies compiled and
/// written as a formula (`Energy::as_formula`), both behind the engine's `Energy` enum: the
/// active-strain response alone, and `Muscle::respond` with the explicit law (frozen).
fn formula_pairs(rounds: usize) {
    use activemuscle::energy::{EhretBolItskov, Energy};
    let (m, f5) = (axial_fibre(), axi_entries());
    for compiled in [
        Energy::GiantesioMusesti(GiantesioMusesti::paper()),
        Energy::EhretBolItskov(EhretBolItskov::paper()),
    ] {
        let written = Energy::Formula(compiled.as_formula().unwrap());
        let response = |e: &Energy| {
            let kin = Kinematics::new(&axisymmetric_f(black_box(&f5)), &m).unwrap();
            let r = active_response(e, &kin, black_box(GAMMA), Order::Tangent, &AXISYMMETRIC);
            black_box(r.unwrap());
        };
        let name = activemuscle::StrainEnergy::name(&compiled).to_string();
        let (a, b) = pair(rounds, || response(&compiled), || response(&written));
        println!("P + dP/dF + dP/dgamma, axisym, {name}: compiled, formula: {a:.1} ns, {b:.1} ns, ratio {:.3}", b / a);
        let frozen = Coupling::Frozen(FrozenTangent::Exact);
        let respond = |mu: &Muscle<Energy>| {
            let kin = Kinematics::new(&axisymmetric_f(black_box(&f5)), &m).unwrap();
            black_box(mu.respond(&kin, Order::Tangent, &AXISYMMETRIC).unwrap());
        };
        let explicit = |e: &Energy| {
            let law = Law::Explicit(ExplicitLaw::paper());
            Muscle::new(e.clone(), law, 0.0, frozen).unwrap()
        };
        let (mc, mf) = (explicit(&compiled), explicit(&written));
        let (a, b) = pair(rounds, || respond(&mc), || respond(&mf));
        println!("Muscle::respond tangent, axisym, explicit law (frozen), {name}: compiled, formula: {a:.1} ns, {b:.1} ns, ratio {:.3}", b / a);
        let implicit = |e: &Energy| {
            let law = Law::Implicit(ImplicitLaw::new(e.clone(), ActiveCurve::paper()));
            Muscle::new(e.clone(), law, 0.0, frozen).unwrap()
        };
        let (mc, mf) = (implicit(&compiled), implicit(&written));
        let (a, b) = pair(rounds / 10 + 1, || respond(&mc), || respond(&mf));
        println!("Muscle::respond tangent, axisym, implicit law exact (frozen), {name}: compiled, formula: {a:.1} ns, {b:.1} ns, ratio {:.3}", b / a);
    }
}
