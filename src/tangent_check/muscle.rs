//! A [`Muscle`] as a tangent check sees it in 3D ([`MusclePoint`]): over all nine entries of F
//! with its reference fibre m, exactly incompressible (the pressure held fixed: its term −p F⁻ᵀ
//! is the solver's, so the check is of ∂Ψ/∂F) or nearly incompressible with a volumetric energy
//! U(J),
//!
//! P = ∂Ψ/∂F + U′(J) cof F,
//! A = ∂²Ψ/∂F² + U″ cof F ⊗ cof F + (U′/J)(cof F ⊗ cof F − cof F ⊠ cof F),
//!
//! (cof F = J F⁻ᵀ; (a ⊠ b)_iAkB = a_kA b_iB, from ∂cof_iA/∂F_kB = (cof_iA cof_kB − cof_kA cof_iB)/J).
//!
//! What it knows of itself ([`Known`]): why its tangent is not symmetric (the frozen coupling's
//! exact tangent), the approximate tangents the solver can use (the frozen model's symmetric
//! approximation; the other representation of a law that solves an equation, tabulated or exact,
//! when asked for with [`MusclePoint::with_table_comparison`]), its edges (λ_min, the explicit
//! law's zero crossing, a table's ends, the reversal of the stretch rate under force–velocity)
//! and strong ellipticity (with the constraint a ⊥ F⁻ᵀN when exactly incompressible, see
//! [`crate::stability`]; over every a otherwise).

use super::material::{Approximation, Edge, Known, TangentMaterial};
use crate::active::{
    ActivationLaw, ActiveCurve, Coupling, ExplicitLaw, ForceVelocity, FrozenTangent, Law,
    LawRepresentation, SolvedLaw, TableSpec,
};
use crate::energy::StrainEnergy;
use crate::invariants::{Entries, Kinematics, FULL};
use crate::response::Order;
use crate::stability::{strong_ellipticity, Ellipticity};
use crate::volumetric::Volumetric;
use crate::{Error, Muscle, Result};
use nalgebra::{Matrix3, SMatrix, SVector, Vector3};

/// Reference normals sampled for strong ellipticity.
pub const ELLIPTICITY_NORMALS: usize = 256;

/// A muscle at a material point in 3D: the model, its fibre, its volumetric energy (`None`:
/// exactly incompressible, the pressure held fixed) and the variants it is compared with.
#[derive(Debug, Clone)]
pub struct MusclePoint<E> {
    muscle: Muscle<E>,
    fibre: Vector3<f64>,
    volumetric: Option<Volumetric>,
    /// The frozen model with the other frozen tangent (exact ↔ symmetric), where they differ.
    other_frozen: Option<(String, Muscle<E>)>,
    /// The law in its other representation (tabulated ↔ exact), if asked for.
    other_representation: Option<(String, Muscle<E>)>,
    edges: Vec<Edge>,
}

impl<E: StrainEnergy> MusclePoint<E> {
    /// `muscle` with reference fibre `fibre` (normalised; finite and non-zero), exactly
    /// incompressible.
    pub fn new(muscle: Muscle<E>, fibre: Vector3<f64>) -> Result<Self> {
        let norm = fibre.norm();
        if !(norm.is_finite() && norm > 1e-12) {
            return Err(Error::InvalidParameter {
                name: "fibre",
                value: norm,
                rule: "the fibre direction must be a finite, non-zero vector (its norm is shown)",
            });
        }
        let other_frozen = match muscle.coupling() {
            Coupling::Frozen(own) if varies(&muscle) => {
                let (other, name) = match own {
                    FrozenTangent::Exact => (FrozenTangent::Symmetric, "symmetric frozen"),
                    FrozenTangent::Symmetric => (FrozenTangent::Exact, "exact frozen"),
                };
                let law = muscle.law().clone();
                Some((
                    name.to_string(),
                    rebuilt(&muscle, law, Coupling::Frozen(other))?,
                ))
            }
            _ => None,
        };
        let edges = edges(&muscle);
        Ok(Self {
            muscle,
            fibre: fibre / norm,
            volumetric: None,
            other_frozen,
            other_representation: None,
            edges,
        })
    }

    /// The same point with the volumetric energy U(J) (`None`: exactly incompressible).
    pub fn with_volumetric(self, volumetric: Option<Volumetric>) -> Self {
        Self { volumetric, ..self }
    }

