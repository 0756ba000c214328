//! The grammar of a formula: text → a syntax tree, by recursive descent.
//!
//! ```text
//! source     = { definition ";" } expression [ ";" ]
//! definition = name "=" expression
//! expression = term { ("+" | "-") term }
//! term       = unary { ("*" | "/") unary }
//! unary      = ("-" | "+") unary | power
//! power      = primary [ ("^" | "**") unary ]          (right-associative: 2^3^2 = 2^9)
//! primary    = number | name | name "(" expression ")" | "(" expression ")"
//! ```
//!
//! Numbers are decimal (`2`, `0.5`, `.5`, `1e-3`); names are ASCII letters, digits and `_`, not
//! starting with a digit; `#` starts a comment to the end of the line; spaces and line breaks
//! separate nothing. So `-x^2` is −(x²), `2^-1` is ½ and `a/b*c` is (a/b)·c, as in mathematics.
//! At most [`MAX_BYTES`] bytes, [`MAX_NODES`] terms and [`MAX_DEPTH`] levels of nesting: a
//! formula is a line or a page, and the limits keep every recursion here and in the compiler
//! shallow.

use super::FormulaError;

/// The longest formula \[bytes\].
pub const MAX_BYTES: usize = 16 * 1024;
/// The most numbers, names, operators and calls a formula may hold.
pub const MAX_NODES: usize = 1000;
/// The deepest nesting of parentheses, signs and powers.
pub const MAX_DEPTH: usize = 64;

/// A binary operator.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum BinaryOp {
    /// a + b.
    Add,
    /// a − b.
    Sub,
    /// a · b.
    Mul,
    /// a / b.
    Div,
    /// a^b.
    Pow,
}

/// A node of the syntax tree, with the bytes of the formula it was read from.
#[derive(Debug, Clone, PartialEq)]
pub struct Expr {
    /// What it is.
    pub kind: ExprKind,
    /// Its text spans `start..end` of the formula.
    pub start: usize,
    /// End of its text (exclusive).
    pub end: usize,
}

/// The kinds of node.
#[derive(Debug, Clone, PartialEq)]
pub enum ExprKind {
    /// A number as written.
    Number(f64),
    /// A name: an invariant, a parameter, a definition.
    Name(String),
    /// A function of one argument.
    Call(String, Box<Expr>),
    /// −a.
    Neg(Box<Expr>),
    /// a ∘ b.
    Binary(BinaryOp, Box<Expr>, Box<Expr>),
}

/// A parsed formula: its definitions in order (name, where the name is, value) and the
/// expression of W.
#[derive(Debug, Clone, PartialEq)]
pub struct Source {
    /// `name = expression;` in the order written.
    pub definitions: Vec<(String, usize, Expr)>,
    /// W.
    pub result: Expr,
}

/// A token and where it starts and ends.
#[derive(Debug, Clone, PartialEq)]
struct Token {
    kind: TokenKind,
    start: usize,
    end: usize,
}

#[derive(Debug, Clone, PartialEq)]
enum TokenKind {
    Number(f64),
    Name(String),
    /// One of `+ - * / ^ ( ) ; =` (`**` is read as `^`).
    Symbol(char),
    End,
}

/// "line 2, column 5" (1-based, in characters) of byte `offset` of `text`; "column 5" in a
/// formula of one line.
pub fn place(text: &str, offset: usize) -> String {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() + 1;
    let column = before.rsplit('\n').next().unwrap_or("").chars().count() + 1;
    if text.contains('\n') {
        format!("line {line}, column {column} of W")
    } else {
        format!("column {column} of W")
    }
}

/// The text of `text[start..end]` with runs of white space as one space.
pub fn excerpt(text: &str, start: usize, end: usize) -> String {
    let piece = text.get(start..end.min(text.len())).unwrap_or("");
    piece.split_whitespace().collect::<Vec<_>>().join(" ")
}

