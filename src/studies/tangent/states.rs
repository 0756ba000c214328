//! The states and directions of a tangent study: the user's deformations (row-major
//! [F11, F12, F13, F21, ..., F33]), named paths at given amounts in the fibre frame, seeded random
//! states (also near λ_min and at large fibre stretch), and the directions ΔF (the user's or
//! seeded random ones, each scaled to unit Frobenius norm).
//!
//! The fibre frame (m, n, t): m the scene's fibre, n ⊥ m, t = m × n; a path's F is Q F̂ Qᵀ with
//! Q = [m n t] and, with k and λ the path's amount,
//!
//! | path | F̂ |
//! |---|---|
//! | `uniaxial_along` | diag(λ, λ^-½, λ^-½) |
//! | `uniaxial_across` | diag(λ^-½, λ, λ^-½) |
//! | `simple_shear` | I + k e₁⊗e₂ (the shear along the fibre) |
//! | `equibiaxial` | diag(λ, λ, λ⁻²) |
//!
//! A random state is F = J^⅓ G/det(G)^⅓ with G = I + H, H's entries uniform in [−0.25, 0.25]
//! (det G > 0.2), and J = 1 (exactly incompressible) or uniform in [0.9, 1.1] (nearly
//! incompressible). Near λ_min and at large fibre stretch it is then stretched along the fibre,
//! F ← F (s M + s^-½ (I − M)) (det unchanged), so that |F m| is a target drawn in
//! λ_min (1 ± 0.01) (within reach of the largest default step) or in [1.3, 1.5].

use crate::app_error::SpecError;
use crate::random::Sampler;
use crate::studies::spec::StretchSpec;
use crate::text::shortest;
use nalgebra::{Matrix3, Vector3};

/// The most states a study may hold (each is a Taylor test per model and direction).
pub const MAX_STATES: usize = 200;
/// The most directions a study may hold.
pub const MAX_DIRECTIONS: usize = 16;

/// A state with its name.
#[derive(Debug, Clone, PartialEq)]
pub struct NamedState {
    /// `uniaxial along λ = 1.2`, `random 2`, `given 1`.
    pub name: String,
    /// F.
    pub f: Matrix3<f64>,
}

/// What the states are drawn from, as validated.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct StateSources {
    /// The user's deformations.
    pub given: Vec<Matrix3<f64>>,
    /// Stretches along the fibres.
    pub along: Vec<f64>,
    /// Stretches across the fibres.
    pub across: Vec<f64>,
    /// Amounts of simple shear along the fibres.
    pub shear: Vec<f64>,
    /// Equibiaxial stretches.
    pub equibiaxial: Vec<f64>,
    /// Random states, near λ_min, at large fibre stretch.
    pub random: [usize; 3],
    /// The seed of the random states and directions.
    pub seed: u64,
}

/// A 3 × 3 matrix from 9 row-major entries under `key`: finite, and with det > 0 if `state`.
pub fn matrix(key: &str, v: &[f64], state: bool) -> Result<Matrix3<f64>, SpecError> {
    let shown = || {
        let items: Vec<String> = v.iter().map(|x| shortest(*x)).collect();
        format!("[{}]", items.join(", "))
    };
    if v.len() != 9 {
        return Err(SpecError::new(
            key,
            shown(),
            format!(
                "give the 9 entries of a matrix row by row, [F11, F12, F13, F21, F22, F23, F31, F32, F33] ({} given)",
                v.len()
            ),
        ));
    }
    if v.iter().any(|x| !x.is_finite()) {
        return Err(SpecError::new(key, shown(), "every entry must be finite"));
    }
    let m = Matrix3::from_row_slice(v);
    let det = m.determinant();
    if state && (det.is_nan() || det <= 0.0) {
        return Err(SpecError::new(
            key,
            shown(),
            format!("det F = {} must be > 0", crate::text::significant(det, 6)),
        ));
    }
    if !state && m.norm() == 0.0 {
        return Err(SpecError::new(key, shown(), "a direction must not be zero"));
    }
    Ok(m)
}

/// The amounts of an optional path key: stretches (> 0) or amounts of shear (any sign).
pub fn amounts(key: &str, spec: &Option<StretchSpec>, shear: bool) -> Result<Vec<f64>, SpecError> {
    match spec {
        None => Ok(Vec::new()),
        Some(s) if shear => s.resolve_amounts(key),
        Some(s) => s.resolve(key),
    }
}

/// A count of states or directions under `key`: an integer in [0, `max`].
pub fn count(key: &str, v: i64, max: usize) -> Result<usize, SpecError> {
    crate::studies::rules::integer_in(key, v, 0..=max as i64, "")
}

/// Q = [m n t], the fibre frame of the unit fibre m.
fn frame(m: &Vector3<f64>) -> Matrix3<f64> {
    let helper = if m.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let n = m.cross(&helper).normalize();
    Matrix3::from_columns(&[*m, n, m.cross(&n)])
}

