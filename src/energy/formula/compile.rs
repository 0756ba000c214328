//! From the syntax tree to the [`Program`]: names resolved (definitions, parameters, invariants,
//! derived invariants), numbers folded, equal subexpressions computed once, the parameter-only
//! subexpressions moved to the constant tape, and what can be refused before any evaluation
//! refused there.
//!
//! **Refused at compile time** (each with where it is in the formula): an unknown name or
//! function (with the nearest known one); a definition that redefines a word of the language, a
//! parameter or an earlier definition, or that W does not use; a declared parameter that W does
//! not use (a fit of it would be singular); a W that does not depend on the deformation; an
//! operation on numbers alone that has no finite result (1/0, ln(−1)); and an operation on
//! parameters alone that may leave its domain for parameter values within their ranges: a
//! division by, or a negative power of, an expression that may be 0, the logarithm of one that
//! may be ≤ 0, the square root of one that may be < 0, a non-integer or parameter power of a base
//! that may be ≤ 0. That last check is a sign analysis: each parameter's sign follows from its
//! open range (lower, upper), each invariant is positive, and signs propagate through the
//! operations (a sum of positives is positive, a product of non-zeros non-zero, eˣ positive, ...).
//! An expression it cannot prove non-zero is refused; the cure is a range that excludes 0.

use super::program::{ConstantOp, Op, Program};
use super::symbols::{self, Function};
use super::syntax::{self, excerpt, place, BinaryOp, Expr, ExprKind};
use super::FormulaError;
use std::collections::HashMap;

/// A node of the expression graph (operands are earlier nodes).
#[derive(Debug, Clone, Copy, PartialEq)]
enum Node {
    Literal(f64),
    Parameter(usize),
    Invariant(usize),
    Unary(Function, usize),
    Binary(BinaryOp, usize, usize),
    PowI(usize, i32),
}

/// [`Node`] with its number as bits, to find equal nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
enum Key {
    Literal(u64),
    Parameter(usize),
    Invariant(usize),
    Unary(Function, usize),
    Binary(BinaryOp, usize, usize),
    PowI(usize, i32),
}

impl Node {
    fn key(self) -> Key {
        match self {
            Node::Literal(x) => Key::Literal(x.to_bits()),
            Node::Parameter(k) => Key::Parameter(k),
            Node::Invariant(k) => Key::Invariant(k),
            Node::Unary(f, a) => Key::Unary(f, a),
            Node::Binary(op, a, b) => Key::Binary(op, a, b),
            Node::PowI(a, n) => Key::PowI(a, n),
        }
    }
}

/// The signs a value may take over every admissible state and parameter set.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Sign {
    negative: bool,
    zero: bool,
    positive: bool,
}

impl Sign {
    const POSITIVE: Sign = Sign {
        negative: false,
        zero: false,
        positive: true,
    };
    const ANY: Sign = Sign {
        negative: true,
        zero: true,
        positive: true,
    };

    fn of_value(x: f64) -> Sign {
        Sign {
            negative: x < 0.0,
            zero: x == 0.0,
            positive: x > 0.0,
        }
    }

    /// A value in the open interval (lower, upper).
    fn of_range((lower, upper): (f64, f64)) -> Sign {
        Sign {
            negative: lower < 0.0,
            zero: lower < 0.0 && upper > 0.0,
            positive: upper > 0.0,
        }
    }

    fn negated(self) -> Sign {
        Sign {
            negative: self.positive,
            zero: self.zero,
            positive: self.negative,
        }
    }

    fn sum(a: Sign, b: Sign) -> Sign {
        Sign {
            negative: a.negative || b.negative,
            zero: (a.zero && b.zero) || (a.negative && b.positive) || (a.positive && b.negative),
            positive: a.positive || b.positive,
        }
    }

    fn product(a: Sign, b: Sign) -> Sign {
        Sign {
            negative: (a.positive && b.negative) || (a.negative && b.positive),
            zero: a.zero || b.zero,
            positive: (a.positive && b.positive) || (a.negative && b.negative),
        }
    }

