//! Fast linear solver for the tangent: GMRES on the exact (possibly non-symmetric) tangent K,
//! right-preconditioned by a sparse LDLᵀ factorisation of its symmetric part S = (K + Kᵀ)/2.
//!
//! Why: faer's sparse LU bounds its fill by the Cholesky factor of KᵀK (static pivoting
//! structure), which for these meshes is several times denser than the factor of K itself.
//! LDLᵀ works on the pattern of K. The saddle point is factorised without pivoting thanks to the
//! ordering: approximate minimum degree on the node graph, and within each node the displacement
//! dofs before the pressure dof, so a pressure pivot is a Schur complement rather than the zero
//! diagonal. A zero pivot (or a non-finite factor) is reported and the caller uses an LU
//! instead. For a symmetric tangent S = K and GMRES converges in one iteration; for a
//! non-symmetric one in a few, or not at all when K is far from symmetric: the caller then
//! switches to an LU ([`super::tangent_solver`]), so the Newton direction is always exact to
//! round-off.

use super::assembly::Pattern;
use super::dofs::DofMap;
use super::mesh::Mesh;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::amd;
use faer::sparse::linalg::cholesky::{
    factorize_symbolic_cholesky, CholeskySymbolicParams, LdltRef, SymbolicCholesky,
    SymmetricOrdering,
};
use faer::sparse::linalg::SupernodalThreshold;
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par, Side};

/// Dofs without a node of their own (the pressure of a Q1/P0 cell): eliminated right after the
/// last, in the node ordering, of the node groups `after` (the cell's nodes), so that their
/// pivot is a Schur complement rather than the zero diagonal. At the end if `after` is empty.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Trailing {
    /// Node groups (indices into `node_dofs`) that must come first.
    pub after: Vec<u32>,
    /// The dofs.
    pub dofs: Vec<u32>,
}

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
        if self.l_values.iter().any(|v| !v.is_finite()) {
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
    let mut entries: Vec<(u32, u32, [u32; 2])> = Vec::with_capacity(pattern.row_idx.len());
    for j in 0..n {
        for k in pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize {
            let (pi, pj) = (perm_inv[pattern.row_idx[k] as usize], perm_inv[j]);
            if !lower || pi >= pj {
                entries.push((pj, pi, [k as u32, transpose_of[k]]));
            }
        }
    }
    entries.sort_unstable_by_key(|&(col, row, _)| (col, row));
    let mut col_ptr = vec![0u32; n + 1];
    for &(col, _, _) in &entries {
        col_ptr[col as usize + 1] += 1;
    }
    for j in 0..n {
        col_ptr[j + 1] += col_ptr[j];
    }
    let row_idx = entries.iter().map(|e| e.1).collect();
    let sources = entries.iter().map(|e| e.2).collect();
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
    let mut transpose_of = vec![0u32; pattern.row_idx.len()];
    for j in 0..pattern.n {
        let range = pattern.col_ptr[j] as usize..pattern.col_ptr[j + 1] as usize;
        for (k, &i) in range.clone().zip(&pattern.row_idx[range]) {
            let i = i as usize;
            let col =
                &pattern.row_idx[pattern.col_ptr[i] as usize..pattern.col_ptr[i + 1] as usize];
            let pos = col
                .binary_search(&(j as u32))
                .map_err(|_| "tangent pattern is not structurally symmetric".to_string())?;
            transpose_of[k] = pattern.col_ptr[i] + pos as u32;
        }
    }
    Ok(transpose_of)
}

