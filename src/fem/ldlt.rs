//! LDLᵀ of the tangent's symmetric part S = (K + Kᵀ)/2: the preconditioner of GMRES on the
//! exact (possibly non-symmetric) tangent K ([`super::gmres`]).
//!
//! Why: faer's sparse LU bounds its fill by the Cholesky factor of KᵀK (static pivoting
//! structure), which for these meshes is several times denser than the factor of K itself.
//! LDLᵀ works on the pattern of K. The saddle point is factorised without pivoting thanks to the
//! ordering ([`super::ordering`]): a dissection of the node graph ([`super::dissection`]), and
//! within each node the displacement dofs before the pressure dof, so a pressure pivot is a
//! Schur complement rather than the zero diagonal. A zero pivot (or a non-finite factor) is reported and the
//! caller uses an LU instead. For a symmetric tangent S = K and GMRES converges in one
//! iteration; for a non-symmetric one in a few, or not at all when K is far from symmetric: the
//! caller then switches to an LU ([`super::tangent_solver`]), so the Newton direction is always
//! exact to round-off.

use super::assembly::Pattern;
use super::dofs::DofMap;
use super::finite::all_finite;
use super::gmres::Preconditioner;
use super::mesh::Mesh;
use super::ordering::{dof_ordering, node_structure, Trailing};
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LdltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// LDLᵀ of the symmetric part, used as a preconditioner.
///
/// The matrix is handed to faer already permuted (Q S Qᵀ, lower triangle, in the elimination
/// order Q of [`dof_ordering`]): one pass over the lower entries forms (K + Kᵀ)/2 in that
/// order, instead of a symmetrisation pass and faer's own permutation pass.
pub struct SymmetricPartLdlt {
    n: usize,
    symbolic: SymbolicCholesky<u32>,
    /// perm[k] = original index of the k-th eliminated dof.
    perm: Vec<u32>,
    /// Lower triangle of Q S Qᵀ: pattern and, per entry, the positions in K's values of the
    /// entry and its transpose.
    lower: Pattern,
    sources: Vec<[u32; 2]>,
    s_values: Vec<f64>,
    l_values: Vec<f64>,
    work: Vec<f64>,
    factor_scratch: MemBuffer,
    solve_scratch: MemBuffer,
    par: Par,
}

impl std::fmt::Debug for SymmetricPartLdlt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SymmetricPartLdlt")
            .field("n", &self.n)
            .finish()
    }
}

impl SymmetricPartLdlt {
    /// Symbolic analysis for the system matrix of `mesh` numbered by `dofs` and `index` (the
    /// system's index of every free dof, [`super::assembly::Assembler::system_index`]), in the
    /// node ordering of [`dof_ordering`].
    pub fn for_mesh(
        pattern: &Pattern,
        mesh: &Mesh,
        dofs: &DofMap,
        index: &[u32],
    ) -> Result<Self, String> {
        let (node_dofs, adjacency, trailing) = node_structure(mesh, dofs, index);
        Self::new(pattern, &node_dofs, &adjacency, &trailing)
    }

