//! Supernodal LU on the symmetric pattern of K, for the non-symmetric tangent.
//!
//! K = Qᵀ L U Q with the fill-reducing symmetric ordering Q of the LDLᵀ (approximate minimum
//! degree on the node graph, each node's displacement dofs before its pressure dof). With
//! pivoting confined to the supernodes' diagonal blocks, L and Uᵀ have the structure of the
//! Cholesky factor of K's (symmetric) pattern, so the factor is as sparse as the LDLᵀ of the
//! symmetric part and sparser than a partial-pivoting LU, whose fill is bounded by the
//! Cholesky factor of KᵀK instead (factorisation at 9 360 dofs: ≈ 15–20 ms against faer's
//! LU ≈ 45 ms, `cargo run --release --example cylinder_sweep -- 16 64 explicit`). The
//! supernodes of faer's symbolic Cholesky are processed right-looking: for a supernode with
//! diagonal block D (w × w) and off-diagonal rows R,
//!
//! P D = L₁₁ U₁₁ (dense, partial pivoting inside D),  L₂₁ = A₂₁ U₁₁⁻¹,  U₁₂ = L₁₁⁻¹ P A₁₂,
//! A_RR ← A_RR − L₂₁ U₁₂ (scattered into the supernodes that own the columns of R).
//!
//! L₂₁ and U₁₂ are triangular solves and the update a matrix product, all faer's blocked
//! kernels; only the w × w block is eliminated column by column. (Eliminating the whole
//! (w + r) × w panel column by column, as before issue 26, was half of the frozen sweep's run
//! time: 16 × 64, the factorisation 1.66 → 1.35 s of dev-profile time for 103 factorisations.)
//!
//! Pivoting is confined to the diagonal blocks (rows never leave their supernode), so a small
//! pivot remains possible: a zero one is reported as an error and the caller falls back to
//! faer's LU with full partial pivoting. The factor is only ever used as a GMRES
//! preconditioner, so a poor pivot costs iterations, not accuracy.

use super::assembly::Pattern;
use super::gmres::Preconditioner;
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_unit_lower_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use faer::{Accum, MatMut, MatRef, Par};

/// Where an entry of K goes: the L panel (diagonal block included) or the U₁₂ panel (offsets
/// into `l` and `u`).
#[derive(Debug, Clone, Copy)]
enum Slot {
    L(u32),
    U(u32),
}

/// Numeric LU on the symmetric pattern, for one symbolic Cholesky analysis.
#[derive(Debug)]
pub struct PatternLu {
    /// perm[k] = original index of the k-th eliminated dof.
    perm: Vec<u32>,
    begin: Vec<usize>,
    end: Vec<usize>,
    /// Off-diagonal row pattern of each supernode (sorted, permuted indices).
    rows: Vec<Vec<u32>>,
    /// Offsets of the L panels ((w + r) × w, column-major) and U₁₂ panels (w × r, column-major).
    l_ptr: Vec<usize>,
    u_ptr: Vec<usize>,
    l: Vec<f64>,
    u: Vec<f64>,
    supernode_of: Vec<u32>,
    /// The entries of K that go to each supernode's panels, `(index into the values, slot)`,
    /// supernode by supernode (`entry_ptr`).
    entries: Vec<(u32, Slot)>,
    entry_ptr: Vec<usize>,
    /// The supernode's panels hold K's entries (zeroed and filled when first reached: by its
    /// own elimination or by the first Schur update into it, so the panel is in cache).
    loaded: Vec<bool>,
    schur: Vec<f64>,
    relpos: Vec<u32>,
    /// Rows of a Schur complement's entries in the target supernode's L panel.
    scatter_rows: Vec<usize>,
    /// Row swaps inside the diagonal blocks: at step k rows k and pivots[k] were exchanged.
    pivots: Vec<u32>,
    work: Vec<f64>,
    /// The entries of a supernode's off-diagonal rows, gathered for the solves.
    gathered: Vec<f64>,
    factorised: bool,
}

