//! The options a user trades, each run at its variants against a reference at its accurate end.
//!
//! | option | variants | reference | error on |
//! |---|---|---|---|
//! | activation law (0D along the fibres) | explicit (frozen), energy (consistent) | implicit (frozen): reproduces P_pas + P_act | P(λ), γ(λ) |
//! | activation law (FE, clamped cylinder) | explicit (frozen), energy (consistent) | implicit (frozen) | P(λ), centre γ |
//! | law representation (0D: implicit frozen, energy consistent; FE: implicit) | tabulated | exact solve | P(λ), γ(λ) or centre γ |
//! | derivative route at a point | oracle (9-entry F), central differences | fast AD | ∂P/∂F |
//! | derivative route in the FE | oracle, central differences | fast AD | P(λ), centre γ |
//! | frozen tangent (FE) | symmetric approximation | exact | P(λ), centre γ |
//! | mesh (clamped cylinder) | coarser meshes | finest | P(λ), centre γ |
//! | Newton tolerance (FE) | 1e-6, 1e-8, 1e-10 | 1e-12 | P(λ), centre γ |
//! | 0D vs FE (sliding bases: homogeneous) | FE | 0D (the exact solution) | P(λ), γ |
//! | incompressibility (0D along the fibres; FE, clamped) | (κ/2)(J − 1)², κ = 10³, …, 10⁸ kPa (FE: 10³, 10⁵, 10⁷) | exact, J = 1 | P(λ), γ (FE: centre γ) |
//! | formula energy (convenience against speed: point and FE, clamped) | the material's energy written as a formula | the compiled energy | ∂P/∂F; P(λ), centre γ |
//!
//! Times are wall times \[s\]: a whole sweep (FE: mesh, set-up and load path), the whole 0D curve,
//! or one material-point call.

use super::measure::{curve_error, time_median, time_runs, CurveError, Measurement, Timing};
use super::routes::{FiniteDifferenceTangent, OracleRoute};
use super::Geometry;
use crate::active::{Approach, Coupling, FrozenTangent, Law, LawRepresentation, TableSpec};
use crate::app_error::AppError;
use crate::energy::Energy;
use crate::fem::{
    AxiF, AxisymmetricMaterial, AxisymmetricSolver, Bases, Element, Mesh, SolverOptions, Stepping,
};
use crate::models::{LawKind, Models};
use crate::studies::Progress;
use crate::uniaxial::{along_fibres, Direction};
use crate::volumetric::{Volumetric, VolumetricForm};
use crate::Muscle;
use crate::StrainEnergy;
use std::time::Instant;

/// Options with the geometry, FE mesh and stretches resolved.
pub(super) struct Resolved {
    /// The approach whose laws and muscles are measured.
    pub approach: Approach,
    pub geom: Geometry,
    pub meshes: Vec<(usize, usize)>,
    pub fe_mesh: (usize, usize),
    pub fe_stretches: Vec<f64>,
    pub curve_stretches: Vec<f64>,
    pub tolerances: Vec<f64>,
    pub fd_step: f64,
    /// Whether the explicit law's formula applies to the material
    /// ([`Models::explicit_formula_holds`], evaluated once per run), and why not: the law
    /// groups measure it where it does.
    pub explicit: Result<(), String>,
    /// Whether it also serves the other groups ([`Resolved::working_law`]): its formula holds
    /// and its (a, b) are a fit for this material ([`Models::explicit_fit_applies`]), and why not.
    pub explicit_working: Result<(), String>,
}

/// One FE sweep, timed.
#[derive(Debug, Clone, PartialEq)]
pub struct FeRun {
    /// Wall times of mesh, set-up and sweep \[s\] (a failed sweep runs once).
    pub time: Timing,
    /// Nominal axial stress P \[kPa\] at each requested stretch (NaN where not reached).
    pub stress: Vec<f64>,
    /// γ at the quadrature point nearest the centre [-] at each stretch.
    pub gamma_centre: Vec<f64>,
    /// Newton iterations of the whole sweep (rejected steps included).
    pub iterations: usize,
    /// Assembly + factorisation + solve time per Newton iteration \[s\].
    pub per_iteration_s: f64,
    /// Free dofs.
    pub dofs: usize,
    /// Why a direction of the sweep stopped, if it did.
    pub failures: Vec<String>,
}

/// Runs and times one FE sweep of `material` on a `cells` = (nr, nz) mesh of `geom`.
pub fn fe_run<M: AxisymmetricMaterial + ?Sized>(
    material: &M,
    geom: Geometry,
    cells: (usize, usize),
    bases: Bases,
    stretches: &[f64],
    options: &SolverOptions,
) -> Result<FeRun, AppError> {
    let once = || -> Result<FeRun, AppError> {
        let mesh = Mesh::structured(geom.radius, geom.length, cells.0, cells.1, geom.grading)?;
        let mut solver = AxisymmetricSolver::new(mesh, bases, material, options.clone())?;
        let sweep = solver.sweep(stretches)?;
        let t = solver.timings();
        let mut stress = vec![f64::NAN; stretches.len()];
        let mut gamma_centre = vec![f64::NAN; stretches.len()];
        let mut iterations = 0;
        for r in &sweep.results {
            iterations += r.steps.iter().map(|s| s.iterations.len()).sum::<usize>();
            if let Some(i) = stretches.iter().position(|&s| s == r.stretch) {
                stress[i] = r.nominal_stress;
                gamma_centre[i] = r.gamma_centre;
            }
        }
        // The results hold the converged stretches only: a sweep that stopped ran the failed
        // step's iterations too (25 and 50 of them, say), which the solver counted.
        if !sweep.failures.is_empty() {
            iterations = iterations.max(t.newton_iterations);
        }
        Ok(FeRun {
            time: Timing::once(0.0),
            stress,
            gamma_centre,
            iterations,
            per_iteration_s: t.per_newton_iteration(),
            dofs: solver.n_free_dofs(),
            failures: sweep.failures.iter().map(|e| e.to_string()).collect(),
        })
    };
    let (time, mut run) = time_runs(once, |r| r.failures.is_empty())?;
    run.time = time;
    Ok(run)
}