/// The elimination order of the dofs: approximate minimum degree on the node graph
/// `node_adjacency`, each node's dofs `node_dofs[a]` in their order (displacement, then
/// pressure), and every [`Trailing`] group right after the last of its node groups.
pub fn dof_ordering(
    node_dofs: &[Vec<u32>],
    node_adjacency: &Pattern,
    trailing: &[Trailing],
) -> Result<Vec<u32>, String> {
    let nn = node_adjacency.n;
    let mut node_perm = vec![0u32; nn];
    let mut node_perm_inv = vec![0u32; nn];
    let a = SymbolicSparseColMatRef::new_checked(
        nn,
        nn,
        &node_adjacency.col_ptr,
        None,
        &node_adjacency.row_idx,
    );
    let mut mem = MemBuffer::try_new(amd::order_scratch::<u32>(nn, node_adjacency.row_idx.len()))
        .map_err(|_| "out of memory for AMD".to_string())?;
    amd::order(
        &mut node_perm,
        &mut node_perm_inv,
        a,
        amd::Control::default(),
        MemStack::new(&mut mem),
    )
    .map_err(|e| format!("AMD: {e:?}"))?;
    // Trailing dofs go right after the last of their node groups in that order.
    let mut after_position: Vec<Vec<usize>> = vec![Vec::new(); nn + 1];
    for (t, tr) in trailing.iter().enumerate() {
        let last = tr
            .after
            .iter()
            .map(|&a| node_perm_inv[a as usize] as usize)
            .max()
            .unwrap_or(nn);
        after_position[last].push(t);
    }
    let mut perm = Vec::new();
    for (k, &a) in node_perm.iter().enumerate() {
        perm.extend_from_slice(&node_dofs[a as usize]);
        for &t in &after_position[k] {
            perm.extend_from_slice(&trailing[t].dofs);
        }
    }
    for &t in &after_position[nn] {
        perm.extend_from_slice(&trailing[t].dofs);
    }
    Ok(perm)
}

/// Dof groups for the LDLᵀ ordering and their adjacency graph. One group per node with free
/// displacement dofs: those dofs, then the node's pressure dof (Q2/Q1). A pressure dof whose node
/// has no free displacement (e.g. on a clamped base) would be a zero pivot if eliminated first,
/// so it joins the group of a neighbouring node (sharing an element) and is eliminated after that
/// node's displacement dofs, which couple to it. A Q1/P0 cell pressure is eliminated right after
/// the last of its cell's node groups (the third return value). Dofs are given in the system's
/// numbering `index` (free dof → system index, `u32::MAX` if condensed out); a node without
/// system dofs (a condensed centre node) has no group.
pub fn node_structure(
    mesh: &Mesh,
    dofs: &DofMap,
    index: &[u32],
) -> (Vec<Vec<u32>>, Pattern, Vec<Trailing>) {
    let (group_of, groups) = node_groups(mesh, dofs, index);
    let nf = dofs.n_free as u32;
    let trailing = dofs
        .element_p
        .iter()
        .zip(mesh.elements())
        .filter(|(&p, _)| p < nf)
        .map(|(&p, e)| Trailing {
            after: e
                .iter()
                .map(|&a| group_of[a as usize])
                .filter(|&g| g != u32::MAX)
                .collect(),
            dofs: vec![index[p as usize]],
        })
        .collect();
    let adjacency = group_adjacency(mesh, &group_of, groups.len());
    (groups, adjacency, trailing)
}

/// The group of every node (`u32::MAX`: none) and the free dofs of every group (see
/// [`node_structure`]).
fn node_groups(mesh: &Mesh, dofs: &DofMap, index: &[u32]) -> (Vec<u32>, Vec<Vec<u32>>) {
    let nf = dofs.n_free as u32;
    let nn_all = mesh.n_nodes();
    let mut group_of = vec![u32::MAX; nn_all];
    let mut groups: Vec<Vec<u32>> = Vec::new();
    // A condensed centre node keeps its (empty) group: the minimum-degree ordering sees the
    // graph of the uncondensed mesh, which orders the remaining nodes better (at 148k dofs the
    // factor of the graph without the centre nodes was 22 % larger).
    let mut has_u = Vec::new();
    for (a, g) in group_of.iter_mut().enumerate() {
        let free: Vec<u32> = dofs.node_u[a].iter().copied().filter(|&g| g < nf).collect();
        if !free.is_empty() {
            let d: Vec<u32> = free
                .iter()
                .map(|&g| index[g as usize])
                .filter(|&s| s != u32::MAX)
                .collect();
            *g = groups.len() as u32;
            has_u.push(!d.is_empty());
            groups.push(d);
        }
    }
    // Node neighbours through elements.
    let mut neighbours: Vec<Vec<u32>> = vec![Vec::new(); nn_all];
    for e in mesh.elements() {
        for &a in e {
            neighbours[a as usize].extend(e.iter().copied().filter(|&b| b != a));
        }
    }
    let mut orphans = Vec::new();
    for a in 0..nn_all {
        let p = dofs.node_p[a];
        if p >= nf {
            continue;
        }
        let host = if group_of[a] != u32::MAX {
            Some(group_of[a])
        } else {
            neighbours[a]
                .iter()
                .map(|&b| group_of[b as usize])
                .find(|&g| g != u32::MAX && has_u[g as usize])
        };
        let p = index[p as usize];
        match host {
            Some(g) => groups[g as usize].push(p),
            None => orphans.push(p),
        }
    }
    if !orphans.is_empty() {
        // No displacement dof anywhere near (degenerate mesh): keep them, the LU will cope.
        groups.push(orphans);
    }
    (group_of, groups)
}