    /// The same point compared with its law in the other representation: an implicit or energy
    /// law solved exactly is tabulated on `spec` (at the muscle's d_eff: one table build,
    /// 0.04–0.1 s for the chapter's laws), a tabulated one is compared with its exact law. A
    /// closed-form law, a drive with a stretch rate (no table holds it) or a negative d_eff
    /// (a > 1) has nothing to compare with.
    pub fn with_table_comparison(mut self, spec: TableSpec) -> Result<Self> {
        let drive = self.muscle.drive();
        let Some(damage) = drive.table_damage().filter(|d| (0.0..=1.0).contains(d)) else {
            return Ok(self);
        };
        let (name, representation) = match self.muscle.law() {
            Law::Implicit(_) | Law::Energy(_) => {
                ("tabulated law", LawRepresentation::Tabulated(spec))
            }
            Law::Tabulated(_) => ("exact law", LawRepresentation::Exact),
            _ => return Ok(self),
        };
        let law = self
            .muscle
            .law()
            .clone()
            .represented(representation, &[damage])?;
        let other = rebuilt(&self.muscle, law, self.muscle.coupling())?;
        self.other_representation = Some((name.to_string(), other));
        Ok(self)
    }

    /// The muscle.
    pub fn muscle(&self) -> &Muscle<E> {
        &self.muscle
    }

    /// The reference fibre direction (unit).
    pub fn fibre(&self) -> Vector3<f64> {
        self.fibre
    }

    /// The volumetric energy (`None`: exactly incompressible).
    pub fn volumetric(&self) -> Option<&Volumetric> {
        self.volumetric.as_ref()
    }

    /// The fibre stretches where the stress is not smooth.
    pub fn edges(&self) -> &[Edge] {
        &self.edges
    }

    /// γ and λ_f at F.
    pub fn activation(&self, f: &Matrix3<f64>) -> Result<(f64, f64)> {
        let kin = Kinematics::new(f, &self.fibre)?;
        let r = self.muscle.respond(&kin, Order::Energy, &FULL)?;
        Ok((r.gamma, r.fibre_stretch))
    }

    /// P (and A with `order` = [`Order::Tangent`]) of `muscle` at F, the volumetric terms
    /// added (module docs).
    fn response(
        &self,
        muscle: &Muscle<E>,
        f: &Matrix3<f64>,
        order: Order,
    ) -> Result<(SVector<f64, 9>, Option<SMatrix<f64, 9, 9>>)> {
        let kin = Kinematics::new(f, &self.fibre)?;
        let r = muscle.respond(&kin, order, &FULL)?;
        let (mut p, mut a) = (r.stress.unwrap_or_default(), r.tangent);
        if let Some(v) = &self.volumetric {
            let j = kin.det_f;
            let [_, du, ddu] = v.derivatives(j)?;
            let inverse = f.try_inverse().ok_or(Error::NonPositiveJacobian {
                det: j,
                f: f.transpose().into(),
            })?;
            let cof = SVector::<f64, 9>::from_fn(|x, _| j * inverse[(x % 3, x / 3)]);
            p += cof * du;
            if let Some(a) = a.as_mut() {
                for x in 0..9 {
                    for y in 0..9 {
                        // x = (i, A), y = (k, B): cof_kA cof_iB is the swap of the columns.
                        let swapped = cof[3 * (y / 3) + x % 3] * cof[3 * (x / 3) + y % 3];
                        a[(x, y)] += ddu * cof[x] * cof[y] + du / j * (cof[x] * cof[y] - swapped);
                    }
                }
            }
        }
        Ok((p, a))
    }

    /// Strong ellipticity of A at F: constrained when exactly incompressible, over every
    /// direction otherwise.
    fn ellipticity(&self, f: &Matrix3<f64>, a: &SMatrix<f64, 9, 9>) -> Result<Ellipticity> {
        match self.volumetric {
            None => strong_ellipticity(a, f, ELLIPTICITY_NORMALS),
            Some(_) => Ok(unconstrained_ellipticity(a, ELLIPTICITY_NORMALS)),
        }
    }
}

impl<E: StrainEnergy> TangentMaterial<9> for MusclePoint<E> {
    fn entries(&self) -> Entries<9> {
        FULL
    }

    fn stress_of(&self, f: &Matrix3<f64>) -> Result<SVector<f64, 9>> {
        Ok(self.response(&self.muscle, f, Order::Stress)?.0)
    }

    fn stress_and_tangent(
        &self,
        f: &Matrix3<f64>,
    ) -> Result<(SVector<f64, 9>, SMatrix<f64, 9, 9>)> {
        let (p, a) = self.response(&self.muscle, f, Order::Tangent)?;
        Ok((p, a.unwrap_or_default()))
    }