impl PatternLu {
    /// Set-up for `pattern` with the supernodal structure of `symbolic`, the analysis of the
    /// matrix permuted by `perm` (`perm[k]`: original index of the k-th eliminated dof; faer's
    /// own ordering composed with it if the analysis carries one).
    pub fn new(
        pattern: &Pattern,
        symbolic: &SymbolicCholesky<u32>,
        perm: &[u32],
    ) -> Result<Self, String> {
        let n = pattern.n;
        let sn = match symbolic.raw() {
            SymbolicCholeskyRaw::Supernodal(s) => s,
            SymbolicCholeskyRaw::Simplicial(_) => {
                return Err("pattern LU needs a supernodal symbolic factorisation".into())
            }
        };
        let perm: Vec<u32> = match symbolic.perm() {
            Some(p) => p.arrays().0.iter().map(|&k| perm[k as usize]).collect(),
            None => perm.to_vec(),
        };
        let mut perm_inv = vec![0u32; n];
        for (k, &i) in perm.iter().enumerate() {
            perm_inv[i as usize] = k as u32;
        }
        let ns = sn.n_supernodes();
        let begin: Vec<usize> = sn.supernode_begin().iter().map(|&b| b as usize).collect();
        let end: Vec<usize> = sn.supernode_end().iter().map(|&e| e as usize).collect();
        let rows: Vec<Vec<u32>> = (0..ns)
            .map(|s| sn.supernode(s).pattern().to_vec())
            .collect();
        let mut supernode_of = vec![0u32; n];
        let (mut l_ptr, mut u_ptr) = (vec![0usize], vec![0usize]);
        for s in 0..ns {
            let (w, r) = (end[s] - begin[s], rows[s].len());
            supernode_of[begin[s]..end[s]].fill(s as u32);
            l_ptr.push(l_ptr[s] + (w + r) * w);
            u_ptr.push(u_ptr[s] + w * r);
        }
        let mut lu = Self {
            perm,
            begin,
            end,
            rows,
            l: vec![0.0; l_ptr[ns]],
            u: vec![0.0; u_ptr[ns]],
            l_ptr,
            u_ptr,
            supernode_of,
            entries: Vec::new(),
            entry_ptr: Vec::new(),
            loaded: vec![false; ns],
            schur: Vec::new(),
            relpos: vec![u32::MAX; n],
            scatter_rows: Vec::new(),
            pivots: (0..n as u32).collect(),
            work: vec![0.0; n],
            gathered: Vec::new(),
            factorised: false,
        };
        let mut entries = Vec::with_capacity(pattern.row_idx.len());
        for j in 0..n {
            let range = pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize;
            for (&i, k) in pattern.row_idx[range.clone()].iter().zip(range) {
                let (pi, pj) = (perm_inv[i as usize] as usize, perm_inv[j] as usize);
                let (t, slot) = lu
                    .slot(pi, pj)
                    .ok_or_else(|| format!("entry ({i}, {j}) outside the symbolic pattern"))?;
                entries.push((t, k as u32, slot));
            }
        }
        entries.sort_by_key(|&(t, k, _)| (t, k));
        lu.entry_ptr = vec![0; ns + 1];
        for &(t, _, _) in &entries {
            lu.entry_ptr[t as usize + 1] += 1;
        }
        for s in 0..ns {
            lu.entry_ptr[s + 1] += lu.entry_ptr[s];
        }
        lu.entries = entries.into_iter().map(|(_, k, slot)| (k, slot)).collect();
        Ok(lu)
    }

    /// Supernode and position of the permuted entry (i, j) in the factor storage.
    fn slot(&self, i: usize, j: usize) -> Option<(u32, Slot)> {
        let t = self.supernode_of[i.min(j)] as usize;
        let (b, e) = (self.begin[t], self.end[t]);
        let (w, r) = (e - b, self.rows[t].len());
        let pos = |k: usize| self.rows[t].binary_search(&(k as u32)).ok();
        let slot = if i >= j {
            let row = if i < e { i - b } else { w + pos(i)? };
            Slot::L((self.l_ptr[t] + row + (j - b) * (w + r)) as u32)
        } else if j < e {
            Slot::L((self.l_ptr[t] + (i - b) + (j - b) * (w + r)) as u32)
        } else {
            Slot::U((self.u_ptr[t] + (i - b) + pos(j)? * w) as u32)
        };
        Some((t as u32, slot))
    }

