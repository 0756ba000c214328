//! The elimination of supernodes: one worker per core, each over the panels it owns.
//!
//! For a supernode with diagonal block D (w × w) and off-diagonal rows R:
//!
//! P D = L₁₁ U₁₁ (dense, partial pivoting inside D),  L₂₁ = A₂₁ U₁₁⁻¹,  U₁₂ = L₁₁⁻¹ P A₁₂,
//! A_RR ← A_RR − L₂₁ U₁₂ (scattered into the supernodes that own the columns of R).
//!
//! A worker owns some supernodes' panels (all of them when one core factorises). An update for
//! a supernode it does not own, an ancestor outside its subtrees, is kept ([`Deferred`]) and
//! applied by the owner after the two workers have joined.

use super::super::finite::all_finite;
use super::Structure;
use faer::dyn_stack::MemStack;
use faer::linalg::lu::partial_pivoting::factor::{lu_in_place, lu_in_place_scratch};
use faer::linalg::matmul::matmul;
use faer::linalg::triangular_solve::{
    solve_lower_triangular_in_place, solve_unit_lower_triangular_in_place,
};
use faer::reborrow::{Reborrow, ReborrowMut};
use faer::{Accum, MatMut, MatRef, Par};

/// A worker's buffers, kept between factorisations.
#[derive(Debug, Default)]
pub(super) struct Workspace {
    schur: Vec<f64>,
    relpos: Vec<u32>,
    /// Rows of a Schur complement's entries in the target supernode's L panel.
    scatter_rows: Vec<usize>,
    /// The supernode's panels hold K's entries (zeroed and filled when first reached: by its
    /// own elimination or by the first Schur update into it, so the panel is in cache).
    loaded: Vec<bool>,
    dense: DenseLu,
}

impl Workspace {
    pub fn new(n: usize, supernodes: usize, widest: usize) -> Self {
        Self {
            relpos: vec![u32::MAX; n],
            loaded: vec![false; supernodes],
            dense: DenseLu::new(widest),
            ..Self::default()
        }
    }

    /// Forgets which panels were loaded (before a factorisation).
    pub fn reset(&mut self) {
        self.loaded.fill(false);
    }
}

/// Schur updates kept for supernodes another worker owns: for supernode s, the trailing block
/// of S = L₂₁ U₁₂ from its off-diagonal row `from` on (the rows whose supernodes it does not own).
#[derive(Debug, Default)]
pub(super) struct Deferred {
    pub updates: Vec<(usize, usize, usize)>,
    data: Vec<f64>,
}

impl Deferred {
    pub fn clear(&mut self) {
        self.updates.clear();
        self.data.clear();
    }
}

/// The panels of the supernodes a worker owns (None: another worker's).
pub(super) struct Worker<'a> {
    pub st: &'a Structure,
    pub values: &'a [f64],
    pub l: Vec<Option<&'a mut [f64]>>,
    pub u: Vec<Option<&'a mut [f64]>>,
    pub pivots: Vec<Option<&'a mut [u32]>>,
    pub ws: &'a mut Workspace,
    /// Where updates for supernodes not owned go (None: the worker owns every target).
    pub deferred: Option<&'a mut Deferred>,
}

/// Eliminates the supernodes of `order` (ascending) after applying the `deferred` updates, with
/// AVX2 where the processor has it (checked at run time; the same operations in the same order).
pub(super) fn run(
    worker: &mut Worker<'_>,
    deferred: Option<&Deferred>,
    order: &[usize],
) -> Result<(), String> {
    #[cfg(target_arch = "x86_64")]
    if std::arch::is_x86_feature_detected!("avx2") {
        // SAFETY: the processor has AVX2 (checked just above).
        return unsafe { run_avx2(worker, deferred, order) };
    }
    run_plain(worker, deferred, order)
}

#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
fn run_avx2(
    worker: &mut Worker<'_>,
    deferred: Option<&Deferred>,
    order: &[usize],
) -> Result<(), String> {
    run_plain(worker, deferred, order)
}

#[inline(always)]
fn run_plain(
    worker: &mut Worker<'_>,
    deferred: Option<&Deferred>,
    order: &[usize],
) -> Result<(), String> {
    if let Some(d) = deferred {
        let st = worker.st;
        let mut at = 0;
        for &(s, from, size) in &d.updates {
            let block = &d.data[at..at + size * size];
            at += size * size;
            if worker.scatter(&st.rows[s][from..], block) < size {
                return Err(format!("an update of supernode {s} has no owner"));
            }
        }
    }
    for &s in order {
        worker.factorise(s)?;
    }
    Ok(())
}

