//! From the syntax tree to an expression graph: names resolved (definitions, parameters,
//! invariants, derived invariants), numbers folded, equal subexpressions one node, and what can
//! be refused before any evaluation refused there ([`super::emit`] turns the graph into the
//! [`super::program::Program`]).
//!
//! **Refused at compile time** (each with where it is in the formula): an unknown name or
//! function (with the nearest known one); a definition that redefines a word of the language, a
//! parameter or an earlier definition, or that W does not use; a declared parameter that W does
//! not use (a fit of it would be singular); a W that does not depend on the deformation; an
//! operation on numbers alone that has no finite result (1/0, ln(−1)); and an operation on
//! parameters alone that may leave its domain for parameter values within their ranges: a
//! division by, or a negative power of, an expression that may be 0, the logarithm of one that
//! may be ≤ 0, the square root of one that may be < 0, a non-integer or parameter power of a base
//! that may be ≤ 0. That last check is a sign analysis ([`super::sign`]); an expression it cannot
//! prove non-zero is refused, and the cure is a range that excludes 0.

use super::sign::Sign;
use super::symbols::{self, Function};
use super::syntax::{self, excerpt, place, BinaryOp, Expr, ExprKind};
use super::FormulaError;
use std::collections::HashMap;

/// A node of the expression graph (operands are earlier nodes).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Node {
    /// A number.
    Literal(f64),
    /// Parameter k.
    Parameter(usize),
    /// Invariant k.
    Invariant(usize),
    /// f(a).
    Unary(Function, usize),
    /// a ∘ b.
    Binary(BinaryOp, usize, usize),
    /// aⁿ, n an integer.
    PowI(usize, i32),
}

/// [`Node`] with its number as bits, to find equal nodes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Key {
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

/// What is known of a node: whether it depends on the invariants, its sign, its text.
#[derive(Debug, Clone, Copy)]
pub struct Info {
    /// It depends on the invariants.
    pub varies: bool,
    /// Its sign.
    pub sign: Sign,
    /// Bytes of the formula it was first read from (derived invariants: the name using them).
    pub start: usize,
    /// End of that text (exclusive).
    pub end: usize,
}

/// A name in scope: a definition (and whether it was used) or a derived invariant.
struct Scope {
    definitions: Vec<(String, usize, bool)>,
    derived: HashMap<&'static str, usize>,
}

/// The expression graph: its nodes (operands first) and what is known of each.
pub struct Graph<'a> {
    text: &'a str,
    parameters: &'a [(String, (f64, f64))],
    used: Vec<bool>,
    /// The nodes.
    pub nodes: Vec<Node>,
    /// What is known of each node.
    pub info: Vec<Info>,
    index: HashMap<Key, usize>,
}

/// The graph of `text` for the parameters `(name, open range)`, in order, and the node of W.
pub fn compile<'a>(
    text: &'a str,
    parameters: &'a [(String, (f64, f64))],
) -> Result<(Graph<'a>, usize), FormulaError> {
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
    Ok((g, root))
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
    pub fn intern(&mut self, node: Node, info: Info) -> usize {
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

    pub fn value(&self, n: usize) -> Option<f64> {
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