    fn known(&self, f: &Matrix3<f64>, tangent: &SMatrix<f64, 9, 9>) -> Result<Known<9>> {
        let mut approximations = Vec::new();
        for (name, other) in [&self.other_frozen, &self.other_representation]
            .into_iter()
            .flatten()
        {
            let (_, a) = self.response(other, f, Order::Tangent)?;
            approximations.push(Approximation {
                name: name.clone(),
                tangent: a.unwrap_or_default(),
            });
        }
        let symmetric = crate::fem::AxisymmetricMaterial::symmetric_tangent(&self.muscle);
        Ok(Known {
            asymmetry: (!symmetric).then(|| {
                "the frozen coupling's exact tangent ∂P/∂F + (dP/dγ) ⊗ G′ ∂(C:M)/∂F: the frozen stress is not a gradient".to_string()
            }),
            approximate: (self.muscle.coupling() == Coupling::Frozen(FrozenTangent::Symmetric)
                && varies(&self.muscle))
            .then(|| {
                "the frozen model's symmetric approximation (frozen_tangent = \"symmetric\"): it drops (dP/dγ) ⊗ G′ ∂(C:M)/∂F, so r₁ is first order by design".to_string()
            }),
            approximations,
            edges: self.edges.clone(),
            fibre: Some(self.fibre),
            ellipticity: Some(self.ellipticity(f, tangent)?),
            // The law's domain is the study's `in_domain` column (crate::studies::domain).
            notes: Vec::new(),
        })
    }
}

/// Whether the muscle's activation varies with the fibre stretch (a law other than none or a
/// constant, or an approach's own energy of the fibre stretch, with the drive on).
fn varies<E: StrainEnergy>(muscle: &Muscle<E>) -> bool {
    let law =
        !matches!(muscle.law(), Law::Passive | Law::Constant(_)) || muscle.fibre_energy().is_some();
    law && !muscle.drive().is_off()
}

/// `muscle` with another law and coupling, the same energy, damage, activation level, map and
/// stretch-rate state.
fn rebuilt<E: StrainEnergy>(
    muscle: &Muscle<E>,
    law: Law<E>,
    coupling: Coupling,
) -> Result<Muscle<E>> {
    let mut out = Muscle::new(muscle.energy().clone(), law, muscle.damage(), coupling)?
        .with_activation(muscle.activation_level())?;
    if let Some((approach, curve)) = muscle.fibre_energy() {
        out = out.with_fibre_energy(approach, *curve);
    }
    let mut out = out.with_map(muscle.map())?;
    out.set_rate(muscle.drive().rate().copied())?;
    Ok(out)
}

/// The active curve a muscle reproduces, if it has one.
fn curve_of<E: StrainEnergy>(muscle: &Muscle<E>) -> Option<ActiveCurve> {
    match muscle.law() {
        Law::Implicit(l) => Some(*l.curve()),
        Law::Energy(l) => Some(*l.curve()),
        Law::Explicit(l) => Some(*l.curve()),
        Law::Tabulated(t) => match t.exact() {
            SolvedLaw::Implicit(l) => Some(*l.curve()),
            SolvedLaw::Energy(l) => Some(*l.curve()),
        },
        Law::Passive | Law::Constant(_) => muscle.fibre_energy().map(|(_, c)| *c),
    }
}

/// The fibre stretches where the muscle's stress is not smooth (module docs).
fn edges<E: StrainEnergy>(muscle: &Muscle<E>) -> Vec<Edge> {
    let mut edges = Vec::new();
    if !varies(muscle) {
        return edges;
    }
    if let Some(curve) = curve_of(muscle) {
        edges.push(lambda_min_edge(muscle, &curve));
    }
    match muscle.law() {
        Law::Explicit(law) => edges.extend(explicit_zero(law, muscle)),
        Law::Tabulated(t) if muscle.drive().table_damage().is_some() => {
            for end in [t.spec().lambda_lo, t.spec().lambda_hi] {
                edges.push(Edge {
                    fibre_stretch: end,
                    kind: "table-end",
                    what: format!("the tabulated law's table ends at λ = {end}: the exact law answers beyond, γ differs there by up to the table's tolerance"),
                });
            }
        }
        _ => {}
    }
    if let Some(rate) = muscle.drive().rate() {
        edges.extend(rate_reversal(&rate.law, rate.previous));
    }
    edges
}

