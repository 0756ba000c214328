//! Parallel assembly of the residual and the tangent into a sparse matrix whose pattern is
//! built once.
//!
//! Each element writes its residual (n dofs) and tangent (n × n) into its own slot of a buffer
//! (no sharing, so the element loop runs in parallel without locks); each global entry is then
//! gathered, again in parallel, from the list of element slots that contribute to it. Both
//! lists are built once with the pattern; the hot loop allocates nothing. The element loop is
//! compiled once per [`Element`] with fixed-size matrices ([`PerElement`]); the choice is made
//! once per assembly.

use super::condensation::Condensation;
use super::dofs::DofMap;
use super::element::{
    zeroed, Element, ElementMatrix, ElementScale, ElementVector, PerElement, PointGeometry,
    ReferenceElement, References, TryMap, Typed, Visit,
};
use super::error::{FemError, FemResult};
use super::finite::first_non_finite;
use super::material::{AxiF, AxisymmetricMaterial};
use super::mesh::Mesh;
use crate::volumetric::Volumetric;
use nalgebra::SVector;
use rayon::prelude::*;

/// Entries gathered per parallel task ([`gather`]).
const GATHER_CHUNK: usize = 4096;

/// out[i] = Σ buf[src[k]] over k in ptr[i]..ptr[i + 1] (the element slots of entry i), in
/// parallel by chunks of [`GATHER_CHUNK`]; returns Σ out[i]², summed per chunk and the chunks in
/// order, so the same whatever the threads (‖K‖_F for GMRES's backward error).
fn gather(out: &mut [f64], ptr: &[u32], src: &[u32], buf: &[f64]) -> f64 {
    let squares: Vec<f64> = out
        .par_chunks_mut(GATHER_CHUNK)
        .enumerate()
        .map(|(c, chunk)| {
            let mut squares = 0.0;
            for (k, o) in chunk.iter_mut().enumerate() {
                let i = c * GATHER_CHUNK + k;
                *o = src[ptr[i] as usize..ptr[i + 1] as usize]
                    .iter()
                    .map(|&s| buf[s as usize])
                    .sum();
                squares += *o * *o;
            }
            squares
        })
        .collect();
    squares.iter().sum()
}

/// Deformation state at one quadrature point (for diagnostics such as an ellipticity check).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct QuadraturePoint {
    /// Element index.
    pub element: usize,
    /// Quadrature point index in the element (0..9 for Q2/Q1, 0..4 for Q1/P0).
    pub point: usize,
    /// Radius.
    pub r: f64,
    /// Axial coordinate.
    pub z: f64,
    /// Volume weight dV.
    pub dv: f64,
    /// Deformation gradient entries.
    pub f: AxiF,
    /// Pressure p.
    pub pressure: f64,
}

/// The cells of one element type: reference element, the mapped geometry of every cell's
/// quadrature points (computed once: the reference mesh does not move) and global dofs.
#[derive(Debug)]
struct Cells<const NN: usize, const NU: usize, const NP: usize, const ND: usize, const NQ: usize> {
    re: ReferenceElement<NN, NU, NP, ND, NQ>,
    geometry: Vec<[PointGeometry<NN>; NQ]>,
    dofs: Vec<[u32; ND]>,
}

/// The cells' type for each element's sizes: the mesh's cells are a `PerElement<CellsOf>`, so
/// that each element loop is monomorphised.
#[derive(Debug)]
struct CellsOf;

impl Typed for CellsOf {
    type Of<const NN: usize, const NU: usize, const NP: usize, const ND: usize, const NQ: usize> =
        Box<Cells<NN, NU, NP, ND, NQ>>;
}

/// The cells of a mesh from their reference element ([`Cells::new`]).
struct BuildCells<'a> {
    mesh: &'a Mesh,
    dofs: &'a DofMap,
}

impl TryMap<References, CellsOf> for BuildCells<'_> {
    type Error = FemError;

    fn map<const NN: usize, const NU: usize, const NP: usize, const ND: usize, const NQ: usize>(
        self,
        re: ReferenceElement<NN, NU, NP, ND, NQ>,
    ) -> FemResult<Box<Cells<NN, NU, NP, ND, NQ>>> {
        Ok(Box::new(Cells::new(re, self.mesh, self.dofs)?))
    }
}

/// One assembly's element loop ([`Cells::evaluate`]).
struct Evaluate<'a, M: ?Sized> {
    x: &'a [f64],
    material: &'a M,
    tangent: bool,
    buf: Buffers<'a>,
}

