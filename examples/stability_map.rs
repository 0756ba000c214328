//! Where each activation law × coupling loses strong ellipticity, and where dP/dλ < 0, along the
//! uniaxial path along the fibres.
//!
//! Run with `cargo run --release --example stability_map`.

use activemuscle::active::{
    ActiveCurve, Coupling, EnergyLaw, ExplicitLaw, FrozenTangent, ImplicitLaw, Law,
};
use activemuscle::energy::GiantesioMusesti;
use activemuscle::stability::along_fibres_stability;
use activemuscle::Muscle;

/// Maximal intervals of the grid on which `flag` holds, as "a–b" strings.
fn intervals(grid: &[f64], flags: &[bool]) -> String {
    let mut out = vec![];
    let mut start = None;
    for (i, &f) in flags.iter().enumerate() {
        match (f, start) {
            (true, None) => start = Some(grid[i]),
            (false, Some(s)) => {
                out.push(format!("{s:.3}–{:.3}", grid[i - 1]));
                start = None;
            }
            _ => {}
        }
    }
    if let Some(s) = start {
        out.push(format!("{s:.3}–{:.3}", grid[grid.len() - 1]));
    }
    if out.is_empty() {
        "none".into()
    } else {
        out.join(", ")
    }
}

fn main() -> activemuscle::Result<()> {
    let (gm, curve) = (GiantesioMusesti::paper(), ActiveCurve::paper());
    let frozen = Coupling::Frozen(FrozenTangent::Exact);
    let models: Vec<(&str, Law<GiantesioMusesti>, Coupling)> = vec![
        ("passive", Law::Passive, Coupling::Consistent),
        (
            "explicit/frozen",
            Law::Explicit(ExplicitLaw::paper()),
            frozen,
        ),
        (
            "implicit/frozen",
            Law::Implicit(ImplicitLaw::new(gm, curve)),
            frozen,
        ),
        (
            "explicit/consistent",
            Law::Explicit(ExplicitLaw::paper()),
            Coupling::Consistent,
        ),
        (
            "implicit/consistent",
            Law::Implicit(ImplicitLaw::new(gm, curve)),
            Coupling::Consistent,
        ),
        (
            "energy/consistent",
            Law::Energy(EnergyLaw::new(gm, curve)),
            Coupling::Consistent,
        ),
    ];
    let grid: Vec<f64> = (0..=950).map(|i| 0.65 + 0.001 * i as f64).collect();
    println!(
        "{:<22} {:>4}  {:<40} {:<40}",
        "model", "d", "dP/dλ < 0 on", "not strongly elliptic on"
    );
    for (name, law, coupling) in models {
        for d in [0.0, 0.5] {
            let muscle = Muscle::new(gm, law.clone(), d, coupling)?;
            let points = grid
                .iter()
                .map(|&l| along_fibres_stability(&muscle, l, 400))
                .collect::<activemuscle::Result<Vec<_>>>()?;
            let softening: Vec<bool> = points.iter().map(|p| p.slope < 0.0).collect();
            let unstable: Vec<bool> = points.iter().map(|p| !p.ellipticity.holds()).collect();
            println!(
                "{name:<22} {d:>4.1}  {:<40} {:<40}",
                intervals(&grid, &softening),
                intervals(&grid, &unstable)
            );
        }
    }
    Ok(())
}