/// The row of an FE run measured against `reference_run`'s stresses and centre γ, at the
/// stretches the reference reached: a run that stopped short has no error (it failed, the
/// reference too), and where the reference stopped short the others are compared at the
/// stretches it reached, which the row's note says.
pub fn fe_row(
    option: &str,
    variant: &str,
    reference: bool,
    run: &FeRun,
    reference_run: &FeRun,
) -> Measurement {
    let reached: Vec<usize> = (0..reference_run.stress.len())
        .filter(|&i| reference_run.stress[i].is_finite())
        .collect();
    let at_reached = |v: &[f64]| -> Vec<f64> {
        reached
            .iter()
            .map(|&i| v.get(i).copied().unwrap_or(f64::NAN))
            .collect()
    };
    let error = |r: &[f64], c: &[f64]| {
        if run.failures.is_empty() {
            curve_error(&at_reached(r), &at_reached(c))
        } else {
            CurveError::FAILED
        }
    };
    let mut m = Measurement::new(
        option,
        variant,
        reference,
        run.time,
        "P(λ) at the FE stretches [kPa]",
        error(&reference_run.stress, &run.stress),
    );
    m.gamma_error = Some(error(&reference_run.gamma_centre, &run.gamma_centre).max_abs);
    m.iterations = Some(run.iterations);
    m.per_iteration_s = Some(run.per_iteration_s);
    m.dofs = Some(run.dofs);
    let n = reference_run.stress.len();
    if !run.failures.is_empty() {
        m.note = format!("did not converge: {}", run.failures.join("; "));
    } else if reached.is_empty() {
        m.note = "not compared: the reference reached none of the stretches".into();
    } else if reached.len() < n {
        m.note = format!(
            "compared at the {} of {n} stretches the reference reached",
            reached.len()
        );
    }
    m
}

pub(super) struct Runner<'a> {
    pub progress: &'a dyn Progress,
    pub rows: Vec<Measurement>,
    pub started: Instant,
}

impl Runner<'_> {
    fn push(&mut self, m: Measurement) {
        self.progress.log(&format!(
            "[{:6.1} s] {:<28} {:<34} time {:>10.3e} s ({} runs)  error {:>9.2e} (rel {:>9.2e}){}",
            self.started.elapsed().as_secs_f64(),
            m.option,
            m.variant,
            m.time.median,
            m.time.runs,
            m.error.max_abs,
            m.error.max_rel,
            m.iterations
                .map_or(String::new(), |i| format!("  {i} Newton its"))
        ));
        self.rows.push(m);
    }
}

/// The muscle of `law` with `coupling` at d = 0, on the map of `approach` (the scene's): the
/// explicit law (the cheap model most groups measure with) has no map of its own and would
/// otherwise run on the chapter's; with another active-strain map its γ(λ) is no longer the fit
/// of eq. (14), which the activation-law groups then measure as part of its error.
fn muscle(
    models: &Models,
    approach: Approach,
    law: LawKind,
    coupling: Coupling,
) -> Result<Muscle<Energy>, AppError> {
    let map = models
        .activation_map(approach)
        .map_err(|reason| crate::Error::Unsupported { reason })?;
    Ok(Muscle::new(models.energy.clone(), models.law(law, map)?, 0.0, coupling)?.with_map(map)?)
}

/// The solver's defaults (tolerance 1e-10, 25 Newton iterations per step).
fn tight() -> SolverOptions {
    SolverOptions::default()
}

fn with_tolerance(tolerance: f64) -> SolverOptions {
    with_stepping(Stepping {
        tolerance,
        ..Stepping::default()
    })
}

fn with_stepping(stepping: Stepping) -> SolverOptions {
    SolverOptions {
        stepping,
        ..SolverOptions::default()
    }
}

const EXACT: Coupling = Coupling::Frozen(FrozenTangent::Exact);

/// Whether the law groups measure the explicit law for `approach` on this material: the
/// approach lists it, and its formula holds ([`Models::explicit_formula_holds`]; on another
/// active-strain map than the chapter's its error then includes the map's); why not otherwise.
pub(super) fn explicit_measured(models: &Models, approach: Approach) -> Result<(), String> {
    if !approach.laws().contains(&LawKind::Explicit) {
        return Err(format!(
            "the explicit law does not apply to approach = \"{}\": {}",
            approach.name(),
            approach.no_law()
        ));
    }
    models.explicit_formula_holds()
}

impl Resolved {
    /// The law the groups that trade something else (derivative route, tangent, mesh, element,
    /// tolerance, 0D vs FE, incompressibility) measure with: the explicit law, the cheapest,
    /// where its formula holds and its (a, b) were fitted for the material, else the implicit
    /// law (the chapter's fit on another material is 90 % off on a softer chapter energy).
    pub fn working_law(&self) -> LawKind {
        if self.explicit_working.is_ok() {
            LawKind::Explicit
        } else {
            LawKind::Implicit
        }
    }

    /// One timed sweep of `material` on the FE mesh of the clamped cylinder.
    fn clamped<M: AxisymmetricMaterial + ?Sized>(
        &self,
        material: &M,
        options: &SolverOptions,
    ) -> Result<FeRun, AppError> {
        fe_run(
            material,
            self.geom,
            self.fe_mesh,
            Bases::Clamped,
            &self.fe_stretches,
            options,
        )
    }
}