impl<M: AxisymmetricMaterial + ?Sized> Visit<CellsOf> for Evaluate<'_, M> {
    type Output = crate::Result<()>;

    fn visit<
        const NN: usize,
        const NU: usize,
        const NP: usize,
        const ND: usize,
        const NQ: usize,
    >(
        self,
        cells: &Box<Cells<NN, NU, NP, ND, NQ>>,
    ) -> crate::Result<()> {
        cells.evaluate(self.x, self.material, self.tangent, self.buf)
    }
}

/// The element systems of a few cells ([`Cells::patch`]).
struct Patch<'a, M: ?Sized> {
    x: &'a [f64],
    material: &'a M,
    volumetric: Option<&'a Volumetric>,
    list: &'a [usize],
}

/// A cell's dofs, element residual and element tangent (column-major).
pub type CellSystem = (Vec<u32>, Vec<f64>, Vec<f64>);

impl<M: AxisymmetricMaterial + ?Sized> Visit<CellsOf> for Patch<'_, M> {
    type Output = crate::Result<Vec<CellSystem>>;

    fn visit<
        const NN: usize,
        const NU: usize,
        const NP: usize,
        const ND: usize,
        const NQ: usize,
    >(
        self,
        cells: &Box<Cells<NN, NU, NP, ND, NQ>>,
    ) -> crate::Result<Vec<CellSystem>> {
        cells.patch(self.x, self.material, self.volumetric, self.list)
    }
}

/// The quadrature points of the cells at the dof values `x` ([`Cells::quadrature_points`]).
struct QuadraturePoints<'a>(&'a [f64]);

impl Visit<CellsOf> for QuadraturePoints<'_> {
    type Output = Vec<QuadraturePoint>;

    fn visit<
        const NN: usize,
        const NU: usize,
        const NP: usize,
        const ND: usize,
        const NQ: usize,
    >(
        self,
        cells: &Box<Cells<NN, NU, NP, ND, NQ>>,
    ) -> Vec<QuadraturePoint> {
        cells.quadrature_points(self.0)
    }
}

/// Element buffers and what the element loop needs besides the cells.
struct Buffers<'a> {
    rbuf: &'a mut [f64],
    kbuf: &'a mut [f64],
    gbuf: &'a mut [f64],
    scale_buf: &'a mut [f64],
    /// Per-cell data of the static condensation (one unused value per cell without it).
    cdata: &'a mut [f64],
    condensation: Option<&'a Condensation>,
    volumetric: Option<&'a Volumetric>,
    rates: &'a [f64],
    n_free: usize,
}

