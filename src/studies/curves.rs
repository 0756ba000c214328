//! `curves.csv`, the table the uniaxial and cylinder kinds share: one row per computed point of
//! a uniaxial curve or an FE sweep ([`Row`], the columns [`table`]), and the [`CurveId`] that
//! tells one curve from the others (the CSV writer, the figures and Python read the same rows).

use crate::active::Approach;
use crate::plot::CurveId;
use crate::studies::cylinder::{bases_name, CylinderResult, Sweep, SweepPoint};
use crate::studies::domain::{in_domain, IN_DOMAIN};
use crate::studies::outputs::{model_cells, OwnTable};
use crate::studies::table::{Table, CURVES_FILE};
use crate::studies::uniaxial::{Curve, CurveModel, CurvePoint, UniaxialResult};
use crate::uniaxial::Direction;

/// What one row of `curves.csv` is.
pub const ROWS_ARE: &str = "one row per computed point of a uniaxial curve or a cylinder sweep";

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
    /// `active-strain` | `active-stress` | `structural` (activated rows).
    pub approach: Option<String>,
    /// `passive` | `constant` | `implicit` | `explicit` | `energy` (none: active stress).
    pub law: Option<String>,
    /// `frozen` | `consistent` (active laws only).
    pub coupling: Option<String>,
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
    /// Whether the law holds at the point (`None`: a law that holds everywhere; see
    /// [`crate::studies::domain`]).
    pub in_domain: Option<bool>,
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
                self.law.as_deref().unwrap_or(""),
                self.coupling.as_deref().unwrap_or(""),
                &number(self.d),
                &number(
                    self.gamma
                        .filter(|_| self.law.as_deref() == Some("constant")),
                ),
            ]
            .join(" | "),
        )
    }
}

/// The (approach, law, coupling) cells and the damage of a uniaxial curve of `approach`.
fn model_of(approach: Approach, model: CurveModel) -> ([Option<String>; 3], Option<f64>) {
    match model {
        CurveModel::Passive => (model_cells(approach, None), None),
        CurveModel::Constant(_) => (
            [Some(approach.name().into()), Some("constant".into()), None],
            None,
        ),
        CurveModel::Active(m) => (model_cells(approach, Some(m)), Some(m.damage)),
    }
}

/// The row of point `p` of curve `c` of uniaxial study `study` (in `direction`, of `approach`).
pub fn uniaxial_row<'a>(
    study: &'a str,
    (direction, approach): (Direction, Approach),
    c: &'a Curve,
    p: &CurvePoint,
) -> Row<'a> {
    let ([approach, law, coupling], d) = model_of(approach, c.model);
    let active = match &c.model {
        CurveModel::Active(m) => Some(m),
        _ => None,
    };
    Row {
        study,
        model: "uniaxial",
        direction: Some(direction.name()),
        bases: None,
        energy: &c.energy,
        approach,
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
        in_domain: in_domain(active, p.outside),
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
    let [approach, law, coupling] = model_cells(c.approach, Some(m));
    Row {
        study,
        model: "cylinder",
        direction: None,
        bases: Some(bases_name(c.bases)),
        energy: &c.energy,
        approach,
        law,
        coupling,
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
        in_domain: in_domain(Some(&m), p.outside[0].or(p.outside[1])),
    }
}

/// The curve of `curves.csv` that uniaxial curve `c` of study `study` writes.
pub fn uniaxial_curve(study: &str, of: (Direction, Approach), c: &Curve) -> CurveId {
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
        outside: None,
    });
    uniaxial_row(study, of, c, &p).curve()
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
        outside: [None; 2],
    });
    sweep_row(study, c, sweep, &p).curve()
}

/// The rows of uniaxial study `study`, curve by curve.
pub fn uniaxial_rows<'a>(study: &'a str, u: &'a UniaxialResult) -> Vec<Row<'a>> {
    u.curves
        .iter()
        .flat_map(|c| {
            c.points
                .iter()
                .map(move |p| uniaxial_row(study, (u.direction, u.approach), c, p))
        })
        .collect()
}

