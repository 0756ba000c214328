//! Points computed outside the domain their activation law holds on ([`crate::active::Domain`]:
//! the explicit law's 0.7 ≤ λ_f ≤ 1.5 and 0 ≤ d_eff ≤ 0.5). What is bound to leave the domain
//! (a damage, an activation schedule or a region with d_eff in (0.5, 1) or below 0) is refused
//! when the scene is read; what leaves it on the way (a stretch beyond the fitted range, as the
//! chapter's own figures draw the explicit law up to λ = 1.6; a force–velocity factor that moves
//! d_eff) is computed and written all the same, each row flagged in its table's `in_domain`
//! column, and each model that left its domain is named in one line of the summary, the report
//! and Python's study ([`LeftDomain`], gathered by a [`Tally`]).

use crate::active::{CouplingKind, Domain, LawKind, OutsideDomain};
use crate::models::ModelChoice;
use crate::text::significant;

/// One model of a study that was evaluated outside its law's domain, in one line.
#[derive(Debug, Clone, PartialEq)]
pub struct LeftDomain {
    /// Which model.
    pub model: String,
    /// Where it left the domain, and how far its stress is then from its target.
    pub message: String,
}

/// The `in_domain` cell of a row computed with `model` (`None`: passive, or an approach without
/// a law) that left the domain at `outside`: empty for a law that holds everywhere, else whether
/// the row lies inside.
pub fn in_domain(model: Option<&ModelChoice>, outside: Option<OutsideDomain>) -> Option<bool> {
    let (law, _) = model?.activation_law()?;
    law.domain().map(|_| outside.is_none())
}

/// The `in_domain` column's description.
pub const IN_DOMAIN: &str = "whether the activation law holds at the row: false where the explicit law is evaluated outside the domain it was fitted on (0.7 ≤ λ_f ≤ 1.5, d_eff = d + (1 − d)(1 − a) ≤ 0.5; cylinder: at some quadrature point), computed all the same; empty for the laws that hold everywhere";

/// How a study's line names its points.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Words {
    /// What a point is (`points`; an FE sweep's `stretches with quadrature points`).
    pub points: &'static str,
    /// The points' coordinate (`λ`, `t`).
    pub x: &'static str,
    /// Its unit, with a leading space (` s`), or empty.
    pub unit: &'static str,
    /// The target the stress is measured from, in words (`P_pas + (1 − d) P_act`), where the
    /// study has one.
    pub target: &'static str,
    /// The file that holds the rows.
    pub file: &'static str,
}

/// Where the points of one law and coupling left the law's domain, gathered point by point and
/// model by model.
#[derive(Debug, Clone, PartialEq)]
pub struct Tally {
    law: LawKind,
    coupling: CouplingKind,
    domain: Domain,
    models: usize,
    points: usize,
    outside: usize,
    /// The points' coordinates (λ, t) where λ_f fell below the domain, and the lowest λ_f.
    below: Option<([f64; 2], f64)>,
    /// The same above it, and the highest λ_f.
    above: Option<([f64; 2], f64)>,
    /// The points' coordinates where d_eff left the domain, and the range of d_eff there.
    damage: Option<([f64; 2], [f64; 2])>,
    /// The largest |distance from the target| outside, where, and the model's label.
    worst_outside: Option<(f64, f64, String)>,
    /// The largest |distance from the target| inside.
    worst_inside: Option<f64>,
}

/// `range` widened to hold `x`.
fn widen(range: Option<[f64; 2]>, x: f64) -> [f64; 2] {
    range.map_or([x, x], |[lo, hi]| [lo.min(x), hi.max(x)])
}

/// The union of two ranges.
fn union(a: Option<[f64; 2]>, b: Option<[f64; 2]>) -> Option<[f64; 2]> {
    match (a, b) {
        (Some(a), Some(b)) => Some([a[0].min(b[0]), a[1].max(b[1])]),
        (a, b) => a.or(b),
    }
}

/// `0.65` or `0.65–0.69` (one number where both ends print alike).
fn span([lo, hi]: [f64; 2]) -> String {
    let (lo, hi) = (significant(lo, 6), significant(hi, 6));
    if lo == hi {
        lo
    } else {
        format!("{lo}–{hi}")
    }
}