impl<const NN: usize, const NU: usize, const NP: usize, const ND: usize, const NQ: usize>
    Cells<NN, NU, NP, ND, NQ>
{
    /// Validates the connectivity and the geometry of every cell, and maps its quadrature points.
    fn new(
        re: ReferenceElement<NN, NU, NP, ND, NQ>,
        mesh: &Mesh,
        dofs: &DofMap,
    ) -> FemResult<Self> {
        let n_el = mesh.n_elements();
        let mut geometry = Vec::with_capacity(n_el);
        let mut cell_dofs = Vec::with_capacity(n_el);
        for (e, conn) in mesh.elements().enumerate() {
            let mut x = [[0.0; 2]; NN];
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
            geometry.push(re.cell_geometry(&x).ok_or_else(|| FemError::InvalidInput {
                name: "element geometry",
                value: format!("element {e}, nodes {x:?}"),
                rule: "mapping must be invertible, counter-clockwise, with r > 0 at quadrature points",
            })?);
            let mut d = [0u32; ND];
            d.copy_from_slice(dofs.cell_dofs(e));
            cell_dofs.push(d);
        }
        Ok(Self {
            re,
            geometry,
            dofs: cell_dofs,
        })
    }

    /// The displacements and pressures of a cell with dofs `d` in `x`.
    fn cell_values(x: &[f64], d: &[u32; ND]) -> (SVector<f64, NU>, SVector<f64, NP>) {
        (
            SVector::from_fn(|i, _| x[d[i] as usize]),
            SVector::from_fn(|i, _| x[d[NU + i] as usize]),
        )
    }

    /// The element residual and tangent (and the stress scale) of the cell with geometry `xe`
    /// and dofs `d` at `x`.
    #[inline(always)]
    fn cell_system<M: AxisymmetricMaterial + ?Sized>(
        &self,
        xe: &[PointGeometry<NN>; NQ],
        d: &[u32; ND],
        x: &[f64],
        material: &M,
        volumetric: Option<&Volumetric>,
    ) -> crate::Result<(ElementVector<ND>, ElementMatrix<ND>, ElementScale)> {
        let (u, p) = Self::cell_values(x, d);
        let (mut r, mut k) = (zeroed::<ND, 1>(), zeroed::<ND, ND>());
        let s = self
            .re
            .residual_tangent(xe, &u, &p, material, volumetric, &mut r, Some(&mut k))?;
        Ok((r, k, s))
    }

    /// Element residuals and tangents of the cells `list` at `x` (all dofs; the full element
    /// system, nothing condensed), with each cell's global dofs.
    fn patch<M: AxisymmetricMaterial + ?Sized>(
        &self,
        x: &[f64],
        material: &M,
        volumetric: Option<&Volumetric>,
        list: &[usize],
    ) -> crate::Result<Vec<CellSystem>> {
        list.iter()
            .map(|&e| {
                let d = &self.dofs[e];
                let (r, k, _) = self.cell_system(&self.geometry[e], d, x, material, volumetric)?;
                Ok((d.to_vec(), r.as_slice().to_vec(), k.as_slice().to_vec()))
            })
            .collect()
    }

    /// Element residuals (and tangents, K_fc d_c) at `x` into the buffers.
    fn evaluate<M: AxisymmetricMaterial + ?Sized>(
        &self,
        x: &[f64],
        material: &M,
        tangent: bool,
        buf: Buffers<'_>,
    ) -> crate::Result<()> {
        let re = &self.re;
        let (rates, n_free, condensation) = (buf.rates, buf.n_free, buf.condensation);
        let volumetric = buf.volumetric;
        let n_k = buf.kbuf.len() / self.geometry.len().max(1);
        let n_c = buf.cdata.len() / self.geometry.len().max(1);
        buf.rbuf
            .par_chunks_mut(ND)
            .zip(buf.kbuf.par_chunks_mut(n_k.max(1)))
            .zip(buf.cdata.par_chunks_mut(n_c.max(1)))
            .zip(buf.gbuf.par_chunks_mut(ND))
            .zip(buf.scale_buf.par_iter_mut())
            .zip(self.geometry.par_iter().zip(self.dofs.par_iter()))
            .try_for_each(|(((((rb, kb), cd), gb), sc), (xe, d))| {
                let (r, scale) = if tangent {
                    let (r, k, s) = self.cell_system(xe, d, x, material, volumetric)?;
                    match condensation {
                        Some(c) => c.condense_cell(k.as_slice(), ND, kb, cd)?,
                        None => kb.copy_from_slice(k.as_slice()),
                    }
                    let mut g = zeroed::<ND, 1>();
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
                    (r, s)
                } else {
                    let (u, p) = Self::cell_values(x, d);
                    let mut r = zeroed::<ND, 1>();
                    let s = re.residual_tangent(xe, &u, &p, material, volumetric, &mut r, None)?;
                    (r, s)
                };
                rb.copy_from_slice(r.as_slice());
                *sc = scale.stress;
                Ok(())
            })
    }

    fn quadrature_points(&self, x: &[f64]) -> Vec<QuadraturePoint> {
        let re = &self.re;
        let mut out = Vec::with_capacity(self.geometry.len() * NQ);
        for (e, (ge, d)) in self.geometry.iter().zip(&self.dofs).enumerate() {
            let (u, p) = Self::cell_values(x, d);
            for (q, g) in ge.iter().enumerate() {
                out.push(QuadraturePoint {
                    element: e,
                    point: q,
                    r: g.r,
                    z: g.z,
                    dv: g.dv,
                    f: g.deformation(&u),
                    pressure: re.m[q].dot(&p),
                });
            }
        }
        out
    }
}

/// Compressed-column pattern of the system matrix: the free–free block of the tangent,
/// condensed ([`Assembler::system_index`]).
#[derive(Debug, Clone)]
pub struct Pattern {
    /// Dimension (number of unknowns of the system).
    pub n: usize,
    /// Column pointers (length n + 1).
    pub col_ptr: Vec<u32>,
    /// Row indices, sorted within each column.
    pub row_idx: Vec<u32>,
}

