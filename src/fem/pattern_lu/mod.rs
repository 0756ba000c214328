//! Supernodal LU on the symmetric pattern of K, for the non-symmetric tangent.
//!
//! K = Qᵀ L U Q with the fill-reducing symmetric ordering Q of the LDLᵀ (a dissection of the
//! node graph, [`super::dissection`], each node's displacement dofs before its pressure dof). With
//! pivoting confined to the supernodes' diagonal blocks, L and Uᵀ have the structure of the
//! Cholesky factor of K's (symmetric) pattern, so the factor is as sparse as the LDLᵀ of the
//! symmetric part and sparser than a partial-pivoting LU, whose fill is bounded by the
//! Cholesky factor of KᵀK instead (factorisation at 9 360 dofs: ≈ 15–20 ms against faer's
//! LU ≈ 45 ms, `cargo run --release --example cylinder_sweep -- 16 64 explicit`). The
//! supernodes of faer's symbolic Cholesky are processed right-looking ([`worker`]: the
//! equations), two independent groups of subtrees of the elimination tree at the same time on
//! two cores, their ancestors after ([`split`]). The dissection order leaves one separator
//! between two halves on top of the tree, so the ancestors are 2–3 % of the flops of the
//! clamped cylinder's Q2/Q1 factor (estimated speed-up 1.89–1.93 at 16 × 64 to 64 × 256 cells;
//! under approximate minimum degree, the order before, 27–34 % and 1.50–1.54).
//!
//! The solves (GMRES's preconditioner, [`solve`]) follow the same split: forward, the two groups
//! at the same time, the second on its own copy of the vector, then on one core their updates
//! of the rest's rows and the rest; backward, the rest on one core, then the two groups at the
//! same time, in one `rayon::join`. Every entry receives the one-core solve's operations in the
//! one-core order, so the solution is the same bit for bit. In the frozen explicit sweep a
//! solve takes 3.5–3.8 ms on two cores against 6.0–6.2 ms on one at 37 152 dofs (32 × 128),
//! 0.44–0.52 against 0.68–0.75 ms at 9 360 (16 × 64).
//!
//! The w × w diagonal block is factorised by faer's recursive LU with partial pivoting, L₂₁
//! and U₁₂ are triangular solves and the update a matrix product, all faer's blocked kernels.
//! (Eliminating the whole (w + r) × w panel column by column, as before issue 26, was half of
//! the frozen sweep's run time: 16 × 64, the factorisation 1.66 → 1.35 s of dev-profile time
//! for 103 factorisations. Eliminating the diagonal block column by column cost 11 % of the
//! factorisation at 37 152 dofs: `fem_assembly 32 128 30 muscle`, 26.3 → 23.6 ms.)
//!
//! Pivoting is confined to the diagonal blocks (rows never leave their supernode), so a small
//! pivot remains possible: a zero one is reported as an error and the caller falls back to
//! faer's LU with full partial pivoting. The factor is only ever used as a GMRES
//! preconditioner, so a poor pivot costs iterations, not accuracy.

mod solve;
mod split;
mod substitution;
mod worker;

use super::assembly::Pattern;
use super::finite::first_non_finite;
use super::gmres::Preconditioner;
use faer::sparse::linalg::cholesky::{SymbolicCholesky, SymbolicCholeskyRaw};
use solve::Schedule;
use split::Split;
use substitution::Factor;
use worker::{Deferred, Worker, Workspace};

/// Where an entry of K goes: the L panel (diagonal block included) or the U₁₂ panel (offsets
/// into the factor's `l` and `u`).
#[derive(Debug, Clone, Copy)]
enum Slot {
    L(u32),
    U(u32),
}

