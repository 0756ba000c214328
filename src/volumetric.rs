//! Near incompressibility: a volumetric energy U(J), J = det F, added to the muscle's energy
//! without a constraint (the alternative to the exact J = 1 of the chapter).
//!
//! Total energy Ŵ(F, γ) + U(J), nominal stress P = ∂Ŵ/∂F + U′(J) cof F (cof F = J F⁻ᵀ). Forms:
//!
//! - [`VolumetricForm::Quadratic`]: U = (κ/2)(J − 1)², κ \[kPa\] the bulk modulus.
//! - [`VolumetricForm::Logarithmic`]: U = (κ/4)(J² − 1 − 2 ln J), κ \[kPa\] (U″(1) = κ).
//! - [`VolumetricForm::Giantesio4C`]: 4C's `MAT_Muscle_Giantesio` (src/mat/4C_mat_muscle_giantesio.cpp,
//!   `evaluate`: "Svol = − gamma/2 · detC^−kappa"), S_vol = −(μ/2) det(C)^(−κ) C⁻¹, i.e.
//!   U = μ/(4κ) J^(−2κ) with κ a dimensionless exponent and μ \[kPa\] (4C's `GAMMA`, the
//!   passive energy's prefactor).
//!
//! **Stress-free reference.** 4C's passive energy Ψ = μ/4 [e^{α(I−1)}/α + e^{β(J−1)}/β] with
//! J = det C tr(C⁻¹ L) is not isochoric: at C = I it has S = (μ/2) I, which 4C's S_vol = −(μ/2) C⁻¹
//! cancels exactly (U′(1) = −μ/2). The chapter's energy is not isochoric either (tr C and tr C⁻¹
//! enter unsplit), but its stress at F = I vanishes on its own: ∂W/∂C = μ/4 (e^{α(I_p−1)} L − C⁻¹ L C⁻¹)
//! = 0 at C = I (L = (w0/3) I + (1 − w0) M). So the volumetric energy must satisfy U′(1) = −s₀,
//! s₀ I the passive stress at F = I (0 for the chapter's energy, μ/2 for 4C's). Every form is
//! therefore used as
//!
//! U(J) = U_form(J) − (U_form′(1) + s₀)(J − 1),
//!
//! a linear term that is zero for the quadratic and logarithmic forms with s₀ = 0 and for 4C's
//! form with 4C's energy (s₀ = μ/2), and that makes 4C's form stress-free with the chapter's
//! energy (U = μ/(4κ) J^(−2κ) + (μ/2)(J − 1), bulk modulus U″(1) = μ(2κ + 1)/2).

use crate::energy::positive;
use crate::{Error, Result};

/// The volumetric energy's form, as a scene names it (`incompressibility = { volumetric = "quadratic", kappa = 1e3 }`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum VolumetricForm {
    /// U = (κ/2)(J − 1)², κ \[kPa\].
    Quadratic {
        /// Bulk modulus κ \[kPa\].
        kappa: f64,
    },
    /// U = (κ/4)(J² − 1 − 2 ln J), κ \[kPa\].
    Logarithmic {
        /// Bulk modulus κ \[kPa\].
        kappa: f64,
    },
    /// 4C's `MAT_Muscle_Giantesio`: U = μ/(4κ) J^(−2κ).
    Giantesio4C {
        /// Exponent κ [-].
        kappa: f64,
        /// Prefactor μ \[kPa\] (4C's `GAMMA`).
        mu: f64,
    },
}