    /// Numeric factorisation of the matrix with this pattern and `values`.
    ///
    /// The loops are compiled twice, and run with AVX2 where the processor has it (checked at
    /// run time; the same operations in the same order, so the same factor, four entries to an
    /// instruction instead of two).
    pub fn factorise(&mut self, values: &[f64]) -> Result<(), String> {
        self.factorised = false;
        self.loaded.fill(false);
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (checked just above).
            unsafe { self.factorise_avx2(values) }?;
            self.factorised = true;
            return Ok(());
        }
        self.factorise_supernodes(values)?;
        self.factorised = true;
        Ok(())
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn factorise_avx2(&mut self, values: &[f64]) -> Result<(), String> {
        self.factorise_supernodes(values)
    }

    #[inline(always)]
    fn factorise_supernodes(&mut self, values: &[f64]) -> Result<(), String> {
        for s in 0..self.begin.len() {
            self.load(s, values);
            self.factorise_supernode(s, values)?;
        }
        Ok(())
    }

    /// Zeroes supernode `t`'s panels and puts K's entries in them, the first time it is reached.
    #[inline(always)]
    fn load(&mut self, t: usize, values: &[f64]) {
        if std::mem::replace(&mut self.loaded[t], true) {
            return;
        }
        self.l[self.l_ptr[t]..self.l_ptr[t + 1]].fill(0.0);
        self.u[self.u_ptr[t]..self.u_ptr[t + 1]].fill(0.0);
        for &(k, slot) in &self.entries[self.entry_ptr[t]..self.entry_ptr[t + 1]] {
            match slot {
                Slot::L(p) => self.l[p as usize] = values[k as usize],
                Slot::U(p) => self.u[p as usize] = values[k as usize],
            }
        }
    }

    #[inline(always)]
    fn factorise_supernode(&mut self, s: usize, values: &[f64]) -> Result<(), String> {
        let (b, e) = (self.begin[s], self.end[s]);
        let (w, r) = (e - b, self.rows[s].len());
        let l = &mut self.l[self.l_ptr[s]..self.l_ptr[s + 1]];
        let ld = w + r;
        let u = &mut self.u[self.u_ptr[s]..self.u_ptr[s + 1]];
        factor_diagonal_block(l, u, w, r, b, &mut self.pivots[b..e])?;
        if r > 0 {
            let lmat = MatRef::from_column_major_slice(l, ld, w);
            let l11 = lmat.submatrix(0, 0, w, w);
            let l21 = lmat.submatrix(w, 0, r, w);
            // U₁₂ = L₁₁⁻¹ P A₁₂ (w × r): solve L₁₁ U₁₂ = P A₁₂.
            let mut u12 = MatMut::from_column_major_slice_mut(u, w, r);
            solve_unit_lower_triangular_in_place(l11, u12.rb_mut(), Par::Seq);
            // Schur complement S = L₂₁ U₁₂ (r × r).
            self.schur.resize(r * r, 0.0);
            let schur = MatMut::from_column_major_slice_mut(&mut self.schur, r, r);
            matmul(schur, Accum::Replace, l21, u12.rb(), 1.0, Par::Seq);
        }
        let finite = |x: &[f64]| x.iter().all(|v| v.is_finite());
        if !finite(&self.l[self.l_ptr[s]..self.l_ptr[s + 1]])
            || !finite(&self.u[self.u_ptr[s]..self.u_ptr[s + 1]])
        {
            return Err(format!("non-finite LU factor at dofs {b}..{e}"));
        }
        if r > 0 {
            self.scatter_schur(s, values);
        }
        Ok(())
    }