    /// Symbolic analysis. `node_dofs[a]` lists the free dofs of node a, displacement first,
    /// `node_adjacency` is the node graph (nodes sharing an element), `trailing` the dofs that
    /// follow groups of nodes (see [`Trailing`]; empty for Q2/Q1).
    pub fn new(
        pattern: &Pattern,
        node_dofs: &[Vec<u32>],
        node_adjacency: &Pattern,
        trailing: &[Trailing],
    ) -> Result<Self, String> {
        let n = pattern.n;
        let par = Par::Seq;
        let perm = dof_ordering(node_dofs, node_adjacency, trailing)?;
        if perm.len() != n {
            return Err(format!("node ordering covers {} of {n} dofs", perm.len()));
        }
        let mut perm_inv = vec![0u32; n];
        for (k, &i) in perm.iter().enumerate() {
            perm_inv[i as usize] = k as u32;
        }
        let (full, _) = permuted(pattern, &perm_inv, false)?;
        let symbolic = factorize_symbolic_cholesky(
            SymbolicSparseColMatRef::new_checked(n, n, &full.col_ptr, None, &full.row_idx),
            Side::Lower,
            SymmetricOrdering::Identity,
            // Supernodal always: as fast as or faster than simplicial at every size measured
            // (945–148k dofs), and its supernodes also serve the pattern LU.
            CholeskySymbolicParams {
                supernodal_flop_ratio_threshold: SupernodalThreshold::FORCE_SUPERNODAL,
                ..Default::default()
            },
        )
        .map_err(|e| format!("symbolic LDLT: {e:?}"))?;
        drop(full);
        let (lower, sources) = permuted(pattern, &perm_inv, true)?;
        let factor_scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_ldlt_scratch::<f64>(par, Default::default()),
        )
        .map_err(|_| "out of memory for LDLT scratch".to_string())?;
        let solve_scratch = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, par))
            .map_err(|_| "out of memory for LDLT scratch".to_string())?;
        Ok(Self {
            n,
            l_values: vec![0.0; symbolic.len_val()],
            symbolic,
            perm,
            s_values: vec![0.0; lower.row_idx.len()],
            lower,
            sources,
            work: vec![0.0; n],
            factor_scratch,
            solve_scratch,
            par,
        })
    }

    /// Factorises S = (K + Kᵀ)/2 (K with the pattern the analysis was made for).
    pub fn factorise(&mut self, values: &[f64]) -> Result<(), String> {
        let mut scale = 0.0f64;
        for (s, &[k, t]) in self.s_values.iter_mut().zip(&self.sources) {
            *s = 0.5 * (values[k as usize] + values[t as usize]);
            scale = scale.max(s.abs());
        }
        if !scale.is_finite() {
            return Err("non-finite tangent".into());
        }
        let n = self.n;
        let (col_ptr, row_idx) = (&self.lower.col_ptr, &self.lower.row_idx);
        let a = SparseColMatRef::new(
            SymbolicSparseColMatRef::new_checked(n, n, col_ptr, None, row_idx),
            &self.s_values,
        );
        // No sign regularisation: K_uu − p H is legitimately indefinite in incompressible
        // elasticity (positive only on the constraint kernel), so pivot signs are not known in
        // advance. A zero pivot is an error and the caller falls back to the LU.
        let reg = faer::linalg::cholesky::ldlt::factor::LdltRegularization::default();
        self.symbolic
            .factorize_numeric_ldlt(
                &mut self.l_values,
                a,
                Side::Lower,
                reg,
                self.par,
                MemStack::new(&mut self.factor_scratch),
                Default::default(),
            )
            .map_err(|e| format!("LDLT: {e:?}"))?;
        if !all_finite(&self.l_values) {
            return Err("non-finite LDLT factor (zero pivot)".into());
        }
        Ok(())
    }

    /// x ← S⁻¹ x.
    pub fn apply(&mut self, x: &mut [f64]) {
        for (w, &i) in self.work.iter_mut().zip(&self.perm) {
            *w = x[i as usize];
        }
        LdltRef::new(&self.symbolic, &self.l_values).solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut self.work, self.n, 1),
            self.par,
            MemStack::new(&mut self.solve_scratch),
        );
        for (w, &i) in self.work.iter().zip(&self.perm) {
            x[i as usize] = *w;
        }
    }

    /// The symbolic analysis of the permuted matrix (supernodes), shared with
    /// [`super::pattern_lu`].
    pub fn symbolic(&self) -> &SymbolicCholesky<u32> {
        &self.symbolic
    }

    /// The elimination order: `perm()[k]` is the original index of the k-th eliminated dof.
    pub fn perm(&self) -> &[u32] {
        &self.perm
    }
}

/// The pattern of Q K Qᵀ (`perm_inv` maps an original index to its place), whole or (`lower`)
/// its lower triangle, rows sorted; with, per entry, the positions in K's values of the
/// original entry and of its transpose (K must be structurally symmetric).
fn permuted(
    pattern: &Pattern,
    perm_inv: &[u32],
    lower: bool,
) -> Result<(Pattern, Vec<[u32; 2]>), String> {
    let n = pattern.n;
    let transpose_of = transpose_positions(pattern)?;
    let kept = |row: u32, col: u32| !lower || row >= col;
    // Counted by permuted column, placed, then each (short) column sorted by row.
    let mut col_ptr = vec![0u32; n + 1];
    for j in 0..n {
        for &i in &pattern.row_idx[pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize] {
            let (pi, pj) = (perm_inv[i as usize], perm_inv[j]);
            if kept(pi, pj) {
                col_ptr[pj as usize + 1] += 1;
            }
        }
    }
    for j in 0..n {
        col_ptr[j + 1] += col_ptr[j];
    }
    let mut next: Vec<u32> = col_ptr[..n].to_vec();
    let mut entries = vec![(0u32, [0u32; 2]); col_ptr[n] as usize];
    for j in 0..n {
        for k in pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize {
            let (pi, pj) = (perm_inv[pattern.row_idx[k] as usize], perm_inv[j]);
            if kept(pi, pj) {
                entries[next[pj as usize] as usize] = (pi, [k as u32, transpose_of[k]]);
                next[pj as usize] += 1;
            }
        }
    }
    for j in 0..n {
        entries[col_ptr[j] as usize..col_ptr[j + 1] as usize].sort_unstable_by_key(|e| e.0);
    }
    let row_idx = entries.iter().map(|e| e.0).collect();
    let sources = entries.iter().map(|e| e.1).collect();
    Ok((
        Pattern {
            n,
            col_ptr,
            row_idx,
        },
        sources,
    ))
}