/// P(λ) \[kPa\] and γ(λ) [-] along a 0D sweep.
type Curves = (Vec<f64>, Vec<f64>);

/// Where the stress error of curves `(p, g)` against `(p_ref, g_ref)` is largest, and how big
/// γ's error is there, in words.
fn largest_error(stretches: &[f64], (p, g): Curves2, (p_ref, g_ref): Curves2) -> String {
    let (i, _) = p
        .iter()
        .zip(p_ref)
        .map(|(a, b)| (a - b).abs())
        .enumerate()
        .fold((0, 0.0), |acc, (i, d)| if d > acc.1 { (i, d) } else { acc });
    let dg = (g[i] - g_ref[i]).abs();
    format!(
        "largest P error at λ = {:.2}: |Δγ| = {:.2e} there gives |ΔP| = {:.2} kPa ({:.1} kPa per 0.01 of γ)",
        stretches[i],
        dg,
        (p[i] - p_ref[i]).abs(),
        (p[i] - p_ref[i]).abs() / dg.max(1e-300) * 0.01
    )
}

/// `, 16 of them outside its domain …` when some of a law's stretches are (`outside`, per
/// stretch), else nothing.
fn outside_words(outside: &[bool]) -> String {
    match outside.iter().filter(|o| **o).count() {
        0 => String::new(),
        n => format!(
            ", {n} of them outside its domain {}",
            crate::active::ExplicitLaw::DOMAIN.describe()
        ),
    }
}

/// `, inside its domain 13.37 kPa`: the largest |P − P_ref| over the stretches not `outside`
/// its law's domain, when some are.
fn inside_error(p_ref: &[f64], p: &[f64], outside: &[bool]) -> String {
    if !outside.contains(&true) {
        return String::new();
    }
    let inside = p_ref
        .iter()
        .zip(p)
        .zip(outside)
        .filter(|(_, o)| !**o)
        .fold(0.0f64, |m, ((a, b), _)| m.max((a - b).abs()));
    format!(", inside its domain {inside:.2} kPa")
}

/// P(λ) and γ(λ) of a 0D sweep, borrowed.
type Curves2<'a> = (&'a [f64], &'a [f64]);

/// The 0D curve along the fibres of `m` at `stretches`, timed (median of repeated runs).
fn fibre_curve(m: &Muscle<Energy>, stretches: &[f64]) -> Result<(Timing, Curves), AppError> {
    time_median(|| -> Result<(Vec<f64>, Vec<f64>), AppError> {
        let mut p = Vec::with_capacity(stretches.len());
        let mut g = Vec::with_capacity(stretches.len());
        for &l in stretches {
            let pt = along_fibres(m, l)?;
            p.push(pt.stress);
            g.push(pt.gamma);
        }
        Ok((p, g))
    })
}

/// Activation law, 0D along the fibres.
pub(super) fn activation_law(
    models: &Models,
    o: &Resolved,
    run: &mut Runner<'_>,
    findings: &mut Vec<String>,
) -> Result<(), AppError> {
    const OPTION: &str = "activation law (0D)";
    let stretches = &o.curve_stretches;
    let curve = |m: &Muscle<Energy>| fibre_curve(m, stretches);
    let implicit = muscle(models, o.approach, LawKind::Implicit, EXACT)?;
    let (t_ref, (p_ref, g_ref)) = curve(&implicit)?;
    // The reference reproduces the target P_pas + P_act.
    let passive = Muscle::passive(models.energy.clone());
    let mut target = Vec::with_capacity(stretches.len());
    for &l in stretches {
        target.push(along_fibres(&passive, l)?.stress + models.curve.value(l));
    }
    let check = curve_error(&target, &p_ref);
    let quantity = "P(λ) over the 0D sweep [kPa]";
    let mut r = Measurement::new(
        OPTION,
        "implicit (frozen)",
        true,
        t_ref,
        quantity,
        CurveError::ZERO,
    );
    r.gamma_error = Some(0.0);
    r.note = format!(
        "{} stretches; vs the target P_pas + P_act: max abs {:.1e} kPa",
        stretches.len(),
        check.max_abs
    );
    run.push(r);
    let variants = [
        ("explicit (frozen)", LawKind::Explicit, EXACT),
        ("energy (consistent)", LawKind::Energy, Coupling::Consistent),
    ];
    for (name, law, coupling) in variants {
        if let (LawKind::Explicit, Err(why)) = (law, &o.explicit) {
            findings.push(format!("explicit law (0D) not measured: {why}."));
            continue;
        }
        let measured = muscle(models, o.approach, law, coupling).and_then(|m| {
            let outside: Vec<bool> = stretches
                .iter()
                .map(|&l| m.outside_domain(l).is_some())
                .collect();
            Ok((curve(&m)?, outside))
        });
        let ((t, (p, g)), outside) = match measured {
            Ok(c) => c,
            Err(e) => {
                findings.push(format!("{} law (0D): failed: {e}.", law.name()));
                run.push(Measurement::failed(OPTION, name, quantity, &e));
                continue;
            }
        };
        let e = curve_error(&p_ref, &p);
        let mut r = Measurement::new(OPTION, name, false, t, quantity, e);
        let ge = curve_error(&g_ref, &g).max_abs;
        r.gamma_error = Some(ge);
        if law == LawKind::Explicit {
            r.note = largest_error(stretches, (&p, &g), (&p_ref, &g_ref));
            findings.push(format!(
                "Explicit law (0D, {} stretches{}): {}; stress error max {:.2} kPa ({:.1} % rel.){}, γ error max {:.2e}.",
                stretches.len(),
                outside_words(&outside),
                t.against(&t_ref, "the implicit law"),
                e.max_abs,
                100.0 * e.max_rel,
                inside_error(&p_ref, &p, &outside),
                ge
            ));
        }
        run.push(r);
    }
    Ok(())
}

