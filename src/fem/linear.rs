//! Sparse LU with partial pivoting (faer) for the saddle-point tangent: the symbolic analysis
//! (column ordering, elimination tree, supernodes) is done once per pattern and reused by every
//! numeric factorisation; numeric storage and scratch memory are reused too.

use super::assembly::Pattern;
use super::finite::first_non_finite;
use faer::dyn_stack::{MemBuffer, MemStack};
use faer::sparse::linalg::lu::{factorize_symbolic_lu, LuRef, NumericLu, SymbolicLu};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMatRef};
use faer::{Conj, MatMut, Par};

/// A reusable sparse LU solver for one sparsity pattern.
pub struct SparseLu {
    symbolic: SymbolicLu<u32>,
    numeric: NumericLu<u32, f64>,
    factor_scratch: MemBuffer,
    solve_scratch: MemBuffer,
    factorised: bool,
    par: Par,
}

impl std::fmt::Debug for SparseLu {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseLu")
            .field("n", &self.symbolic.nrows())
            .field("factorised", &self.factorised)
            .finish()
    }
}

fn symbolic_view(p: &Pattern) -> SymbolicSparseColMatRef<'_, u32> {
    SymbolicSparseColMatRef::new_checked(p.n, p.n, &p.col_ptr, None, &p.row_idx)
}

impl SparseLu {
    /// Symbolic analysis of `pattern`.
    pub fn new(pattern: &Pattern) -> Result<Self, String> {
        let par = Par::Seq;
        let symbolic = factorize_symbolic_lu(symbolic_view(pattern), Default::default())
            .map_err(|e| format!("symbolic LU: {e:?}"))?;
        let factor_scratch = MemBuffer::try_new(
            symbolic.factorize_numeric_lu_scratch::<f64>(par, Default::default()),
        )
        .map_err(|_| "out of memory for LU scratch".to_string())?;
        let solve_scratch = MemBuffer::try_new(symbolic.solve_in_place_scratch::<f64>(1, par))
            .map_err(|_| "out of memory for solve scratch".to_string())?;
        Ok(Self {
            symbolic,
            numeric: NumericLu::new(),
            factor_scratch,
            solve_scratch,
            factorised: false,
            par,
        })
    }

    /// Numeric factorisation of the matrix with `pattern` and `values`.
    pub fn factorise(&mut self, pattern: &Pattern, values: &[f64]) -> Result<(), String> {
        self.factorised = false;
        if let Some(i) = first_non_finite(values) {
            return Err(format!(
                "non-finite tangent entry {} at nonzero {i}",
                values[i]
            ));
        }
        let a = SparseColMatRef::new(symbolic_view(pattern), values);
        self.symbolic
            .factorize_numeric_lu(
                &mut self.numeric,
                a,
                self.par,
                MemStack::new(&mut self.factor_scratch),
                Default::default(),
            )
            .map_err(|e| format!("numeric LU: {e:?}"))?;
        self.factorised = true;
        Ok(())
    }

    /// Solves A x = b in place; fails if there is no factorisation or the solution is not finite.
    pub fn solve_in_place(&mut self, rhs: &mut [f64]) -> Result<(), String> {
        if !self.factorised {
            return Err("no valid factorisation".into());
        }
        let n = rhs.len();
        let lu = LuRef::new_unchecked(&self.symbolic, &self.numeric);
        lu.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(rhs, n, 1),
            self.par,
            MemStack::new(&mut self.solve_scratch),
        );
        match first_non_finite(rhs) {
            Some(i) => Err(format!(
                "solution entry {i} is {} (zero pivot: the tangent is singular)",
                rhs[i]
            )),
            None => Ok(()),
        }
    }
}