/// The graph of `ng` groups: two groups are adjacent when their nodes share an element.
fn group_adjacency(mesh: &Mesh, group_of: &[u32], ng: usize) -> Pattern {
    let mut cols: Vec<Vec<u32>> = vec![Vec::new(); ng];
    for e in mesh.elements() {
        for &a in e {
            let ga = group_of[a as usize];
            if ga == u32::MAX {
                continue;
            }
            for &b in e {
                let gb = group_of[b as usize];
                if gb != u32::MAX {
                    cols[ga as usize].push(gb);
                }
            }
        }
    }
    let mut col_ptr = vec![0u32];
    let mut row_idx = Vec::new();
    for (j, c) in cols.iter_mut().enumerate() {
        c.push(j as u32);
        c.sort_unstable();
        c.dedup();
        row_idx.extend_from_slice(c);
        col_ptr.push(row_idx.len() as u32);
    }
    Pattern {
        n: ng,
        col_ptr,
        row_idx,
    }
}

/// y = K x for K in compressed columns.
fn matvec(pattern: &Pattern, values: &[f64], x: &[f64], y: &mut [f64]) {
    y.fill(0.0);
    for (j, &xj) in x.iter().enumerate() {
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

impl Preconditioner for SymmetricPartLdlt {
    fn apply(&mut self, x: &mut [f64]) {
        SymmetricPartLdlt::apply(self, x);
    }
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
        matvec(pattern, values, &self.zs[k], &mut self.w);
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
    /// ≈ 1e-16 times a modest growth factor.) Returns the iterations used, or `None` if the
    /// tolerance was not met.
    pub fn solve(
        &mut self,
        pattern: &Pattern,
        values: &[f64],
        pre: &mut dyn Preconditioner,
        rhs: &mut [f64],
        tol: f64,
        max_iter: usize,
    ) -> Option<usize> {
        let bnorm = rhs.iter().map(|v| v * v).sum::<f64>().sqrt();
        if bnorm == 0.0 {
            return Some(0);
        }
        let knorm = values.iter().map(|v| v * v).sum::<f64>().sqrt();
        let norm = |v: &[f64]| v.iter().map(|v| v * v).sum::<f64>().sqrt();
        // First guess x₀ = M⁻¹ b, r₀ = b − K x₀: the solution itself when M is a factorisation
        // of K (a symmetric tangent), found with one product by K where a GMRES iteration
        // from x = 0 takes two (its Arnoldi vector and the true residual).
        self.x.copy_from_slice(rhs);
        pre.apply(&mut self.x);
        matvec(pattern, values, &self.x, &mut self.w);
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
                let target = 0.1 * tol * (knorm * x_estimate + bnorm);
                if self.g[k + 1].abs() <= target || total >= max_iter {
                    break;
                }
            }
            self.update_solution(k_used);
            // True residual.
            matvec(pattern, values, &self.x, &mut self.w);
            for ((ri, bi), wi) in self.r.iter_mut().zip(rhs.iter()).zip(&self.w) {
                *ri = bi - wi;
            }
        }
        let beta = norm(&self.r);
        if beta <= tol * (knorm * norm(&self.x) + bnorm) && self.x.iter().all(|v| v.is_finite()) {
            rhs.copy_from_slice(&self.x);
            Some(total)
        } else {
            None
        }
    }
}
