//! `curves.csv`'s rows, the table the uniaxial and cylinder kinds share: one row per computed
//! point of a uniaxial curve or an FE sweep, and the [`CurveId`] that tells one curve from the
//! others (the CSV writer, the figures and Python read the same rows). The columns' units and
//! descriptions are [`crate::output::csv::CURVE_FIELDS`].

use crate::plot::CurveId;
use crate::studies::cylinder::{bases_name, CylinderResult, Sweep, SweepPoint};
use crate::studies::uniaxial::{Curve, CurveModel, CurvePoint};
use crate::uniaxial::Direction;

/// One point of one curve as `curves.csv` writes it. `None` is an empty cell.
#[derive(Debug, Clone, PartialEq)]
pub struct Row<'a> {
    /// The study's name.
    pub study: &'a str,
    /// `uniaxial` | `cylinder`.
    pub model: &'static str,
    /// `along` | `across` (uniaxial).
    pub direction: Option<&'static str>,
    /// `sliding` | `clamped` (cylinder).
    pub bases: Option<&'static str>,
    /// Energy name.
    pub energy: &'a str,
    /// `passive` | `constant` | `implicit` | `explicit` | `energy`.
    pub law: &'static str,
    /// `frozen` | `consistent` (active laws only).
    pub coupling: Option<&'static str>,
    /// Damage (active laws only).
    pub d: Option<f64>,
    /// Stretch λ.
    pub lambda: f64,
    /// γ (uniaxial) or γ at the centre of the cylinder.
    pub gamma: Option<f64>,
    /// Nominal stress along the stretch \[kPa\].
    pub p: f64,
    /// Passive stress of the material at λ \[kPa\] (active uniaxial rows along the fibres).
    pub p_pas: Option<f64>,
    /// Target active stress (1 − d) P_act(λ) \[kPa\] (same rows).
    pub p_act: Option<f64>,
    /// Newton iterations to reach this stretch from the previous one (cylinder).
    pub newton_iterations: Option<usize>,
    /// Cauchy stress along the stretch σ = J⁻¹ P Fᵀ \[kPa\] (uniaxial).
    pub cauchy: Option<f64>,
    /// Volume ratio J [-] (uniaxial rows of a nearly incompressible scene; empty: J = 1).
    pub volume: Option<f64>,
    /// The 0D stress of the same model at λ \[kPa\] (cylinder).
    pub p_0d: Option<f64>,
    /// Free dofs of the FE solve (cylinder).
    pub dofs: Option<usize>,
    /// `Q2/Q1` | `Q1/P0` (cylinder).
    pub element: Option<&'static str>,
    /// The cylinder's regions in words (cylinder with regions).
    pub regions: Option<String>,
}

impl Row<'_> {
    /// The curve this point belongs to.
    pub fn curve(&self) -> CurveId {
        let number = |x: Option<f64>| x.map_or(String::new(), |v| v.to_string());
        CurveId(
            [
                self.study,
                self.model,
                self.direction.unwrap_or(""),
                self.bases.unwrap_or(""),
                self.energy,
                self.law,
                self.coupling.unwrap_or(""),
                &number(self.d),
                &number(self.gamma.filter(|_| self.law == "constant")),
            ]
            .join(" | "),
        )
    }
}

/// The (law, coupling, d) cells of a uniaxial curve.
fn law_cells(model: CurveModel) -> (&'static str, Option<&'static str>, Option<f64>) {
    match model {
        CurveModel::Passive => ("passive", None, None),
        CurveModel::Constant(_) => ("constant", None, None),
        CurveModel::Active(m) => (m.law.name(), Some(m.coupling.name()), Some(m.damage)),
    }
}

/// The row of point `p` of curve `c` of uniaxial study `study`.
pub fn uniaxial_row<'a>(
    study: &'a str,
    direction: Direction,
    c: &'a Curve,
    p: &CurvePoint,
) -> Row<'a> {
    let (law, coupling, d) = law_cells(c.model);
    Row {
        study,
        model: "uniaxial",
        direction: Some(direction.name()),
        bases: None,
        energy: &c.energy,
        law,
        coupling,
        d,
        lambda: p.lambda,
        gamma: Some(p.gamma),
        p: p.stress,
        p_pas: p.passive,
        p_act: p.active_target,
        newton_iterations: None,
        cauchy: Some(p.cauchy),
        volume: p.volume,
        p_0d: None,
        dofs: None,
        element: None,
        regions: None,
    }
}

/// The row of point `p` of sweep `sweep` of cylinder study `study`.
pub fn sweep_row<'a>(
    study: &'a str,
    c: &'a CylinderResult,
    sweep: &Sweep,
    p: &SweepPoint,
) -> Row<'a> {
    let m = sweep.model;
    Row {
        study,
        model: "cylinder",
        direction: None,
        bases: Some(bases_name(c.bases)),
        energy: &c.energy,
        law: m.law.name(),
        coupling: Some(m.coupling.name()),
        d: Some(m.damage),
        lambda: p.lambda,
        gamma: Some(p.gamma_centre),
        p: p.stress,
        p_pas: None,
        p_act: None,
        newton_iterations: Some(p.newton_iterations),
        cauchy: None,
        volume: None,
        p_0d: p.stress_0d,
        dofs: Some(sweep.dofs),
        element: Some(c.element.name()),
        regions: c.regions_in_words(),
    }
}

/// The curve of `curves.csv` that uniaxial curve `c` of study `study` writes.
pub fn uniaxial_curve(study: &str, direction: Direction, c: &Curve) -> CurveId {
    let p = c.points.first().copied().unwrap_or(CurvePoint {
        lambda: 1.0,
        gamma: match c.model {
            CurveModel::Constant(g) => g,
            _ => 0.0,
        },
        stress: 0.0,
        cauchy: 0.0,
        passive: None,
        active_target: None,
        volume: None,
    });
    uniaxial_row(study, direction, c, &p).curve()
}

/// The curve of `curves.csv` that FE sweep `sweep` of cylinder study `study` writes.
pub fn sweep_curve(study: &str, c: &CylinderResult, sweep: &Sweep) -> CurveId {
    let p = sweep.points.first().copied().unwrap_or(SweepPoint {
        lambda: 1.0,
        gamma_centre: 0.0,
        fibre_stretch_centre: 1.0,
        stress: 0.0,
        newton_iterations: 0,
        stress_0d: None,
        passive_0d: None,
        active_0d: 0.0,
    });
    sweep_row(study, c, sweep, &p).curve()
}