/// Builds the residual and tangent of the whole mesh.
#[derive(Debug)]
pub struct Assembler {
    cells: PerElement<CellsOf>,
    n_free: usize,
    /// Sparsity pattern of the system matrix: the free–free tangent, the Q2/Q1 centre nodes
    /// condensed out ([`super::condensation`]).
    pub pattern: Pattern,
    /// System matrix values (aligned with `pattern.row_idx`).
    pub values: Vec<f64>,
    /// Their Frobenius norm ‖K‖_F, summed while they are gathered (GMRES's backward error).
    pub values_norm: f64,
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
    cdata: Vec<f64>,
    condensation: Option<Condensation>,
    volumetric: Option<Volumetric>,
    index: Vec<u32>,
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

/// Which entries of a cell's matrix enter the system: `couples(i, j)` for local dofs i, j.
type Couples<'a> = &'a (dyn Fn(usize, usize) -> bool + Sync);

/// The pattern of the system matrix on `n` unknowns from the cells' system dofs (`m` per cell
/// in `cell_dofs`, `u32::MAX` for a dof outside the system) and the local `couples` rule.
fn system_pattern(
    cell_dofs: &[u32],
    m: usize,
    n: usize,
    couples: Couples<'_>,
    mesh: &Mesh,
) -> FemResult<Pattern> {
    let inside = |g: u32| g != u32::MAX;
    // Two passes over the cells into one flat buffer (column j's rows, duplicates included, at
    // start[j]..), then each column sorted and deduplicated in place: one allocation, not one
    // per column.
    let mut start = vec![0usize; n + 1];
    for d in cell_dofs.chunks_exact(m) {
        for j in (0..m).filter(|&j| inside(d[j])) {
            start[d[j] as usize + 1] += (0..m).filter(|&i| inside(d[i]) && couples(i, j)).count();
        }
    }
    for j in 0..n {
        start[j + 1] += start[j];
    }
    let mut flat = vec![0u32; start[n]];
    let mut fill = start.clone();
    for d in cell_dofs.chunks_exact(m) {
        for j in (0..m).filter(|&j| inside(d[j])) {
            for i in (0..m).filter(|&i| inside(d[i]) && couples(i, j)) {
                flat[fill[d[j] as usize]] = d[i];
                fill[d[j] as usize] += 1;
            }
        }
    }
    drop(fill);
    if let Some(i) = (0..n).find(|&j| start[j] == start[j + 1]) {
        return Err(FemError::InvalidInput {
            name: "mesh",
            value: format!(
                "free dof {i} of {} {} cells",
                mesh.n_elements(),
                mesh.element
            ),
            rule: "every free dof must couple to a free displacement dof (refine the mesh)",
        });
    }
    let (col_ptr, row_idx) = deduplicate_columns(flat, &start)?;
    Ok(Pattern {
        n,
        col_ptr,
        row_idx,
    })
}

/// Sorts and deduplicates each column `flat[start[j]..start[j + 1]]` in place and compacts them.
fn deduplicate_columns(mut flat: Vec<u32>, start: &[usize]) -> FemResult<(Vec<u32>, Vec<u32>)> {
    let n = start.len() - 1;
    let mut col_ptr = Vec::with_capacity(n + 1);
    col_ptr.push(0u32);
    let mut len = 0usize;
    for j in 0..n {
        let column = &mut flat[start[j]..start[j + 1]];
        column.sort_unstable();
        let mut kept = 0;
        for k in 0..column.len() {
            if k == 0 || column[k] != column[kept - 1] {
                column[kept] = column[k];
                kept += 1;
            }
        }
        flat.copy_within(start[j]..start[j] + kept, len);
        len += kept;
        if len >= u32::MAX as usize {
            return Err(FemError::InvalidInput {
                name: "pattern",
                value: len.to_string(),
                rule: "too many nonzeros for 32-bit indices",
            });
        }
        col_ptr.push(len as u32);
    }
    flat.truncate(len);
    flat.shrink_to_fit();
    Ok((col_ptr, flat))
}

/// Position in the system's values of every cell-matrix entry (m × m per cell, column-major;
/// u32::MAX: not in the system).
fn value_positions(
    cell_dofs: &[u32],
    m: usize,
    pattern: &Pattern,
    couples: Couples<'_>,
) -> Vec<u32> {
    let inside = |g: u32| g != u32::MAX;
    let n_k = m * m;
    let mut pos = vec![u32::MAX; cell_dofs.len() / m * n_k];
    pos.par_chunks_mut(n_k)
        .zip(cell_dofs.par_chunks_exact(m))
        .for_each(|(p, d)| {
            for j in (0..m).filter(|&j| inside(d[j])) {
                let (lo, hi) = (
                    pattern.col_ptr[d[j] as usize] as usize,
                    pattern.col_ptr[d[j] as usize + 1] as usize,
                );
                let rows = &pattern.row_idx[lo..hi];
                for i in (0..m).filter(|&i| inside(d[i]) && couples(i, j)) {
                    if let Ok(k) = rows.binary_search(&d[i]) {
                        p[i + m * j] = (lo + k) as u32;
                    }
                }
            }
        });
    pos
}

/// The system's numbering of the free dofs (`u32::MAX` for a condensed bubble dof) and its size.
fn system_numbering(n_free: usize, condensation: Option<&Condensation>) -> (Vec<u32>, usize) {
    let bubble = condensation.map(Condensation::bubble_flags);
    let mut index = vec![u32::MAX; n_free];
    let mut next = 0u32;
    for (g, slot) in index.iter_mut().enumerate() {
        if !bubble.as_ref().is_some_and(|b| b[g]) {
            *slot = next;
            next += 1;
        }
    }
    (index, next as usize)
}

/// Whether `dofs` numbers `mesh` (same element, a dof list per cell) and the cells' matrices
/// fit 32-bit gather lists.
fn check_numbering(mesh: &Mesh, dofs: &DofMap) -> FemResult<()> {
    let n_el = mesh.n_elements();
    let nd = dofs.dofs_per_element();
    if mesh.element != dofs.element || dofs.element_dofs.len() != n_el * nd {
        return Err(FemError::InvalidInput {
            name: "dof map",
            value: format!(
                "{} dofs for {} {} cells",
                dofs.element_dofs.len(),
                n_el,
                mesh.element
            ),
            rule: "must be the numbering of this mesh",
        });
    }
    if n_el
        .checked_mul(nd * nd)
        .is_none_or(|v| v >= u32::MAX as usize)
    {
        return Err(FemError::InvalidInput {
            name: "elements",
            value: n_el.to_string(),
            rule: "too many elements for 32-bit gather lists",
        });
    }
    Ok(())
}

/// The system's index of each of the dofs `global` (`u32::MAX` for a prescribed one, ≥ `n_free`).
fn in_system(global: &[u32], index: &[u32], n_free: usize) -> Vec<u32> {
    global
        .iter()
        .map(|&g| {
            if (g as usize) < n_free {
                index[g as usize]
            } else {
                u32::MAX
            }
        })
        .collect()
}

impl Assembler {
    /// Validates the element geometry and builds the pattern and the gather lists (exact
    /// incompressibility).
    pub fn new(mesh: &Mesh, dofs: &DofMap) -> FemResult<Self> {
        Self::with_volumetric(mesh, dofs, None)
    }