/// The rows of cylinder study `study`, sweep by sweep.
pub fn cylinder_rows<'a>(study: &'a str, c: &'a CylinderResult) -> Vec<Row<'a>> {
    c.sweeps
        .iter()
        .flat_map(|s| s.points.iter().map(move |p| sweep_row(study, c, s, p)))
        .collect()
}

/// `rows` as the study's table of `curves.csv`.
pub fn own_table(rows: &[Row]) -> OwnTable {
    OwnTable::rows(CURVES_FILE, ROWS_ARE, table(rows))
}

/// The columns of `curves.csv` over `rows` (none: the header alone). The approach is the last
/// column but one, `in_domain` the last, so that readers of the columns before them by position
/// keep working.
pub fn table(rows: &[Row]) -> Table {
    let text = |f: for<'r> fn(&'r Row<'r>) -> Option<&'r str>| {
        rows.iter().map(move |r| f(r).map(String::from))
    };
    let number = |f: fn(&Row) -> Option<f64>| rows.iter().map(f);
    Table::default()
        .text("study", "the study's name", text(|r| Some(r.study)))
        .text(
            "model",
            "uniaxial (homogeneous 0D tension) or cylinder (axisymmetric FE)",
            text(|r| Some(r.model)),
        )
        .text("direction", "along or across the fibres (uniaxial rows)", text(|r| r.direction))
        .text("bases", "sliding or clamped (cylinder rows)", text(|r| r.bases))
        .text("energy", "the strain energy's name", text(|r| Some(r.energy)))
        .text(
            "law",
            "passive, constant, implicit, explicit or energy (empty: an approach without a law, active stress)",
            text(|r| r.law.as_deref()),
        )
        .text(
            "coupling",
            "frozen or consistent (rows of an activation law; empty: passive, constant γ, or an approach without a law)",
            text(|r| r.coupling.as_deref()),
        )
        .number("d", "-", "damage d (active rows); in a cylinder with regions, the body's outside its regions (see regions)", number(|r| r.d))
        .number("lambda", "-", "stretch λ along the loading (cylinder: the imposed L/L₀)", number(|r| Some(r.lambda)))
        .number("gamma", "-", "γ at the point (uniaxial), at the quadrature point nearest the centre (cylinder); ω for the structural approach, 0 for active stress", number(|r| r.gamma))
        .number("P", "kPa", "nominal (first Piola–Kirchhoff) stress along the stretch; cylinder: axial reaction / πR²", number(|r| Some(r.p)))
        .number("P_pas", "kPa", "passive stress of the material at λ (active uniaxial rows along the fibres)", number(|r| r.p_pas))
        .number("P_act", "kPa", "target active stress (1 − d) P_act(λ) (same rows)", number(|r| r.p_act))
        .integer(
            "newton_iterations",
            "Newton iterations from the previous stretch to this one (cylinder rows)",
            rows.iter().map(|r| r.newton_iterations.map(|n| n as i64)),
        )
        .number("cauchy", "kPa", "Cauchy stress along the stretch, σ = J⁻¹ P Fᵀ (uniaxial rows)", number(|r| r.cauchy))
        .number("J", "-", "volume ratio (uniaxial rows of a nearly incompressible scene; empty: J = 1)", number(|r| r.volume))
        .number("P_0d", "kPa", "homogeneous uniaxial (0D) stress of the same model at λ (cylinder rows; with regions, the uniform model's at d)", number(|r| r.p_0d))
        .integer(
            "dofs",
            "free degrees of freedom of the FE solve (cylinder rows)",
            rows.iter().map(|r| r.dofs.map(|n| n as i64)),
        )
        .text("element", "finite element, Q2/Q1 or Q1/P0 (cylinder rows)", text(|r| r.element))
        .text(
            "regions",
            "the cylinder's regions with their own damage or activation, '; '-separated (empty: a uniform body)",
            text(|r| r.regions.as_deref()),
        )
        .text(
            "approach",
            "activation approach, active-strain, active-stress or structural (empty: a passive curve)",
            text(|r| r.approach.as_deref()),
        )
        .boolean("in_domain", IN_DOMAIN, rows.iter().map(|r| r.in_domain))
}