impl Worker<'_> {
    /// Zeroes supernode `t`'s panels and puts K's entries in them, the first time it is reached.
    #[inline(always)]
    fn load(&mut self, t: usize) {
        if std::mem::replace(&mut self.ws.loaded[t], true) {
            return;
        }
        let (Some(l), Some(u)) = (self.l[t].as_deref_mut(), self.u[t].as_deref_mut()) else {
            return;
        };
        l.fill(0.0);
        u.fill(0.0);
        let st = self.st;
        let (first, middle, last) = (st.entry_ptr[t], st.u_entries[t], st.entry_ptr[t + 1]);
        for &(k, p) in &st.entries[first..middle] {
            l[p as usize] = self.values[k as usize];
        }
        for &(k, p) in &st.entries[middle..last] {
            u[p as usize] = self.values[k as usize];
        }
    }

    /// Eliminates supernode `s` and sends its Schur update to its ancestors.
    #[inline(always)]
    fn factorise(&mut self, s: usize) -> Result<(), String> {
        self.load(s);
        let st = self.st;
        let (b, e) = (st.begin[s], st.end[s]);
        let (w, r) = (e - b, st.rows[s].len());
        let (Some(l), Some(u), Some(pivots)) = (
            self.l[s].as_deref_mut(),
            self.u[s].as_deref_mut(),
            self.pivots[s].as_deref_mut(),
        ) else {
            return Err(format!("supernode {s} is not this worker's"));
        };
        factor_diagonal_block(l, u, w, r, b, pivots, &mut self.ws.dense)?;
        let ld = w + r;
        if r > 0 {
            let lmat = MatRef::from_column_major_slice(l, ld, w);
            let l11 = lmat.submatrix(0, 0, w, w);
            let l21 = lmat.submatrix(w, 0, r, w);
            // U₁₂ = L₁₁⁻¹ P A₁₂ (w × r): solve L₁₁ U₁₂ = P A₁₂.
            let mut u12 = MatMut::from_column_major_slice_mut(u, w, r);
            solve_unit_lower_triangular_in_place(l11, u12.rb_mut(), Par::Seq);
            // Schur complement S = L₂₁ U₁₂ (r × r).
            self.ws.schur.resize(r * r, 0.0);
            let schur = MatMut::from_column_major_slice_mut(&mut self.ws.schur, r, r);
            matmul(schur, Accum::Replace, l21, u12.rb(), 1.0, Par::Seq);
        }
        if !(all_finite(l) && all_finite(u)) {
            return Err(format!("non-finite LU factor at dofs {b}..{e}"));
        }
        if r > 0 {
            let schur = std::mem::take(&mut self.ws.schur);
            let done = self.scatter(&st.rows[s], &schur);
            let kept = done == r || self.defer(s, done, &schur);
            self.ws.schur = schur;
            if !kept {
                return Err(format!("an update of supernode {s} has no owner"));
            }
        }
        Ok(())
    }

    /// Keeps the trailing block of supernode `s`'s Schur complement `schur` from row `from` on
    /// (false: this worker has no place for it).
    fn defer(&mut self, s: usize, from: usize, schur: &[f64]) -> bool {
        let r = self.st.rows[s].len();
        let Some(d) = self.deferred.as_deref_mut() else {
            return false;
        };
        d.updates.push((s, from, r - from));
        for j in from..r {
            d.data.extend_from_slice(&schur[from + j * r..(j + 1) * r]);
        }
        true
    }

    /// Subtracts the Schur complement S (r × r, `schur`) on the rows `rows` from the supernodes
    /// that own their columns, up to the first supernode this worker does not own; returns how
    /// many rows were done. For each target supernode t, the row of every remaining entry in
    /// t's L panel is looked up once (`pos`); each destination entry receives one subtraction.
    /// S is read column by column: its lower triangle goes to the columns of t's L panel, its
    /// upper triangle to the rows of t's diagonal block and U₁₂ panel, whose columns are
    /// contiguous in t's dofs.
    #[inline(always)]
    fn scatter(&mut self, rows: &[u32], schur: &[f64]) -> usize {
        let st = self.st;
        let r = rows.len();
        let mut jj = 0;
        while jj < r {
            let t = st.supernode_of[rows[jj] as usize] as usize;
            if self.l[t].is_none() {
                return jj;
            }
            self.load(t);
            let (bt, et) = (st.begin[t], st.end[t]);
            let (wt, rt) = (et - bt, st.rows[t].len());
            for (k, &i) in st.rows[t].iter().enumerate() {
                self.ws.relpos[i as usize] = (wt + k) as u32;
            }
            // The entries of R from jj on: inside t's diagonal block up to `inside`, then in
            // its off-diagonal rows.
            let relpos = &self.ws.relpos;
            let pos = &mut self.ws.scatter_rows;
            pos.clear();
            pos.extend(rows[jj..].iter().map(|&i| {
                let i = i as usize;
                if i < et {
                    i - bt
                } else {
                    relpos[i] as usize
                }
            }));
            let first = jj;
            let inside = first + rows[first..].partition_point(|&i| (i as usize) < et);
            let (Some(l), Some(u)) = (self.l[t].as_deref_mut(), self.u[t].as_deref_mut()) else {
                return jj;
            };
            let ldt = wt + rt;
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
                let (target, column_start) = if ii < inside {
                    (&mut *l, p * ldt)
                } else {
                    (&mut *u, (p - wt) * wt)
                };
                let m = ii.min(inside) - first;
                let source = &schur[first + ii * r..first + ii * r + m];
                if run {
                    let start = column_start + columns[0];
                    for (d, &v) in target[start..start + m].iter_mut().zip(source) {
                        *d -= v;
                    }
                } else {
                    for (&cj, &v) in columns[..m].iter().zip(source) {
                        target[column_start + cj] -= v;
                    }
                }
            }
            jj = inside;
        }
        r
    }
}

