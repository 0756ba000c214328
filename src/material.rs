//! A muscle material: an energy, an activation law, a damage and a coupling, answering at a point.

use crate::active::coupling::{invariant_slopes, Coupling, FrozenTangent};
use crate::active::law::{check_damage, effective_damage, ActivationLaw, Law, LawValue};
use crate::active::strain::ActiveStrainMap;
use crate::energy::StrainEnergy;
use crate::invariants::{axial_fibre, axisymmetric_f, Entries, Kinematics, AXISYMMETRIC};
use crate::response::{check_returned, in_f_space, unchecked_derivatives, Order};
use crate::Result;
use nalgebra::{SMatrix, SVector};

/// Active skeletal muscle: Ŵ(F, γ) = det F_a · W(C_e) with γ = g(λ_f, d_eff) and the active-strain
/// map F_a(γ) of [`ActiveStrainMap`], coupled frozen or consistently (see
/// [`crate::active::coupling`]). The law's target active stress is (1 − d)·a·P_act: damage d and
/// activation level a (default 1) in one effective damage d_eff = 1 − (1 − d)·a
/// ([`effective_damage`]).
#[derive(Debug, Clone)]
pub struct Muscle<E> {
    energy: E,
    law: Law<E>,
    damage: f64,
    level: f64,
    /// d_eff = 1 − (1 − d)·a of `damage` and `level`, cached: private, and written only where
    /// those are (`new`, `passive`, `set_activation`), so it cannot go stale.
    effective: f64,
    coupling: Coupling,
    map: ActiveStrainMap,
}

/// A muscle's answer at one point over the entries of F in use.
#[derive(Debug, Clone, Copy)]
pub struct MuscleResponse<const N: usize> {
    /// Activation γ = g(λ_f, d) [-].
    pub gamma: f64,
    /// Fibre stretch λ_f = sqrt(C:M) [-].
    pub fibre_stretch: f64,
    /// Ŵ(F, γ) \[kPa\].
    pub energy: f64,
    /// First Piola stress without the pressure term \[kPa\] (orders ≥ [`Order::Stress`]).
    pub stress: Option<SVector<f64, N>>,
    /// Its derivative in F \[kPa\] ([`Order::Tangent`]); non-symmetric for the exact frozen model.
    pub tangent: Option<SMatrix<f64, N, N>>,
    /// dP/dγ = ∂²Ŵ/∂F∂γ at F held \[kPa\] ([`Order::Tangent`]): the stress's rate in the
    /// activation, whatever the coupling (for the consistent model it is not the γ-rate of `stress`).
    pub dstress_dgamma: Option<SVector<f64, N>>,
}

impl<E: StrainEnergy> Muscle<E> {
    /// A muscle with activation law `law`, damage d ∈ [0, 1] and coupling; its active-strain
    /// map is the law's (see [`Law::map`]), the chapter's for a law that has none.
    pub fn new(energy: E, law: Law<E>, damage: f64, coupling: Coupling) -> Result<Self> {
        let damage = check_damage(damage)?;
        Ok(Self {
            map: law.map().unwrap_or_default(),
            energy,
            law,
            damage,
            level: 1.0,
            effective: damage,
            coupling,
        })
    }

    /// The same muscle at activation level a ∈ [0, 1] (the fraction of the optimal active stress
    /// recruited, e.g. a(t) of [`crate::active::time::ActivationInTime`]); a = 1 is the
    /// tetanised muscle of the chapter.
    pub fn with_activation(mut self, level: f64) -> Result<Self> {
        self.set_activation(level)?;
        Ok(self)
    }

    /// Sets the activation level a ∈ [0, 1] (see [`with_activation`](Self::with_activation)).
    pub fn set_activation(&mut self, level: f64) -> Result<()> {
        self.effective = effective_damage(self.damage, level)?;
        self.level = level;
        Ok(())
    }

    /// The same muscle with the active-strain map `map`. Rejects a map other than the one the
    /// law is solved with (the law's γ would not reproduce its target with this map).
    pub fn with_map(self, map: ActiveStrainMap) -> Result<Self> {
        match self.law.map() {
            Some(own) if own != map => Err(crate::Error::MapMismatch {
                law: self.law.name(),
                law_map: own.name(),
                map: map.name(),
            }),
            _ => Ok(Self { map, ..self }),
        }
    }

    /// The passive material (γ ≡ 0).
    pub fn passive(energy: E) -> Self {
        Self {
            energy,
            law: Law::Passive,
            damage: 0.0,
            level: 1.0,
            effective: 0.0,
            coupling: Coupling::Consistent,
            map: ActiveStrainMap::Chapter,
        }
    }