impl VolumetricForm {
    /// Name in scene files and outputs.
    pub fn name(&self) -> &'static str {
        match self {
            VolumetricForm::Quadratic { .. } => "quadratic",
            VolumetricForm::Logarithmic { .. } => "logarithmic",
            VolumetricForm::Giantesio4C { .. } => "4c-giantesio",
        }
    }

    /// The form with its parameters, as report captions write it (`(κ/2)(J − 1)², κ = 1000 kPa`).
    pub fn formula(&self) -> String {
        format!("{}, {}", self.expression(), self.parameters())
    }

    /// The form's expression (`(κ/2)(J − 1)²`).
    pub fn expression(&self) -> &'static str {
        match self {
            VolumetricForm::Quadratic { .. } => "(κ/2)(J − 1)²",
            VolumetricForm::Logarithmic { .. } => "(κ/4)(J² − 1 − 2 ln J)",
            VolumetricForm::Giantesio4C { .. } => "μ/(4κ) J^(−2κ) (4C MAT_Muscle_Giantesio)",
        }
    }

    /// The form's parameters with their values (`κ = 1000 kPa`).
    pub fn parameters(&self) -> String {
        match *self {
            VolumetricForm::Quadratic { kappa } | VolumetricForm::Logarithmic { kappa } => {
                format!("κ = {kappa} kPa")
            }
            VolumetricForm::Giantesio4C { kappa, mu } => format!("κ = {kappa}, μ = {mu} kPa"),
        }
    }

    /// (U, U′, U″) of the form itself at J > 0.
    fn derivatives(&self, j: f64) -> [f64; 3] {
        match *self {
            VolumetricForm::Quadratic { kappa } => {
                [0.5 * kappa * (j - 1.0).powi(2), kappa * (j - 1.0), kappa]
            }
            VolumetricForm::Logarithmic { kappa } => [
                0.25 * kappa * (j * j - 1.0 - 2.0 * j.ln()),
                0.5 * kappa * (j - 1.0 / j),
                0.5 * kappa * (1.0 + 1.0 / (j * j)),
            ],
            VolumetricForm::Giantesio4C { kappa, mu } => {
                let u = mu / (4.0 * kappa) * j.powf(-2.0 * kappa);
                [
                    u,
                    -2.0 * kappa * u / j,
                    2.0 * kappa * (2.0 * kappa + 1.0) * u / (j * j),
                ]
            }
        }
    }
}

/// The largest ratio of the bulk modulus U″(1) to the passive energy's initial modulus E₀ along
/// the fibres, checked when a scene is read. J − 1 ≈ σ/U″(1): at 1e10, J − 1 ≈ 1e-10 of the
/// strains and f64 still resolves it with six digits; from ≈ 2e16 (κ = 1e16 kPa for the chapter's
/// energy, whose E₀ = 0.42 kPa: measured) the lateral equilibrium of the homogeneous tests is
/// singular in f64.
/// No solid is stiffer than diamond (K ≈ 4.4e8 kPa), so a real study stays far below.
pub const MAX_STIFFNESS_RATIO: f64 = 1e10;

/// A volumetric energy U(J) = U_form(J) + c (J − 1), c chosen so that the reference is stress
/// free with the passive energy it is paired with (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Volumetric {
    form: VolumetricForm,
    shift: f64,
}

impl Volumetric {
    /// The volumetric energy of `form` for a passive energy whose stress at F = I is
    /// `reference_stress` · I \[kPa\] (0 for the chapter's energy): U′(1) = −`reference_stress`.
    /// κ (and μ) must be finite and > 0.
    pub fn new(form: VolumetricForm, reference_stress: f64) -> Result<Self> {
        match form {
            VolumetricForm::Quadratic { kappa } | VolumetricForm::Logarithmic { kappa } => {
                positive("kappa", kappa)?;
            }
            VolumetricForm::Giantesio4C { kappa, mu } => {
                positive("kappa", kappa)?;
                positive("mu", mu)?;
            }
        }
        if !reference_stress.is_finite() {
            return Err(Error::InvalidParameter {
                name: "reference_stress",
                value: reference_stress,
                rule: "must be finite",
            });
        }
        let shift = -(form.derivatives(1.0)[1] + reference_stress);
        Ok(Self { form, shift })
    }

    /// The form.
    pub fn form(&self) -> VolumetricForm {
        self.form
    }

    /// U(J) with its parameters, as report captions write it: the form, its linear term
    /// `c (J − 1)` where c ≠ 0, then the parameters
    /// (`(κ/2)(J − 1)² − 0.07995 kPa (J − 1), κ = 1000 kPa`).
    pub fn formula(&self) -> String {
        let linear = match self.shift {
            0.0 => String::new(),
            c if c > 0.0 => format!(" + {c} kPa (J − 1)"),
            c => format!(" − {} kPa (J − 1)", -c),
        };
        format!(
            "{}{linear}, {}",
            self.form.expression(),
            self.form.parameters()
        )
    }

