//! The chapter's least-squares fits, redone with `activemuscle::fit`, with plots of data vs fit in
//! `out/fit/` (PNG and SVG):
//!
//! 1. the chapter's energy (α, w0; μ = 0.1599 kPa fixed) fitted to the EBI passive curve along
//!    the fibres on λ ∈ [1, 1.5];
//! 2. the active curve (λ_min, λ_opt, k; P_opt fixed) from a tetanised total curve with noise of
//!    1 % of P_opt, the passive part subtracted by the model;
//! 3. (a, b) of the explicit law against the implicit law on λ ∈ [0.7, 1.5], in the stress and in γ;
//! 4. the damage d of weakened total curves (d = 0.1, 0.3, 0.5; exact and with noise of 1 % of P_opt).
//!
//! Run: `cargo run --release --example fit_paper`.

use activemuscle::active::{ActivationLaw, ActiveCurve, ExplicitLaw, ImplicitLaw};
use activemuscle::energy::{EhretBolItskov, GiantesioMusesti};
use activemuscle::fit::{
    active_from_total, explicit_law_errors, fit_active_curve, fit_damage, fit_explicit_law,
    fit_passive, Data, Direction, ExplicitTarget, FitSetup,
};
use activemuscle::material::Muscle;
use activemuscle::plot::{render, Figure, Panel, Scale, Series, Stroke};
use activemuscle::uniaxial::along_fibres;
use rand::rngs::StdRng;
use rand::{Rng, SeedableRng};
use std::error::Error;
use std::path::Path;

fn grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

