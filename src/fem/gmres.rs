//! Restarted, flexible right-preconditioned GMRES on the exact (possibly non-symmetric) tangent
//! K, converged to a normwise backward error: the preconditioner ([`Preconditioner`]) is a
//! factorisation of K's symmetric part ([`super::ldlt`]) or of K on that pattern
//! ([`super::pattern_lu`]), chosen by [`super::tangent_solver`].

use super::assembly::Pattern;
use super::finite::all_finite;
use std::ops::Range;

/// Nonzeros of K from which a product runs on two cores (a join costs ≈ 10 µs).
const PARALLEL_NONZEROS: usize = 100_000;

/// y = K x for K in compressed columns. From [`PARALLEL_NONZEROS`] on, the two halves of the
/// columns at the same time (`rayon::join`), the second half's sum in `half`, then y += half:
/// the same operations whatever the threads, so the same y.
fn matvec(pattern: &Pattern, values: &[f64], x: &[f64], y: &mut [f64], half: &mut Vec<f64>) {
    let n = x.len();
    if values.len() < PARALLEL_NONZEROS {
        columns(pattern, values, x, 0..n, y);
        return;
    }
    half.resize(n, 0.0);
    let mid = n / 2;
    rayon::join(
        || columns(pattern, values, x, 0..mid, y),
        || columns(pattern, values, x, mid..n, half),
    );
    for (yi, hi) in y.iter_mut().zip(half.iter()) {
        *yi += hi;
    }
}

/// y = Σ_{j in `range`} K[:, j] x_j.
fn columns(pattern: &Pattern, values: &[f64], x: &[f64], range: Range<usize>, y: &mut [f64]) {
    y.fill(0.0);
    for j in range {
        let xj = x[j];
        if xj == 0.0 {
            continue;
        }
        for k in pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize {
            y[pattern.row_idx[k] as usize] += values[k] * xj;
        }
    }
}

/// An approximate inverse M⁻¹ applied in place, for right-preconditioned GMRES.
pub trait Preconditioner {
    /// x ← M⁻¹ x.
    fn apply(&mut self, x: &mut [f64]);
}

/// Workspace of restarted, flexible right-preconditioned GMRES (FGMRES, Saad 1993): the
/// preconditioned vectors z_k = M⁻¹ v_k are kept, so x = x₀ + Z y needs no further
/// application of M⁻¹ (allocated once; the Krylov vectors v_k and z_k as they are first
/// needed, so a solve in one iteration holds three vectors, not 2 × restart).
#[derive(Debug)]
pub struct Gmres {
    restart: usize,
    v: Vec<Vec<f64>>,
    zs: Vec<Vec<f64>>,
    n: usize,
    w: Vec<f64>,
    /// The second half of the columns' part of a product ([`matvec`]).
    half: Vec<f64>,
    h: Vec<Vec<f64>>,
    cs: Vec<f64>,
    sn: Vec<f64>,
    g: Vec<f64>,
    x: Vec<f64>,
    r: Vec<f64>,
}

impl Gmres {
    /// Step k of the Arnoldi process with Givens rotations: z_k = M⁻¹ v_k, w = K z_k
    /// orthogonalised against v_0 … v_k, v_{k+1} = w / ‖w‖, then H's column k rotated to upper
    /// triangular form and the rotated residual g updated. None on breakdown.
    fn arnoldi_step(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        pre: &mut dyn Preconditioner,
        k: usize,
    ) -> Option<()> {
        if self.zs.len() <= k {
            self.zs.push(vec![0.0; self.n]);
        }
        self.zs[k].copy_from_slice(&self.v[k]);
        pre.apply(&mut self.zs[k]);
        matvec(pattern, values, &self.zs[k], &mut self.w, &mut self.half);
        for i in 0..=k {
            let hik: f64 = self.w.iter().zip(&self.v[i]).map(|(a, b)| a * b).sum();
            self.h[i][k] = hik;
            for (wj, vj) in self.w.iter_mut().zip(&self.v[i]) {
                *wj -= hik * vj;
            }
        }
        let hk1 = self.w.iter().map(|v| v * v).sum::<f64>().sqrt();
        self.h[k + 1][k] = hk1;
        if self.v.len() <= k + 1 {
            self.v.push(vec![0.0; self.n]);
        }
        if hk1 > 0.0 {
            for (vj, wj) in self.v[k + 1].iter_mut().zip(&self.w) {
                *vj = wj / hk1;
            }
        }
        for i in 0..k {
            let t = self.cs[i] * self.h[i][k] + self.sn[i] * self.h[i + 1][k];
            self.h[i + 1][k] = -self.sn[i] * self.h[i][k] + self.cs[i] * self.h[i + 1][k];
            self.h[i][k] = t;
        }
        let d = (self.h[k][k].powi(2) + self.h[k + 1][k].powi(2)).sqrt();
        if d == 0.0 || !d.is_finite() {
            return None;
        }
        self.cs[k] = self.h[k][k] / d;
        self.sn[k] = self.h[k + 1][k] / d;
        self.h[k][k] = d;
        self.h[k + 1][k] = 0.0;
        self.g[k + 1] = -self.sn[k] * self.g[k];
        self.g[k] *= self.cs[k];
        Some(())
    }

