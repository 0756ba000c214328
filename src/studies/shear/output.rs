//! The shear kind's figure (σ₁₂ against k per approach and fibre angle, active strain minus
//! active stress, the normal stresses) and its report section (what differs and why).

use super::{ShearCurve, ShearResult};
use crate::active::Approach;
use crate::app_error::AppError;
use crate::plot::{Figure, Panel, Series, Stroke};
use crate::studies::outputs::{
    each_study, hidden_curves, panel_of, prefixed, strokes, Context, KindOutput, Of, OwnTable, Used,
};
use crate::text::escape_html as escape;
use std::fmt::Write;

const SHEAR: &str = "amount of shear k [-]";
const CAUCHY: &str = "Cauchy stress [kPa]";

/// The file.
pub const FILE: &str = "shear.csv";

impl KindOutput for ShearResult {
    fn tables(&self, study: &str) -> Vec<OwnTable> {
        vec![OwnTable::rows(
            FILE,
            "one row per shear study, approach and amount of shear",
            self.table(study),
        )]
    }

    fn used(&self) -> Used {
        Used {
            models: self.curves.iter().map(|c| c.model.clone()).collect(),
            ..Used::default()
        }
    }

    fn figures(studies: &[Of<Self>], _: &Context) -> Vec<Figure> {
        each_study(studies, shear_figure)
    }

    fn report(studies: &[Of<Self>], _: &Context, h: &mut String) -> Result<(), AppError> {
        shear_section(h, studies);
        Ok(())
    }
}

/// Simple shear: σ₁₂(k) of every model and fibre angle, active strain minus active stress at
/// the same damage and angle, and the normal stresses σ₁₁, σ₂₂.
pub fn shear_figure(study: &str, r: &ShearResult) -> Option<Figure> {
    let mut angles: Vec<f64> = Vec::new();
    for c in &r.curves {
        if !angles.contains(&c.angle) {
            angles.push(c.angle);
        }
    }
    let mut models: Vec<String> = Vec::new();
    for c in &r.curves {
        let w = c.model.words();
        if !models.contains(&w) {
            models.push(w);
        }
    }
    let style = |c: &ShearCurve| {
        let colour = models
            .iter()
            .position(|m| *m == c.model.words())
            .unwrap_or(0);
        let stroke = strokes(angles.iter().position(|a| *a == c.angle).unwrap_or(0));
        (stroke, colour % 6)
    };
    let of = |y: fn(&[f64; 4]) -> f64| -> Vec<Series> {
        r.curves
            .iter()
            .map(|c| {
                let (stroke, colour) = style(c);
                Series::new(
                    format!("{}, θ = {}°", c.model.words(), c.angle),
                    c.points.iter().map(|p| (p.k, y(&p.sigma))).collect(),
                    stroke,
                    colour,
                )
            })
            .collect()
    };
    let difference = differences(r, &style);
    let mut panels: Vec<Panel> = [
        panel_of("Shear stress σ₁₂", SHEAR, CAUCHY, of(|s| s[0])),
        panel_of(
            "σ₁₂ of each activated approach minus that of active stress (same d, same θ)",
            SHEAR,
            "Δσ₁₂ [kPa]",
            difference,
        ),
        panel_of(
            "Normal stress σ₁₁ (along the shear direction)",
            SHEAR,
            CAUCHY,
            of(|s| s[1]),
        ),
        panel_of(
            "Normal stress σ₂₂ (across the shear plane's normal)",
            SHEAR,
            CAUCHY,
            of(|s| s[2]),
        ),
    ]
    .into_iter()
    .flatten()
    .collect();
    // Every panel says which curve hides which, in its legend and in the caption.
    let hidden = hidden_curves(&mut panels);
    (!panels.is_empty()).then(|| {
        Figure::new(
            prefixed("shear", study),
            format!("Simple shear: the activation approaches compared (study \"{study}\")"),
            format!(
                "Homogeneous simple shear F = I + k e₁⊗e₂ of the {} energy, incompressible, the faces normal to e₃ traction free (σ₃₃ = 0 gives the pressure), the fibre in the shear plane at θ to the shear direction e₁ (solid, dashed, dotted: θ = {} in order). Every approach is calibrated to the same uniaxial target along the fibres, P_pas + (1 − d) P_act, and agrees there; in shear they differ. At θ = 0 the fibre stretch stays 1: active stress adds only σ₁₁ = (1 − d) P_act(1), while active strain changes the shear stiffness itself (Giantesio, Musesti & Riccobelli 2019).{hidden} Values in shear.csv.",
                r.energy,
                angles.iter().map(|a| format!("{a}°")).collect::<Vec<_>>().join(", ")
            ),
            panels,
        )
    })
}

/// σ₁₂ of every activated model but active stress minus that of active stress at the same
/// damage and angle, each in the model's `style`.
fn differences(r: &ShearResult, style: &dyn Fn(&ShearCurve) -> (Stroke, usize)) -> Vec<Series> {
    let stress = |c: &ShearCurve| {
        c.model
            .model
            .is_some_and(|m| m.approach == Approach::ActiveStress)
    };
    let mut difference = Vec::new();
    for c in r
        .curves
        .iter()
        .filter(|c| c.model.model.is_some() && !stress(c))
    {
        let d = c.model.model.map(|m| m.damage);
        let Some(s) = r
            .curves
            .iter()
            .find(|s| stress(s) && s.model.model.map(|m| m.damage) == d && s.angle == c.angle)
        else {
            continue;
        };
        let points: Vec<(f64, f64)> = c
            .points
            .iter()
            .filter_map(|p| {
                s.points
                    .iter()
                    .find(|q| q.k == p.k)
                    .map(|q| (p.k, p.sigma[0] - q.sigma[0]))
            })
            .collect();
        let (stroke, colour) = style(c);
        difference.push(Series::new(
            format!("{} − active stress, θ = {}°", c.model.words(), c.angle),
            points,
            stroke,
            colour,
        ));
    }
    difference
}

/// What differs in simple shear and why: σ₁₂ at the largest amount of shear per model and fibre
/// angle, with the boundary conditions.
fn shear_section(h: &mut String, studies: &[Of<ShearResult>]) {
    for s in studies {
        let r = s.result;
        let _ = writeln!(
            h,
            "<h2>Simple shear (study \"{}\")</h2>\n<p>F = I + k e₁⊗e₂, incompressible; the faces normal to e₃ are traction free (σ₃₃ = 0 fixes the pressure), the others carry what the homogeneous state needs. The fibre lies in the shear plane at θ to e₁. Every approach is calibrated to the same uniaxial target along the fibres, so uniaxial tests cannot tell them apart; in shear they differ. With the fibre along the shear direction (θ = 0) the fibre stretch stays 1: active stress adds only a tension (1 − d) P_act(1) along e₁ (σ₁₁), while active strain (and the structural activation) stiffen or soften the shear response itself (Giantesio, Musesti &amp; Riccobelli 2019).</p>\n<table><tr><th>model</th><th>θ</th><th>k</th><th>σ₁₂ [kPa]</th><th>σ₁₁ [kPa]</th><th>σ₂₂ [kPa]</th></tr>",
            escape(s.name)
        );
        for c in &r.curves {
            let Some(p) = c.points.last() else { continue };
            let words = c.model.words();
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}°</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(&words),
                c.angle,
                p.k,
                crate::text::significant(p.sigma[0], 6),
                crate::text::significant(p.sigma[1], 6),
                crate::text::significant(p.sigma[2], 6)
            );
        }
        h.push_str("</table>\n");
    }
}