/// Position of the transposed entry of every nonzero (the pattern must be structurally
/// symmetric).
fn transpose_positions(pattern: &Pattern) -> Result<Vec<u32>, String> {
    // Visiting the columns j in order, entry (i, j) is the next unvisited row of column i when
    // the pattern is symmetric (column i's rows ascend): one pass, each match checked.
    let mut next: Vec<u32> = pattern.col_ptr[..pattern.n].to_vec();
    let mut transpose_of = vec![0u32; pattern.row_idx.len()];
    let asymmetric = || "tangent pattern is not structurally symmetric".to_string();
    for j in 0..pattern.n {
        let range = pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize;
        for (k, &i) in range.clone().zip(&pattern.row_idx[range]) {
            let at = next[i as usize];
            if at >= pattern.col_ptr[i as usize + 1] || pattern.row_idx[at as usize] != j as u32 {
                return Err(asymmetric());
            }
            transpose_of[k] = at;
            next[i as usize] += 1;
        }
    }
    // Every entry of every column matched.
    if (0..pattern.n).any(|i| next[i] != pattern.col_ptr[i + 1]) {
        return Err(asymmetric());
    }
    Ok(transpose_of)
}

impl Preconditioner for SymmetricPartLdlt {
    fn apply(&mut self, x: &mut [f64]) {
        SymmetricPartLdlt::apply(self, x);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pattern from its columns' rows.
    fn pattern(columns: &[&[u32]]) -> Pattern {
        let mut col_ptr = vec![0u32];
        let mut row_idx = Vec::new();
        for c in columns {
            row_idx.extend_from_slice(c);
            col_ptr.push(row_idx.len() as u32);
        }
        Pattern {
            n: columns.len(),
            col_ptr,
            row_idx,
        }
    }

    #[test]
    fn transposed_positions_swap_row_and_column_and_an_asymmetric_pattern_is_refused() {
        let p = pattern(&[&[0, 2, 3], &[1, 3], &[0, 2], &[0, 1, 3]]);
        let t = transpose_positions(&p).unwrap();
        let column_of = |k: usize| (0..p.n).find(|&j| (p.col_ptr[j + 1] as usize) > k).unwrap();
        for (k, &tk) in t.iter().enumerate() {
            let tk = tk as usize;
            assert_eq!(p.row_idx[tk] as usize, column_of(k));
            assert_eq!(column_of(tk), p.row_idx[k] as usize);
            assert_eq!(t[tk] as usize, k);
        }
        // (2, 1) without (1, 2), and (1, 3) missing its partner in the last column.
        assert!(transpose_positions(&pattern(&[&[0], &[1, 2], &[2]])).is_err());
        assert!(transpose_positions(&pattern(&[&[0], &[1, 3], &[2], &[3]])).is_err());
    }

    #[test]
    fn the_permuted_lower_triangle_holds_each_entry_once_with_its_sources() {
        let p = pattern(&[&[0, 2, 3], &[1, 3], &[0, 2], &[0, 1, 3]]);
        // perm = [3, 0, 2, 1]: original i goes to perm_inv[i].
        let perm_inv = [1, 3, 2, 0];
        let (lower, sources) = permuted(&p, &perm_inv, true).unwrap();
        let mut seen = 0;
        for j in 0..lower.n {
            let rows = &lower.row_idx[lower.col_ptr[j] as usize..lower.col_ptr[j + 1] as usize];
            assert!(rows.windows(2).all(|w| w[0] < w[1]), "column {j}: {rows:?}");
            for (k, &i) in (lower.col_ptr[j] as usize..).zip(rows) {
                assert!(i as usize >= j);
                let [a, b] = sources[k];
                // The source entry sits at (i, j) in the permuted order, its transpose at (j, i).
                let (ra, rb) = (p.row_idx[a as usize], p.row_idx[b as usize]);
                assert!(perm_inv[ra as usize] == i || perm_inv[ra as usize] == j as u32);
                assert_eq!(perm_inv[ra as usize] + perm_inv[rb as usize], i + j as u32);
                seen += 1;
            }
        }
        // The lower triangle (diagonal included) of the 10-entry symmetric pattern.
        assert_eq!(seen, 4 + 3);
    }
}