fn tokens(text: &str) -> Result<Vec<Token>, FormulaError> {
    let bytes = text.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let c = bytes[i];
        let start = i;
        let kind = if c.is_ascii_whitespace() {
            i += 1;
            continue;
        } else if c == b'#' {
            while i < bytes.len() && bytes[i] != b'\n' {
                i += 1;
            }
            continue;
        } else if c.is_ascii_digit()
            || (c == b'.' && bytes.get(i + 1).is_some_and(u8::is_ascii_digit))
        {
            i = number_end(bytes, i);
            let written = &text[start..i];
            match written.parse::<f64>() {
                Ok(x) if x.is_finite() => TokenKind::Number(x),
                _ => {
                    return Err(FormulaError::formula(
                        written,
                        format!("not a finite number ({})", place(text, start)),
                    ))
                }
            }
        } else if c.is_ascii_alphabetic() || c == b'_' {
            while i < bytes.len() && (bytes[i].is_ascii_alphanumeric() || bytes[i] == b'_') {
                i += 1;
            }
            TokenKind::Name(text[start..i].to_string())
        } else if c == b'*' && bytes.get(i + 1) == Some(&b'*') {
            i += 2;
            TokenKind::Symbol('^')
        } else if b"+-*/^();=,".contains(&c) {
            i += 1;
            TokenKind::Symbol(c as char)
        } else {
            let ch = text[start..].chars().next().unwrap_or('?');
            return Err(FormulaError::formula(
                ch.to_string(),
                format!(
                    "unexpected character ({}): a formula has numbers, names, + - * / ^ ( ) and ; between definitions",
                    place(text, start)
                ),
            ));
        };
        out.push(Token {
            kind,
            start,
            end: i,
        });
    }
    out.push(Token {
        kind: TokenKind::End,
        start: text.len(),
        end: text.len(),
    });
    Ok(out)
}

/// The end of the number starting at `i`: digits, a point, digits, an exponent.
fn number_end(bytes: &[u8], mut i: usize) -> usize {
    let digits = |mut i: usize| {
        while i < bytes.len() && bytes[i].is_ascii_digit() {
            i += 1;
        }
        i
    };
    i = digits(i);
    if bytes.get(i) == Some(&b'.') {
        i = digits(i + 1);
    }
    if matches!(bytes.get(i), Some(b'e' | b'E')) {
        let mut j = i + 1;
        if matches!(bytes.get(j), Some(b'+' | b'-')) {
            j += 1;
        }
        if bytes.get(j).is_some_and(u8::is_ascii_digit) {
            i = digits(j);
        }
    }
    i
}

/// Parses `text` into its definitions and the expression of W.
pub fn parse(text: &str) -> Result<Source, FormulaError> {
    if text.len() > MAX_BYTES {
        return Err(FormulaError::formula(
            format!("({} bytes)", text.len()),
            format!("a formula has at most {MAX_BYTES} bytes"),
        ));
    }
    let mut p = Parser {
        text,
        tokens: tokens(text)?,
        next: 0,
        nodes: 0,
        depth: 0,
    };
    let mut definitions = Vec::new();
    loop {
        if p.peek() == &TokenKind::End {
            return Err(p.expected("an expression for W"));
        }
        let assigned = p.tokens.get(p.next + 1).map(|t| &t.kind) == Some(&TokenKind::Symbol('='));
        if let (TokenKind::Name(name), true) = (p.peek().clone(), assigned) {
            let at = p.advance().start;
            p.advance();
            let value = p.expression()?;
            if !p.eat(';') {
                return Err(p.expected("`;` after the definition"));
            }
            definitions.push((name, at, value));
            continue;
        }
        let result = p.expression()?;
        p.eat(';');
        if p.peek() != &TokenKind::End {
            return Err(
                p.expected("the end of W (definitions come first, `name = expression;`, then W)")
            );
        }
        return Ok(Source {
            definitions,
            result,
        });
    }
}

struct Parser<'a> {
    text: &'a str,
    tokens: Vec<Token>,
    next: usize,
    nodes: usize,
    depth: usize,
}

