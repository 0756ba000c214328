//! From the expression graph to the [`Program`]: each node once, operands first; the nodes of
//! the parameters alone to the constant tape, the others to the energy tape with the constants
//! entering as numbers (a division by a constant as a product with its reciprocal, x·k ± y·l as one
//! instruction, a constant base's power through its logarithm).

use super::compile::{Graph, Info, Node};
use super::program::{ConstantOp, Op, Program, PRELOADED};
use super::sign::Sign;
use super::symbols::Function;
use super::syntax::BinaryOp;
use std::collections::HashMap;

/// The program of the graph `graph` whose node of W is `root`.
pub fn program(graph: &mut Graph, root: usize) -> Program {
    Emitter::new(graph).program(root)
}

/// Emits the two tapes from the graph, each node once, operands first.
struct Emitter<'g, 'a> {
    graph: &'g mut Graph<'a>,
    constants: Vec<ConstantOp>,
    constant_of: HashMap<usize, usize>,
    ops: Vec<Op>,
    op_of: HashMap<usize, usize>,
}

impl<'g, 'a> Emitter<'g, 'a> {
    fn new(graph: &'g mut Graph<'a>) -> Self {
        Self {
            graph,
            constants: Vec::new(),
            constant_of: HashMap::new(),
            ops: Vec::new(),
            op_of: HashMap::new(),
        }
    }

    fn program(mut self, root: usize) -> Program {
        let root = self.variable(root);
        Program::new(self.constants, &self.ops, root)
    }

    /// The constant-tape result of parameter-only node `n`.
    fn constant(&mut self, n: usize) -> usize {
        if let Some(&k) = self.constant_of.get(&n) {
            return k;
        }
        let op = match self.graph.nodes[n] {
            Node::Literal(x) => ConstantOp::Literal(x),
            Node::Parameter(k) => ConstantOp::Parameter(k),
            Node::Unary(f, a) => ConstantOp::Unary(f, self.constant(a)),
            Node::PowI(a, m) => ConstantOp::PowI(self.constant(a), m),
            Node::Binary(BinaryOp::Pow, a, b) if self.graph.value(b).is_some() => {
                ConstantOp::PowF(self.constant(a), self.graph.value(b).unwrap_or(1.0))
            }
            Node::Binary(op, a, b) => ConstantOp::Binary(op, self.constant(a), self.constant(b)),
            Node::Invariant(_) => unreachable!("the constant tape holds parameter-only nodes"),
        };
        self.constants.push(op);
        self.constant_of.insert(n, self.constants.len() - 1);
        self.constants.len() - 1
    }

    /// The constant-tape result 1/b of parameter-only node `b` (not 0: checked when the
    /// division was built).
    fn reciprocal(&mut self, b: usize) -> usize {
        let info = self.graph.info[b];
        let node = match self.graph.value(b) {
            Some(y) => Node::Literal(1.0 / y),
            None => {
                let one = self.graph.intern(
                    Node::Literal(1.0),
                    Info {
                        sign: Sign::POSITIVE,
                        ..info
                    },
                );
                Node::Binary(BinaryOp::Div, one, b)
            }
        };
        let r = self.graph.intern(node, info);
        self.constant(r)
    }

    /// The energy-tape result of node `n`, which depends on the invariants (invariant k is
    /// result k, preloaded).
    fn variable(&mut self, n: usize) -> usize {
        if let Some(&k) = self.op_of.get(&n) {
            return k;
        }
        let op = match self.graph.nodes[n] {
            Node::Invariant(k) => return k,
            Node::Unary(f, a) => Op::Unary(f, self.variable(a)),
            Node::PowI(a, m) => Op::PowI(self.variable(a), m),
            Node::Binary(op, a, b) => self.mixed(op, a, b),
            Node::Literal(_) | Node::Parameter(_) => {
                unreachable!("parameter-only nodes enter the energy tape as constants")
            }
        };
        self.ops.push(op);
        let result = PRELOADED + self.ops.len() - 1;
        self.op_of.insert(n, result);
        result
    }

    /// (x, k) if node `n` is x · k with x depending on the invariants and k not, and has no
    /// result of its own yet (a linear combination then computes it in place).
    fn scaled(&self, n: usize) -> Option<(usize, usize)> {
        let Node::Binary(BinaryOp::Mul, a, b) = self.graph.nodes[n] else {
            return None;
        };
        if self.op_of.contains_key(&n) {
            return None;
        }
        match (self.graph.info[a].varies, self.graph.info[b].varies) {
            (true, false) => Some((a, b)),
            (false, true) => Some((b, a)),
            _ => None,
        }
    }

    /// x·k ± y·l as one instruction, if `a` and `b` are such products.
    fn linear(&mut self, op: BinaryOp, a: usize, b: usize) -> Option<Op> {
        if !matches!(op, BinaryOp::Add | BinaryOp::Sub) {
            return None;
        }
        let ((x, k), (y, l)) = (self.scaled(a)?, self.scaled(b)?);
        let l = if op == BinaryOp::Sub {
            let info = self.graph.info[l];
            let sign = info.sign;
            self.graph.intern(
                Node::Unary(Function::Neg, l),
                Info {
                    sign: Sign::unary(Function::Neg, sign),
                    ..info
                },
            )
        } else {
            l
        };
        let (x, y) = (self.variable(x), self.variable(y));
        Some(Op::Linear(x, self.constant(k), y, self.constant(l)))
    }

    /// a ∘ b where at least one operand depends on the invariants: the other, if it does not,
    /// enters as a constant.
    fn mixed(&mut self, op: BinaryOp, a: usize, b: usize) -> Op {
        let varies = |s: &Self, n: usize| s.graph.info[n].varies;
        match (varies(self, a), varies(self, b)) {
            (true, true) => {
                if let Some(linear) = self.linear(op, a, b) {
                    return linear;
                }
                let (x, y) = (self.variable(a), self.variable(b));
                match op {
                    BinaryOp::Add => Op::Add(x, y),
                    BinaryOp::Sub => Op::Sub(x, y),
                    BinaryOp::Mul => Op::Mul(x, y),
                    BinaryOp::Div => Op::Div(x, y),
                    BinaryOp::Pow => Op::Pow(x, y),
                }
            }
            (true, false) => {
                let x = self.variable(a);
                match (op, self.graph.value(b)) {
                    (BinaryOp::Pow, Some(y)) => return Op::PowF(x, y),
                    // A dual number times a number costs less than over it.
                    (BinaryOp::Div, _) => return Op::MulC(x, self.reciprocal(b)),
                    _ => {}
                }
                let k = self.constant(b);
                match op {
                    BinaryOp::Add => Op::AddC(x, k),
                    BinaryOp::Sub => Op::SubC(x, k),
                    BinaryOp::Mul => Op::MulC(x, k),
                    _ => Op::PowC(x, k),
                }
            }
            _ => {
                let y = self.variable(b);
                if op == BinaryOp::Pow {
                    // c^y = e^{y ln c}; the base is positive (checked when it was built).
                    let info = self.graph.info[a];
                    let ln = self.graph.intern(
                        Node::Unary(Function::Ln, a),
                        Info {
                            sign: Sign::ANY,
                            ..info
                        },
                    );
                    return Op::ExpMulC(y, self.constant(ln));
                }
                let k = self.constant(a);
                match op {
                    BinaryOp::Add => Op::AddC(y, k),
                    BinaryOp::Sub => Op::CSub(y, k),
                    BinaryOp::Mul => Op::MulC(y, k),
                    _ => Op::CDiv(y, k),
                }
            }
        }
    }
}