/// The supernodal structure, fixed by the symbolic analysis and shared by the workers.
#[derive(Debug)]
struct Structure {
    /// perm[k] = original index of the k-th eliminated dof.
    perm: Vec<u32>,
    begin: Vec<usize>,
    end: Vec<usize>,
    /// Off-diagonal row pattern of each supernode (sorted, permuted indices).
    rows: Vec<Vec<u32>>,
    /// Offsets of the L panels ((w + r) × w, column-major) and U₁₂ panels (w × r, column-major).
    l_ptr: Vec<usize>,
    u_ptr: Vec<usize>,
    supernode_of: Vec<u32>,
    /// The entries of K that go to each supernode's panels, `(index into the values, offset in
    /// the panel)`, supernode by supernode (`entry_ptr`), those of its L panel first and those
    /// of its U₁₂ panel from `u_entries[t]` on (two loops without a branch per entry).
    entries: Vec<(u32, u32)>,
    entry_ptr: Vec<usize>,
    u_entries: Vec<usize>,
}

/// Estimated speed-up (in flops) below which one core factorises alone.
const MIN_SPEEDUP: f64 = 1.2;
/// Flops of a factorisation below which one core factorises alone (a join costs ≈ 10 µs).
const MIN_PARALLEL_FLOPS: f64 = 1e6;

/// Numeric LU on the symmetric pattern, for one symbolic Cholesky analysis.
#[derive(Debug)]
pub struct PatternLu {
    st: Structure,
    l: Vec<f64>,
    u: Vec<f64>,
    /// Row swaps inside the diagonal blocks: at step k rows k and pivots[k] were exchanged.
    pivots: Vec<u32>,
    /// The two groups of subtrees eliminated at the same time (None: one core).
    split: Option<Split>,
    workspaces: [Workspace; 2],
    deferred: Deferred,
    /// The steps of a solve, on one core and on two.
    schedule: Schedule,
    /// The permuted vector of a solve, and the second core's copy.
    work: [Vec<f64>; 2],
    /// The entries of a supernode's off-diagonal rows, gathered for the solves (one per core).
    gathered: [Vec<f64>; 2],
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
        let mut st = Structure {
            perm,
            begin,
            end,
            rows,
            l_ptr,
            u_ptr,
            supernode_of,
            entries: Vec::new(),
            entry_ptr: vec![0; ns + 1],
            u_entries: vec![0; ns],
        };
        st.place_entries(pattern, &perm_inv)?;
        let split = st.split();
        let widest = (0..ns).map(|s| st.end[s] - st.begin[s]).max().unwrap_or(0);
        let schedule = Schedule::new(&st, split.as_ref());
        Ok(Self {
            l: vec![0.0; st.l_ptr[ns]],
            u: vec![0.0; st.u_ptr[ns]],
            pivots: (0..n as u32).collect(),
            split,
            workspaces: [Workspace::new(n, ns, widest), Workspace::new(n, ns, widest)],
            deferred: Deferred::default(),
            schedule,
            work: [vec![0.0; n], vec![0.0; n]],
            gathered: [Vec::new(), Vec::new()],
            factorised: false,
            st,
        })
    }

    /// Numeric factorisation of the matrix with this pattern and `values`: with a split and two
    /// threads in rayon's pool, its two groups of subtrees at the same time, then the rest.
    pub fn factorise(&mut self, values: &[f64]) -> Result<(), String> {
        self.factorised = false;
        let st = &self.st;
        let ns = st.begin.len();
        let mut dof_ptr = st.begin.clone();
        dof_ptr.push(st.end.last().copied().unwrap_or(0));
        let mut l = panels(&mut self.l, &st.l_ptr);
        let mut u = panels(&mut self.u, &st.u_ptr);
        let mut pivots = panels(&mut self.pivots, &dof_ptr);
        let [first, second] = &mut self.workspaces;
        first.reset();
        second.reset();
        self.deferred.clear();
        let split = self
            .split
            .as_ref()
            .filter(|_| rayon::current_num_threads() >= 2);
        let Some(split) = split else {
            let mut worker = Worker {
                st,
                values,
                l,
                u,
                pivots,
                ws: first,
                deferred: None,
            };
            let all: Vec<usize> = (0..ns).collect();
            worker::run(&mut worker, None, &all)?;
            self.factorised = true;
            return Ok(());
        };
        // The second group's panels go to its worker; the first's and the rest's stay.
        let group = &split.groups[1];
        let (l2, u2) = (take(&mut l, group), take(&mut u, group));
        let pivots2 = take(&mut pivots, group);
        let mut a = Worker {
            st,
            values,
            l,
            u,
            pivots,
            ws: first,
            deferred: None,
        };
        let mut b = Worker {
            st,
            values,
            l: l2,
            u: u2,
            pivots: pivots2,
            ws: second,
            deferred: Some(&mut self.deferred),
        };
        let (ra, rb) = rayon::join(
            || worker::run(&mut a, None, &split.groups[0]),
            || worker::run(&mut b, None, &split.groups[1]),
        );
        ra?;
        rb?;
        drop(b);
        worker::run(&mut a, Some(&self.deferred), &split.rest)?;
        self.factorised = true;
        Ok(())
    }

    /// x ← K⁻¹ x with the factorisation (fails if there is none): with a split and two threads
    /// in rayon's pool, the two groups of subtrees at the same time ([`solve`]).
    pub fn solve_in_place(&mut self, x: &mut [f64]) -> Result<(), String> {
        if !self.factorised {
            return Err("no factorisation".into());
        }
        let factor = Factor {
            st: &self.st,
            l: &self.l,
            u: &self.u,
            pivots: &self.pivots,
        };
        let [y, copy] = &mut self.work;
        for (k, &i) in self.st.perm.iter().enumerate() {
            y[k] = x[i as usize];
        }
        let two_cores = rayon::current_num_threads() >= 2;
        self.schedule
            .run(&factor, y, copy, &mut self.gathered, two_cores);
        for (k, &i) in self.st.perm.iter().enumerate() {
            x[i as usize] = y[k];
        }
        match first_non_finite(x) {
            Some(i) => Err(format!("solution entry {i} is {}", x[i])),
            None => Ok(()),
        }
    }
}