/// The FE sweeps of the activation-law option: the cylinder on `cells` with `bases`, swept to
/// `stretches` with the implicit law (frozen, exact tangent: the reference), the explicit law
/// (frozen) and the energy law (consistent), each timed. Rows in that order, named `option`.
pub fn activation_law_fe_rows(
    models: &Models,
    approach: Approach,
    option: &str,
    geom: Geometry,
    cells: (usize, usize),
    bases: Bases,
    stretches: &[f64],
) -> Result<Vec<Measurement>, AppError> {
    let sweep = |law: LawKind, coupling: Coupling| -> Result<FeRun, AppError> {
        fe_run(
            &muscle(models, approach, law, coupling)?,
            geom,
            cells,
            bases,
            stretches,
            &tight(),
        )
    };
    let reference = sweep(LawKind::Implicit, EXACT)?;
    let mut rows = vec![fe_row(
        option,
        "implicit (frozen)",
        true,
        &reference,
        &reference,
    )];
    for (name, law, coupling) in [
        ("explicit (frozen)", LawKind::Explicit, EXACT),
        ("energy (consistent)", LawKind::Energy, Coupling::Consistent),
    ] {
        if law == LawKind::Explicit && explicit_measured(models, approach).is_err() {
            continue;
        }
        let r = match sweep(law, coupling) {
            Ok(r) => r,
            Err(e) => {
                rows.push(Measurement::failed(
                    option,
                    name,
                    "P(λ) at the FE stretches [kPa]",
                    &e,
                ));
                continue;
            }
        };
        let mut row = fe_row(option, name, false, &r, &reference);
        // Where is the stress error largest?
        if let Some((i, d)) = r
            .stress
            .iter()
            .zip(&reference.stress)
            .map(|(a, b)| (a - b).abs())
            .enumerate()
            .filter(|(_, d)| d.is_finite())
            .max_by(|a, b| a.1.total_cmp(&b.1))
        {
            let largest = format!("largest P error at λ = {}: {d:.3} kPa", stretches[i]);
            row.note = if row.note.is_empty() {
                largest
            } else {
                format!("{largest}; {}", row.note)
            };
        }
        rows.push(row);
    }
    Ok(rows)
}

/// Activation law in the clamped cylinder.
pub(super) fn activation_law_fe(
    models: &Models,
    o: &Resolved,
    run: &mut Runner<'_>,
    findings: &mut Vec<String>,
) -> Result<(), AppError> {
    let rows = activation_law_fe_rows(
        models,
        o.approach,
        "activation law (FE)",
        o.geom,
        o.fe_mesh,
        Bases::Clamped,
        &o.fe_stretches,
    )?;
    if let Err(why) = &o.explicit {
        findings.push(format!("Explicit law (FE) not measured: {why}."));
    }
    let explicit = rows.iter().find(|r| r.variant == "explicit (frozen)");
    if let (Some(reference), Some(explicit)) = (rows.first(), explicit) {
        findings.push(if explicit.error.max_abs.is_finite() {
            format!(
                "Explicit law in the clamped cylinder ({} × {} cells, {} stretches): {}; nominal stress error max {:.3} kPa ({:.2} % rel.), centre γ error max {:.2e}.",
                o.fe_mesh.0,
                o.fe_mesh.1,
                o.fe_stretches.len(),
                explicit.time.against(&reference.time, "the implicit law"),
                explicit.error.max_abs,
                100.0 * explicit.error.max_rel,
                explicit.gamma_error.unwrap_or(f64::NAN)
            )
        } else {
            format!("Explicit law in the clamped cylinder: {}.", explicit.note)
        });
    }
    for r in rows {
        run.push(r);
    }
    Ok(())
}

/// `law` (with `coupling`, d = 0) tabulated as the scene asks, or on the default [`TableSpec`] if
/// the scene's laws are exact; with the table's build time \[s\] and a description of it.
fn tabulated_muscle(
    models: &Models,
    approach: Approach,
    law: LawKind,
    coupling: Coupling,
) -> Result<(Muscle<Energy>, f64, String), AppError> {
    let map = models
        .activation_map(approach)
        .map_err(|reason| crate::Error::Unsupported { reason })?;
    let spec = match models.representation {
        LawRepresentation::Tabulated(spec) => spec,
        LawRepresentation::Exact => TableSpec::default(),
    };
    let started = Instant::now();
    let table = models
        .law(law, map)?
        .represented(LawRepresentation::Tabulated(spec), &[0.0])?;
    let build = started.elapsed().as_secs_f64();
    let described = match &table {
        Law::Tabulated(t) => t
            .reports()
            .iter()
            .map(|r| {
                format!(
                    "table on λ ∈ [{}, {}]: {} pieces, {:.1} kB, built in {:.1} ms, checked |Δγ| ≤ {:.1e}, frozen/consistent fibre stress ≤ {:.1e}/{:.1e} kPa{}",
                    spec.lambda_lo,
                    spec.lambda_hi,
                    r.pieces,
                    r.bytes as f64 / 1e3,
                    1e3 * build,
                    r.gamma_error,
                    r.frozen_stress_error,
                    r.consistent_stress_error,
                    match r.exact_intervals {
                        0 => String::new(),
                        n => format!(
                            "; {n} interval(s) of total width {:.1e} left to the exact solve (its own rounding above the tolerances there)",
                            r.exact_width
                        ),
                    }
                )
            })
            .collect::<Vec<_>>()
            .join("; "),
        _ => String::new(),
    };
    let muscle = Muscle::new(models.energy.clone(), table, 0.0, coupling)?.with_map(map)?;
    Ok((muscle, build, described))
}