    /// Subtracts the Schur complement S (in `schur`) of supernode `s` from the supernodes that
    /// own the columns of its off-diagonal rows R. For each target supernode t, the row of every
    /// remaining entry of R in t's L panel is looked up once (`pos`); each destination entry
    /// receives one subtraction. S is read column by column: its lower triangle goes to the
    /// columns of t's L panel, its upper triangle to the rows of t's diagonal block and U₁₂
    /// panel, whose columns are contiguous in t's dofs.
    #[inline(always)]
    fn scatter_schur(&mut self, s: usize, values: &[f64]) {
        let r = self.rows[s].len();
        let mut jj = 0;
        while jj < r {
            let t = self.supernode_of[self.rows[s][jj] as usize] as usize;
            self.load(t, values);
            let rows = &self.rows[s];
            let (bt, et) = (self.begin[t], self.end[t]);
            let (wt, rt) = (et - bt, self.rows[t].len());
            for (k, &i) in self.rows[t].iter().enumerate() {
                self.relpos[i as usize] = (wt + k) as u32;
            }
            // The entries of R from jj on: inside t's diagonal block up to `inside`, then in
            // its off-diagonal rows.
            let pos = &mut self.scatter_rows;
            pos.clear();
            pos.extend(rows[jj..].iter().map(|&i| {
                let i = i as usize;
                if i < et {
                    i - bt
                } else {
                    self.relpos[i] as usize
                }
            }));
            let first = jj;
            let inside = first + rows[first..].partition_point(|&i| (i as usize) < et);
            let l = &mut self.l[self.l_ptr[t]..self.l_ptr[t + 1]];
            let u = &mut self.u[self.u_ptr[t]..self.u_ptr[t + 1]];
            let ldt = wt + rt;
            let schur = &self.schur;
            // t's columns reached, and whether they are consecutive (one slice).
            let columns = &pos[..inside - first];
            let run = columns[columns.len() - 1] - columns[0] + 1 == columns.len();
            // L entries (i, j), i ≥ j: column cj of t's L panel.
            for (jj, &cj) in (first..inside).zip(columns) {
                let column = &mut l[cj * ldt..(cj + 1) * ldt];
                for (&p, &v) in pos[jj - first..]
                    .iter()
                    .zip(&schur[jj + jj * r..(jj + 1) * r])
                {
                    column[p] -= v;
                }
            }
            // U entries (j, i), j < i: row cj of t's diagonal block (column pos(i) of its L
            // panel) while i is inside the block, then of its U₁₂ panel (column pos(i) − wt).
            for ii in first + 1..r {
                let p = pos[ii - first];
                let (target, stride_start) = if ii < inside {
                    (&mut *l, p * ldt)
                } else {
                    (&mut *u, (p - wt) * wt)
                };
                let m = ii.min(inside) - first;
                let source = &schur[first + ii * r..first + ii * r + m];
                if run {
                    let start = stride_start + columns[0];
                    for (d, &v) in target[start..start + m].iter_mut().zip(source) {
                        *d -= v;
                    }
                } else {
                    for (&cj, &v) in columns[..m].iter().zip(source) {
                        target[stride_start + cj] -= v;
                    }
                }
            }
            jj = inside;
        }
    }

    /// x ← K⁻¹ x with the factorisation (fails if there is none).
    pub fn solve_in_place(&mut self, x: &mut [f64]) -> Result<(), String> {
        if !self.factorised {
            return Err("no factorisation".into());
        }
        #[cfg(target_arch = "x86_64")]
        if std::arch::is_x86_feature_detected!("avx2") {
            // SAFETY: the processor has AVX2 (checked just above).
            unsafe { self.solve_permuted_avx2(x) };
        } else {
            self.solve_permuted(x);
        }
        #[cfg(not(target_arch = "x86_64"))]
        self.solve_permuted(x);
        match x.iter().position(|v| !v.is_finite()) {
            Some(i) => Err(format!("solution entry {i} is {}", x[i])),
            None => Ok(()),
        }
    }

    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    fn solve_permuted_avx2(&mut self, x: &mut [f64]) {
        self.solve_permuted(x);
    }