    /// The linear term's coefficient c \[kPa\] (0 for 4C's form with 4C's energy, or a
    /// quadratic form with the chapter's).
    pub fn shift(&self) -> f64 {
        self.shift
    }

    /// U(J), U′(J), U″(J) \[kPa\]; J must be > 0 (an error naming J otherwise, and for a
    /// non-finite value).
    pub fn derivatives(&self, j: f64) -> Result<[f64; 3]> {
        if !(j > 0.0 && j.is_finite()) {
            return Err(Error::NonFinite {
                quantity: "volumetric energy",
                value: j,
                context: format!("at J = {j} (must be finite and > 0)"),
            });
        }
        let [u, du, ddu] = self.form.derivatives(j);
        let out = [u + self.shift * (j - 1.0), du + self.shift, ddu];
        if let Some(v) = out.iter().find(|v| !v.is_finite()) {
            return Err(Error::NonFinite {
                quantity: "volumetric energy",
                value: *v,
                context: format!("{} at J = {j}", self.form.name()),
            });
        }
        Ok(out)
    }

    /// The bulk modulus U″(1) \[kPa\].
    pub fn bulk_modulus(&self) -> f64 {
        self.form.derivatives(1.0)[2]
    }

    /// The volume ratio J̃(p) = (U′)⁻¹(−p) at which U′(J̃) = −p, and the compliance 1/U″(J̃)
    /// \[1/kPa\], for the pressure p \[kPa\]: the Legendre transform behind the mixed FE form
    /// (Φ(p) = sup_J [−p (J − 1) − U(J)], Φ′(p) = 1 − J̃(p), Φ″(p) = 1/U″(J̃)). Closed forms:
    /// quadratic J̃ = 1 + a/κ; logarithmic J̃ = a/κ + √((a/κ)² + 1); 4C's
    /// J̃ = (−2a/μ)^(−1/(2κ+1)), with a = −p − c. A pressure outside the range of U′ on J > 0
    /// has no J̃ (an error naming p): 4C's U′ = −(μ/2) J^(−2κ−1) + c stays below c (a hydrostatic
    /// tension −p ≥ c), the quadratic U′ above −κ (p ≥ κ).
    pub fn dilatation(&self, pressure: f64) -> Result<(f64, f64)> {
        let a = -pressure - self.shift;
        let j = match self.form {
            VolumetricForm::Quadratic { kappa } => 1.0 + a / kappa,
            VolumetricForm::Logarithmic { kappa } => {
                let x = a / kappa;
                let root = x.hypot(1.0);
                // x + √(x² + 1), written without cancellation for x < 0.
                if x >= 0.0 {
                    x + root
                } else {
                    1.0 / (root - x)
                }
            }
            VolumetricForm::Giantesio4C { kappa, mu } => {
                if a < 0.0 {
                    (-2.0 * a / mu).powf(-1.0 / (2.0 * kappa + 1.0))
                } else {
                    f64::NAN
                }
            }
        };
        if !(j > 0.0 && j.is_finite()) {
            return Err(Error::NoSolution {
                equation: format!(
                    "U'(J) = -p at p = {pressure} kPa ({} volumetric energy)",
                    self.form.name()
                ),
                reason: format!(
                    "no J > 0 has this volumetric stress (got J = {j}; the quadratic form's U' is above -kappa on J > 0, 4C's below its linear coefficient {} kPa)",
                    self.shift
                ),
            });
        }
        let [_, _, ddu] = self.derivatives(j)?;
        Ok((j, 1.0 / ddu))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// One of each form, at moduli where every derivative is of order one.
    const FORMS: [VolumetricForm; 3] = [
        VolumetricForm::Quadratic { kappa: 7.0 },
        VolumetricForm::Logarithmic { kappa: 7.0 },
        VolumetricForm::Giantesio4C {
            kappa: 3.0,
            mu: 0.16,
        },
    ];

    /// U′ and U″ against central differences of U, for every form, and U′(1) = −s₀.
    #[test]
    fn derivatives_match_central_differences_and_reference_is_stress_free() {
        for form in FORMS {
            for s0 in [0.0, 0.08] {
                let v = Volumetric::new(form, s0).unwrap();
                assert!((v.derivatives(1.0).unwrap()[1] + s0).abs() < 1e-15);
                for j in [0.8, 1.0, 1.3] {
                    let h = 1e-5;
                    let d = |x: f64| v.derivatives(x).unwrap();
                    let fd1 = (d(j + h)[0] - d(j - h)[0]) / (2.0 * h);
                    let fd2 = (d(j + h)[1] - d(j - h)[1]) / (2.0 * h);
                    assert!(
                        (fd1 - d(j)[1]).abs() < 1e-8 * (1.0 + d(j)[1].abs()),
                        "{form:?}"
                    );
                    assert!(
                        (fd2 - d(j)[2]).abs() < 1e-8 * (1.0 + d(j)[2].abs()),
                        "{form:?}"
                    );
                }
            }
        }
    }

    /// J̃(p) inverts U′: U′(J̃(p)) = −p, and the compliance is 1/U″ (central differences of J̃).
    #[test]
    fn dilatation_inverts_the_volumetric_stress() {
        for form in FORMS {
            let v = Volumetric::new(form, 0.0).unwrap();
            for p in [-0.07, -0.01, 0.0, 0.5, 5.0] {
                let (j, compliance) = v.dilatation(p).unwrap();
                let du = v.derivatives(j).unwrap()[1];
                assert!(
                    (du + p).abs() < 1e-12 * (1.0 + p.abs()),
                    "{form:?} p = {p}: {du}"
                );
                let h = 1e-6 * (1.0 + p.abs());
                let fd =
                    -(v.dilatation(p + h).unwrap().0 - v.dilatation(p - h).unwrap().0) / (2.0 * h);
                assert!(
                    (fd - compliance).abs() < 1e-6 * compliance,
                    "{form:?} p = {p}"
                );
            }
        }
        // 4C's form with the chapter's energy: U′ < μ/2, so no J̃ for a tension −p ≥ μ/2.
        let v = Volumetric::new(
            VolumetricForm::Giantesio4C {
                kappa: 3.0,
                mu: 0.16,
            },
            0.0,
        )
        .unwrap();
        assert!(v.dilatation(-0.08).is_err());
        assert!(v.dilatation(-0.0799).is_ok());
    }

    /// 4C's form with 4C's reference stress μ/2 is 4C's S_vol unchanged: no linear term.
    #[test]
    fn four_c_form_with_four_c_energy_needs_no_shift() {
        let mu = 0.1599;
        let v = Volumetric::new(VolumetricForm::Giantesio4C { kappa: 2.0, mu }, mu / 2.0).unwrap();
        assert_eq!(v.shift(), 0.0);
        // S_vol = U′(J) J C⁻¹ = −(μ/2) J^(−2κ) C⁻¹.
        let j: f64 = 1.1;
        let du = v.derivatives(j).unwrap()[1];
        assert!((du * j + 0.5 * mu * j.powf(-4.0)).abs() < 1e-15);
    }

    #[test]
    fn rejects_bad_parameters_and_states() {
        assert!(Volumetric::new(VolumetricForm::Quadratic { kappa: 0.0 }, 0.0).is_err());
        assert!(Volumetric::new(VolumetricForm::Quadratic { kappa: f64::NAN }, 0.0).is_err());
        assert!(Volumetric::new(
            VolumetricForm::Giantesio4C {
                kappa: 1.0,
                mu: -1.0
            },
            0.0
        )
        .is_err());
        let v = Volumetric::new(VolumetricForm::Logarithmic { kappa: 1.0 }, 0.0).unwrap();
        assert!(v.derivatives(0.0).is_err());
        assert!(v.derivatives(-1.0).is_err());
    }
}