/// Law representation: each law that solves for γ, exact (the reference) against tabulated
/// ([`crate::active::TabulatedLaw`]): the implicit law (frozen) and the energy law (consistent)
/// along the 0D fibre curve, the implicit law in the clamped cylinder. Times exclude the table's
/// build, which the notes and findings state beside them (it is paid once per damage).
pub(super) fn law_representation(
    models: &Models,
    o: &Resolved,
    run: &mut Runner<'_>,
    findings: &mut Vec<String>,
) -> Result<(), AppError> {
    let stretches = &o.curve_stretches;
    let quantity = "P(λ) over the 0D sweep [kPa]";
    for (law, coupling) in [
        (LawKind::Implicit, EXACT),
        (LawKind::Energy, Coupling::Consistent),
    ] {
        let option = format!("{} law representation (0D)", law.name());
        let (t_ref, (p_ref, g_ref)) =
            fibre_curve(&muscle(models, o.approach, law, coupling)?, stretches)?;
        let mut r = Measurement::new(&option, "exact", true, t_ref, quantity, CurveError::ZERO);
        r.gamma_error = Some(0.0);
        run.push(r);
        let (tabulated, build, described) = tabulated_muscle(models, o.approach, law, coupling)?;
        let (t, (p, g)) = fibre_curve(&tabulated, stretches)?;
        let e = curve_error(&p_ref, &p);
        let ge = curve_error(&g_ref, &g).max_abs;
        let mut r = Measurement::new(&option, "tabulated", false, t, quantity, e);
        r.gamma_error = Some(ge);
        r.note = described;
        run.push(r);
        findings.push(format!(
            "Tabulated {} law (0D, {} stretches): {}; stress error max {:.1e} kPa, γ error max {:.1e}; building the table ({:.1} ms) takes as long as {:.0} of these curves solved exactly.",
            law.name(),
            stretches.len(),
            t.against(&t_ref, "the exact solve"),
            e.max_abs,
            ge,
            1e3 * build,
            build / t_ref.median
        ));
    }
    const OPTION: &str = "implicit law representation (FE)";
    let exact = o.clamped(
        &muscle(models, o.approach, LawKind::Implicit, EXACT)?,
        &tight(),
    )?;
    run.push(fe_row(OPTION, "exact", true, &exact, &exact));
    let (tabulated, build, described) =
        tabulated_muscle(models, o.approach, LawKind::Implicit, EXACT)?;
    let table = o.clamped(&tabulated, &tight())?;
    let mut row = fe_row(OPTION, "tabulated", false, &table, &exact);
    row.note = if row.note.is_empty() {
        described
    } else {
        format!("{}; {described}", row.note)
    };
    findings.push(format!(
        "Tabulated implicit law in the clamped cylinder ({} × {} cells, {} stretches): {}; per Newton iteration {:.2e} s against {:.2e} s; nominal stress error max {:.1e} kPa, centre γ error max {:.1e} (table built once in {:.1} ms).",
        o.fe_mesh.0,
        o.fe_mesh.1,
        o.fe_stretches.len(),
        table.time.against(&exact.time, "the exact solve"),
        table.per_iteration_s,
        exact.per_iteration_s,
        row.error.max_abs,
        row.gamma_error.unwrap_or(f64::NAN),
        1e3 * build
    ));
    run.push(row);
    Ok(())
}

/// The representative point of BENCHMARKS.md: fibre stretch ≈ 1.10.
fn representative_point() -> AxiF {
    let t = 1.1f64.sqrt().recip();
    AxiF::from([t, 0.05, 0.02, 1.1, t])
}

fn max_rel(a: &nalgebra::SMatrix<f64, 5, 5>, b: &nalgebra::SMatrix<f64, 5, 5>) -> f64 {
    (a - b).amax() / b.amax()
}

/// The wall time of one stress-and-tangent call of `m` at the representative point (median of
/// repeated batches of 200) and the tangent there.
fn per_point(
    m: &dyn AxisymmetricMaterial,
) -> Result<(Timing, nalgebra::SMatrix<f64, 5, 5>), AppError> {
    const BATCH: usize = 200;
    let f = representative_point();
    let (t, k) = time_median(|| -> Result<_, AppError> {
        let mut last = None;
        for _ in 0..BATCH {
            last = Some(m.stress_tangent(std::hint::black_box(&f))?);
        }
        Ok(last.map(|v| v.1).unwrap_or_default())
    })?;
    Ok((t.per(BATCH), k))
}

/// Derivative routes at one material point and in the FE.
pub(super) fn derivative_route(
    models: &Models,
    o: &Resolved,
    run: &mut Runner<'_>,
) -> Result<(), AppError> {
    let fast = muscle(models, o.approach, o.working_law(), EXACT)?;
    let oracle = OracleRoute::new(&fast);
    let fd = FiniteDifferenceTangent::new(&fast, o.fd_step)?;
    const POINT: &str = "derivative route (point)";
    let quantity = &format!(
        "∂P/∂F at one point [kPa] ({} law, frozen exact)",
        o.working_law().name()
    );
    let (t_fast, k_fast) = per_point(&fast)?;
    run.push(Measurement::new(
        POINT,
        "fast AD (invariants)",
        true,
        t_fast,
        quantity,
        CurveError::ZERO,
    ));
    let variants: [(&str, &dyn AxisymmetricMaterial); 2] = [
        ("oracle (9-entry F + γ)", &oracle),
        ("central differences of P", &fd),
    ];
    for (name, m) in variants {
        let (t, k) = per_point(m)?;
        let e = CurveError {
            max_abs: (k - k_fast).amax(),
            max_rel: max_rel(&k, &k_fast),
        };
        run.push(Measurement::new(POINT, name, false, t, quantity, e));
    }
    const FE: &str = "derivative route (FE)";
    let reference = o.clamped(&fast, &tight())?;
    run.push(fe_row(
        FE,
        "fast AD (invariants)",
        true,
        &reference,
        &reference,
    ));
    for (name, m) in variants {
        let r = o.clamped(m, &tight())?;
        run.push(fe_row(FE, name, false, &r, &reference));
    }
    Ok(())
}