/// Gaussian noise of standard deviation `sigma` [kPa], seeded.
fn with_noise(data: &Data, sigma: f64, seed: u64) -> Result<Data, Box<dyn Error>> {
    let mut rng = StdRng::seed_from_u64(seed);
    let noisy = data
        .stress()
        .iter()
        .map(|&p| {
            let (u1, u2): (f64, f64) = (rng.random::<f64>().max(1e-300), rng.random());
            p + sigma * (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
        })
        .collect();
    Ok(Data::new(data.lambda().to_vec(), noisy)?)
}

fn curve_of(lambda: &[f64], f: impl Fn(f64) -> f64) -> Vec<(f64, f64)> {
    lambda.iter().map(|&l| (l, f(l))).collect()
}

/// Data (red circles) and model curves (the first solid, the others dashed) against λ, written
/// as `<stem>.png` and `<stem>.svg`.
struct FitPlot {
    title: String,
    y_label: String,
    data_label: String,
    data: Vec<(f64, f64)>,
    curves: Vec<(String, Vec<(f64, f64)>)>,
}

impl FitPlot {
    fn write(self, stem: &Path) -> Result<(), Box<dyn Error>> {
        if let Some(dir) = stem.parent() {
            std::fs::create_dir_all(dir)?;
        }
        let mut series = vec![Series::new(self.data_label, self.data, Stroke::Markers, 1)];
        for (k, (label, points)) in self.curves.into_iter().enumerate() {
            let stroke = if k == 0 {
                Stroke::Solid
            } else {
                Stroke::Dashed
            };
            series.push(Series::new(
                label,
                points,
                stroke,
                if k == 0 { 0 } else { k + 1 },
            ));
        }
        let figure = Figure {
            stem: stem.display().to_string(),
            heading: self.title.clone(),
            caption: String::new(),
            panels: vec![Panel {
                title: self.title,
                x_label: "stretch λ [-]".into(),
                y_label: self.y_label,
                series,
                x_range: None,
                y_range: None,
                scale: Scale::Linear,
            }],
        };
        render(
            &figure,
            &stem.with_extension("png"),
            &stem.with_extension("svg"),
        )?;
        Ok(())
    }
}

fn main() -> Result<(), Box<dyn Error>> {
    let out = Path::new("out/fit");
    let (gm, curve) = (GiantesioMusesti::paper(), ActiveCurve::paper());
    let fine = grid(0.62, 1.6, 400);
    let mut table: Vec<(String, String, String)> = Vec::new();

    // 1. The chapter's energy fitted to the EBI passive curve.
    let ebi = Muscle::passive(EhretBolItskov::paper());
    let data = Data::sampled(grid(1.0, 1.5, 51), |l| Ok(along_fibres(&ebi, l)?.stress))?;
    let fit = fit_passive(&gm, &[(Direction::Along, &data)], &FitSetup::new())?;
    println!(
        "== 1. GM energy (alpha, w0; mu fixed) fitted to the EBI curve on [1, 1.5]\n{}\n",
        fit.report
    );
    let r = &fit.report;
    table.push((
        "alpha, w0 (GM fitted to EBI)".into(),
        format!(
            "{:.4} ± {:.1e}, {:.4} ± {:.1e} (corr {:.4})",
            fit.energy.alpha(),
            r.standard_errors[0],
            fit.energy.w0(),
            r.standard_errors[1],
            r.correlation[0][1]
        ),
        "19.35, 0.7335".into(),
    ));
    let fitted = Muscle::passive(fit.energy);
    let chapter = Muscle::passive(gm);
    let lam = grid(1.0, 1.5, 200);
    FitPlot {
        title: "Chapter's energy fitted to the EBI passive curve".into(),
        y_label: "P_pas [kPa]".into(),
        data_label: "EBI (eq. (4))".into(),
        data: data.points(),
        curves: vec![
            (
                format!(
                    "GM fitted: α = {:.3}, w0 = {:.4}",
                    fit.energy.alpha(),
                    fit.energy.w0()
                ),
                curve_of(&lam, |l| {
                    along_fibres(&fitted, l).map_or(f64::NAN, |p| p.stress)
                }),
            ),
            (
                "GM, Table 1".into(),
                curve_of(&lam, |l| {
                    along_fibres(&chapter, l).map_or(f64::NAN, |p| p.stress)
                }),
            ),
        ],
    }
    .write(&out.join("passive_ebi"))?;

    // 2. The active curve from a noisy tetanised total curve, passive part subtracted.
    let passive = Muscle::passive(gm);
    let total = Data::sampled(grid(0.66, 1.5, 43), |l| {
        Ok(along_fibres(&passive, l)?.stress + curve.value(l))
    })?;
    let total = with_noise(&total, 0.01 * curve.parameter("p_opt").unwrap(), 2)?;
    let active = active_from_total(&gm, &total)?;
    let start = ActiveCurve::chapter(0.55, 1.1, 0.6, curve.parameter("p_opt").unwrap())?;
    let fit = fit_active_curve(&start, &active, &FitSetup::new())?;
    println!(
        "== 2. Active curve from a total curve with noise of 1 % of P_opt\n{}\n",
        fit.report
    );
    let c = fit.curve;
    table.push((
        "lambda_min, lambda_opt, k (noise 1 % P_opt)".into(),
        format!(
            "{:.4}, {:.4}, {:.4}",
            c.lambda_min(),
            c.parameter("lambda_opt").unwrap(),
            c.parameter("k").unwrap()
        ),
        "0.6243, 1.1704, 0.4342".into(),
    ));
    FitPlot {
        title: "Active curve fitted to P_total − P_pas (noise 1 % of P_opt)".into(),
        y_label: "P_act [kPa]".into(),
        data_label: "data − P_pas".into(),
        data: active.points(),
        curves: vec![
            ("fitted P_act".into(), curve_of(&fine, |l| c.value(l))),
            ("Table 2".into(), curve_of(&fine, |l| curve.value(l))),
        ],
    }
    .write(&out.join("active_curve"))?;

    // 3. (a, b) of the explicit law against the implicit law on [0.7, 1.5].
    let lambda = grid(0.7, 1.5, 81);
    let implicit = ImplicitLaw::new(gm, curve);
    let (paper_dg, paper_dp) =
        explicit_law_errors(&ExplicitLaw::paper(), &gm, &curve, &lambda, 0.0)?;
    table.push((
        "chapter's a, b: max |dgamma|, max |dP|".into(),
        format!("{paper_dg:.3e}, {paper_dp:.3} kPa"),
        "1.0133, 0.2050".into(),
    ));
    let mut laws = Vec::new();
    for target in [ExplicitTarget::Stress, ExplicitTarget::Activation] {
        let fit = fit_explicit_law(&gm, &curve, &lambda, 0.0, target, &FitSetup::new())?;
        println!(
            "== 3. Explicit law against the implicit law, residual in {target:?}\n{}",
            fit.report
        );
        let (a, b) = fit.law.coefficients();
        println!(
            "max |dgamma| = {:.3e}, max |dP| = {:.3} kPa\n",
            fit.max_activation_error, fit.max_stress_error
        );
        table.push((
            format!("a, b (residual in {target:?})"),
            format!(
                "{a:.4}, {b:.4}; max |dgamma| {:.3e}, max |dP| {:.3} kPa",
                fit.max_activation_error, fit.max_stress_error
            ),
            "1.0133, 0.2050".into(),
        ));
        laws.push((target, fit.law));
    }
    let gammas: Vec<(f64, f64)> = lambda
        .iter()
        .map(|&l| Ok((l, implicit.evaluate(l, 0.0)?.gamma)))
        .collect::<activemuscle::Result<_>>()?;
    let lam = grid(0.7, 1.5, 300);
    let mut curves: Vec<(String, Vec<(f64, f64)>)> = laws
        .iter()
        .map(|(t, law)| {
            let (a, b) = law.coefficients();
            (
                format!("explicit, fitted in {t:?}: a = {a:.4}, b = {b:.4}"),
                curve_of(&lam, |l| law.gamma(l, 0.0).unwrap_or(f64::NAN)),
            )
        })
        .collect();
    curves.push((
        "explicit, chapter's a, b".into(),
        curve_of(&lam, |l| {
            ExplicitLaw::paper().gamma(l, 0.0).unwrap_or(f64::NAN)
        }),
    ));
    FitPlot {
        title: "Explicit law (eq. (14)) against the implicit law".into(),
        y_label: "activation γ [-]".into(),
        data_label: "implicit γ (eq. (13))".into(),
        data: gammas,
        curves,
    }
    .write(&out.join("explicit_law"))?;

    // 4. Damage of weakened total curves.
    for (k, d) in [0.1, 0.3, 0.5].into_iter().enumerate() {
        let exact = Data::sampled(grid(0.75, 1.5, 31), |l| {
            Ok(along_fibres(&passive, l)?.stress + (1.0 - d) * curve.value(l))
        })?;
        let exact_fit = fit_damage(&gm, &curve, &exact, &FitSetup::new())?;
        let noisy = with_noise(
            &exact,
            0.01 * curve.parameter("p_opt").unwrap(),
            10 + k as u64,
        )?;
        let noisy_fit = fit_damage(&gm, &curve, &noisy, &FitSetup::new())?;
        println!(
            "== 4. d = {d}: exact data -> {:.12}; noise 1 % of P_opt -> {:.4} ± {:.4}",
            exact_fit.damage, noisy_fit.damage, noisy_fit.report.standard_errors[0]
        );
        table.push((
            format!("damage d = {d} (exact; noise 1 % P_opt)"),
            format!(
                "{:.10}; {:.4} ± {:.4}",
                exact_fit.damage, noisy_fit.damage, noisy_fit.report.standard_errors[0]
            ),
            format!("{d}"),
        ));
        if d == 0.3 {
            let df = noisy_fit.damage;
            FitPlot {
                title: format!(
                    "Damage from a weakened total curve (true d = {d}, noise 1 % of P_opt)"
                ),
                y_label: "P_total [kPa]".into(),
                data_label: "weakened muscle".into(),
                data: noisy.points(),
                curves: vec![
                    (
                        format!("P_pas + (1 − d) P_act, fitted d = {df:.4}"),
                        curve_of(&grid(0.75, 1.5, 200), |l| {
                            along_fibres(&passive, l).map_or(f64::NAN, |p| p.stress)
                                + (1.0 - df) * curve.value(l)
                        }),
                    ),
                    (
                        "healthy muscle (d = 0)".into(),
                        curve_of(&grid(0.75, 1.5, 200), |l| {
                            along_fibres(&passive, l).map_or(f64::NAN, |p| p.stress)
                                + curve.value(l)
                        }),
                    ),
                ],
            }
            .write(&out.join("damage"))?;
        }
    }

    println!("\n{:<44} {:<70} chapter / truth", "fit", "obtained");
    for (what, got, reference) in &table {
        println!("{what:<44} {got:<70} {reference}");
    }
    println!("\nplots written to {}/ (PNG and SVG)", out.display());
    Ok(())
}