    fn power(a: Sign, n: i32) -> Sign {
        if n % 2 == 0 {
            Sign {
                negative: false,
                zero: a.zero,
                positive: a.positive || a.negative,
            }
        } else {
            a
        }
    }

    fn unary(f: Function, a: Sign) -> Sign {
        match f {
            Function::Neg => a.negated(),
            Function::Exp | Function::Cosh => Sign::POSITIVE,
            Function::Sqrt => Sign {
                negative: false,
                zero: a.zero,
                positive: a.positive,
            },
            Function::Ln => Sign::ANY,
            Function::ExpM1
            | Function::Ln1p
            | Function::Cbrt
            | Function::Sinh
            | Function::Tanh
            | Function::Atan => a,
        }
    }
}

/// What is known of a node: whether it depends on the invariants, its sign, its text.
#[derive(Debug, Clone, Copy)]
struct Info {
    varies: bool,
    sign: Sign,
    /// Bytes of the formula it was first read from (derived invariants: the name using them).
    start: usize,
    end: usize,
}

/// A name in scope: a definition (and whether it was used) or a derived invariant.
struct Scope {
    definitions: Vec<(String, usize, bool)>,
    derived: HashMap<&'static str, usize>,
}

/// The expression graph under construction.
struct Graph<'a> {
    text: &'a str,
    parameters: &'a [(String, (f64, f64))],
    used: Vec<bool>,
    nodes: Vec<Node>,
    info: Vec<Info>,
    index: HashMap<Key, usize>,
}

/// Compiles `text` for the parameters `(name, open range)`, in order.
pub fn compile(text: &str, parameters: &[(String, (f64, f64))]) -> Result<Program, FormulaError> {
    let source = syntax::parse(text)?;
    let mut g = Graph {
        text,
        parameters,
        used: vec![false; parameters.len()],
        nodes: Vec::new(),
        info: Vec::new(),
        index: HashMap::new(),
    };
    let mut scope = Scope {
        definitions: Vec::new(),
        derived: HashMap::new(),
    };
    for (name, at, value) in &source.definitions {
        g.may_define(name, *at, &scope)?;
        let node = g.build(value, &mut scope)?;
        scope.definitions.push((name.clone(), node, false));
    }
    let root = g.build(&source.result, &mut scope)?;
    g.all_used(&source, &scope)?;
    if !g.info[root].varies {
        return Err(FormulaError::formula(
            excerpt(text, source.result.start, source.result.end),
            "W does not depend on the deformation: write it in the invariants (tr_c, c_m, tr_c_inv, c_inv_m, det_c, I1, I4, J, ...)",
        ));
    }
    Ok(Emitter::new(&mut g).program(root))
}