    /// The volumetric energy of a nearly incompressible material (`None`: the exact constraint).
    pub fn volumetric(&self) -> Option<&Volumetric> {
        self.volumetric.as_ref()
    }

    /// [`Self::new`] for the nearly incompressible material Ψ + U(J) when `volumetric` is given
    /// (the perturbed Lagrangian of [`super::element::ReferenceElement::residual_tangent`]: the
    /// pressure–pressure block −∫ M Mᵀ/κ₀ dV enters the pattern).
    pub fn with_volumetric(
        mesh: &Mesh,
        dofs: &DofMap,
        volumetric: Option<Volumetric>,
    ) -> FemResult<Self> {
        check_numbering(mesh, dofs)?;
        let (n_el, nd) = (mesh.n_elements(), dofs.dofs_per_element());
        let nu = 2 * mesh.element.nodes();
        let cells = mesh
            .element
            .reference()
            .try_map(BuildCells { mesh, dofs })?;
        let n = dofs.n_free;
        let condensation = Condensation::new(mesh, dofs);
        let (index, n_system) = system_numbering(n, condensation.as_ref());
        // The cells' dofs in the system: all but the condensed bubble, in the system numbering;
        // the condensed cell matrix couples every pair, the plain one all but pressure–pressure.
        let (m, global) = match &condensation {
            Some(c) => (c.dofs_per_cell(), c.cell_dofs()),
            None => (nd, dofs.element_dofs.as_slice()),
        };
        let system = in_system(global, &index, n);
        let condensed = condensation.is_some();
        let penalised = volumetric.is_some();
        let couples = move |i: usize, j: usize| condensed || penalised || !(i >= nu && j >= nu);
        let pattern = system_pattern(&system, m, n_system, &couples, mesh)?;
        let nnz = pattern.row_idx.len();
        let pos = value_positions(&system, m, &pattern, &couples);
        drop(system);
        let (val_ptr, val_src) = counting_lists(nnz, &pos);
        drop(pos);
        let (res_ptr, res_src) = counting_lists(dofs.n_total, &dofs.element_dofs);
        let mut rates = vec![0.0; dofs.n_total];
        rates[dofs.n_free..].copy_from_slice(&dofs.prescribed_rate);
        let n_c = condensation.as_ref().map_or(1, Condensation::data_per_cell);
        Ok(Self {
            cells,
            n_free: n,
            pattern,
            values: vec![0.0; nnz],
            values_norm: 0.0,
            residual: vec![0.0; dofs.n_total],
            rate_force: vec![0.0; dofs.n_total],
            stress_scale: 0.0,
            val_ptr,
            val_src,
            res_ptr,
            res_src,
            kbuf: vec![0.0; n_el * m * m],
            rbuf: vec![0.0; n_el * nd],
            gbuf: vec![0.0; n_el * nd],
            scale_buf: vec![0.0; n_el],
            cdata: vec![0.0; n_el * n_c],
            condensation,
            volumetric,
            index,
            rates,
        })
    }