    /// The forward and back substitutions, with the symmetric permutation applied around them.
    #[inline(always)]
    fn solve_permuted(&mut self, x: &mut [f64]) {
        let y = &mut self.work;
        for (k, &i) in self.perm.iter().enumerate() {
            y[k] = x[i as usize];
        }
        let ns = self.begin.len();
        // The off-diagonal rows R of a supernode are gathered into `t`, updated as a dense
        // vector (contiguous, so the loops vectorise) and scattered back.
        let t = &mut self.gathered;
        // L y = P b, with the row swaps of each diagonal block applied as it is reached.
        for s in 0..ns {
            let (b, e) = (self.begin[s], self.end[s]);
            let rows = &self.rows[s];
            let (w, r) = (e - b, rows.len());
            let ld = w + r;
            for k in b..e {
                y.swap(k, self.pivots[k] as usize);
            }
            let l = &self.l[self.l_ptr[s]..self.l_ptr[s + 1]];
            t.clear();
            t.extend(rows.iter().map(|&i| y[i as usize]));
            let block = &mut y[b..e];
            for (k, column) in l.chunks_exact(ld).enumerate() {
                let yk = block[k];
                if yk == 0.0 {
                    continue;
                }
                for (v, &lik) in block[k + 1..].iter_mut().zip(&column[k + 1..w]) {
                    *v -= lik * yk;
                }
                for (v, &lik) in t.iter_mut().zip(&column[w..]) {
                    *v -= lik * yk;
                }
            }
            for (&i, &v) in rows.iter().zip(t.iter()) {
                y[i as usize] = v;
            }
        }
        // U z = y.
        for s in (0..ns).rev() {
            let (b, e) = (self.begin[s], self.end[s]);
            let rows = &self.rows[s];
            let (w, r) = (e - b, rows.len());
            let ld = w + r;
            let l = &self.l[self.l_ptr[s]..self.l_ptr[s + 1]];
            let u = &self.u[self.u_ptr[s]..self.u_ptr[s + 1]];
            // The off-diagonal rows all come after the block: y[i] for i in R is in `later`.
            let (head, later) = y.split_at_mut(e);
            let block = &mut head[b..];
            for (column, &i) in u.chunks_exact(w).zip(rows) {
                let yi = later[i as usize - e];
                if yi != 0.0 {
                    for (v, &uki) in block.iter_mut().zip(column) {
                        *v -= uki * yi;
                    }
                }
            }
            for k in (0..w).rev() {
                let column = &l[k * ld..k * ld + k];
                let yk = block[k] / l[k + k * ld];
                block[k] = yk;
                for (v, &lik) in block[..k].iter_mut().zip(column) {
                    *v -= lik * yk;
                }
            }
        }
        for (k, &i) in self.perm.iter().enumerate() {
            x[i as usize] = y[k];
        }
    }
}

/// P D = L₁₁ U₁₁ in place for the diagonal block D (w × w) of a supernode's L panel `l`
/// (column-major, leading dimension w + r; the block's first dof is `b`), unblocked, with
/// partial pivoting inside the block: rows never leave it, so the pattern is kept. A row swap is
/// applied to the L panel and to the rows of the U₁₂ panel `u` (w × r: the same equations'
/// entries right of the block); `pivots[k]` records the row exchanged with row k. The rows below
/// the block become L₂₁ = A₂₁ U₁₁⁻¹.
#[inline(always)]
fn factor_diagonal_block(
    l: &mut [f64],
    u: &mut [f64],
    w: usize,
    r: usize,
    b: usize,
    pivots: &mut [u32],
) -> Result<(), String> {
    let ld = w + r;
    for k in 0..w {
        // Partial pivoting inside the diagonal block (rows b..e only, so the pattern is
        // kept): the row swap is applied to the L panel and to the rows of the U₁₂ panel
        // (the same equations' entries right of the block).
        let mut p = k;
        for i in k + 1..w {
            if l[i + k * ld].abs() > l[p + k * ld].abs() {
                p = i;
            }
        }
        pivots[k] = (b + p) as u32;
        if p != k {
            for j in 0..w {
                l.swap(k + j * ld, p + j * ld);
            }
            for column in u.chunks_exact_mut(w) {
                column.swap(k, p);
            }
        }
        let pivot = l[k + k * ld];
        if pivot == 0.0 || !pivot.is_finite() {
            return Err(format!("pivot {pivot:e} at dof {}", b + k));
        }
        // Column k of L₁₁ below the pivot and the update of the block's trailing columns, as
        // column slices (no index checks, so the loops vectorise).
        let (left, right) = l.split_at_mut((k + 1) * ld);
        let below = &mut left[k * ld + k + 1..k * ld + w];
        for v in below.iter_mut() {
            *v /= pivot;
        }
        for column in right.chunks_exact_mut(ld).take(w - k - 1) {
            let ukj = column[k];
            if ukj != 0.0 {
                for (v, &lik) in column[k + 1..w].iter_mut().zip(below.iter()) {
                    *v -= lik * ukj;
                }
            }
        }
    }
    // The rows below the block: L₂₁ U₁₁ = A₂₁, i.e. U₁₁ᵀ L₂₁ᵀ = A₂₁ᵀ, one triangular solve
    // (faer's blocked kernel) instead of w rank-one updates of the r rows.
    if r > 0 {
        let panel = MatMut::from_column_major_slice_mut(l, ld, w);
        let (block, mut l21) = panel.split_at_row_mut(w);
        solve_lower_triangular_in_place(
            block.rb().transpose(),
            l21.rb_mut().transpose_mut(),
            Par::Seq,
        );
    }
    Ok(())
}