impl Graph<'_> {
    /// A definition may not take a word of the language, a parameter's name or an earlier
    /// definition's.
    fn may_define(&self, name: &str, at: usize, scope: &Scope) -> Result<(), FormulaError> {
        let clash = if symbols::reserved(name) {
            Some("a word of the formula language (an invariant or a function)")
        } else if self.parameters.iter().any(|p| p.0 == name) {
            Some("a parameter")
        } else if scope.definitions.iter().any(|d| d.0 == name) {
            Some("defined earlier")
        } else {
            None
        };
        match clash {
            Some(what) => Err(FormulaError::formula(
                name,
                format!(
                    "`{name}` is {what}: give the definition another name ({})",
                    place(self.text, at)
                ),
            )),
            None => Ok(()),
        }
    }

    /// Every definition and every declared parameter is used.
    fn all_used(&self, source: &syntax::Source, scope: &Scope) -> Result<(), FormulaError> {
        for ((name, at, _), (_, _, used)) in source.definitions.iter().zip(&scope.definitions) {
            if !used {
                return Err(FormulaError::formula(
                    name.as_str(),
                    format!(
                        "`{name}` is defined ({}) but not used",
                        place(self.text, *at)
                    ),
                ));
            }
        }
        match self.used.iter().position(|u| !u) {
            Some(k) => {
                let name = &self.parameters[k].0;
                Err(FormulaError::parameter(
                    name,
                    "",
                    "(declared)",
                    format!("W does not use parameter {name}: remove it, or use it in W (a fit of it would have no data to go on)"),
                ))
            }
            None => Ok(()),
        }
    }

    /// The node of `node`, shared with an equal one built before.
    fn intern(&mut self, node: Node, info: Info) -> usize {
        if let Some(&i) = self.index.get(&node.key()) {
            return i;
        }
        self.nodes.push(node);
        self.info.push(info);
        self.index.insert(node.key(), self.nodes.len() - 1);
        self.nodes.len() - 1
    }

    fn literal(&mut self, x: f64, e: &Expr) -> Result<usize, FormulaError> {
        if !x.is_finite() {
            return Err(FormulaError::formula(
                excerpt(self.text, e.start, e.end),
                format!(
                    "has no finite value ({}): it is {x}",
                    place(self.text, e.start)
                ),
            ));
        }
        let info = Info {
            varies: false,
            sign: Sign::of_value(x),
            start: e.start,
            end: e.end,
        };
        Ok(self.intern(Node::Literal(x), info))
    }

    fn value(&self, n: usize) -> Option<f64> {
        match self.nodes[n] {
            Node::Literal(x) => Some(x),
            _ => None,
        }
    }

    fn build(&mut self, e: &Expr, scope: &mut Scope) -> Result<usize, FormulaError> {
        match &e.kind {
            ExprKind::Number(x) => self.literal(*x, e),
            ExprKind::Name(name) => self.name(name, e, scope),
            ExprKind::Call(name, argument) => {
                let Some(f) = symbols::function(name) else {
                    return Err(self.unknown_function(name, e, scope));
                };
                let a = self.build(argument, scope)?;
                self.unary(f, a, e)
            }
            ExprKind::Neg(a) => {
                let a = self.build(a, scope)?;
                self.unary(Function::Neg, a, e)
            }
            ExprKind::Binary(op, a, b) => {
                let (a, b) = (self.build(a, scope)?, self.build(b, scope)?);
                self.binary(*op, a, b, e)
            }
        }
    }

    fn name(&mut self, name: &str, e: &Expr, scope: &mut Scope) -> Result<usize, FormulaError> {
        if let Some(d) = scope.definitions.iter_mut().find(|d| d.0 == name) {
            d.2 = true;
            return Ok(d.1);
        }
        if let Some(k) = self.parameters.iter().position(|p| p.0 == name) {
            self.used[k] = true;
            let info = Info {
                varies: false,
                sign: Sign::of_range(self.parameters[k].1),
                start: e.start,
                end: e.end,
            };
            return Ok(self.intern(Node::Parameter(k), info));
        }
        if let Some(k) = symbols::invariant(name) {
            let info = Info {
                varies: true,
                sign: Sign::POSITIVE,
                start: e.start,
                end: e.end,
            };
            return Ok(self.intern(Node::Invariant(k), info));
        }
        if let Some(definition) = symbols::DERIVED.iter().find(|d| d.0 == name) {
            if let Some(&n) = scope.derived.get(definition.0) {
                return Ok(n);
            }
            // The vocabulary is written in the language; its text is not the user's, so its
            // nodes are placed at the name that uses it.
            let mut expr = syntax::parse(definition.1)?.result;
            place_at(&mut expr, e.start, e.end);
            let n = self.build(&expr, scope)?;
            scope.derived.insert(definition.0, n);
            return Ok(n);
        }
        if symbols::function(name).is_some() {
            return Err(FormulaError::formula(
                name,
                format!(
                    "`{name}` is a function: write {name}(x) ({})",
                    place(self.text, e.start)
                ),
            ));
        }
        let mut known: Vec<&str> = self.parameters.iter().map(|p| p.0.as_str()).collect();
        known.extend(scope.definitions.iter().map(|d| d.0.as_str()));
        known.extend(symbols::INVARIANTS.iter().map(|i| i.0));
        known.extend(symbols::DERIVED.iter().map(|d| d.0));
        Err(FormulaError::formula(
            name,
            format!(
                "unknown name `{name}` ({}){}; the names are the parameters ({}), the definitions, the invariants tr_c, c_m, tr_c_inv, c_inv_m, det_c and I1, I2, I3, J, I4, lambda_f, I1_bar, I2_bar, I4_bar",
                place(self.text, e.start),
                symbols::suggestion(name, &known),
                self.parameter_names()
            ),
        ))
    }

    fn parameter_names(&self) -> String {
        if self.parameters.is_empty() {
            "none declared".into()
        } else {
            let names: Vec<&str> = self.parameters.iter().map(|p| p.0.as_str()).collect();
            names.join(", ")
        }
    }

    fn unknown_function(&self, name: &str, e: &Expr, scope: &Scope) -> FormulaError {
        let not_a_function = self.parameters.iter().any(|p| p.0 == name)
            || scope.definitions.iter().any(|d| d.0 == name)
            || symbols::invariant(name).is_some()
            || symbols::derived(name).is_some();
        let names: Vec<&str> = symbols::FUNCTIONS.iter().map(|f| f.0).collect();
        let rule = if not_a_function {
            format!("`{name}` is not a function: a product is written {name}*(...)")
        } else {
            format!(
                "unknown function `{name}`{}; the functions are {}",
                symbols::suggestion(name, &names),
                names.join(", ")
            )
        };
        FormulaError::formula(name, format!("{rule} ({})", place(self.text, e.start)))
    }

    /// The parameters a parameter-only node depends on, with their ranges, in words.
    fn ranges_in(&self, n: usize) -> String {
        let mut found = Vec::new();
        let mut stack = vec![n];
        while let Some(m) = stack.pop() {
            match self.nodes[m] {
                Node::Parameter(k) if !found.contains(&k) => found.push(k),
                Node::Unary(_, a) | Node::PowI(a, _) => stack.push(a),
                Node::Binary(_, a, b) => stack.extend([a, b]),
                _ => {}
            }
        }
        found.sort_unstable();
        let words: Vec<String> = found
            .iter()
            .map(|&k| {
                let (name, (lo, hi)) = &self.parameters[k];
                format!("{name} ∈ ({lo}, {hi})")
            })
            .collect();
        words.join(", ")
    }

    /// Refuses `what` (`a division by`) of operand `n` if it depends on parameters only and
    /// `bad` (its sign may be what the operation cannot take: `may`, e.g. `may be 0`).
    fn domain(&self, n: usize, bad: bool, what: &str, may: &str) -> Result<(), FormulaError> {
        let i = self.info[n];
        if i.varies || !bad || self.value(n).is_some() {
            return Ok(());
        }
        Err(FormulaError::formula(
            excerpt(self.text, i.start, i.end),
            format!(
                "{what} `{}`, which {may} for parameter values within their ranges ({}) ({}): give the parameters ranges that exclude it (range = [lower, upper] means lower < value < upper; e.g. range = [0, inf] for a positive parameter)",
                excerpt(self.text, i.start, i.end),
                self.ranges_in(n),
                place(self.text, i.start)
            ),
        ))
    }

    fn unary(&mut self, f: Function, a: usize, e: &Expr) -> Result<usize, FormulaError> {
        let s = self.info[a].sign;
        match f {
            Function::Ln => {
                self.domain(a, s.negative || s.zero, "the logarithm of", "may be ≤ 0")?
            }
            Function::Sqrt => self.domain(a, s.negative, "the square root of", "may be < 0")?,
            _ => {}
        }
        if let Some(x) = self.value(a) {
            return self.literal(f.apply(x), e);
        }
        if let (Function::Neg, Node::Unary(Function::Neg, inner)) = (f, self.nodes[a]) {
            return Ok(inner);
        }
        let info = Info {
            varies: self.info[a].varies,
            sign: Sign::unary(f, s),
            start: e.start,
            end: e.end,
        };
        Ok(self.intern(Node::Unary(f, a), info))
    }

    fn binary(
        &mut self,
        op: BinaryOp,
        a: usize,
        b: usize,
        e: &Expr,
    ) -> Result<usize, FormulaError> {
        let (sa, sb) = (self.info[a].sign, self.info[b].sign);
        if let Some(y) = self.value(b) {
            if op == BinaryOp::Pow && y == y.trunc() && y.abs() <= 64.0 {
                return self.integer_power(a, y as i32, e);
            }
            if op == BinaryOp::Div && y == 0.0 {
                return Err(FormulaError::formula(
                    excerpt(self.text, e.start, e.end),
                    format!("a division by 0 ({})", place(self.text, e.start)),
                ));
            }
        }
        match op {
            BinaryOp::Div => self.domain(b, sb.zero, "a division by", "may be 0")?,
            BinaryOp::Pow => self.domain(
                a,
                sa.negative || sa.zero,
                "a non-integer or parameter power of",
                "may be ≤ 0",
            )?,
            _ => {}
        }
        if let (Some(x), Some(y)) = (self.value(a), self.value(b)) {
            let folded = match op {
                BinaryOp::Add => x + y,
                BinaryOp::Sub => x - y,
                BinaryOp::Mul => x * y,
                BinaryOp::Div => x / y,
                BinaryOp::Pow => x.powf(y),
            };
            return self.literal(folded, e);
        }
        let sign = match op {
            BinaryOp::Add => Sign::sum(sa, sb),
            BinaryOp::Sub => Sign::sum(sa, sb.negated()),
            BinaryOp::Mul => Sign::product(sa, sb),
            BinaryOp::Div => Sign {
                zero: sa.zero,
                ..Sign::product(sa, sb)
            },
            BinaryOp::Pow => Sign {
                zero: sa.zero,
                ..Sign::POSITIVE
            },
        };
        let info = Info {
            varies: self.info[a].varies || self.info[b].varies,
            sign,
            start: e.start,
            end: e.end,
        };
        Ok(self.intern(Node::Binary(op, a, b), info))
    }

    fn integer_power(&mut self, a: usize, n: i32, e: &Expr) -> Result<usize, FormulaError> {
        let s = self.info[a].sign;
        if n < 0 {
            self.domain(a, s.zero, "a negative power of", "may be 0")?;
        }
        match (n, self.value(a)) {
            (_, Some(x)) => self.literal(x.powi(n), e),
            (0, None) => self.literal(1.0, e),
            (1, None) => Ok(a),
            _ => {
                let info = Info {
                    varies: self.info[a].varies,
                    sign: Sign::power(s, n),
                    start: e.start,
                    end: e.end,
                };
                Ok(self.intern(Node::PowI(a, n), info))
            }
        }
    }
}