impl Parser<'_> {
    fn peek(&self) -> &TokenKind {
        &self.tokens[self.next.min(self.tokens.len() - 1)].kind
    }

    fn advance(&mut self) -> Token {
        let t = self.tokens[self.next.min(self.tokens.len() - 1)].clone();
        if self.next < self.tokens.len() - 1 {
            self.next += 1;
        }
        t
    }

    fn eat(&mut self, symbol: char) -> bool {
        if self.peek() == &TokenKind::Symbol(symbol) {
            self.advance();
            true
        } else {
            false
        }
    }

    /// "expected X, found Y (line 1, column 7 of W)".
    fn expected(&self, what: &str) -> FormulaError {
        let t = &self.tokens[self.next.min(self.tokens.len() - 1)];
        let found = match &t.kind {
            TokenKind::End => "the end of the formula".to_string(),
            _ => format!("`{}`", &self.text[t.start..t.end]),
        };
        FormulaError::formula(
            excerpt(self.text, t.start, t.end.max(t.start + 1)),
            format!(
                "expected {what}, found {found} ({})",
                place(self.text, t.start)
            ),
        )
    }

    /// A new node spanning `start..end`, counted against [`MAX_NODES`].
    fn node(&mut self, kind: ExprKind, start: usize, end: usize) -> Result<Expr, FormulaError> {
        self.nodes += 1;
        if self.nodes > MAX_NODES {
            return Err(FormulaError::formula(
                excerpt(self.text, start, end),
                format!("a formula has at most {MAX_NODES} numbers, names and operations (split it into definitions? they count too)"),
            ));
        }
        Ok(Expr { kind, start, end })
    }

    fn nested<T>(
        &mut self,
        at: usize,
        f: impl FnOnce(&mut Self) -> Result<T, FormulaError>,
    ) -> Result<T, FormulaError> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(FormulaError::formula(
                excerpt(self.text, at, at + 1),
                format!(
                    "nested more than {MAX_DEPTH} levels deep ({})",
                    place(self.text, at)
                ),
            ));
        }
        let out = f(self);
        self.depth -= 1;
        out
    }

    fn binary(&mut self, op: BinaryOp, a: Expr, b: Expr) -> Result<Expr, FormulaError> {
        let (start, end) = (a.start, b.end);
        self.node(ExprKind::Binary(op, Box::new(a), Box::new(b)), start, end)
    }

    fn expression(&mut self) -> Result<Expr, FormulaError> {
        let mut left = self.term()?;
        loop {
            let op = match self.peek() {
                TokenKind::Symbol('+') => BinaryOp::Add,
                TokenKind::Symbol('-') => BinaryOp::Sub,
                _ => return Ok(left),
            };
            self.advance();
            let right = self.term()?;
            left = self.binary(op, left, right)?;
        }
    }

    fn term(&mut self) -> Result<Expr, FormulaError> {
        let mut left = self.unary()?;
        loop {
            let op = match self.peek() {
                TokenKind::Symbol('*') => BinaryOp::Mul,
                TokenKind::Symbol('/') => BinaryOp::Div,
                _ => return Ok(left),
            };
            self.advance();
            let right = self.unary()?;
            left = self.binary(op, left, right)?;
        }
    }

    fn unary(&mut self) -> Result<Expr, FormulaError> {
        let t = self.tokens[self.next.min(self.tokens.len() - 1)].clone();
        match t.kind {
            TokenKind::Symbol('-') => {
                self.advance();
                let inner = self.nested(t.start, Self::unary)?;
                let end = inner.end;
                self.node(ExprKind::Neg(Box::new(inner)), t.start, end)
            }
            TokenKind::Symbol('+') => {
                self.advance();
                self.nested(t.start, Self::unary)
            }
            _ => self.power(),
        }
    }

    fn power(&mut self) -> Result<Expr, FormulaError> {
        let base = self.primary()?;
        if !self.eat('^') {
            return Ok(base);
        }
        let exponent = self.nested(base.start, Self::unary)?;
        self.binary(BinaryOp::Pow, base, exponent)
    }

    fn primary(&mut self) -> Result<Expr, FormulaError> {
        let t = self.tokens[self.next.min(self.tokens.len() - 1)].clone();
        match t.kind {
            TokenKind::Number(x) => {
                self.advance();
                self.node(ExprKind::Number(x), t.start, t.end)
            }
            TokenKind::Name(name) => {
                self.advance();
                if !self.eat('(') {
                    return self.node(ExprKind::Name(name), t.start, t.end);
                }
                let argument = self.nested(t.start, Self::expression)?;
                if self.peek() == &TokenKind::Symbol(',') {
                    return Err(self.expected(&format!("`)`: {name}(...) takes one argument")));
                }
                let close = self.tokens[self.next.min(self.tokens.len() - 1)].end;
                if !self.eat(')') {
                    return Err(self.expected(&format!("`)` closing {name}(")));
                }
                self.node(ExprKind::Call(name, Box::new(argument)), t.start, close)
            }
            TokenKind::Symbol('(') => {
                self.advance();
                let mut inner = self.nested(t.start, Self::expression)?;
                let close = self.tokens[self.next.min(self.tokens.len() - 1)].end;
                if !self.eat(')') {
                    return Err(self.expected("`)`"));
                }
                // The parentheses belong to the text of the expression inside.
                inner.start = t.start;
                inner.end = close;
                Ok(inner)
            }
            _ => Err(self.expected("a number, a name or `(`")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn shape(e: &Expr) -> String {
        match &e.kind {
            ExprKind::Number(x) => x.to_string(),
            ExprKind::Name(n) => n.clone(),
            ExprKind::Call(f, a) => format!("{f}({})", shape(a)),
            ExprKind::Neg(a) => format!("(-{})", shape(a)),
            ExprKind::Binary(op, a, b) => {
                let o = match op {
                    BinaryOp::Add => "+",
                    BinaryOp::Sub => "-",
                    BinaryOp::Mul => "*",
                    BinaryOp::Div => "/",
                    BinaryOp::Pow => "^",
                };
                format!("({}{o}{})", shape(a), shape(b))
            }
        }
    }

    fn read(text: &str) -> String {
        shape(&parse(text).expect("parses").result)
    }

    #[test]
    fn precedence_and_associativity_are_those_of_mathematics() {
        assert_eq!(read("a + b*c"), "(a+(b*c))");
        assert_eq!(read("a - b - c"), "((a-b)-c)");
        assert_eq!(read("a/b*c"), "((a/b)*c)");
        assert_eq!(read("-x^2"), "(-(x^2))");
        assert_eq!(read("2^3^2"), "(2^(3^2))");
        assert_eq!(read("2**-1"), "(2^(-1))");
        assert_eq!(read("exp(a*(x - 1)) # comment\n"), "exp((a*(x-1)))");
        assert_eq!(read(".5e1 + 1E-3"), "(5+0.001)");
    }

    #[test]
    fn definitions_come_first_and_end_with_a_semicolon() {
        let s = parse("Ip = w0/3*tr_c;\n K = 2;\n mu*(Ip - 1);").expect("parses");
        let names: Vec<&str> = s.definitions.iter().map(|d| d.0.as_str()).collect();
        assert_eq!(names, ["Ip", "K"]);
        assert_eq!(shape(&s.result), "(mu*(Ip-1))");
        let e = parse("a = 1 b").expect_err("no semicolon");
        assert!(e.rule.contains("expected `;`"), "{e}");
        let e = parse("a = 1;").expect_err("no W");
        assert!(e.rule.contains("expected an expression for W"), "{e}");
    }

    #[test]
    fn errors_say_where_and_what_was_expected() {
        let e = parse("mu*(x - 1").expect_err("unclosed");
        assert_eq!(e.key, "W");
        assert!(
            e.rule.contains("expected `)`") && e.rule.contains("column 10"),
            "{e}"
        );
        let e = parse("a $ b").expect_err("bad character");
        assert!(e.rule.contains("column 3"), "{e}");
        let e = parse("1\n + * 2").expect_err("two operators");
        assert!(e.rule.contains("line 2, column 4"), "{e}");
        let e = parse("pow(x, 2)").expect_err("two arguments");
        assert!(e.rule.contains("one argument"), "{e}");
    }

    #[test]
    fn limits_refuse_before_any_recursion_gets_deep() {
        let deep = format!("{}x{}", "(".repeat(200), ")".repeat(200));
        assert!(parse(&deep)
            .expect_err("deep")
            .rule
            .contains("nested more than"));
        let signs = format!("{}x", "-".repeat(200));
        assert!(parse(&signs).is_err());
        let long = vec!["x"; 2000].join("+");
        assert!(parse(&long)
            .expect_err("long")
            .rule
            .contains("at most 1000"));
        assert!(parse(&"1".repeat(MAX_BYTES + 1)).is_err());
    }
}