    /// The passive energy W.
    pub fn energy(&self) -> &E {
        &self.energy
    }
    /// The activation law.
    pub fn law(&self) -> &Law<E> {
        &self.law
    }
    /// Damage d [-].
    pub fn damage(&self) -> f64 {
        self.damage
    }
    /// Activation level a [-] (1: tetanised).
    pub fn activation_level(&self) -> f64 {
        self.level
    }
    /// The damage the law sees, d_eff = 1 − (1 − d)·a [-].
    pub fn effective_damage(&self) -> f64 {
        self.effective
    }
    /// The coupling.
    pub fn coupling(&self) -> Coupling {
        self.coupling
    }
    /// The active-strain map.
    pub fn map(&self) -> ActiveStrainMap {
        self.map
    }

    /// γ with its λ-derivatives at fibre stretch `lambda`.
    pub fn activation(&self, lambda: f64) -> Result<LawValue> {
        self.law.evaluate(lambda, self.effective)
    }

    /// Energy, stress and tangent at the point described by `kinematics`, to the order asked.
    pub fn respond<const N: usize>(
        &self,
        kinematics: &Kinematics,
        order: Order,
        entries: &Entries<N>,
    ) -> Result<MuscleResponse<N>> {
        let fibre_stretch = kinematics.fibre_stretch();
        // The law's derivatives enter only the consistent stress and the exact tangents.
        let needs_slope = !matches!(
            (order, self.coupling),
            (Order::Energy, _)
                | (Order::Stress, Coupling::Frozen(_))
                | (Order::Tangent, Coupling::Frozen(FrozenTangent::Symmetric))
        );
        let law = if needs_slope {
            self.activation(fibre_stretch)?
        } else {
            LawValue {
                gamma: self.law.activation(fibre_stretch, self.effective)?,
                ..LawValue::default()
            }
        };
        let j = SVector::from(kinematics.invariants);
        let d = unchecked_derivatives(&self.energy, self.map, &j, law.gamma, order)?;
        let mut out = MuscleResponse {
            gamma: law.gamma,
            fibre_stretch,
            energy: d.energy,
            stress: None,
            tangent: None,
            dstress_dgamma: None,
        };
        if order == Order::Energy {
            return Ok(out);
        }
        // The coupling (see crate::active::coupling): Ŵ's stress and tangent with ∂Ŵ/∂j₂ and
        // ∂²Ŵ/∂j₂² raised for the consistent model, then the rank-one terms in dP/dγ ⊗ G′D₂.
        let (g1, g2) = invariant_slopes(&law, fibre_stretch);
        let (a, b) = match (self.coupling, &d.second) {
            (Coupling::Consistent, Some(s)) => {
                (d.d_gamma * g1, s.d_gammagamma * g1 * g1 + d.d_gamma * g2)
            }
            (Coupling::Consistent, None) => (d.d_gamma * g1, 0.0),
            _ => (0.0, 0.0),
        };
        out.tangent = d.second.map(|_| SMatrix::zeros());
        let f = in_f_space(kinematics, entries, &d, (a, b), out.tangent.as_mut());
        if let (Some(t), Some(q)) = (out.tangent.as_mut(), &f.dstress_dgamma) {
            let r = f.fibre_gradient * g1;
            let (frozen, consistent) = match self.coupling {
                Coupling::Frozen(FrozenTangent::Symmetric) => (false, false),
                Coupling::Frozen(FrozenTangent::Exact) => (true, false),
                Coupling::Consistent => (true, true),
            };
            for x in 0..N {
                for y in 0..N {
                    if frozen {
                        t[(x, y)] += q[x] * r[y];
                    }
                    if consistent {
                        t[(x, y)] += r[x] * q[y];
                    }
                }
            }
        }
        check_returned(&d, &f, out.tangent.as_ref(), &kinematics.invariants)?;
        out.stress = Some(f.stress);
        out.dstress_dgamma = f.dstress_dgamma;
        Ok(out)
    }
}

/// The FE solver's view of a muscle: fibres along the cylinder axis, F given by its five
/// axisymmetric entries, derivatives over those five entries only.
impl<E: StrainEnergy> crate::fem::AxisymmetricMaterial for Muscle<E> {
    fn stress(&self, f: &crate::fem::AxiF) -> Result<SVector<f64, 5>> {
        let kin = Kinematics::new(&axisymmetric_f(f), &axial_fibre())?;
        let r = self.respond(&kin, Order::Stress, &AXISYMMETRIC)?;
        Ok(r.stress.unwrap_or_default())
    }

    fn stress_tangent(
        &self,
        f: &crate::fem::AxiF,
    ) -> Result<(SVector<f64, 5>, SMatrix<f64, 5, 5>)> {
        let kin = Kinematics::new(&axisymmetric_f(f), &axial_fibre())?;
        let r = self.respond(&kin, Order::Tangent, &AXISYMMETRIC)?;
        Ok((r.stress.unwrap_or_default(), r.tangent.unwrap_or_default()))
    }

    fn point_fields(&self, f: &crate::fem::AxiF) -> Result<(f64, f64)> {
        let kin = Kinematics::new(&axisymmetric_f(f), &axial_fibre())?;
        let lambda = kin.fibre_stretch();
        Ok((self.law.activation(lambda, self.effective)?, lambda))
    }
}
