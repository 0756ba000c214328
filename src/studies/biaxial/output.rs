//! The biaxial kind's figure (both nominal stresses along the path, per model) and its report
//! section (the boundary conditions, both stresses at the end of the path).

use super::BiaxialResult;
use crate::app_error::AppError;
use crate::plot::{Figure, Panel, Scale, Series, Stroke};
use crate::studies::outputs::{
    each_study, hidden_curves, panel_of, prefixed, Context, KindOutput, Of, OwnTable, Used,
};
use crate::text::escape_html as escape;
use std::fmt::Write;

/// The file.
pub const FILE: &str = "biaxial.csv";

impl KindOutput for BiaxialResult {
    fn tables(&self, study: &str) -> Vec<OwnTable> {
        vec![OwnTable::rows(
            FILE,
            "one row per biaxial study, model and stretch pair",
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
        each_study(studies, biaxial_figure)
    }

    fn report(studies: &[Of<Self>], _: &Context, h: &mut String) -> Result<(), AppError> {
        biaxial_section(h, studies);
        Ok(())
    }
}

/// Planar biaxial stretch: P₁₁ and P₂₂ along the path, per model.
pub fn biaxial_figure(study: &str, r: &BiaxialResult) -> Option<Figure> {
    let x = if r.path == "pairs" {
        "(λ₁, λ₂) pair n, as listed in pairs [-]"
    } else {
        "stretch along the fibres λ₁ [-]"
    };
    let series = |i: usize| -> Vec<Series> {
        r.curves
            .iter()
            .enumerate()
            .map(|(j, c)| {
                let words = c.model.words();
                let points = c
                    .points
                    .iter()
                    .enumerate()
                    .map(|(n, p)| {
                        let at = if r.path == "pairs" {
                            (n + 1) as f64
                        } else {
                            p.stretches[0]
                        };
                        (at, p.nominal[i])
                    })
                    .collect();
                Series::new(words, points, Stroke::Solid, j % 6)
            })
            .collect()
    };
    let mut panels: Vec<Panel> = [
        panel_of(
            "Nominal stress along the fibres P₁₁",
            x,
            "P₁₁ [kPa]",
            series(0),
        ),
        panel_of(
            "Nominal stress across the fibres P₂₂",
            x,
            "P₂₂ [kPa]",
            series(1),
        ),
    ]
    .into_iter()
    .flatten()
    .map(|mut p| {
        if r.path == "pairs" {
            p.scale = Scale::Counted;
        }
        p
    })
    .collect();
    let hidden = hidden_curves(&mut panels);
    (!panels.is_empty()).then(|| {
        Figure::new(
            prefixed("biaxial", study),
            format!("Planar biaxial stretch, {} (study \"{study}\")", r.path),
            format!(
                "Homogeneous planar biaxial stretch F = diag(λ₁, λ₂, λ₃) of the {} energy, λ₁ along the fibres and λ₂ across, the faces normal to e₃ traction free (λ₃ from incompressibility or the volumetric energy).{hidden} Cauchy stresses and λ₃ in biaxial.csv.",
                r.energy
            ),
            panels,
        )
    })
}

/// Planar biaxial stretch: the boundary conditions, and both stresses at the last state of the
/// path per model.
fn biaxial_section(h: &mut String, studies: &[Of<BiaxialResult>]) {
    for s in studies {
        let r = s.result;
        let _ = writeln!(
            h,
            "<h2>Planar biaxial stretch (study \"{}\", {} path)</h2>\n<p>F = diag(λ₁, λ₂, λ₃), λ₁ along the fibres and λ₂ across; the faces normal to e₃ are traction free, so λ₃ = 1/(λ₁λ₂) (incompressible) or solves P₃₃ = 0 with the volumetric energy. An isotropic material has P₁₁ = P₂₂ on the equibiaxial path; the fibres, and an activation along them, break that symmetry. Active stress adds (1 − d) P_act(λ₁) to P₁₁ alone; active strain changes the stiffness across the fibres too.</p>\n<table><tr><th>model</th><th>λ₁</th><th>λ₂</th><th>λ₃</th><th>P₁₁ [kPa]</th><th>P₂₂ [kPa]</th><th>σ₁₁ [kPa]</th><th>σ₂₂ [kPa]</th></tr>",
            escape(s.name),
            r.path
        );
        let number = |x: f64| crate::text::significant(x, 6);
        for c in &r.curves {
            let Some(p) = c.points.last() else { continue };
            let [l1, l2, l3] = p.stretches;
            let _ = writeln!(
                h,
                "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
                escape(&c.model.words()),
                number(l1),
                number(l2),
                number(l3),
                number(p.nominal[0]),
                number(p.nominal[1]),
                number(p.cauchy[0]),
                number(p.cauchy[1])
            );
        }
        h.push_str("</table>\n");
    }
}