/// Moves every node of `e` to the bytes `start..end` (a derived invariant's nodes to the name
/// that uses it).
fn place_at(e: &mut Expr, start: usize, end: usize) {
    e.start = start;
    e.end = end;
    match &mut e.kind {
        ExprKind::Call(_, a) | ExprKind::Neg(a) => place_at(a, start, end),
        ExprKind::Binary(_, a, b) => {
            place_at(a, start, end);
            place_at(b, start, end);
        }
        ExprKind::Number(_) | ExprKind::Name(_) => {}
    }
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
        self.variable(root);
        Program {
            constants: self.constants,
            ops: self.ops,
        }
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

    /// The energy-tape result of node `n`, which depends on the invariants.
    fn variable(&mut self, n: usize) -> usize {
        if let Some(&k) = self.op_of.get(&n) {
            return k;
        }
        let op = match self.graph.nodes[n] {
            Node::Invariant(k) => Op::Invariant(k),
            Node::Unary(f, a) => Op::Unary(f, self.variable(a)),
            Node::PowI(a, m) => Op::PowI(self.variable(a), m),
            Node::Binary(op, a, b) => self.mixed(op, a, b),
            Node::Literal(_) | Node::Parameter(_) => {
                unreachable!("parameter-only nodes enter the energy tape as constants")
            }
        };
        self.ops.push(op);
        self.op_of.insert(n, self.ops.len() - 1);
        self.ops.len() - 1
    }

    /// a ∘ b where at least one operand depends on the invariants: the other, if it does not,
    /// enters as a constant.
    fn mixed(&mut self, op: BinaryOp, a: usize, b: usize) -> Op {
        let varies = |s: &Self, n: usize| s.graph.info[n].varies;
        match (varies(self, a), varies(self, b)) {
            (true, true) => Op::Binary(op, self.variable(a), self.variable(b)),
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
