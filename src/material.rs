//! A muscle material: an energy, an activation law, a damage and a coupling, answering at a point.

use crate::active::approach::Approach;
use crate::active::coupling::{invariant_slopes, Coupling, FrozenTangent};
use crate::active::curve::ActiveCurve;
use crate::active::drive::{check_damage, Drive, StretchRate};
use crate::active::law::{ActivationLaw, Law, LawValue, OutsideDomain};
use crate::active::map::ActivationMap;
use crate::energy::StrainEnergy;
use crate::invariants::{axial_fibre, axisymmetric_f, Entries, Kinematics, AXISYMMETRIC};
use crate::response::{check_returned, in_f_space, unchecked_derivatives, Order};
use crate::Result;
use nalgebra::{SMatrix, SVector};

/// Active skeletal muscle, by one of the approaches of [`crate::active::approach`]:
///
/// Ψ(F) = φ(γ) W(A(γ) j) + E(C:M), with
///
/// - an activation map (active strain or structural): γ = g(λ_f, drive) ([`ActivationMap`]),
///   coupled frozen or consistently (see [`crate::active::coupling`]);
/// - the energy of the fibre stretch an approach adds of its own, E ([`Approach::fibre_energy`]):
///   active stress ([`Muscle::active_stress`]), with dE/dλ = T(λ_f) and no law (γ ≡ 0); none
///   (E = 0) for the approaches whose activation is the map's.
///
/// The target active stress is T = (1 − d)·a·f_v·P_act ([`Drive`]): damage d, activation level a
/// (default 1) and, in a time study with force–velocity, the stretch-rate state.
#[derive(Debug, Clone)]
pub struct Muscle<E> {
    energy: E,
    law: Law<E>,
    drive: Drive,
    coupling: Coupling,
    map: ActivationMap,
    /// The approach that adds an energy of the fibre stretch E(C:M), and the active curve that
    /// energy is scaled from (`None`: E = 0, the activation is the map's).
    fibre_energy: Option<(Approach, ActiveCurve)>,
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
            drive: Drive::from(damage),
            coupling,
            fibre_energy: None,
        })
    }

    /// The active-stress muscle (FEBio's prescribed active contraction, Blemker's muscle):
    /// Ψ = W(C) + E(λ_f) with dE/dλ = (1 − d)·a·f_v·P_act(λ), so that
    /// P = ∂W/∂F + T(λ_f) F M/λ_f (− p F⁻ᵀ under the constraint). No law: the target is met by
    /// construction along the fibres. Hyperelastic without force–velocity (symmetric tangent).
    pub fn active_stress(energy: E, curve: ActiveCurve, damage: f64) -> Result<Self> {
        let mut muscle = Self::passive(energy).with_fibre_energy(Approach::ActiveStress, curve);
        muscle.drive = Drive::from(check_damage(damage)?);
        Ok(muscle)
    }

    /// The same muscle with the energy of the fibre stretch that `approach` adds, scaled from
    /// `curve` under the muscle's drive ([`Approach::fibre_energy`]); nothing changes for an
    /// approach that adds none.
    pub fn with_fibre_energy(self, approach: Approach, curve: ActiveCurve) -> Self {
        Self {
            fibre_energy: approach.adds_fibre_energy().then_some((approach, curve)),
            ..self
        }
    }

    /// The same muscle at activation level a ≥ 0 (the fraction of the optimal active stress
    /// recruited, e.g. a(t) of [`crate::active::time::ActivationInTime`]; 4C's twitch trains
    /// with P_opt = N_a exceed 1); a = 1 is the tetanised muscle of the chapter.
    pub fn with_activation(mut self, level: f64) -> Result<Self> {
        self.set_activation(level)?;
        Ok(self)
    }

    /// Sets the activation level a ≥ 0 (see [`with_activation`](Self::with_activation)).
    pub fn set_activation(&mut self, level: f64) -> Result<()> {
        let drive = Drive::new(self.drive.damage(), level)?;
        self.drive = match self.drive.rate() {
            Some(rate) => drive.with_rate(*rate)?,
            None => drive,
        };
        Ok(())
    }

    /// Sets (`Some`) or clears (`None`, quasi-static: f_v = 1) the stretch-rate state of a time
    /// step for the force–velocity factor.
    pub fn set_rate(&mut self, rate: Option<StretchRate>) -> Result<()> {
        self.drive = match rate {
            Some(rate) => self.drive.without_rate().with_rate(rate)?,
            None => self.drive.without_rate(),
        };
        Ok(())
    }

    /// The same muscle with the activation map `map`. Rejects a map other than the one the law
    /// is solved with (the law's γ would not reproduce its target with this map), and any map
    /// for an active-stress muscle.
    pub fn with_map(self, map: impl Into<ActivationMap>) -> Result<Self> {
        let map = map.into();
        match self.law.map() {
            Some(own) if own != map => Err(crate::Error::MapMismatch {
                law: self.law.name(),
                law_map: own.name(),
                map: map.name(),
            }),
            _ if self.fibre_energy.is_some() && map != ActivationMap::Chapter => {
                Err(crate::Error::MapMismatch {
                    law: self.fibre_energy.map_or("", |(a, _)| a.name()),
                    law_map: "none",
                    map: map.name(),
                })
            }
            _ => Ok(Self { map, ..self }),
        }
    }

    /// The passive material (γ ≡ 0).
    pub fn passive(energy: E) -> Self {
        Self {
            energy,
            law: Law::Passive,
            drive: Drive::from(0.0),
            coupling: Coupling::Consistent,
            map: ActivationMap::Chapter,
            fibre_energy: None,
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
        self.drive.damage()
    }
    /// Activation level a [-] (1: tetanised).
    pub fn activation_level(&self) -> f64 {
        self.drive.level()
    }
    /// d_eff = 1 − (1 − d)·a [-] ([`Drive::effective_damage`]).
    pub fn effective_damage(&self) -> f64 {
        self.drive.effective_damage()
    }
    /// What drives the activation: damage, level, stretch rate.
    pub fn drive(&self) -> &Drive {
        &self.drive
    }
    /// The approach that adds an energy of the fibre stretch, with its curve (active stress;
    /// `None` for the approaches whose activation is the map's).
    pub fn fibre_energy(&self) -> Option<(Approach, &ActiveCurve)> {
        self.fibre_energy.as_ref().map(|(a, c)| (*a, c))
    }
    /// The coupling.
    pub fn coupling(&self) -> Coupling {
        self.coupling
    }
    /// The activation map.
    pub fn map(&self) -> ActivationMap {
        self.map
    }

    /// γ with its λ-derivatives at fibre stretch `lambda`.
    pub fn activation(&self, lambda: f64) -> Result<LawValue> {
        self.law.evaluate(lambda, self.drive)
    }

    /// Where the law at fibre stretch `fibre_stretch` under this muscle's drive is outside the
    /// domain it holds on, if it is ([`ActivationLaw::outside`]: the explicit law's
    /// 0.7 ≤ λ_f ≤ 1.5, d_eff ≤ 0.5).
    pub fn outside_domain(&self, fibre_stretch: f64) -> Option<OutsideDomain> {
        self.law.outside(fibre_stretch, self.drive)
    }

    /// γ at the fibre stretch with the derivatives `order` needs under this coupling, the others
    /// 0: the law's derivatives enter only the consistent stress and the exact tangents, and
    /// d²γ/dλ² only the consistent tangent (nothing else reads `curvature`).
    fn law_value(&self, fibre_stretch: f64, order: Order) -> Result<LawValue> {
        let needs_slope = !matches!(
            (order, self.coupling),
            (Order::Energy, _)
                | (Order::Stress, Coupling::Frozen(_))
                | (Order::Tangent, Coupling::Frozen(FrozenTangent::Symmetric))
        );
        let needs_curvature = order == Order::Tangent && self.coupling == Coupling::Consistent;
        if needs_curvature {
            self.activation(fibre_stretch)
        } else if needs_slope {
            let (gamma, slope) = self.law.gamma_and_slope(fibre_stretch, self.drive)?;
            Ok(LawValue {
                gamma,
                slope,
                curvature: 0.0,
            })
        } else {
            Ok(LawValue {
                gamma: self.law.activation(fibre_stretch, self.drive)?,
                ..LawValue::default()
            })
        }
    }

    /// Energy, stress and tangent at the point described by `kinematics`, to the order asked.
    /// Always inlined: the response is then built in its caller's frame, not copied out of
    /// this one (the copy was 4.5 % of the 16 × 64 frozen FE sweep).
    #[inline(always)]
    pub fn respond<const N: usize>(
        &self,
        kinematics: &Kinematics,
        order: Order,
        entries: &Entries<N>,
    ) -> Result<MuscleResponse<N>> {
        let fibre_stretch = kinematics.fibre_stretch();
        let law = self.law_value(fibre_stretch, order)?;
        let j = SVector::from(kinematics.invariants);
        let mut d = unchecked_derivatives(&self.energy, self.map, &j, law.gamma, order)?;
        if let Some((approach, curve)) = &self.fibre_energy {
            // Ψ = Ŵ + E(C:M): an approach that adds E has no law (γ ≡ 0), so the map is the
            // identity, Ŵ_jj = H, and the term adds to the C:M entries of the gradient and of H.
            let (e, e_c, e_cc) = approach.fibre_energy(&self.drive, curve, j[1]);
            d.energy += e;
            d.d_j[1] += e_c;
            if let Some(s) = d.second.as_mut() {
                s.energy_hessian[(1, 1)] += e_cc;
            }
        }
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
        Ok((self.law.activation(lambda, self.drive)?, lambda))
    }

    /// The frozen model's exact tangent has the non-symmetric term (dP/dγ) ⊗ g′ ∂λ_f/∂F
    /// wherever γ varies with the fibre stretch: any law but none and a constant γ, with the
    /// activation on.
    fn symmetric_tangent(&self) -> bool {
        let varies = !matches!(self.law, Law::Passive | Law::Constant(_)) && !self.drive.is_off();
        !(varies && self.coupling == Coupling::Frozen(FrozenTangent::Exact))
    }
}