/// λ_min: where the energy law that is inactive below it jumps, or the active curve starts with
/// a slope (a kink), or starts flat to all orders (smooth, but the law is steep just above).
fn lambda_min_edge<E: StrainEnergy>(muscle: &Muscle<E>, curve: &ActiveCurve) -> Edge {
    let at = curve.lambda_min();
    if muscle.law().jump().is_some() {
        return Edge {
            fibre_stretch: at,
            kind: "lambda-min-jump",
            what: format!("λ_min = {at}: the energy law (below_minimum = \"inactive\") jumps there from γ = 0 to its zero-work root, so P jumps off the fibre path"),
        };
    }
    let above = at + 1e-9 * at.max(1.0);
    let (_, slope) = num_dual::first_derivative(|l| curve.value(l), above);
    if slope != 0.0 {
        Edge {
            fibre_stretch: at,
            kind: "lambda-min-kink",
            what: format!(
                "λ_min = {at}: the active curve starts there with slope P_act′ = {} kPa (0 below), a kink of the stress",
                crate::text::significant(slope, 4)
            ),
        }
    } else {
        Edge {
            fibre_stretch: at,
            kind: "lambda-min",
            what: format!("λ_min = {at}: the active curve starts there flat to all orders (smooth, but the activation is steep just above: an ill-conditioned law)"),
        }
    }
}

/// The explicit law's zero crossing above λ_min, beyond which it is clamped to γ = 0 (a kink):
/// the first stretch on a grid of 0.05 from λ_min where γ is 0, refined by 60 bisections.
fn explicit_zero<E: StrainEnergy>(law: &ExplicitLaw, muscle: &Muscle<E>) -> Option<Edge> {
    let drive = *muscle.drive();
    let positive = |l: f64| law.activation(l, drive).is_ok_and(|g| g > 0.0);
    let start = law.curve().lambda_min() + 0.05;
    let mut lo = start;
    if !positive(lo) {
        return None;
    }
    let mut hi = (1..=100)
        .map(|k| start + 0.05 * k as f64)
        .find(|&l| !positive(l))?;
    for _ in 0..60 {
        let mid = 0.5 * (lo + hi);
        if positive(mid) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let at = 0.5 * (lo + hi);
    Some(Edge {
        fibre_stretch: at,
        kind: "explicit-zero",
        what: format!(
            "λ = {}: the explicit law's γ crosses 0 there and is clamped to 0 beyond, a kink",
            crate::text::significant(at, 6)
        ),
    })
}

/// λ_f = λ_prev, where the stretch rate changes sign: the force–velocity factor's slope jumps
/// there unless the two branches' slopes −d_e (1 + k_e k_c)/λ̇_min and −d_c (1 + k_c)/λ̇_min
/// agree.
fn rate_reversal(law: &ForceVelocity, previous: f64) -> Option<Edge> {
    let lengthening = -law.de * (1.0 + law.ke * law.kc) / law.min_rate;
    let shortening = -law.dc * (1.0 + law.kc) / law.min_rate;
    (lengthening != shortening).then(|| Edge {
        fibre_stretch: previous,
        kind: "rate-reversal",
        what: format!(
            "λ_f = λ_prev = {}: the stretch rate changes sign there and the force–velocity factor's slope jumps from {} to {} s, a kink",
            crate::text::significant(previous, 6),
            crate::text::significant(shortening, 4),
            crate::text::significant(lengthening, 4)
        ),
    })
}

/// Strong ellipticity without a constraint: the least eigenvalue of the symmetric part of
/// Q_ik(N) = A_iJkL N_J N_L over `samples` reference normals on a Fibonacci half-sphere.
pub fn unconstrained_ellipticity(tangent: &SMatrix<f64, 9, 9>, samples: usize) -> Ellipticity {
    let scale = tangent.norm().max(f64::MIN_POSITIVE);
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut best = Ellipticity {
        least: f64::INFINITY,
        relative: f64::INFINITY,
        normal: Vector3::z(),
        direction: Vector3::x(),
    };
    for i in 0..samples.max(1) {
        let z = (i as f64 + 0.5) / samples.max(1) as f64;
        let (r, phi) = ((1.0 - z * z).sqrt(), golden * i as f64);
        let normal = Vector3::new(r * phi.cos(), r * phi.sin(), z);
        let q = Matrix3::from_fn(|i, k| {
            let mut s = 0.0;
            for jj in 0..3 {
                for l in 0..3 {
                    s += tangent[(3 * i + jj, 3 * k + l)] * normal[jj] * normal[l];
                }
            }
            s
        });
        let eig = ((q + q.transpose()) * 0.5).symmetric_eigen();
        let k = eig.eigenvalues.imin();
        if eig.eigenvalues[k] < best.least {
            best = Ellipticity {
                least: eig.eigenvalues[k],
                relative: eig.eigenvalues[k] / scale,
                normal,
                direction: eig.eigenvectors.column(k).into(),
            };
        }
    }
    best
}
