//! Local relaxation of an overshooting predictor (nonlinear elimination of a patch).
//!
//! The tangent predictor x_k + Δλ dx/dλ can carry a few quadrature points far into the fibres'
//! exponential stiffening: on the chapter's clamped cylinder at 32 × 128 cells, the predicted
//! state at λ = 1.40 has a largest stress of 6.1e6 kPa near a clamped corner, against 296 kPa
//! once converged. Newton on an exponential from above moves its exponent by about one per
//! step, so the global Newton then spends 9–10 full iterations (a tangent assembly and a
//! factorisation each) bringing that one corner down by a factor e at a time.
//!
//! Here the corner is brought down on its own first. The patch is every cell whose largest
//! stress exceeds [`OVERSHOOT`] × the last converged state's, plus one ring of neighbours (cells
//! sharing a dof). Its unknowns are the free dofs that no cell outside the patch holds; every
//! other dof stays at its predicted value. On them, Newton solves the patch's own equilibrium,
//!
//! R_i(x) = Σ_{e ∈ patch} R_i^e(x) = 0 for every patch unknown i,
//!
//! with the element residuals and tangents (centre nodes and pressures included, no
//! condensation) assembled into a sparse system of the patch alone, backtracking on ‖R‖₂. Its
//! iterations cost a patch's assembly and a small sparse LU, not the mesh's. The global Newton
//! then starts from the relaxed state: the result is the one it converges to, to its own
//! tolerance, whatever the start.
//!
//! Measured (frozen explicit sweep, `examples/cylinder_sweep`): 32 × 128 Newton iterations
//! 117 → 102 (1.35 → 1.40: 15 → 7; 1.40 → 1.45: 13 → 6), d = 0.5 98 → 91; 16 × 64 102 → 95;
//! P within 1.8e-11 relative.

use super::assembly::{Assembler, CellSystem, Pattern};
use super::dofs::DofMap;
use super::linear::SparseLu;
use super::material::AxisymmetricMaterial;

/// A cell is in the patch when its largest stress exceeds this multiple of the last converged
/// state's largest stress. At 32 × 128 the stalled steps' predictors are 4 000–40 000× over;
/// a well-predicted step stays within 1–5×. Lower thresholds do not pay (16 × 64 Newton
/// iterations, `LARGEST_SHARE` 0.1 / 0.3; 95 with 10): 5: 95 / 95, 3: 102 / 96, 2: 99 / 95,
/// 1.5: 99 / 96. The steps above λ = 1.2 take 5–6 iterations with a patch or without: what
/// slows them is not local.
pub const OVERSHOOT: f64 = 10.0;
/// The patch is at most this share of the cells; beyond, the predictor is kept as it is (the
/// overshoot is not local, and the global Newton is the cheaper patch).
const LARGEST_SHARE: f64 = 0.1;
/// Local Newton iterations (each divides an exponential overshoot by about e).
const MAX_ITERATIONS: usize = 40;
/// Halvings of the local step.
const MAX_BACKTRACKS: usize = 10;
/// The local Newton stops once ‖R‖₂ is this fraction of its start.
const REDUCTION: f64 = 1e-8;

/// The patch around the cells over `OVERSHOOT` × `converged_scale` (`cell_scales`: each
/// cell's largest stress), with one ring of neighbours; empty if none is over.
fn patch_cells(dofs: &DofMap, cell_scales: &[f64], converged_scale: f64) -> Vec<usize> {
    let n_cells = cell_scales.len();
    let seeds: Vec<usize> = (0..n_cells)
        .filter(|&e| cell_scales[e] > OVERSHOOT * converged_scale)
        .collect();
    if seeds.is_empty() {
        return seeds;
    }
    let mut touched = vec![false; dofs.n_total];
    for &e in &seeds {
        for &d in dofs.cell_dofs(e) {
            touched[d as usize] = true;
        }
    }
    (0..n_cells)
        .filter(|&e| dofs.cell_dofs(e).iter().any(|&d| touched[d as usize]))
        .collect()
}

/// The patch's unknowns (free dofs held by patch cells only) and each dof's local index
/// (`usize::MAX`: not a patch unknown).
fn patch_unknowns(dofs: &DofMap, n_cells: usize, patch: &[usize]) -> (Vec<usize>, Vec<usize>) {
    let mut in_patch = vec![false; n_cells];
    for &e in patch {
        in_patch[e] = true;
    }
    let mut outside = vec![false; dofs.n_total];
    for e in (0..n_cells).filter(|&e| !in_patch[e]) {
        for &d in dofs.cell_dofs(e) {
            outside[d as usize] = true;
        }
    }
    let mut local = vec![usize::MAX; dofs.n_total];
    let mut unknowns = Vec::new();
    for &e in patch {
        for &d in dofs.cell_dofs(e) {
            let d = d as usize;
            if d < dofs.n_free && !outside[d] && local[d] == usize::MAX {
                local[d] = unknowns.len();
                unknowns.push(d);
            }
        }
    }
    (unknowns, local)
}