/// Exact versus symmetric frozen tangent in the FE.
pub(super) fn frozen_tangent(
    models: &Models,
    o: &Resolved,
    run: &mut Runner<'_>,
) -> Result<(), AppError> {
    const OPTION: &str = "frozen tangent (FE)";
    let exact = muscle(models, o.approach, o.working_law(), EXACT)?;
    let symmetric = muscle(
        models,
        o.approach,
        o.working_law(),
        Coupling::Frozen(FrozenTangent::Symmetric),
    )?;
    let reference = o.clamped(&exact, &tight())?;
    run.push(fe_row(
        OPTION,
        "exact (non-symmetric)",
        true,
        &reference,
        &reference,
    ));
    // The symmetric part of a non-symmetric tangent converges linearly at best: where it fails,
    // cutting the step 9 times down to 1e-4 does not rescue it and cost 14 s of the default
    // study. These variants give up at their first failed step (min step = first step): a
    // failure is their measured result, not a failure of the study.
    let no_cuts = |s: Stepping| Stepping {
        min_step: s.initial_step,
        ..s
    };
    let r = o.clamped(&symmetric, &with_stepping(no_cuts(Stepping::default())))?;
    run.push(fe_row(
        OPTION,
        "symmetric, 25 its/step",
        false,
        &r,
        &reference,
    ));
    // Linear convergence: a looser tolerance and twice the iterations per step.
    let patient = with_stepping(no_cuts(Stepping {
        tolerance: 1e-6,
        max_iterations: 50,
        ..Stepping::default()
    }));
    let r = o.clamped(&symmetric, &patient)?;
    run.push(fe_row(
        OPTION,
        "symmetric, tol 1e-6, 50 its/step",
        false,
        &r,
        &reference,
    ));
    Ok(())
}

/// Mesh refinement of the clamped cylinder.
pub(super) fn mesh(
    models: &Models,
    o: &Resolved,
    run: &mut Runner<'_>,
    findings: &mut Vec<String>,
) -> Result<(), AppError> {
    const OPTION: &str = "mesh (clamped)";
    let m = muscle(models, o.approach, o.working_law(), EXACT)?;
    let mut runs = Vec::new();
    for &cells in &o.meshes {
        runs.push((
            cells,
            fe_run(&m, o.geom, cells, Bases::Clamped, &o.fe_stretches, &tight())?,
        ));
    }
    let Some((_, finest)) = runs.last().cloned() else {
        return Ok(());
    };
    let at = o
        .fe_stretches
        .iter()
        .position(|&s| (s - 1.17).abs() < 1e-12);
    let mut coarsest = None;
    for (k, (cells, r)) in runs.iter().enumerate() {
        let reference = k + 1 == runs.len();
        let mut row = fe_row(
            OPTION,
            &format!("{} × {} cells", cells.0, cells.1),
            reference,
            r,
            &finest,
        );
        let (p, p_ref) = match at {
            Some(i) => (r.stress[i], finest.stress[i]),
            None => (f64::NAN, f64::NAN),
        };
        if p.is_finite() && p_ref.is_finite() {
            let rel = ((p - p_ref) / p_ref).abs();
            row.note = format!("P(1.17) = {p:.6} kPa, rel. error {rel:.1e}; {}", row.note);
            if !reference && rel <= 1e-4 && coarsest.is_none() {
                coarsest = Some((*cells, rel, r.dofs));
            }
        }
        run.push(row);
    }
    if !finest.failures.is_empty() {
        findings.push(format!(
            "Mesh: the finest mesh ({} × {}) failed, so no mesh is judged against it: {}.",
            o.meshes[o.meshes.len() - 1].0,
            o.meshes[o.meshes.len() - 1].1,
            finest.failures.join("; ")
        ));
    } else if at.is_some() {
        findings.push(match coarsest {
            Some((c, rel, dofs)) => format!(
                "Mesh: the coarsest mesh with P(1.17) within 1e-4 (relative) of the finest ({} × {}) is {} × {} cells ({} dofs, rel. error {:.1e}).",
                o.meshes[o.meshes.len() - 1].0, o.meshes[o.meshes.len() - 1].1, c.0, c.1, dofs, rel
            ),
            None => "Mesh: no mesh coarser than the finest has P(1.17) within 1e-4 of it.".to_string(),
        });
    }
    Ok(())
}

/// Element: Q2/Q1 and the cheaper Q1/P0 (on the FE mesh and on cells halved once and twice)
/// against Q2/Q1 on cells halved once (the accurate end), clamped cylinder, [`Resolved::working_law`].
pub(super) fn element(
    models: &Models,
    o: &Resolved,
    run: &mut Runner<'_>,
    findings: &mut Vec<String>,
) -> Result<(), AppError> {
    const OPTION: &str = "element (clamped)";
    let m = muscle(models, o.approach, o.working_law(), EXACT)?;
    let (nr, nz) = o.fe_mesh;
    let with = |element| SolverOptions { element, ..tight() };
    let reference = fe_run(
        &m,
        o.geom,
        (2 * nr, 2 * nz),
        Bases::Clamped,
        &o.fe_stretches,
        &with(Element::Q2Q1),
    )?;
    let mut best = None;
    for (element, k) in [
        (Element::Q2Q1, 1),
        (Element::Q1P0, 1),
        (Element::Q1P0, 2),
        (Element::Q1P0, 4),
    ] {
        let cells = (k * nr, k * nz);
        let r = fe_run(
            &m,
            o.geom,
            cells,
            Bases::Clamped,
            &o.fe_stretches,
            &with(element),
        )?;
        let row = fe_row(
            OPTION,
            &format!("{element} {} × {} cells", cells.0, cells.1),
            false,
            &r,
            &reference,
        );
        if element == Element::Q1P0 && row.measured() {
            best = Some((cells, row.error.max_rel, r.time));
        }
        run.push(row);
    }
    run.push(fe_row(
        OPTION,
        &format!("Q2/Q1 {} × {} cells", 2 * nr, 2 * nz),
        true,
        &reference,
        &reference,
    ));
    if let Some((cells, rel, time)) = best {
        findings.push(format!(
            "Element: Q1/P0 on {} × {} cells misses Q2/Q1 on {} × {} by {:.1e} (relative), {}.",
            cells.0,
            cells.1,
            2 * nr,
            2 * nz,
            rel,
            time.against(&reference.time, "the reference")
        ));
    }
    Ok(())
}