impl Structure {
    /// Fills `entries`, `entry_ptr` and `u_entries`: where each entry of K (`pattern`, in the
    /// original order; `perm_inv[i]` its permuted index) goes in the panels.
    fn place_entries(&mut self, pattern: &Pattern, perm_inv: &[u32]) -> Result<(), String> {
        let (n, ns) = (pattern.n, self.begin.len());
        let mut entries = Vec::with_capacity(pattern.row_idx.len());
        for j in 0..n {
            let range = pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize;
            for (&i, k) in pattern.row_idx[range.clone()].iter().zip(range) {
                let (pi, pj) = (perm_inv[i as usize] as usize, perm_inv[j] as usize);
                let (t, slot) = self
                    .slot(pi, pj)
                    .ok_or_else(|| format!("entry ({i}, {j}) outside the symbolic pattern"))?;
                entries.push((t, k as u32, slot));
            }
        }
        // Placed by (supernode, L before U) in one counting pass: `entries` is in ascending k
        // already (column by column), and each bucket keeps that order.
        let mut l_entries = vec![0usize; ns];
        for &(t, _, slot) in &entries {
            self.entry_ptr[t as usize + 1] += 1;
            if let Slot::L(_) = slot {
                l_entries[t as usize] += 1;
            }
        }
        for (s, l_count) in l_entries.into_iter().enumerate() {
            self.entry_ptr[s + 1] += self.entry_ptr[s];
            self.u_entries[s] = self.entry_ptr[s] + l_count;
        }
        let mut next: Vec<[usize; 2]> = (0..ns)
            .map(|s| [self.entry_ptr[s], self.u_entries[s]])
            .collect();
        self.entries = vec![(0, 0); entries.len()];
        for (t, k, slot) in entries {
            let t = t as usize;
            let (at, offset) = match slot {
                Slot::L(p) => (&mut next[t][0], p as usize - self.l_ptr[t]),
                Slot::U(p) => (&mut next[t][1], p as usize - self.u_ptr[t]),
            };
            self.entries[*at] = (k, offset as u32);
            *at += 1;
        }
        Ok(())
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

    /// The flops of every supernode's elimination (w columns, r off-diagonal rows): the
    /// diagonal block's LU 2w³/3, the triangular solves for L₂₁ and U₁₂ 2w²r, the update 2r²w.
    fn flops(&self) -> Vec<f64> {
        (0..self.begin.len())
            .map(|s| {
                let (w, r) = (
                    (self.end[s] - self.begin[s]) as f64,
                    self.rows[s].len() as f64,
                );
                2.0 * w * w * w / 3.0 + 2.0 * w * w * r + 2.0 * r * r * w
            })
            .collect()
    }

    /// The split of the elimination tree for two cores, if it pays ([`MIN_SPEEDUP`],
    /// [`MIN_PARALLEL_FLOPS`]). A supernode's parent owns the column of its first
    /// off-diagonal row; its flops are [`Self::flops`].
    fn split(&self) -> Option<Split> {
        let ns = self.begin.len();
        let parent: Vec<Option<usize>> = (0..ns)
            .map(|s| {
                self.rows[s]
                    .first()
                    .map(|&i| self.supernode_of[i as usize] as usize)
            })
            .collect();
        let flops = self.flops();
        if flops.iter().sum::<f64>() < MIN_PARALLEL_FLOPS {
            return None;
        }
        Split::choose(&parent, &flops).filter(|s| s.speedup >= MIN_SPEEDUP)
    }
}

/// The pieces of `group` moved out of `pieces` into a list of the same length.
fn take<'a, T>(pieces: &mut [Option<&'a mut [T]>], group: &[usize]) -> Vec<Option<&'a mut [T]>> {
    let mut out: Vec<Option<&'a mut [T]>> = (0..pieces.len()).map(|_| None).collect();
    for &s in group {
        out[s] = pieces[s].take();
    }
    out
}