impl Preconditioner for PatternLu {
    fn apply(&mut self, x: &mut [f64]) {
        if self.solve_in_place(x).is_err() {
            x.fill(f64::NAN);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use faer::sparse::linalg::cholesky::{
        factorize_symbolic_cholesky, CholeskySymbolicParams, SymmetricOrdering,
    };
    use faer::sparse::linalg::SupernodalThreshold;
    use faer::sparse::SymbolicSparseColMatRef;
    use faer::Side;

    /// A non-symmetric matrix on the symmetric pattern of a 2D grid graph (5-point stencil on
    /// an m × m grid plus the diagonals, so supernodes form), diagonally dominant.
    fn grid(m: usize, diagonal: f64) -> (Pattern, Vec<f64>) {
        let n = m * m;
        let mut col_ptr = vec![0u32];
        let mut row_idx = Vec::new();
        let mut values = Vec::new();
        for j in 0..n {
            let (x, y) = (j % m, j / m);
            let mut rows = Vec::new();
            for dy in -1i64..=1 {
                for dx in -1i64..=1 {
                    let (xi, yi) = (x as i64 + dx, y as i64 + dy);
                    if xi >= 0 && yi >= 0 && (xi as usize) < m && (yi as usize) < m {
                        rows.push(yi as usize * m + xi as usize);
                    }
                }
            }
            rows.sort_unstable();
            for i in rows {
                row_idx.push(i as u32);
                // Non-symmetric: a_ij ≠ a_ji off the diagonal.
                let v = if i == j {
                    diagonal
                } else {
                    -1.0 - 0.7 * ((i * 7 + j * 3) % 5) as f64 / 5.0
                };
                values.push(v);
            }
            col_ptr.push(row_idx.len() as u32);
        }
        (
            Pattern {
                n,
                col_ptr,
                row_idx,
            },
            values,
        )
    }

    #[test]
    fn solves_a_non_symmetric_system_to_round_off() {
        check(20.0, 1e-12);
    }

    /// Small diagonal entries: elimination without row exchanges would amplify round-off;
    /// the pivoting inside the diagonal blocks keeps the solve accurate.
    #[test]
    fn pivots_inside_the_diagonal_blocks() {
        check(1e-3, 1e-9);
    }

    fn check(diagonal: f64, tolerance: f64) {
        let (pattern, values) = grid(30, diagonal);
        let n = pattern.n;
        let a =
            SymbolicSparseColMatRef::new_checked(n, n, &pattern.col_ptr, None, &pattern.row_idx);
        let symbolic = factorize_symbolic_cholesky(
            a,
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .unwrap();
        let identity: Vec<u32> = (0..n as u32).collect();
        let mut lu = PatternLu::new(&pattern, &symbolic, &identity).unwrap();
        lu.factorise(&values).unwrap();
        let x_true: Vec<f64> = (0..n).map(|i| ((i * 13) % 17) as f64 - 8.0).collect();
        // b = A x.
        let mut b = vec![0.0; n];
        for (j, xj) in x_true.iter().enumerate() {
            for k in pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize {
                b[pattern.row_idx[k] as usize] += values[k] * xj;
            }
        }
        lu.solve_in_place(&mut b).unwrap();
        let err = b
            .iter()
            .zip(&x_true)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max);
        assert!(err < tolerance, "max error {err:e}");
        assert!(
            lu.pivots.iter().enumerate().any(|(k, &p)| p as usize != k) == (diagonal < 1.0),
            "row exchanges happen exactly when the diagonal is small"
        );
    }
}
