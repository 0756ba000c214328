//! The compiled formula: two flat tapes, evaluated on any scalar.
//!
//! - The **constant tape** computes every subexpression that depends on the parameters only
//!   (μ/(4α), w0/3, ...) on the parameters' scalar P: once per parameter set for the responses
//!   (P = f64, stored with the energy), per call in a fit (P a dual number, derivatives in the
//!   parameters).
//! - The **energy tape** computes W from the five invariants on the invariants' scalar T (the dual
//!   numbers of the responses), each instruction reading earlier results (T) and constants (P). A
//!   constant enters as T ∘ P (T · f64 for the responses), never lifted to a dual number: dual
//!   arithmetic costs with every operand that carries derivatives ([`crate::response`]).
//!
//! Both tapes are in SSA form (instruction i writes result i), in an order where operands come
//! first, so evaluation is one loop over the instructions into a buffer kept on the stack (up to
//! [`INLINE`] results; a longer formula spills to the heap).

use super::symbols::Function;
use super::syntax::BinaryOp;
use crate::energy::Invariants;
use crate::parameter::ScalarWith;
use crate::Scalar;
use smallvec::SmallVec;

/// Results of a tape held on the stack before the buffer moves to the heap.
pub const INLINE: usize = 64;

/// An instruction of the constant tape (operands: earlier results).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum ConstantOp {
    /// A number.
    Literal(f64),
    /// Parameter k.
    Parameter(usize),
    /// f(a).
    Unary(Function, usize),
    /// a ∘ b (a^b = e^{b ln a}).
    Binary(BinaryOp, usize, usize),
    /// aⁿ, n an integer.
    PowI(usize, i32),
    /// aˣ, x a number.
    PowF(usize, f64),
}

/// An instruction of the energy tape: `a`, `b` are earlier results (T), `k` a result of the
/// constant tape (P).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Op {
    /// Invariant k of [`Invariants::to_array`].
    Invariant(usize),
    /// a ∘ b (a^b = e^{b ln a}).
    Binary(BinaryOp, usize, usize),
    /// a + c_k.
    AddC(usize, usize),
    /// a − c_k.
    SubC(usize, usize),
    /// c_k − a.
    CSub(usize, usize),
    /// a · c_k.
    MulC(usize, usize),
    /// c_k / a.
    CDiv(usize, usize),
    /// aⁿ, n an integer.
    PowI(usize, i32),
    /// aˣ, x a number.
    PowF(usize, f64),
    /// a^{c_k} = e^{c_k ln a}.
    PowC(usize, usize),
    /// e^{c_k a} (a constant base raised to a: c_k is the base's logarithm).
    ExpMulC(usize, usize),
    /// f(a).
    Unary(Function, usize),
}

/// A compiled formula.
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    /// The constant tape.
    pub constants: Vec<ConstantOp>,
    /// The energy tape; its last result is W.
    pub ops: Vec<Op>,
}

#[inline(always)]
fn binary<T: Scalar>(op: BinaryOp, a: T, b: T) -> T {
    match op {
        BinaryOp::Add => a + b,
        BinaryOp::Sub => a - b,
        BinaryOp::Mul => a * b,
        BinaryOp::Div => a / b,
        BinaryOp::Pow => (a.ln() * b).exp(),
    }
}

impl Program {
    /// Whether W depends on det C.
    pub fn uses_det_c(&self) -> bool {
        self.ops.contains(&Op::Invariant(4))
    }

    /// The results of the constant tape for `parameters` (in the order declared).
    pub fn constants<P: Scalar>(&self, parameters: &[P]) -> Vec<P> {
        let mut c: Vec<P> = Vec::with_capacity(self.constants.len());
        for op in &self.constants {
            let x = match *op {
                ConstantOp::Literal(x) => P::from(x),
                ConstantOp::Parameter(k) => parameters[k],
                ConstantOp::Unary(f, a) => f.apply(c[a]),
                ConstantOp::Binary(op, a, b) => binary(op, c[a], c[b]),
                ConstantOp::PowI(a, n) => c[a].powi(n),
                ConstantOp::PowF(a, x) => c[a].powf(x),
            };
            c.push(x);
        }
        c
    }

    /// W from the invariants, with the constant tape's results `c` (P = f64 for the responses,
    /// P = T in a fit).
    #[inline(always)]
    pub fn energy<P: Scalar, T: ScalarWith<P>>(&self, c: &[P], invariants: &Invariants<T>) -> T {
        let j = invariants.to_array();
        let mut v: SmallVec<[T; INLINE]> = SmallVec::new();
        for op in &self.ops {
            let x = match *op {
                Op::Invariant(k) => j[k],
                Op::Binary(op, a, b) => binary(op, v[a], v[b]),
                Op::AddC(a, k) => v[a] + c[k],
                Op::SubC(a, k) => v[a] - c[k],
                Op::CSub(a, k) => -v[a] + c[k],
                Op::MulC(a, k) => v[a] * c[k],
                Op::CDiv(a, k) => v[a].recip() * c[k],
                Op::PowI(a, n) => v[a].powi(n),
                Op::PowF(a, x) => v[a].powf(x),
                Op::PowC(a, k) => (v[a].ln() * c[k]).exp(),
                Op::ExpMulC(a, k) => (v[a] * c[k]).exp(),
                Op::Unary(f, a) => f.apply(v[a]),
            };
            v.push(x);
        }
        // The compiler emits at least one instruction (W depends on an invariant).
        v.last().copied().unwrap_or_else(|| T::from(f64::NAN))
    }
}