impl Tally {
    /// An empty tally of the points of model `m`; `None` for a model without a law or whose
    /// law holds everywhere.
    pub fn of(m: &ModelChoice) -> Option<Self> {
        let (law, coupling) = m.activation_law()?;
        Some(Self {
            law,
            coupling,
            domain: law.domain()?,
            models: 1,
            points: 0,
            outside: 0,
            below: None,
            above: None,
            damage: None,
            worst_outside: None,
            worst_inside: None,
        })
    }

    /// One point at `at` (its λ or t), outside the domain where `outside` names a value (an FE
    /// point names the extremes over its quadrature points), with the distance of its stress
    /// from the target where the study has one.
    pub fn add(
        &mut self,
        at: f64,
        outside: impl IntoIterator<Item = OutsideDomain>,
        distance: Option<f64>,
    ) {
        self.points += 1;
        let mut left = false;
        for o in outside {
            left = true;
            match o {
                OutsideDomain::Stretch(l) if l < self.domain.stretch[0] => {
                    let (x, low) = self.below.map_or((None, l), |(x, m)| (Some(x), m.min(l)));
                    self.below = Some((widen(x, at), low));
                }
                OutsideDomain::Stretch(l) => {
                    let (x, high) = self.above.map_or((None, l), |(x, m)| (Some(x), m.max(l)));
                    self.above = Some((widen(x, at), high));
                }
                OutsideDomain::EffectiveDamage(d) => {
                    let (x, v) = self
                        .damage
                        .map_or((None, None), |(x, v)| (Some(x), Some(v)));
                    self.damage = Some((widen(x, at), widen(v, d)));
                }
            }
        }
        let distance = distance.map(f64::abs).filter(|d| d.is_finite());
        if left {
            self.outside += 1;
            if let Some(d) =
                distance.filter(|d| self.worst_outside.as_ref().is_none_or(|w| *d > w.0))
            {
                self.worst_outside = Some((d, at, String::new()));
            }
        } else if let Some(d) = distance {
            self.worst_inside = Some(self.worst_inside.map_or(d, |w| w.max(d)));
        }
    }

    /// `other` (a tally of the same law, of the model `label`) added to this one.
    fn merge(&mut self, other: Tally, label: &str) {
        self.models += other.models;
        self.points += other.points;
        self.outside += other.outside;
        let low = |a: Option<([f64; 2], f64)>,
                   b: Option<([f64; 2], f64)>,
                   f: fn(f64, f64) -> f64| match (a, b) {
            (Some(a), Some(b)) => Some((union(Some(a.0), Some(b.0)).unwrap_or(a.0), f(a.1, b.1))),
            (a, b) => a.or(b),
        };
        self.below = low(self.below, other.below, f64::min);
        self.above = low(self.above, other.above, f64::max);
        self.damage = match (self.damage, other.damage) {
            (Some(a), Some(b)) => Some((
                union(Some(a.0), Some(b.0)).unwrap_or(a.0),
                union(Some(a.1), Some(b.1)).unwrap_or(a.1),
            )),
            (a, b) => a.or(b),
        };
        if let Some((d, at, _)) = other.worst_outside {
            if self.worst_outside.as_ref().is_none_or(|w| d > w.0) {
                self.worst_outside = Some((d, at, label.to_string()));
            }
        }
        self.worst_inside = match (self.worst_inside, other.worst_inside) {
            (Some(a), Some(b)) => Some(a.max(b)),
            (a, b) => a.or(b),
        };
    }

    /// Where the points left the domain, in words.
    fn places(&self, words: &Words) -> Vec<String> {
        let Words { x, unit, .. } = *words;
        let [lo, hi] = self.domain.stretch;
        let mut places = Vec::new();
        if let Some((at, low)) = self.below {
            places.push(format!(
                "λ_f below {lo} at {x} = {}{unit} (down to {})",
                span(at),
                significant(low, 6)
            ));
        }
        if let Some((at, high)) = self.above {
            places.push(format!(
                "λ_f above {hi} at {x} = {}{unit} (up to {})",
                span(at),
                significant(high, 6)
            ));
        }
        if let Some((at, d)) = self.damage {
            places.push(format!("d_eff = {} at {x} = {}{unit}", span(d), span(at)));
        }
        places
    }

