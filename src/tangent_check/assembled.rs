//! The Taylor test of the FE solver's assembled residual R and tangent K = ∂R_f/∂x_f at a state x
//! (all dofs) along v (free dofs), as FEBio's tangent diagnostic does for one element and PETSc's
//! `-snes_test_jacobian` for a whole residual:
//!
//! r₀(h) = ‖R(x + hv) − R(x)‖_s,   r₁(h) = ‖R(x + hv) − R(x) − h K v‖_s,
//!
//! over the displacement rows and the pressure rows apart, each in the solver's scale,
//! ‖r_u‖₂/(σ πR²) and ‖r_p‖₂/(πR²L) ([`crate::fem::problem`]; σ the largest stress at x plus
//! 1e-6 kPa). K v = Σ_cells K_e v_e from
//! the element systems (the Q2/Q1 centre nodes not condensed: the tangent of the residual the
//! solver drives to zero, whatever it factorises). Orders as in [`super::taylor`]; the rounding
//! floor is 10³ ε √n (n free dofs) in the scaled norm, a bound on the rounding of R whose terms
//! are at most of the scale σ.

use super::taylor::{Remainders, FLOOR_EPSILONS};
use crate::fem::assembly::Assembler;
use crate::fem::dofs::DofMap;
use crate::fem::{AxisymmetricMaterial, Mesh};
use crate::{Error, Result};
use std::f64::consts::PI;

/// The stress floor of the solver's force scale \[kPa\] ([`crate::fem::SolverOptions`]).
const STRESS_FLOOR: f64 = 1e-6;

/// The remainders of the assembled residual along one direction, for the displacement rows
/// (where the material's tangent enters) and the pressure rows apart: in one norm the larger
/// block would hide the other (under the exact constraint the pressure rows, ∫ q (J − 1) dV,
/// do not see the material at all).
#[derive(Debug, Clone, PartialEq)]
pub struct AssembledTaylor {
    /// The displacement rows, ‖·‖₂/(σ πR²) (no flag: the causes of [`super::flag`] are a
    /// material's at one state, not an assembly's).
    pub u: Remainders,
    /// The pressure rows, ‖·‖₂/(πR²L).
    pub p: Remainders,
    /// The least of the two blocks' median orders of r₁.
    pub order_1: Option<f64>,
}

impl AssembledTaylor {
    /// The steps h, descending.
    pub fn h(&self) -> &[f64] {
        &self.u.h
    }

    /// The rounding floor of both blocks.
    pub fn floor(&self) -> f64 {
        self.u.floor
    }
}

/// The scaled norms of the displacement and pressure rows of `r` (module docs).
fn scaled(r: &[f64], dofs: &DofMap, mesh: &Mesh, sigma: f64) -> [f64; 2] {
    let norm = |v: &[f64]| v.iter().map(|x| x * x).sum::<f64>().sqrt();
    let area = PI * mesh.radius * mesh.radius;
    let (u, p) = r.split_at(dofs.n_free_u);
    [norm(u) / (sigma * area), norm(p) / (area * mesh.length)]
}

/// K v over the free dofs from the element systems at x.
fn tangent_product<M: AxisymmetricMaterial + ?Sized>(
    asm: &Assembler,
    mesh: &Mesh,
    material: &M,
    x: &[f64],
    v: &[f64],
) -> Result<Vec<f64>> {
    let n = v.len();
    let cells: Vec<usize> = (0..mesh.n_elements()).collect();
    let mut kv = vec![0.0; n];
    for (d, _, k) in asm.patch(x, material, &cells)? {
        let m = d.len();
        for (j, &gj) in d.iter().enumerate() {
            let Some(&vj) = v.get(gj as usize) else {
                continue;
            };
            for (i, &gi) in d.iter().enumerate() {
                if let Some(out) = kv.get_mut(gi as usize) {
                    *out += k[i + m * j] * vj;
                }
            }
        }
    }
    Ok(kv)
}

/// The Taylor test of the residual and tangent `asm` assembles for `material` on `mesh` (whose
/// dofs `dofs` numbers), at `x` (all dofs) along `v` (free dofs) for the steps `h` (each in
/// (0, 1)); see the module docs. The material's error at x is returned; at x + hv it is a
/// missing remainder.
pub fn assembled_taylor_test<M: AxisymmetricMaterial + ?Sized>(
    asm: &mut Assembler,
    (mesh, dofs): (&Mesh, &DofMap),
    material: &M,
    x: &[f64],
    v: &[f64],
    h: &[f64],
) -> Result<AssembledTaylor> {
    let nf = dofs.n_free;
    if x.len() != dofs.n_total || v.len() != nf {
        return Err(Error::InvalidParameter {
            name: "v",
            value: v.len() as f64,
            rule: "x must hold every dof and v every free dof of the mesh",
        });
    }
    if let Some(bad) = h.iter().find(|h| !(**h > 0.0 && **h < 1.0)) {
        return Err(Error::InvalidParameter {
            name: "h",
            value: *bad,
            rule: "every step must lie in (0, 1)",
        });
    }
    let mut h = h.to_vec();
    h.sort_by(|a, b| b.total_cmp(a));
    h.dedup();
    asm.assemble(x, material, false)?;
    let base = asm.residual[..nf].to_vec();
    let sigma = asm.stress_scale + STRESS_FLOOR;
    let kv = tangent_product(asm, mesh, material, x, v)?;
    // [block][step] remainders.
    let mut r0 = [Vec::new(), Vec::new()];
    let mut r1 = [Vec::new(), Vec::new()];
    let mut unevaluable = None;
    for &step in &h {
        let mut y = x.to_vec();
        for (yi, vi) in y[..nf].iter_mut().zip(v) {
            *yi += step * vi;
        }
        if let Err(e) = asm.assemble(&y, material, false) {
            unevaluable.get_or_insert((step, e.to_string()));
            for b in 0..2 {
                r0[b].push(None);
                r1[b].push(None);
            }
            continue;
        }
        let change: Vec<f64> = asm.residual[..nf]
            .iter()
            .zip(&base)
            .map(|(a, b)| a - b)
            .collect();
        let rest: Vec<f64> = change.iter().zip(&kv).map(|(c, k)| c - step * k).collect();
        let (s0, s1) = (
            scaled(&change, dofs, mesh, sigma),
            scaled(&rest, dofs, mesh, sigma),
        );
        for b in 0..2 {
            r0[b].push(Some(s0[b]));
            r1[b].push(Some(s1[b]));
        }
    }
    let floor = FLOOR_EPSILONS * f64::EPSILON * (nf as f64).sqrt();
    let [r0_u, r0_p] = r0;
    let [r1_u, r1_p] = r1;
    let u = Remainders {
        unevaluable: unevaluable.clone(),
        ..Remainders::of(h.clone(), r0_u, r1_u, floor)
    };
    let p = Remainders {
        unevaluable,
        ..Remainders::of(h, r0_p, r1_p, floor)
    };
    let order_1 = [u.order_1, p.order_1]
        .into_iter()
        .flatten()
        .reduce(f64::min);
    Ok(AssembledTaylor { u, p, order_1 })
}