/// `data` cut at the offsets `ptr` (ascending, from 0) into one mutable slice per piece.
fn panels<'a, T>(data: &'a mut [T], ptr: &[usize]) -> Vec<Option<&'a mut [T]>> {
    let mut out = Vec::with_capacity(ptr.len().saturating_sub(1));
    let mut rest = data;
    for w in ptr.windows(2) {
        let (piece, tail) = std::mem::take(&mut rest).split_at_mut(w[1] - w[0]);
        out.push(Some(piece));
        rest = tail;
    }
    out
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

    /// Entry (i, j) of the test matrices: `diagonal` on the diagonal, non-symmetric off it
    /// (a_ij ≠ a_ji).
    fn entry(i: usize, j: usize, diagonal: f64) -> f64 {
        if i == j {
            diagonal
        } else {
            -1.0 - 0.7 * ((i * 7 + j * 3) % 5) as f64 / 5.0
        }
    }

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
                values.push(entry(i, j, diagonal));
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

    /// A zero column stays zero through the elimination, so its pivot is exactly zero: the
    /// factorisation reports it (the caller then falls back to faer's LU) instead of returning
    /// a factor with infinities.
    #[test]
    fn a_zero_pivot_is_an_error() {
        let (pattern, mut values, symbolic) = analysed(30, 20.0);
        let j = pattern.n / 2;
        let column = pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize;
        values[column].fill(0.0);
        let identity: Vec<u32> = (0..pattern.n as u32).collect();
        let mut lu = PatternLu::new(&pattern, &symbolic, &identity).unwrap();
        let error = lu.factorise(&values).unwrap_err();
        assert!(error.contains("pivot 0e0"), "{error}");
        assert!(lu.solve_in_place(&mut vec![1.0; pattern.n]).is_err());
    }

    /// The grid's matrix and its supernodal symbolic analysis (AMD ordering).
    fn analysed(m: usize, diagonal: f64) -> (Pattern, Vec<f64>, SymbolicCholesky<u32>) {
        let (pattern, values) = grid(m, diagonal);
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
        (pattern, values, symbolic)
    }

    /// max |x − x_true| after solving A x = A x_true with the factorisation.
    fn solve_error(lu: &mut PatternLu, pattern: &Pattern, values: &[f64]) -> f64 {
        let n = pattern.n;
        let x_true: Vec<f64> = (0..n).map(|i| ((i * 13) % 17) as f64 - 8.0).collect();
        // b = A x.
        let mut b = vec![0.0; n];
        for (j, xj) in x_true.iter().enumerate() {
            for k in pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize {
                b[pattern.row_idx[k] as usize] += values[k] * xj;
            }
        }
        lu.solve_in_place(&mut b).unwrap();
        b.iter()
            .zip(&x_true)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    }

    fn check(diagonal: f64, tolerance: f64) {
        let (pattern, values, symbolic) = analysed(30, diagonal);
        let identity: Vec<u32> = (0..pattern.n as u32).collect();
        let mut lu = PatternLu::new(&pattern, &symbolic, &identity).unwrap();
        lu.factorise(&values).unwrap();
        let err = solve_error(&mut lu, &pattern, &values);
        assert!(err < tolerance, "max error {err:e}");
        assert!(
            lu.pivots.iter().enumerate().any(|(k, &p)| p as usize != k) == (diagonal < 1.0),
            "row exchanges happen exactly when the diagonal is small"
        );
    }

    /// The pattern LU of the clamped cylinder's tangent (R = 1, L = 4, nr × nz Q2/Q1 cells)
    /// in the order of the node order `node_order` (None: the solver's), with the tangent's
    /// pattern.
    fn cylinder_lu(
        nr: usize,
        nz: usize,
        node_order: Option<fn(&Pattern) -> Vec<u32>>,
    ) -> (PatternLu, Pattern) {
        use crate::fem::assembly::Assembler;
        use crate::fem::dofs::{Bases, DofMap};
        use crate::fem::ldlt::SymmetricPartLdlt;
        use crate::fem::mesh::Mesh;
        use crate::fem::ordering::{dofs_in_node_order, node_structure};
        let mesh = Mesh::structured(1.0, 4.0, nr, nz, 1.0).unwrap();
        let dofs = DofMap::new(&mesh, Bases::Clamped);
        let asm = Assembler::new(&mesh, &dofs).unwrap();
        let pattern = &asm.pattern;
        let (groups, adjacency, trailing) = node_structure(&mesh, &dofs, asm.system_index());
        let lu = match node_order {
            None => {
                let ldlt = SymmetricPartLdlt::new(pattern, &groups, &adjacency, &trailing).unwrap();
                PatternLu::new(pattern, ldlt.symbolic(), ldlt.perm()).unwrap()
            }
            Some(order) => {
                let perm = dofs_in_node_order(&order(&adjacency), &groups, &trailing);
                let n = pattern.n;
                let mut perm_inv = vec![0u32; n];
                for (k, &i) in perm.iter().enumerate() {
                    perm_inv[i as usize] = k as u32;
                }
                let symbolic = factorize_symbolic_cholesky(
                    SymbolicSparseColMatRef::new_checked(
                        n,
                        n,
                        &pattern.col_ptr,
                        None,
                        &pattern.row_idx,
                    ),
                    Side::Lower,
                    SymmetricOrdering::Custom(faer::perm::PermRef::new_checked(
                        &perm, &perm_inv, n,
                    )),
                    CholeskySymbolicParams {
                        supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                        ..Default::default()
                    },
                )
                .unwrap();
                let identity: Vec<u32> = (0..n as u32).collect();
                PatternLu::new(pattern, &symbolic, &identity).unwrap()
            }
        };
        (lu, pattern.clone())
    }

    /// Approximate minimum degree on the node graph (the order before the dissection).
    fn minimum_degree(graph: &Pattern) -> Vec<u32> {
        use faer::dyn_stack::{MemBuffer, MemStack};
        use faer::sparse::linalg::amd;
        let n = graph.n;
        let (mut perm, mut perm_inv) = (vec![0u32; n], vec![0u32; n]);
        let mut mem = MemBuffer::new(amd::order_scratch::<u32>(n, graph.row_idx.len()));
        amd::order(
            &mut perm,
            &mut perm_inv,
            SymbolicSparseColMatRef::new_checked(n, n, &graph.col_ptr, None, &graph.row_idx),
            amd::Control::default(),
            MemStack::new(&mut mem),
        )
        .unwrap();
        perm
    }

    /// On the 16 × 64 cylinder the solver's order (a dissection of the node graph) costs the
    /// flops of minimum degree's (measured +0.7 %) and splits for two cores with an estimated
    /// speed-up of 1.93 against 1.50: the two cores' subtrees hold 97 % of the flops.
    #[test]
    fn the_dissection_order_splits_the_cylinder_for_two_cores_at_minimum_degree_flops() {
        let (dissection, _) = cylinder_lu(16, 64, None);
        let (amd, _) = cylinder_lu(16, 64, Some(minimum_degree));
        let total = |lu: &PatternLu| lu.st.flops().iter().sum::<f64>();
        let (flops, amd_flops) = (total(&dissection), total(&amd));
        let speedup = |lu: &PatternLu| lu.split.as_ref().map_or(1.0, |s| s.speedup);
        let (s, s_amd) = (speedup(&dissection), speedup(&amd));
        println!("flops {flops:.4e} ({amd_flops:.4e} AMD), speed-up {s:.3} ({s_amd:.3} AMD)");
        assert!(flops < 1.03 * amd_flops);
        assert!(s > 1.85 && s_amd < 1.6);
        assert!(flops / s < 0.85 * amd_flops / s_amd);
    }

    /// On a 60 × 60 grid the tree splits for two cores: the two groups of subtrees eliminated
    /// at the same time (their updates of the ancestors kept and applied after) give the factor
    /// of one core to round-off, entry by entry, and the same row exchanges. A lost or doubled
    /// update would change entries by O(1).
    #[test]
    fn two_groups_of_subtrees_at_the_same_time_give_the_one_core_factor() {
        let (pattern, values, symbolic) = analysed(60, 1e-3);
        let identity: Vec<u32> = (0..pattern.n as u32).collect();
        let mut two = PatternLu::new(&pattern, &symbolic, &identity).unwrap();
        let split = two.split.clone().expect("the 60 × 60 grid splits");
        assert!(!split.groups[0].is_empty() && !split.groups[1].is_empty());
        let mut one = PatternLu::new(&pattern, &symbolic, &identity).unwrap();
        one.split = None;
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .unwrap();
        pool.install(|| two.factorise(&values)).unwrap();
        one.factorise(&values).unwrap();
        assert!(
            !two.deferred.updates.is_empty(),
            "updates crossed the groups"
        );
        assert_eq!(two.pivots, one.pivots);
        for (a, b) in [(&two.l, &one.l), (&two.u, &one.u)] {
            let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let diff = a
                .iter()
                .zip(b)
                .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()));
            assert!(
                diff <= 1e-12 * scale,
                "factor differs by {diff:e} (scale {scale:e})"
            );
        }
        // The same accuracy as one core's (the small diagonal makes both ≈ 1e-8).
        let (e_two, e_one) = (
            solve_error(&mut two, &pattern, &values),
            solve_error(&mut one, &pattern, &values),
        );
        assert!(
            e_two <= 1.01 * e_one + 1e-14,
            "error {e_two:e} against {e_one:e}"
        );
    }

    /// b = A x for A on `pattern` with `values`.
    fn product(pattern: &Pattern, values: &[f64], x: &[f64]) -> Vec<f64> {
        let mut b = vec![0.0; pattern.n];
        for (j, xj) in x.iter().enumerate() {
            for k in pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize {
                b[pattern.row_idx[k] as usize] += values[k] * xj;
            }
        }
        b
    }

    /// The solutions of A x = b on one core and on two (rayon pools of one and two threads; the
    /// second also with one of its threads busy), and the normwise backward error
    /// ‖b − A x‖∞ / (‖A‖∞ ‖x‖∞ + ‖b‖∞) of the two cores'.
    fn one_and_two_core_solutions(
        lu: &mut PatternLu,
        pattern: &Pattern,
        values: &[f64],
    ) -> (Vec<f64>, [Vec<f64>; 2], f64) {
        let n = pattern.n;
        lu.factorise(values).unwrap();
        let b: Vec<f64> = (0..n).map(|i| ((i * 13) % 17) as f64 - 8.0).collect();
        let solve = |lu: &mut PatternLu, threads: usize| {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut x = b.clone();
            pool.install(|| lu.solve_in_place(&mut x)).unwrap();
            x
        };
        // Two threads, one of them busy until the solve ends: the other does every step.
        let busy = |lu: &mut PatternLu| {
            use std::sync::mpsc::channel;
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(2)
                .build()
                .unwrap();
            let (started, wait_started) = channel();
            let (end, wait_end) = channel::<()>();
            pool.spawn(move || {
                started.send(()).unwrap();
                let _ = wait_end.recv();
            });
            wait_started.recv().unwrap();
            let mut x = b.clone();
            pool.install(|| lu.solve_in_place(&mut x)).unwrap();
            end.send(()).unwrap();
            x
        };
        let (one, two, two_busy) = (solve(lu, 1), solve(lu, 2), busy(lu));
        let norm = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let mut row_sums = vec![0.0; n];
        for (k, &i) in pattern.row_idx.iter().enumerate() {
            row_sums[i as usize] += values[k].abs();
        }
        let residual: Vec<f64> = product(pattern, values, &two)
            .iter()
            .zip(&b)
            .map(|(ax, b)| b - ax)
            .collect();
        let error = norm(&residual) / (norm(&row_sums) * norm(&two) + norm(&b));
        (one, [two, two_busy], error)
    }

    /// The two cores' solve is the one core's bit for bit (also when one thread does all the
    /// steps, the other being busy) and solves A x = b to a backward error below `tolerance`
    /// (a lost or doubled update of the rest's rows would change x by O(1)).
    fn check_two_core_solve(lu: &mut PatternLu, pattern: &Pattern, values: &[f64], tolerance: f64) {
        let (one, two, error) = one_and_two_core_solutions(lu, pattern, values);
        for (x, case) in two.iter().zip(["two cores", "two threads, one busy"]) {
            let differ = one
                .iter()
                .zip(x)
                .filter(|(a, b)| a.to_bits() != b.to_bits());
            assert_eq!(
                differ.count(),
                0,
                "entries differ between one core and {case}"
            );
        }
        assert!(error < tolerance, "backward error {error:e}");
    }

    /// Rows steps (updates of the rest's rows applied after the join) of each group.
    fn rows_steps(lu: &PatternLu) -> [usize; 2] {
        let p = lu.schedule.parallel.as_ref().expect("a split");
        let split = lu.split.as_ref().unwrap();
        let in_group = |g: usize, s: usize| split.groups[g].binary_search(&s).is_ok();
        [0, 1].map(|g| {
            p.middle
                .iter()
                .filter(
                    |step| matches!(step, substitution::Step::Rows { s, .. } if in_group(g, *s)),
                )
                .count()
        })
    }

    /// The 60 × 60 grid under minimum degree: its groups' supernodes interleave, so both
    /// groups' updates of the rest's rows are applied after the join, in the one core's order.
    /// The small diagonal exchanges rows inside the diagonal blocks; the growth of the factor
    /// leaves a backward error of ≈ 1e-13 (one core's too).
    #[test]
    fn two_cores_solve_as_one_with_the_updates_of_the_rest_applied_after_the_join() {
        let (pattern, values, symbolic) = analysed(60, 1e-3);
        let identity: Vec<u32> = (0..pattern.n as u32).collect();
        let mut lu = PatternLu::new(&pattern, &symbolic, &identity).unwrap();
        let [a, b] = rows_steps(&lu);
        assert!(a > 0 && b > 0);
        check_two_core_solve(&mut lu, &pattern, &values, 1e-12);
    }

    /// The 16 × 64 cylinder under the dissection order (diagonally dominant values on the
    /// tangent's pattern): one half's supernodes all come first, so its updates of the
    /// separator's rows are applied in place, the other half's after the join.
    #[test]
    fn two_cores_solve_as_one_with_the_first_half_updating_the_separator_in_place() {
        let (mut lu, pattern) = cylinder_lu(16, 64, None);
        let values: Vec<f64> = (0..pattern.n)
            .flat_map(|j| {
                let range = pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize;
                let count = range.len() as f64;
                pattern.row_idx[range]
                    .iter()
                    .map(move |&i| entry(i as usize, j, 2.0 * count))
            })
            .collect();
        let steps = rows_steps(&lu);
        assert!(steps.iter().filter(|&&c| c == 0).count() == 1 && steps.iter().any(|&c| c > 0));
        check_two_core_solve(&mut lu, &pattern, &values, 1e-15);
    }
}