    /// Largest stress of each cell at the last assembly.
    pub fn cell_scales(&self) -> &[f64] {
        &self.scale_buf
    }

    /// Element residuals and tangents of the cells `list` at `x` (all dofs, no condensation).
    pub fn patch<M: AxisymmetricMaterial + ?Sized>(
        &self,
        x: &[f64],
        material: &M,
        list: &[usize],
    ) -> crate::Result<Vec<CellSystem>> {
        self.cells.visit(Patch {
            x,
            material,
            volumetric: self.volumetric.as_ref(),
            list,
        })
    }

    /// The system's index of every free dof (`u32::MAX`: a condensed centre-node dof); the
    /// identity without condensation.
    pub fn system_index(&self) -> &[u32] {
        &self.index
    }

    /// Whether the Q2/Q1 centre nodes are condensed out of the system ([`super::condensation`]).
    pub fn is_condensed(&self) -> bool {
        self.condensation.is_some()
    }

    /// The system's right-hand side for `f` on the free dofs: f_e − W f_b
    /// ([`Condensation::condense`]), or f itself without condensation.
    pub fn condense(&self, f: &[f64], system: &mut [f64]) {
        match &self.condensation {
            Some(c) => c.condense(&self.cdata, &self.index, f, system),
            None => system.copy_from_slice(f),
        }
    }

    /// The solution on the free dofs of K x = f from the system's solution `y`
    /// ([`Condensation::expand`]), or y itself without condensation.
    pub fn expand(&self, f: &[f64], y: &[f64], x: &mut [f64]) {
        match &self.condensation {
            Some(c) => c.expand(&self.cdata, &self.index, f, y, x),
            None => x.copy_from_slice(y),
        }
    }

    /// The element of the cells.
    pub fn element(&self) -> Element {
        self.cells.element()
    }

    /// F, p, position and volume weight at every quadrature point of every cell for the dof
    /// values `x` (all dofs), cell by cell.
    pub fn quadrature_points(&self, x: &[f64]) -> Vec<QuadraturePoint> {
        self.cells.visit(QuadraturePoints(x))
    }

    /// Assembles the residual at `x` (all dofs) and, if `tangent`, the free–free tangent and
    /// K_fc d_c. A material error at any quadrature point is returned as is.
    pub fn assemble<M: AxisymmetricMaterial + ?Sized>(
        &mut self,
        x: &[f64],
        material: &M,
        tangent: bool,
    ) -> crate::Result<()> {
        let buf = Buffers {
            rbuf: &mut self.rbuf,
            kbuf: &mut self.kbuf,
            gbuf: &mut self.gbuf,
            scale_buf: &mut self.scale_buf,
            cdata: &mut self.cdata,
            condensation: self.condensation.as_ref(),
            volumetric: self.volumetric.as_ref(),
            rates: &self.rates,
            n_free: self.n_free,
        };
        self.cells.visit(Evaluate {
            x,
            material,
            tangent,
            buf,
        })?;
        gather(&mut self.residual, &self.res_ptr, &self.res_src, &self.rbuf);
        self.stress_scale = self.scale_buf.par_iter().cloned().reduce(|| 0.0, f64::max);
        if tangent {
            let squares = gather(&mut self.values, &self.val_ptr, &self.val_src, &self.kbuf);
            self.values_norm = squares.sqrt();
            gather(
                &mut self.rate_force,
                &self.res_ptr,
                &self.res_src,
                &self.gbuf,
            );
        }
        let bad = first_non_finite(&self.residual);
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