/// Newton tolerance in the FE.
pub(super) fn tolerance(
    models: &Models,
    o: &Resolved,
    run: &mut Runner<'_>,
    findings: &mut Vec<String>,
) -> Result<(), AppError> {
    const OPTION: &str = "Newton tolerance (FE)";
    let m = muscle(models, o.approach, o.working_law(), EXACT)?;
    let mut runs = Vec::new();
    for &tol in &o.tolerances {
        runs.push((tol, o.clamped(&m, &with_tolerance(tol))?));
    }
    let Some((_, reference)) = runs.last().cloned() else {
        return Ok(());
    };
    let mut words = Vec::new();
    for (k, (tol, r)) in runs.iter().enumerate() {
        let row = fe_row(
            OPTION,
            &format!("tol {tol:.0e}"),
            k + 1 == runs.len(),
            r,
            &reference,
        );
        if !row.reference {
            words.push(if row.error.max_abs.is_finite() {
                format!(
                    "{tol:.0e}: P within {:.1e} kPa, {}",
                    row.error.max_abs,
                    r.time.against(&reference.time, "the reference")
                )
            } else {
                format!("{tol:.0e}: failed")
            });
        }
        run.push(row);
    }
    if let Some((tightest, _)) = runs.last() {
        findings.push(format!(
            "Newton tolerance against {tightest:.0e}: {}.",
            words.join("; ")
        ));
    }
    Ok(())
}

/// 0D versus FE on the sliding cylinder, whose exact solution is homogeneous.
pub(super) fn zero_d_vs_fe(
    models: &Models,
    o: &Resolved,
    run: &mut Runner<'_>,
) -> Result<(), AppError> {
    const OPTION: &str = "0D vs FE (sliding)";
    let m = muscle(models, o.approach, o.working_law(), EXACT)?;
    let (t0, (p0, g0)) = time_median(|| -> Result<(Vec<f64>, Vec<f64>), AppError> {
        let mut p = Vec::new();
        let mut g = Vec::new();
        for &l in &o.fe_stretches {
            let pt = along_fibres(&m, l)?;
            p.push(pt.stress);
            g.push(pt.gamma);
        }
        Ok((p, g))
    })?;
    let quantity = "P(λ) at the FE stretches [kPa]";
    let mut r = Measurement::new(
        OPTION,
        "0D (exact here)",
        true,
        t0,
        quantity,
        CurveError::ZERO,
    );
    r.gamma_error = Some(0.0);
    run.push(r);
    for cells in [o.meshes[0], o.fe_mesh] {
        let fe = fe_run(&m, o.geom, cells, Bases::Sliding, &o.fe_stretches, &tight())?;
        let reference = FeRun {
            stress: p0.clone(),
            gamma_centre: g0.clone(),
            ..fe.clone()
        };
        let row = fe_row(
            OPTION,
            &format!("FE {} × {} cells", cells.0, cells.1),
            false,
            &fe,
            &reference,
        );
        run.push(row);
        if o.meshes[0] == o.fe_mesh {
            break;
        }
    }
    Ok(())
}

/// Incompressibility: the quadratic volumetric energy (κ/2)(J − 1)² at growing κ against the
/// exact constraint (the accurate end: κ = ∞), [`Resolved::working_law`], frozen; 0D along the fibres (the
/// lateral stretches solved per point) and the clamped cylinder (perturbed Lagrangian: the
/// Newton iterations show whether the mixed form stays well posed as κ grows).
pub(super) fn incompressibility(
    models: &Models,
    o: &Resolved,
    run: &mut Runner<'_>,
    findings: &mut Vec<String>,
) -> Result<(), AppError> {
    let m = muscle(models, o.approach, o.working_law(), EXACT)?;
    let s0 = crate::uniaxial::reference_stress(&models.energy)?;
    let quadratic = |kappa: f64| Volumetric::new(VolumetricForm::Quadratic { kappa }, s0);
    incompressibility_0d(models, &m, &quadratic, o, run, findings)?;
    const OPTION_FE: &str = "incompressibility (clamped)";
    let reference = o.clamped(&m, &tight())?;
    run.push(fe_row(
        OPTION_FE,
        "exact (J = 1)",
        true,
        &reference,
        &reference,
    ));
    let mut words = Vec::new();
    for kappa in [1e3, 1e5, 1e7] {
        let options = SolverOptions {
            volumetric: Some(quadratic(kappa)?),
            ..tight()
        };
        let r = o.clamped(&m, &options)?;
        let row = fe_row(
            OPTION_FE,
            &format!("quadratic κ = {kappa:.0e} kPa"),
            false,
            &r,
            &reference,
        );
        words.push(format!(
            "κ = {kappa:.0e} kPa: {:.2e} kPa, {} Newton its (exact {})",
            row.error.max_abs, r.iterations, reference.iterations
        ));
        run.push(row);
    }
    findings.push(format!(
        "Incompressibility (clamped cylinder, {} × {} cells{}): {}.",
        o.fe_mesh.0,
        o.fe_mesh.1,
        not_the_scenes(models),
        words.join("; ")
    ));
    Ok(())
}

