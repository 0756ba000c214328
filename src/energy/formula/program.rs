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
//! The constant tape is in SSA form (instruction i writes result i). The energy tape comes from
//! the compiler in SSA form too (its first five results the invariants,
//! [`INVARIANTS`](super::INVARIANTS)) and is then given registers ([`Program::new`]): each result
//! goes to a register freed by a value no later instruction reads, so that the few registers a
//! formula needs at once (about eight for the chapter's energy) are all the memory an evaluation
//! touches. Evaluation is one loop over the instructions on an array of registers on the stack,
//! sized to the program (8, 16, 32, or a small vector beyond): its initialisation is the one cost
//! the interpreter adds per call besides the loop itself.

use super::symbols::Function;
use super::syntax::BinaryOp;
use crate::energy::Invariants;
use crate::parameter::ScalarWith;
use crate::Scalar;
use smallvec::SmallVec;

/// Registers of the small vector held inline, for programs of more than 32 registers.
pub const INLINE: usize = 64;

/// The energy tape's results before its first instruction: the five invariants.
pub const PRELOADED: usize = 5;

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

/// An operation of the energy tape: `a`, `b` are earlier results (T; in SSA form 0–4 are the
/// invariants, after [`Program::new`] registers), `k`, `l` results of the constant tape (P).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Op {
    /// a + b.
    Add(usize, usize),
    /// a − b.
    Sub(usize, usize),
    /// a · b.
    Mul(usize, usize),
    /// a / b.
    Div(usize, usize),
    /// aᵇ = e^{b ln a}.
    Pow(usize, usize),
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
    /// a · c_k + b · c_l (a combination of invariants, the commonest line of an energy).
    Linear(usize, usize, usize, usize),
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

impl Op {
    /// The results it reads.
    fn operands(&self) -> [Option<usize>; 2] {
        match *self {
            Op::Add(a, b) | Op::Sub(a, b) | Op::Mul(a, b) | Op::Div(a, b) | Op::Pow(a, b) => {
                [Some(a), Some(b)]
            }
            Op::Linear(a, _, b, _) => [Some(a), Some(b)],
            Op::AddC(a, _)
            | Op::SubC(a, _)
            | Op::CSub(a, _)
            | Op::MulC(a, _)
            | Op::CDiv(a, _)
            | Op::PowI(a, _)
            | Op::PowF(a, _)
            | Op::PowC(a, _)
            | Op::ExpMulC(a, _)
            | Op::Unary(_, a) => [Some(a), None],
        }
    }

    /// The same operation reading `at(a)`, `at(b)` instead of `a`, `b`.
    fn renamed(self, at: impl Fn(usize) -> usize) -> Op {
        match self {
            Op::Add(a, b) => Op::Add(at(a), at(b)),
            Op::Sub(a, b) => Op::Sub(at(a), at(b)),
            Op::Mul(a, b) => Op::Mul(at(a), at(b)),
            Op::Div(a, b) => Op::Div(at(a), at(b)),
            Op::Pow(a, b) => Op::Pow(at(a), at(b)),
            Op::Linear(a, k, b, l) => Op::Linear(at(a), k, at(b), l),
            Op::AddC(a, k) => Op::AddC(at(a), k),
            Op::SubC(a, k) => Op::SubC(at(a), k),
            Op::CSub(a, k) => Op::CSub(at(a), k),
            Op::MulC(a, k) => Op::MulC(at(a), k),
            Op::CDiv(a, k) => Op::CDiv(at(a), k),
            Op::PowI(a, n) => Op::PowI(at(a), n),
            Op::PowF(a, x) => Op::PowF(at(a), x),
            Op::PowC(a, k) => Op::PowC(at(a), k),
            Op::ExpMulC(a, k) => Op::ExpMulC(at(a), k),
            Op::Unary(f, a) => Op::Unary(f, at(a)),
        }
    }
}

/// An instruction of the allocated energy tape: an operation and the register it writes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Instruction {
    /// What it computes (operands: registers).
    pub op: Op,
    /// Where the result goes.
    pub dest: usize,
}