/// F = s M + s^-½ (I − M) with M = m ⊗ m: stretch s along m, volume kept.
fn along_fibre(m: &Vector3<f64>, s: f64) -> Matrix3<f64> {
    let mm = m * m.transpose();
    mm * s + (Matrix3::identity() - mm) / s.sqrt()
}

/// A named path: its words, its amounts and F̂ of an amount.
type Path<'a> = (&'static str, &'a [f64], fn(f64) -> Matrix3<f64>);

/// F̂ of uniaxial stretch λ along the fibre e₁: diag(λ, λ^-½, λ^-½).
fn along(l: f64) -> Matrix3<f64> {
    let r = 1.0 / l.sqrt();
    Matrix3::from_diagonal(&Vector3::new(l, r, r))
}

/// F̂ of uniaxial stretch λ across the fibre, along e₂: diag(λ^-½, λ, λ^-½).
fn across(l: f64) -> Matrix3<f64> {
    let r = 1.0 / l.sqrt();
    Matrix3::from_diagonal(&Vector3::new(r, l, r))
}

/// F̂ of simple shear k along the fibre: I + k e₁⊗e₂.
fn shear(k: f64) -> Matrix3<f64> {
    let mut fh = Matrix3::identity();
    fh[(0, 1)] = k;
    fh
}

/// F̂ of equibiaxial stretch λ in the plane (e₁, e₂): diag(λ, λ, λ⁻²).
fn equibiaxial(l: f64) -> Matrix3<f64> {
    Matrix3::from_diagonal(&Vector3::new(l, l, 1.0 / (l * l)))
}

impl StateSources {
    /// The number of states.
    pub fn len(&self) -> usize {
        self.given.len()
            + self.along.len()
            + self.across.len()
            + self.shear.len()
            + self.equibiaxial.len()
            + self.random.iter().sum::<usize>()
    }

    /// Whether there is none.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The states for the unit fibre `m`, λ_min `lambda_min`; random states leave det F = 1
    /// unless `compressible`.
    pub fn states(&self, m: &Vector3<f64>, lambda_min: f64, compressible: bool) -> Vec<NamedState> {
        let q = frame(m);
        let rotated = |fh: Matrix3<f64>| q * fh * q.transpose();
        let named = |name: String, f| NamedState { name, f };
        let mut out: Vec<NamedState> = self
            .given
            .iter()
            .enumerate()
            .map(|(i, f)| named(format!("given {}", i + 1), *f))
            .collect();
        let paths: [Path<'_>; 4] = [
            ("uniaxial along λ", &self.along, along),
            ("uniaxial across λ", &self.across, across),
            ("simple shear k", &self.shear, shear),
            ("equibiaxial λ", &self.equibiaxial, equibiaxial),
        ];
        for (what, amounts, path) in paths {
            for &a in amounts {
                out.push(named(format!("{what} = {}", shortest(a)), rotated(path(a))));
            }
        }
        out.extend(self.random_states(m, lambda_min, compressible));
        out
    }

    /// The seeded random states (module docs).
    fn random_states(
        &self,
        m: &Vector3<f64>,
        lambda_min: f64,
        compressible: bool,
    ) -> Vec<NamedState> {
        let mut s = Sampler::new(self.seed);
        let draw = |s: &mut Sampler| {
            let g = s.deformation(0.25);
            let j = if compressible { s.range(0.9, 1.1) } else { 1.0 };
            g * (j / g.determinant()).cbrt()
        };
        let mut out = Vec::new();
        for i in 0..self.random[0] {
            out.push(NamedState {
                name: format!("random {}", i + 1),
                f: draw(&mut s),
            });
        }
        let groups = [
            (
                self.random[1],
                "near λ_min",
                (lambda_min * 0.99, lambda_min * 1.01),
            ),
            (self.random[2], "large λ_f", (1.3, 1.5)),
        ];
        for (n, what, (lo, hi)) in groups {
            for i in 0..n {
                let f = draw(&mut s);
                let target = s.range(lo, hi);
                let f = f * along_fibre(m, target / (f * m).norm());
                out.push(NamedState {
                    name: format!(
                        "{what} {} (λ_f = {})",
                        i + 1,
                        crate::text::significant(target, 4)
                    ),
                    f,
                });
            }
        }
        out
    }
}

/// The directions: the user's, then `random` seeded ones (normal entries), each scaled to unit
/// Frobenius norm.
pub fn directions(given: &[Matrix3<f64>], random: usize, seed: u64) -> Vec<(String, Matrix3<f64>)> {
    let mut out: Vec<(String, Matrix3<f64>)> = given
        .iter()
        .enumerate()
        .map(|(i, d)| (format!("given {}", i + 1), d / d.norm()))
        .collect();
    // A stream of its own, so that adding states does not change the directions.
    let mut s = Sampler::new(seed ^ 0x5DEE_CE66_D1CE_4E5B);
    for i in 0..random {
        let d = Matrix3::from_fn(|_, _| s.normal());
        out.push((format!("random {}", i + 1), d / d.norm()));
    }
    out
}
