//! Trade-off studies (`kind = "tradeoff"`): speed versus accuracy of the options a user trades
//! ([`crate::tradeoff`]), restricted to the option groups, meshes, tolerances and stretches the
//! scene names. A scene holds at most one: its outputs are `tradeoff.csv`, `tradeoff.md`,
//! `tradeoff.html` and one `tradeoff_*.png`/`.svg` per option.
//!
//! | key | meaning | default |
//! |---|---|---|
//! | `options` | option groups: `activation-law`, `activation-law-fe`, `derivative-route`, `frozen-tangent`, `mesh`, `newton-tolerance`, `zero-d-vs-fe` | all |
//! | `stretch` | stretches of every sweep (FE and 0D) | FE: 0.8, 1, 1.17, 1.3; 0D: the first uniaxial study along the fibres, or 0.65:0.01:1.60 |
//! | `meshes` | `[[nr, nz], ...]` of the mesh option, coarse to fine (the last is the reference) | 2 × 8, 4 × 16, 8 × 32, 16 × 64 |
//! | `nr`, `nz` | mesh of the other FE options | the first cylinder study's, or 4 × 16 |
//! | `radius`, `length`, `grading` | the cylinder | the first cylinder study's, or 1, 4, 3 |
//! | `tolerances` | Newton tolerances, loose to tight (the last is the reference) | 1e-6, 1e-8, 1e-10, 1e-12 |

use super::resolve::{cell_count, grading, non_empty, only_keys, positive, Ctx};
use super::schema::StudySpec;
use super::SceneError;
use crate::tradeoff::study::{Geometry, OptionGroup, TradeoffOptions};

/// A validated trade-off study.
#[derive(Debug, Clone, PartialEq)]
pub struct TradeoffStudy {
    /// Label.
    pub name: String,
    /// What to run (geometry and FE mesh resolved).
    pub options: TradeoffOptions,
}

/// What a trade-off study leaves to the scene's first cylinder study.
pub(super) struct Pending {
    radius: Option<f64>,
    length: Option<f64>,
    grading: Option<f64>,
    nr: Option<usize>,
    nz: Option<usize>,
}

pub(super) fn resolve_tradeoff(
    ctx: &Ctx,
    key: &str,
    s: &StudySpec,
    lambdas: Option<Vec<f64>>,
) -> Result<(TradeoffStudy, StudySpec, Pending), SceneError> {
    let k = |name: &str| format!("{key}.{name}");
    only_keys(
        ctx,
        key,
        s,
        "tradeoff",
        &[
            "options",
            "meshes",
            "tolerances",
            "nr",
            "nz",
            "radius",
            "length",
            "grading",
        ],
    )?;
    if s.damage.is_some() {
        return Err(ctx.err(
            k("damage"),
            "(given)",
            "not a key of a tradeoff study: every variant runs at d = 0",
        ));
    }
    let defaults = TradeoffOptions::default();

    let groups = s.options.clone().unwrap_or_else(|| defaults.groups.clone());
    non_empty(
        ctx,
        &k("options"),
        &groups,
        &format!(
            "name at least one option group of {:?}",
            OptionGroup::ALL.map(OptionGroup::key)
        ),
    )?;
    for (j, g) in groups.iter().enumerate() {
        if groups[..j].contains(g) {
            return Err(ctx.err(
                format!("{key}.options[{j}]"),
                format!("{:?}", g.key()),
                "named twice",
            ));
        }
    }

    let meshes = match &s.meshes {
        None => defaults.meshes.clone(),
        Some(v) => {
            non_empty(
                ctx,
                &k("meshes"),
                v,
                "give at least one mesh [nr, nz] (the last is the reference)",
            )?;
            let mut meshes = Vec::with_capacity(v.len());
            for (j, [nr, nz]) in v.iter().enumerate() {
                let at = format!("{key}.meshes[{j}]");
                let cells = (cell_count(ctx, &at, *nr)?, cell_count(ctx, &at, *nz)?);
                if let Some(&(pr, pz)) = meshes.last() {
                    if cells.0 * cells.1 <= pr * pz {
                        return Err(ctx.err(
                            at,
                            format!("[{nr}, {nz}]"),
                            format!(
                                "meshes go from coarse to fine (the last is the reference): \
                                 {nr} × {nz} cells is not finer than the {pr} × {pz} before it"
                            ),
                        ));
                    }
                }
                meshes.push(cells);
            }
            meshes
        }
    };

    let tolerances = match &s.tolerances {
        None => defaults.tolerances.clone(),
        Some(v) => {
            non_empty(
                ctx,
                &k("tolerances"),
                v,
                "give at least one Newton tolerance (the last is the reference)",
            )?;
            for (j, t) in v.iter().enumerate() {
                let at = format!("{key}.tolerances[{j}]");
                if !(t.is_finite() && *t > 0.0 && *t < 1.0) {
                    return Err(ctx.err(at, t, "a Newton tolerance must lie in (0, 1)"));
                }
                if j > 0 && *t >= v[j - 1] {
                    return Err(ctx.err(
                        at,
                        t,
                        format!(
                            "tolerances go from loose to tight (the last is the reference): \
                             not below the {} before it",
                            v[j - 1]
                        ),
                    ));
                }
            }
            v.clone()
        }
    };

    let pending = Pending {
        radius: s
            .radius
            .map(|v| positive(ctx, &k("radius"), v))
            .transpose()?,
        length: s
            .length
            .map(|v| positive(ctx, &k("length"), v))
            .transpose()?,
        grading: s
            .grading
            .map(|g| grading(ctx, &k("grading"), g))
            .transpose()?,
        nr: s.nr.map(|v| cell_count(ctx, &k("nr"), v)).transpose()?,
        nz: s.nz.map(|v| cell_count(ctx, &k("nz"), v)).transpose()?,
    };

    let name = s
        .name
        .clone()
        .unwrap_or_else(|| "speed versus accuracy".into());
    let options = TradeoffOptions {
        groups: groups.clone(),
        meshes: meshes.clone(),
        fe_stretches: lambdas.clone().unwrap_or(defaults.fe_stretches.clone()),
        curve_stretches: lambdas,
        tolerances: tolerances.clone(),
        ..defaults
    };
    let mut r = s.clone();
    r.name = Some(name.clone());
    r.options = Some(groups);
    r.meshes = Some(meshes.iter().map(|&(a, b)| [a as i64, b as i64]).collect());
    r.tolerances = Some(tolerances);
    // Without `stretch` the FE and 0D sweeps take different defaults; the printed scene leaves
    // it out so that it runs as this one does.
    Ok((TradeoffStudy { name, options }, r, pending))
}

impl Pending {
    /// Fills what the study left out from `cylinder` (the scene's first cylinder study's
    /// geometry and mesh, or the defaults), in the study and in its resolved spec `r`.
    pub(super) fn complete(
        self,
        study: &mut TradeoffStudy,
        r: &mut StudySpec,
        (geometry, cells): (Geometry, (usize, usize)),
    ) {
        let g = Geometry {
            radius: self.radius.unwrap_or(geometry.radius),
            length: self.length.unwrap_or(geometry.length),
            grading: self.grading.unwrap_or(geometry.grading),
        };
        let fe_mesh = (self.nr.unwrap_or(cells.0), self.nz.unwrap_or(cells.1));
        study.options.geometry = Some(g);
        study.options.fe_mesh = Some(fe_mesh);
        r.radius = Some(g.radius);
        r.length = Some(g.length);
        r.grading = Some(g.grading);
        r.nr = Some(fe_mesh.0 as i64);
        r.nz = Some(fe_mesh.1 as i64);
    }
}