    /// x += Z y with y = H⁻¹ g over the first `k_used` Arnoldi vectors (H upper triangular).
    fn update_solution(&mut self, k_used: usize) {
        let mut y = [0.0f64; 64];
        for i in (0..k_used).rev() {
            let mut s = self.g[i];
            for (hij, yj) in self.h[i][i + 1..k_used].iter().zip(&y[i + 1..k_used]) {
                s -= hij * yj;
            }
            y[i] = s / self.h[i][i];
        }
        for (j, yj) in y.iter().enumerate().take(k_used) {
            for (xi, zi) in self.x.iter_mut().zip(&self.zs[j]) {
                *xi += yj * zi;
            }
        }
    }

    /// Workspace for dimension `n` and restart length `restart`.
    pub fn new(n: usize, restart: usize) -> Self {
        Self {
            restart,
            v: vec![vec![0.0; n]],
            zs: Vec::new(),
            n,
            w: vec![0.0; n],
            half: Vec::new(),
            h: vec![vec![0.0; restart]; restart + 1],
            cs: vec![0.0; restart],
            sn: vec![0.0; restart],
            g: vec![0.0; restart + 1],
            x: vec![0.0; n],
            r: vec![0.0; n],
        }
    }

    /// Solves K x = b (b in `rhs`, x returned in `rhs`) to the normwise backward error
    /// ‖b − K x‖ ≤ `tol` (‖K‖_F ‖x‖ + ‖b‖) with at most `max_iter` iterations. (A relative
    /// residual ‖b − K x‖ ≤ tol ‖b‖ is out of reach of any solver once the condition number
    /// exceeds tol/ε; the backward error is what a direct solve with partial pivoting attains,
    /// ≈ 1e-16 times a modest growth factor.) `knorm` is ‖K‖_F (the assembly's
    /// [`values_norm`](super::assembly::Assembler::values_norm)). Returns the iterations used, or
    /// `None` if the tolerance was not met.
    #[allow(clippy::too_many_arguments)]
    pub fn solve(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        knorm: f64,
        pre: &mut dyn Preconditioner,
        rhs: &mut [f64],
        tol: f64,
        max_iter: usize,
    ) -> Option<usize> {
        let bnorm = rhs.iter().map(|v| v * v).sum::<f64>().sqrt();
        if bnorm == 0.0 {
            return Some(0);
        }
        let norm = |v: &[f64]| v.iter().map(|v| v * v).sum::<f64>().sqrt();
        // First guess x₀ = M⁻¹ b, r₀ = b − K x₀: the solution itself when M is a factorisation
        // of K (a symmetric tangent), found with one product by K where a GMRES iteration
        // from x = 0 takes two (its Arnoldi vector and the true residual).
        self.x.copy_from_slice(rhs);
        pre.apply(&mut self.x);
        matvec(pattern, values, &self.x, &mut self.w, &mut self.half);
        for ((ri, bi), wi) in self.r.iter_mut().zip(rhs.iter()).zip(&self.w) {
            *ri = bi - wi;
        }
        let mut total = 1;
        // Estimate of ‖x‖ for the inner stopping test.
        let mut x_estimate = norm(&self.x);
        while total < max_iter {
            let beta = norm(&self.r);
            if beta <= tol * (knorm * norm(&self.x) + bnorm) {
                rhs.copy_from_slice(&self.x);
                return Some(total);
            }
            for (vi, ri) in self.v[0].iter_mut().zip(&self.r) {
                *vi = ri / beta;
            }
            self.g.fill(0.0);
            self.g[0] = beta;
            let mut k_used = 0;
            for k in 0..self.restart {
                total += 1;
                k_used = k + 1;
                self.arnoldi_step(pattern, values, pre, k)?;
                if k == 0 {
                    x_estimate = x_estimate.max(norm(&self.x) + beta * norm(&self.zs[0]));
                }
                // The estimate |g_{k+1}| of ‖b − K x‖ against the bound the true residual is then
                // checked against: where it is optimistic, one more cycle follows. (With a tenth
                // of the bound, one more Arnoldi step followed in 8–20 % of the solves:
                // `examples/cylinder_sweep`, frozen explicit, Krylov iterations 16 × 64
                // 278 → 256, 32 × 128 283 → 250 with the bound itself; the same Newton iterations.)
                let target = tol * (knorm * x_estimate + bnorm);
                if self.g[k + 1].abs() <= target || total >= max_iter {
                    break;
                }
            }
            self.update_solution(k_used);
            // True residual.
            matvec(pattern, values, &self.x, &mut self.w, &mut self.half);
            for ((ri, bi), wi) in self.r.iter_mut().zip(rhs.iter()).zip(&self.w) {
                *ri = bi - wi;
            }
        }
        let beta = norm(&self.r);
        if beta <= tol * (knorm * norm(&self.x) + bnorm) && all_finite(&self.x) {
            rhs.copy_from_slice(&self.x);
            Some(total)
        } else {
            None
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A non-symmetric banded matrix of `n` columns, 2 b + 1 entries per column.
    fn banded(n: usize, b: usize) -> (Pattern, Vec<f64>) {
        let (mut col_ptr, mut row_idx, mut values) = (vec![0u32], Vec::new(), Vec::new());
        for j in 0..n {
            for i in j.saturating_sub(b)..(j + b + 1).min(n) {
                row_idx.push(i as u32);
                values.push(1.0 + ((3 * i + 7 * j) % 11) as f64 / 10.0);
            }
            col_ptr.push(row_idx.len() as u32);
        }
        let pattern = Pattern {
            n,
            col_ptr,
            row_idx,
        };
        (pattern, values)
    }

    /// The two-core product against the entries summed row by row (another order), and the
    /// same bits on one thread and on two.
    #[test]
    fn the_product_in_two_halves_is_the_product_and_the_same_on_any_threads() {
        for n in [50, 30_000] {
            let (pattern, values) = banded(n, 3);
            assert_eq!(values.len() >= PARALLEL_NONZEROS, n > 50);
            let x: Vec<f64> = (0..n).map(|i| ((i * 13) % 17) as f64 - 8.0).collect();
            let mut expected = vec![0.0; n];
            for (i, e) in expected.iter_mut().enumerate() {
                let first = i.saturating_sub(3);
                for (j, xj) in x.iter().enumerate().take((i + 4).min(n)).skip(first) {
                    let k = pattern.col_ptr[j] as usize + i - j.saturating_sub(3);
                    assert_eq!(pattern.row_idx[k] as usize, i);
                    *e += values[k] * xj;
                }
            }
            let product = |threads: usize| {
                let pool = rayon::ThreadPoolBuilder::new()
                    .num_threads(threads)
                    .build()
                    .unwrap();
                let (mut y, mut half) = (vec![f64::NAN; n], Vec::new());
                pool.install(|| matvec(&pattern, &values, &x, &mut y, &mut half));
                y
            };
            let (one, two) = (product(1), product(2));
            assert_eq!(one, two, "n = {n}");
            for (y, e) in two.iter().zip(&expected) {
                assert!((y - e).abs() <= 1e-13 * e.abs().max(1.0), "{y} against {e}");
            }
        }
    }
}