/// `, the quadratic U at growing κ, not the scene's 4c-giantesio U = …` where the scene's
/// volumetric energy is not the quadratic form the incompressibility group measures; else
/// nothing.
fn not_the_scenes(models: &Models) -> String {
    match &models.volumetric {
        Some(v) if v.form().name() != "quadratic" => format!(
            ", the quadratic U = (κ/2)(J − 1)² at growing κ, not the scene's {} U = {}",
            v.form().name(),
            v.formula()
        ),
        _ => String::new(),
    }
}

/// The 0D part of [`incompressibility`]: muscle `m` along the fibres, exact against the
/// `quadratic` volumetric energy of growing κ.
fn incompressibility_0d(
    models: &Models,
    m: &Muscle<Energy>,
    quadratic: &dyn Fn(f64) -> crate::Result<Volumetric>,
    o: &Resolved,
    run: &mut Runner<'_>,
    findings: &mut Vec<String>,
) -> Result<(), AppError> {
    const OPTION_0D: &str = "incompressibility (0D)";
    let stretches = &o.curve_stretches;
    let curve = |v: Option<&Volumetric>| -> Result<(Timing, Curves), AppError> {
        time_median(|| -> Result<Curves, AppError> {
            let mut p = Vec::with_capacity(stretches.len());
            let mut g = Vec::with_capacity(stretches.len());
            for &l in stretches {
                let pt = crate::uniaxial::point(m, v, Direction::Along, l)?;
                p.push(pt.stress);
                g.push(pt.gamma);
            }
            Ok((p, g))
        })
    };
    let quantity = "P(λ) over the 0D sweep [kPa]";
    let (t_ref, (p_ref, g_ref)) = curve(None)?;
    let mut r = Measurement::new(
        OPTION_0D,
        "exact (J = 1)",
        true,
        t_ref,
        quantity,
        CurveError::ZERO,
    );
    r.gamma_error = Some(0.0);
    run.push(r);
    let mut words = Vec::new();
    for kappa in [1e3, 1e4, 1e5, 1e6, 1e7, 1e8] {
        let v = quadratic(kappa)?;
        let (t, (p, g)) = curve(Some(&v))?;
        let e = curve_error(&p_ref, &p);
        let mut r = Measurement::new(
            OPTION_0D,
            &format!("quadratic κ = {kappa:.0e} kPa"),
            false,
            t,
            quantity,
            e,
        );
        r.gamma_error = Some(curve_error(&g_ref, &g).max_abs);
        words.push(format!(
            "κ = {kappa:.0e} kPa: {:.2e} kPa, {}",
            e.max_abs,
            t.against(&t_ref, "exact")
        ));
        run.push(r);
    }
    findings.push(format!(
        "Incompressibility (0D, max |P_κ − P_exact| over {} stretches{}): {}.",
        stretches.len(),
        not_the_scenes(models),
        words.join("; ")
    ));
    Ok(())
}

/// Convenience against speed: the material's energy written as a formula
/// ([`Energy::as_formula`], parsed and interpreted at run time) against the same energy compiled
/// (the reference), per material point (stress, tangent and dP/dγ of the working law, frozen,
/// exact tangent) and per sweep of the clamped cylinder. Not measured for a material that is
/// itself a formula (it has no compiled twin).
pub(super) fn formula_energy(
    models: &Models,
    o: &Resolved,
    run: &mut Runner<'_>,
    findings: &mut Vec<String>,
) -> Result<(), AppError> {
    if let Energy::Formula(_) = models.energy {
        findings.push("Formula energy not measured: the material is itself a formula, with no compiled form to compare with.".into());
        return Ok(());
    }
    let formula = models
        .energy
        .as_formula()
        .map_err(|e| AppError::Invalid(format!("the material's energy as a formula: {e}")))?;
    let written = Models {
        energy: Energy::Formula(formula),
        ..models.clone()
    };
    let law = o.working_law();
    let (compiled, interpreted) = (
        muscle(models, o.approach, law, EXACT)?,
        muscle(&written, o.approach, law, EXACT)?,
    );
    const POINT: &str = "formula energy (point)";
    let quantity = format!(
        "∂P/∂F at one point [kPa] ({} law, frozen exact)",
        law.name()
    );
    let (t_ref, k_ref) = per_point(&compiled)?;
    run.push(Measurement::new(
        POINT,
        "compiled",
        true,
        t_ref,
        &quantity,
        CurveError::ZERO,
    ));
    let (t, k) = per_point(&interpreted)?;
    let e = CurveError {
        max_abs: (k - k_ref).amax(),
        max_rel: max_rel(&k, &k_ref),
    };
    run.push(Measurement::new(POINT, "formula", false, t, &quantity, e));
    const FE: &str = "formula energy (FE)";
    let reference = o.clamped(&compiled, &tight())?;
    run.push(fe_row(FE, "compiled", true, &reference, &reference));
    let sweep = o.clamped(&interpreted, &tight())?;
    let row = fe_row(FE, "formula", false, &sweep, &reference);
    findings.push(format!(
        "Formula energy ({} written as a formula, {} law): per material point (stress, tangent, dP/dγ) {}; per sweep of the clamped cylinder ({} × {} cells) {}; tangent within {:.1e} (relative), nominal stress within {:.1e} kPa.",
        models.energy.name(),
        law.name(),
        t.against(&t_ref, "the compiled energy"),
        o.fe_mesh.0,
        o.fe_mesh.1,
        sweep.time.against(&reference.time, "the compiled energy"),
        e.max_rel,
        row.error.max_abs
    ));
    run.push(row);
    Ok(())
}
