//! Parallel assembly of the residual and the tangent into a sparse matrix whose pattern is
//! built once.
//!
//! Each element writes its residual (22) and tangent (22 × 22) into its own slot of a buffer
//! (no sharing, so the element loop runs in parallel without locks); each global entry is then
//! gathered, again in parallel, from the list of element slots that contribute to it. Both
//! lists are built once with the pattern; the hot loop allocates nothing.

use super::dofs::DofMap;
use super::element::{
    element_residual_tangent, geometry, ElementMatrix, ElementVector, ReferenceElement, N_DOF, N_P,
    N_QP, N_U,
};
use super::error::{FemError, FemResult};
use super::material::AxisymmetricMaterial;
use super::mesh::Mesh;
use nalgebra::SVector;
use rayon::prelude::*;

const N_K: usize = N_DOF * N_DOF;

/// Compressed-column pattern of the free–free block of the tangent.
#[derive(Debug, Clone)]
pub struct Pattern {
    /// Dimension (number of free dofs).
    pub n: usize,
    /// Column pointers (length n + 1).
    pub col_ptr: Vec<u32>,
    /// Row indices, sorted within each column.
    pub row_idx: Vec<u32>,
}

/// Builds the residual and tangent of the whole mesh.
#[derive(Debug)]
pub struct Assembler {
    re: ReferenceElement,
    coords: Vec<[[f64; 2]; 9]>,
    element_dofs: Vec<[u32; N_DOF]>,
    n_free: usize,
    /// Sparsity pattern of the free–free tangent.
    pub pattern: Pattern,
    /// Tangent values (aligned with `pattern.row_idx`).
    pub values: Vec<f64>,
    /// Residual on every dof, prescribed ones included (there it is the reaction).
    pub residual: Vec<f64>,
    /// K_fc d_c: the tangent times the rate of the prescribed dofs (for the tangent predictor).
    pub rate_force: Vec<f64>,
    /// Largest stress magnitude of the last assembly \[kPa\].
    pub stress_scale: f64,
    val_ptr: Vec<u32>,
    val_src: Vec<u32>,
    res_ptr: Vec<u32>,
    res_src: Vec<u32>,
    kbuf: Vec<f64>,
    rbuf: Vec<f64>,
    gbuf: Vec<f64>,
    scale_buf: Vec<f64>,
    rates: Vec<f64>,
}

fn counting_lists(n: usize, targets: &[u32]) -> (Vec<u32>, Vec<u32>) {
    let mut ptr = vec![0u32; n + 1];
    for &t in targets {
        if t != u32::MAX {
            ptr[t as usize + 1] += 1;
        }
    }
    for i in 0..n {
        ptr[i + 1] += ptr[i];
    }
    let mut fill = ptr.clone();
    let mut src = vec![0u32; ptr[n] as usize];
    for (s, &t) in targets.iter().enumerate() {
        if t != u32::MAX {
            let slot = &mut fill[t as usize];
            src[*slot as usize] = s as u32;
            *slot += 1;
        }
    }
    (ptr, src)
}

impl Assembler {
    /// Validates the element geometry and builds the pattern and the gather lists.
    pub fn new(mesh: &Mesh, dofs: &DofMap) -> FemResult<Self> {
        let re = ReferenceElement::new();
        let n_el = mesh.elements.len();
        if n_el.checked_mul(N_K).is_none_or(|v| v >= u32::MAX as usize) {
            return Err(FemError::InvalidInput {
                name: "elements",
                value: n_el.to_string(),
                rule: "too many elements for 32-bit gather lists",
            });
        }
        let mut coords = Vec::with_capacity(n_el);
        for (e, conn) in mesh.elements.iter().enumerate() {
            let mut x = [[0.0; 2]; 9];
            for (a, &node) in conn.iter().enumerate() {
                x[a] = *mesh
                    .nodes
                    .get(node as usize)
                    .ok_or(FemError::InvalidInput {
                        name: "element connectivity",
                        value: format!("element {e} node {node}"),
                        rule: "node index out of range",
                    })?;
            }
            for q in 0..N_QP {
                if geometry(&re, q, &x).is_none() {
                    return Err(FemError::InvalidInput {
                        name: "element geometry",
                        value: format!("element {e}, nodes {x:?}"),
                        rule: "mapping must be invertible, counter-clockwise, with r > 0 at quadrature points",
                    });
                }
            }
            coords.push(x);
        }
        let n = dofs.n_free;
        let free = |g: u32| (g as usize) < n;
        // Column lists of the free–free pattern (no pressure–pressure block: K_pp = 0).
        let mut cols: Vec<Vec<u32>> = vec![Vec::new(); n];
        for d in &dofs.element_dofs {
            for j in 0..N_DOF {
                if !free(d[j]) {
                    continue;
                }
                for i in 0..N_DOF {
                    if free(d[i]) && !(i >= N_U && j >= N_U) {
                        cols[d[j] as usize].push(d[i]);
                    }
                }
            }
        }
        let mut col_ptr = Vec::with_capacity(n + 1);
        col_ptr.push(0u32);
        let mut row_idx = Vec::new();
        for c in cols.iter_mut() {
            c.sort_unstable();
            c.dedup();
            row_idx.extend_from_slice(c);
            if row_idx.len() >= u32::MAX as usize {
                return Err(FemError::InvalidInput {
                    name: "pattern",
                    value: row_idx.len().to_string(),
                    rule: "too many nonzeros for 32-bit indices",
                });
            }
            col_ptr.push(row_idx.len() as u32);
        }
        drop(cols);
        let nnz = row_idx.len();
        // Position of every element-matrix entry in `values` (u32::MAX: not in the system).
        let mut pos = vec![u32::MAX; n_el * N_K];
        pos.par_chunks_mut(N_K)
            .zip(dofs.element_dofs.par_iter())
            .for_each(|(p, d)| {
                for j in 0..N_DOF {
                    if !free(d[j]) {
                        continue;
                    }
                    let (lo, hi) = (
                        col_ptr[d[j] as usize] as usize,
                        col_ptr[d[j] as usize + 1] as usize,
                    );
                    let rows = &row_idx[lo..hi];
                    for i in 0..N_DOF {
                        if free(d[i]) && !(i >= N_U && j >= N_U) {
                            if let Ok(k) = rows.binary_search(&d[i]) {
                                p[i + N_DOF * j] = (lo + k) as u32;
                            }
                        }
                    }
                }
            });
        let (val_ptr, val_src) = counting_lists(nnz, &pos);
        drop(pos);
        let res_targets: Vec<u32> = dofs.element_dofs.iter().flatten().copied().collect();
        let (res_ptr, res_src) = counting_lists(dofs.n_total, &res_targets);
        let mut rates = vec![0.0; dofs.n_total];
        rates[dofs.n_free..].copy_from_slice(&dofs.prescribed_rate);
        Ok(Self {
            re,
            coords,
            element_dofs: dofs.element_dofs.clone(),
            n_free: n,
            pattern: Pattern {
                n,
                col_ptr,
                row_idx,
            },
            values: vec![0.0; nnz],
            residual: vec![0.0; dofs.n_total],
            rate_force: vec![0.0; dofs.n_total],
            stress_scale: 0.0,
            val_ptr,
            val_src,
            res_ptr,
            res_src,
            kbuf: vec![0.0; n_el * N_K],
            rbuf: vec![0.0; n_el * N_DOF],
            gbuf: vec![0.0; n_el * N_DOF],
            scale_buf: vec![0.0; n_el],
            rates,
        })
    }