/// The compressed-column pattern of the patch's system (rows sorted within each column).
fn patch_pattern(dofs: &DofMap, patch: &[usize], local: &[usize], m: usize) -> Pattern {
    let mut columns: Vec<Vec<u32>> = vec![Vec::new(); m];
    for &e in patch {
        let d = dofs.cell_dofs(e);
        for &db in d {
            let j = local[db as usize];
            if j == usize::MAX {
                continue;
            }
            columns[j].extend(
                d.iter()
                    .map(|&da| local[da as usize])
                    .filter(|&i| i != usize::MAX)
                    .map(|i| i as u32),
            );
        }
    }
    let mut col_ptr = vec![0u32; m + 1];
    let mut row_idx = Vec::new();
    for (j, c) in columns.iter_mut().enumerate() {
        c.sort_unstable();
        c.dedup();
        row_idx.extend_from_slice(c);
        col_ptr[j + 1] = row_idx.len() as u32;
    }
    Pattern {
        n: m,
        col_ptr,
        row_idx,
    }
}

/// The patch's residual and tangent values from its cells' element systems.
fn patch_system(cells: &[CellSystem], local: &[usize], pattern: &Pattern) -> (Vec<f64>, Vec<f64>) {
    let mut r = vec![0.0; pattern.n];
    let mut k = vec![0.0; pattern.row_idx.len()];
    for (d, re, ke) in cells {
        let nd = d.len();
        for (b, &db) in d.iter().enumerate() {
            let j = local[db as usize];
            if j == usize::MAX {
                continue;
            }
            let (start, end) = (pattern.col_ptr[j] as usize, pattern.col_ptr[j + 1] as usize);
            let rows = &pattern.row_idx[start..end];
            for (a, &da) in d.iter().enumerate() {
                let i = local[da as usize];
                if i != usize::MAX {
                    let p = start + rows.binary_search(&(i as u32)).expect("in the pattern");
                    k[p] += ke[b * nd + a];
                }
            }
        }
        for (a, &da) in d.iter().enumerate() {
            let i = local[da as usize];
            if i != usize::MAX {
                r[i] += re[a];
            }
        }
    }
    (r, k)
}

fn norm2(v: &[f64]) -> f64 {
    v.iter().map(|x| x * x).sum::<f64>().sqrt()
}

/// Relaxes the patch of cells over [`OVERSHOOT`] × `converged_scale` in `x` (all dofs), the
/// cells' largest stresses `cell_scales` being those of `x`. Returns whether `x` changed. A
/// local state the material refuses, or a singular patch system, ends the relaxation where it
/// is (every accepted local step lowered the patch's residual).
pub fn relax<M: AxisymmetricMaterial + ?Sized>(
    asm: &Assembler,
    dofs: &DofMap,
    material: &M,
    x: &mut [f64],
    converged_scale: f64,
) -> bool {
    let cell_scales = asm.cell_scales();
    let n_cells = cell_scales.len();
    let patch = patch_cells(dofs, cell_scales, converged_scale);
    if patch.is_empty() || patch.len() as f64 > LARGEST_SHARE * n_cells as f64 {
        return false;
    }
    let (unknowns, local) = patch_unknowns(dofs, n_cells, &patch);
    let m = unknowns.len();
    if m == 0 {
        return false;
    }
    let pattern = patch_pattern(dofs, &patch, &local, m);
    let Ok(mut lu) = SparseLu::new(&pattern) else {
        return false;
    };
    let evaluate = |x: &[f64]| {
        asm.patch(x, material, &patch)
            .ok()
            .map(|cells| patch_system(&cells, &local, &pattern))
    };
    let Some((mut r, mut k)) = evaluate(x) else {
        return false;
    };
    let start = norm2(&r);
    let mut changed = false;
    let mut trial = x.to_vec();
    for _ in 0..MAX_ITERATIONS {
        if norm2(&r) <= REDUCTION * start || lu.factorise(&pattern, &k).is_err() {
            break;
        }
        let mut dx: Vec<f64> = r.iter().map(|v| -v).collect();
        if lu.solve_in_place(&mut dx).is_err() || !dx.iter().all(|v| v.is_finite()) {
            break;
        }
        let mut alpha = 1.0;
        let mut accepted = None;
        for _ in 0..=MAX_BACKTRACKS {
            trial.copy_from_slice(x);
            for (&d, dxi) in unknowns.iter().zip(&dx) {
                trial[d] += alpha * dxi;
            }
            if let Some((r1, k1)) = evaluate(&trial) {
                if norm2(&r1) <= (1.0 - 1e-4 * alpha) * norm2(&r) {
                    accepted = Some((r1, k1));
                    break;
                }
            }
            alpha *= 0.5;
        }
        let Some((r1, k1)) = accepted else { break };
        x.copy_from_slice(&trial);
        (r, k) = (r1, k1);
        changed = true;
    }
    changed
}