/// P D = L₁₁ U₁₁ in place for the diagonal block D (w × w) of a supernode's L panel `l`
/// (column-major, leading dimension w + r; the block's first dof is `b`), by faer's blocked
/// (recursive) LU with partial pivoting inside the block: rows never leave it, so the pattern is
/// kept. The row exchanges are recorded as swaps, `pivots[k]` the row exchanged with row k, and
/// applied to the rows of the U₁₂ panel `u` (w × r: the same equations' entries right of the
/// block). The rows below the block become L₂₁ = A₂₁ U₁₁⁻¹.
#[inline(always)]
fn factor_diagonal_block(
    l: &mut [f64],
    u: &mut [f64],
    w: usize,
    r: usize,
    b: usize,
    pivots: &mut [u32],
    dense: &mut DenseLu,
) -> Result<(), String> {
    let ld = w + r;
    let panel = MatMut::from_column_major_slice_mut(l, ld, w);
    let (mut block, mut l21) = panel.split_at_row_mut(w);
    let DenseLu {
        perm,
        perm_inv,
        at,
        scratch,
    } = dense;
    let (perm, perm_inv) = (&mut perm[..w], &mut perm_inv[..w]);
    lu_in_place(
        block.rb_mut(),
        perm,
        perm_inv,
        Par::Seq,
        MemStack::new(scratch),
        Default::default(),
    );
    // The permutation as swaps: at step k, row perm[k] (now at position at[perm[k]]) is
    // exchanged with the row at position k. `at` and `perm_inv` are reused as position ↔ row.
    let (row_at, at) = (perm_inv, &mut at[..w]);
    for k in 0..w {
        row_at[k] = k as u32;
        at[k] = k as u32;
    }
    for k in 0..w {
        let p = at[perm[k] as usize] as usize;
        pivots[k] = (b + p) as u32;
        if p != k {
            let (rk, rp) = (row_at[k], row_at[p]);
            row_at.swap(k, p);
            at[rk as usize] = p as u32;
            at[rp as usize] = k as u32;
            for column in u.chunks_exact_mut(w) {
                column.swap(k, p);
            }
        }
    }
    for k in 0..w {
        let pivot = block[(k, k)];
        if pivot == 0.0 || !pivot.is_finite() {
            return Err(format!("pivot {pivot:e} at dof {}", b + k));
        }
    }
    // The rows below the block: L₂₁ U₁₁ = A₂₁, i.e. U₁₁ᵀ L₂₁ᵀ = A₂₁ᵀ (faer's blocked kernel).
    if r > 0 {
        solve_lower_triangular_in_place(
            block.rb().transpose(),
            l21.rb_mut().transpose_mut(),
            Par::Seq,
        );
    }
    Ok(())
}

/// Buffers of the diagonal blocks' dense LU, for blocks up to the widest supernode.
#[derive(Debug, Default)]
pub(super) struct DenseLu {
    perm: Vec<u32>,
    perm_inv: Vec<u32>,
    at: Vec<u32>,
    scratch: Vec<std::mem::MaybeUninit<u8>>,
}

impl DenseLu {
    fn new(width: usize) -> Self {
        Self {
            perm: vec![0; width],
            perm_inv: vec![0; width],
            at: vec![0; width],
            scratch: vec![
                std::mem::MaybeUninit::uninit();
                lu_in_place_scratch::<u32, f64>(
                    width,
                    width,
                    Par::Seq,
                    Default::default()
                )
                .unaligned_bytes_required()
            ],
        }
    }
}