    /// Nodal coordinates of each element.
    pub fn coords(&self) -> &[[[f64; 2]; 9]] {
        &self.coords
    }

    /// The tabulated reference element.
    pub fn reference(&self) -> &ReferenceElement {
        &self.re
    }

    /// Global dofs of each element.
    pub fn element_dofs(&self) -> &[[u32; N_DOF]] {
        &self.element_dofs
    }

    /// Assembles the residual at `x` (all dofs) and, if `tangent`, the free–free tangent and
    /// K_fc d_c. A material error at any quadrature point is returned as is.
    pub fn assemble<M: AxisymmetricMaterial + ?Sized>(
        &mut self,
        x: &[f64],
        material: &M,
        tangent: bool,
    ) -> crate::Result<()> {
        let re = &self.re;
        let rates = &self.rates;
        let n_free = self.n_free;
        self.rbuf
            .par_chunks_mut(N_DOF)
            .zip(self.kbuf.par_chunks_mut(N_K))
            .zip(self.gbuf.par_chunks_mut(N_DOF))
            .zip(self.scale_buf.par_iter_mut())
            .zip(self.coords.par_iter().zip(self.element_dofs.par_iter()))
            .try_for_each(|((((rb, kb), gb), sc), (xe, d))| {
                let u = SVector::<f64, N_U>::from_fn(|i, _| x[d[i] as usize]);
                let p = SVector::<f64, N_P>::from_fn(|i, _| x[d[N_U + i] as usize]);
                let mut r = ElementVector::zeros();
                let scale = if tangent {
                    let mut k = ElementMatrix::zeros();
                    let s =
                        element_residual_tangent(re, xe, &u, &p, material, &mut r, Some(&mut k))?;
                    kb.copy_from_slice(k.as_slice());
                    let mut g = ElementVector::zeros();
                    let mut any = false;
                    for (j, &dj) in d.iter().enumerate() {
                        if (dj as usize) >= n_free && rates[dj as usize] != 0.0 {
                            g += k.column(j) * rates[dj as usize];
                            any = true;
                        }
                    }
                    if any {
                        gb.copy_from_slice(g.as_slice());
                    } else {
                        gb.fill(0.0);
                    }
                    s
                } else {
                    element_residual_tangent(re, xe, &u, &p, material, &mut r, None)?
                };
                rb.copy_from_slice(r.as_slice());
                *sc = scale.stress;
                Ok(())
            })?;
        let gather = |out: &mut [f64], ptr: &[u32], src: &[u32], buf: &[f64]| {
            out.par_iter_mut().enumerate().for_each(|(i, o)| {
                *o = src[ptr[i] as usize..ptr[i + 1] as usize]
                    .iter()
                    .map(|&s| buf[s as usize])
                    .sum();
            });
        };
        gather(&mut self.residual, &self.res_ptr, &self.res_src, &self.rbuf);
        self.stress_scale = self.scale_buf.par_iter().cloned().reduce(|| 0.0, f64::max);
        if tangent {
            gather(&mut self.values, &self.val_ptr, &self.val_src, &self.kbuf);
            gather(
                &mut self.rate_force,
                &self.res_ptr,
                &self.res_src,
                &self.gbuf,
            );
        }
        let bad = self.residual.iter().position(|v| !v.is_finite());
        if let Some(i) = bad {
            return Err(crate::Error::NonFinite {
                quantity: "assembled residual",
                value: self.residual[i],
                context: format!("at global dof {i}"),
            });
        }
        Ok(())
    }
}