    /// The line of these points if some left the domain (`model`: the models' names): how many,
    /// where, and how far the stress was then from its target against the largest distance
    /// inside.
    fn note(&self, model: String, words: &Words) -> Option<LeftDomain> {
        if self.outside == 0 {
            return None;
        }
        let Words {
            points,
            x,
            unit,
            target,
            file,
        } = *words;
        let mut message = format!(
            "{} of {} {points} outside the {} law's domain {}: {}",
            self.outside,
            self.points,
            self.law.name(),
            self.domain.describe(),
            self.places(words).join("; ")
        );
        if let Some((d, at, label)) = &self.worst_outside {
            let whose = if self.models > 1 {
                format!("{label}, ")
            } else {
                String::new()
            };
            message.push_str(&format!(
                "; there |P − ({target})| reaches {} kPa ({whose}at {x} = {}{unit}){}",
                significant(*d, 4),
                significant(*at, 6),
                self.worst_inside.map_or(String::new(), |w| format!(
                    ", inside the domain at most {} kPa",
                    significant(w, 4)
                ))
            ));
        }
        message.push_str(&format!(
            "; computed all the same, in_domain = false in {file}"
        ));
        Some(LeftDomain { model, message })
    }
}

/// One line per law and coupling over the `tallies` of a study's models (each with the model's
/// label; the distances from the target of the frozen and the consistent models differ by the
/// consistent stress's own term, so they are not mixed), for those that left the law's domain:
/// the model's label if one model did, else the law, the coupling and the number of models.
pub fn lines(tallies: Vec<(String, Tally)>, words: &Words) -> Vec<LeftDomain> {
    let mut merged: Vec<(String, Tally)> = Vec::new();
    for (label, t) in tallies {
        match merged
            .iter_mut()
            .find(|(_, m)| (m.law, m.coupling) == (t.law, t.coupling))
        {
            Some((_, m)) => m.merge(t, &label),
            None => {
                let mut first = t.clone();
                if let Some(w) = first.worst_outside.as_mut() {
                    w.2 = label.clone();
                }
                merged.push((label, first));
            }
        }
    }
    merged
        .into_iter()
        .filter_map(|(label, t)| {
            let model = if t.models == 1 {
                label
            } else {
                format!(
                    "{} law, {} coupling, {} models",
                    t.law.name(),
                    t.coupling.name(),
                    t.models
                )
            };
            t.note(model, words)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    const WORDS: Words = Words {
        points: "points",
        x: "λ",
        unit: "",
        target: "P_pas + T",
        file: "c.csv",
    };

    #[test]
    fn a_tally_says_where_the_points_left_and_compares_their_distance_with_the_inside() {
        let explicit = ModelChoice {
            approach: crate::active::Approach::ActiveStrain,
            law: LawKind::Explicit,
            coupling: CouplingKind::Frozen,
            damage: 0.0,
        };
        let mut t = Tally::of(&explicit).unwrap();
        t.add(0.65, Some(OutsideDomain::Stretch(0.65)), Some(-0.04));
        t.add(1.0, None, Some(1.9));
        t.add(1.6, Some(OutsideDomain::Stretch(1.6)), Some(174.4));
        let mut u = Tally::of(&explicit).unwrap();
        u.add(1.0, Some(OutsideDomain::EffectiveDamage(0.9)), Some(200.0));
        let one = lines(vec![("m".into(), t.clone())], &WORDS);
        assert_eq!(
            one[0].message,
            "2 of 3 points outside the explicit law's domain 0.7 ≤ λ_f ≤ 1.5 and 0 ≤ d_eff ≤ 0.5: \
             λ_f below 0.7 at λ = 0.65 (down to 0.65); λ_f above 1.5 at λ = 1.6 (up to 1.6); \
             there |P − (P_pas + T)| reaches 174.4 kPa (at λ = 1.6), inside the domain at most \
             1.9 kPa; computed all the same, in_domain = false in c.csv"
        );
        assert_eq!(one[0].model, "m");
        let two = lines(vec![("m".into(), t), ("n".into(), u)], &WORDS);
        assert_eq!(two.len(), 1);
        assert_eq!(two[0].model, "explicit law, frozen coupling, 2 models");
        assert!(
            two[0].message.starts_with("3 of 4 points")
                && two[0].message.contains("d_eff = 0.9 at λ = 1")
                && two[0].message.contains("200 kPa (n, at λ = 1)"),
            "{}",
            two[0].message
        );
        let mut inside = Tally::of(&explicit).unwrap();
        inside.add(1.0, None, Some(1.9));
        assert!(lines(vec![("m".into(), inside)], &WORDS).is_empty());
        let implicit = ModelChoice {
            law: LawKind::Implicit,
            ..explicit
        };
        assert!(Tally::of(&implicit).is_none());
    }
}