/// A compiled formula.
#[derive(Debug, Clone, PartialEq)]
pub struct Program {
    /// The constant tape.
    pub constants: Vec<ConstantOp>,
    /// The energy tape, on registers (0–4 hold the invariants when it starts).
    pub code: Vec<Instruction>,
    /// Registers it needs.
    pub registers: usize,
    /// The register of W at the end.
    pub result: usize,
    /// Whether W depends on det C.
    pub uses_det_c: bool,
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
    /// The program of the constant tape `constants` and the energy tape `ops` in SSA form (result
    /// 5 + i of operation i), W its result `root`: registers allocated by liveness (a register is
    /// free once the last operation that reads its value has read it; W's is never freed).
    pub fn new(constants: Vec<ConstantOp>, ops: &[Op], root: usize) -> Self {
        let values = PRELOADED + ops.len();
        let mut last_use: Vec<Option<usize>> = vec![None; values];
        for (i, op) in ops.iter().enumerate() {
            for v in op.operands().into_iter().flatten() {
                last_use[v] = Some(i);
            }
        }
        let uses_det_c = last_use[4].is_some() || root == 4;
        last_use[root] = Some(ops.len());
        let mut register = vec![0; values];
        let mut free: Vec<usize> = Vec::new();
        for (k, slot) in register.iter_mut().enumerate().take(PRELOADED) {
            *slot = k;
            if last_use[k].is_none() {
                free.push(k);
            }
        }
        let mut registers = PRELOADED;
        let mut code = Vec::with_capacity(ops.len());
        for (i, op) in ops.iter().enumerate() {
            let renamed = op.renamed(|v| register[v]);
            let [a, b] = op.operands();
            for v in [a, b.filter(|b| Some(*b) != a)].into_iter().flatten() {
                if last_use[v] == Some(i) {
                    free.push(register[v]);
                }
            }
            let dest = free.pop().unwrap_or_else(|| {
                registers += 1;
                registers - 1
            });
            register[PRELOADED + i] = dest;
            code.push(Instruction { op: renamed, dest });
        }
        Program {
            uses_det_c,
            constants,
            result: register[root],
            code,
            registers,
        }
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
        match self.registers {
            0..=8 => self.run(c, &j, &mut [j[0]; 8]),
            9..=16 => self.run(c, &j, &mut [j[0]; 16]),
            17..=32 => self.run(c, &j, &mut [j[0]; 32]),
            n => self.run(c, &j, &mut SmallVec::<[T; INLINE]>::from_elem(j[0], n)),
        }
    }

    fn run<P: Scalar, T: ScalarWith<P>>(
        &self,
        c: &[P],
        j: &[T; 5],
        v: &mut (impl std::ops::IndexMut<usize, Output = T> + ?Sized),
    ) -> T {
        for (k, x) in j.iter().enumerate() {
            v[k] = *x;
        }
        for ins in &self.code {
            let x = match ins.op {
                Op::Add(a, b) => v[a] + v[b],
                Op::Sub(a, b) => v[a] - v[b],
                Op::Mul(a, b) => v[a] * v[b],
                Op::Div(a, b) => v[a] / v[b],
                Op::Pow(a, b) => (v[a].ln() * v[b]).exp(),
                Op::AddC(a, k) => v[a] + c[k],
                Op::SubC(a, k) => v[a] - c[k],
                Op::CSub(a, k) => -v[a] + c[k],
                Op::MulC(a, k) => v[a] * c[k],
                Op::CDiv(a, k) => v[a].recip() * c[k],
                Op::Linear(a, k, b, l) => v[a] * c[k] + v[b] * c[l],
                Op::PowI(a, n) => v[a].powi(n),
                Op::PowF(a, x) => v[a].powf(x),
                Op::PowC(a, k) => (v[a].ln() * c[k]).exp(),
                Op::ExpMulC(a, k) => (v[a] * c[k]).exp(),
                Op::Unary(f, a) => f.apply(v[a]),
            };
            v[ins.dest] = x;
        }
        v[self.result]
    }
}
