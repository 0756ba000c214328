//! What can be said of a value's sign over every admissible state and parameter set: each
//! parameter's sign follows from its open range (lower, upper), each invariant is positive, and
//! signs propagate through the operations (a sum of positives is positive, a product of non-zeros
//! non-zero, eˣ positive, ...). The compiler refuses an operation on parameters alone that may
//! leave its domain (a division by what may be 0, ...).

use super::symbols::Function;

/// The signs a value may take over every admissible state and parameter set.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sign {
    /// It may be < 0.
    pub negative: bool,
    /// It may be 0.
    pub zero: bool,
    /// It may be > 0.
    pub positive: bool,
}

impl Sign {
    /// Always > 0.
    pub const POSITIVE: Sign = Sign {
        negative: false,
        zero: false,
        positive: true,
    };
    /// Any sign.
    pub const ANY: Sign = Sign {
        negative: true,
        zero: true,
        positive: true,
    };

    pub fn of_value(x: f64) -> Sign {
        Sign {
            negative: x < 0.0,
            zero: x == 0.0,
            positive: x > 0.0,
        }
    }

    /// A value in the open interval (lower, upper).
    pub fn of_range((lower, upper): (f64, f64)) -> Sign {
        Sign {
            negative: lower < 0.0,
            zero: lower < 0.0 && upper > 0.0,
            positive: upper > 0.0,
        }
    }

    pub fn negated(self) -> Sign {
        Sign {
            negative: self.positive,
            zero: self.zero,
            positive: self.negative,
        }
    }

    pub fn sum(a: Sign, b: Sign) -> Sign {
        Sign {
            negative: a.negative || b.negative,
            zero: (a.zero && b.zero) || (a.negative && b.positive) || (a.positive && b.negative),
            positive: a.positive || b.positive,
        }
    }

    pub fn product(a: Sign, b: Sign) -> Sign {
        Sign {
            negative: (a.positive && b.negative) || (a.negative && b.positive),
            zero: a.zero || b.zero,
            positive: (a.positive && b.positive) || (a.negative && b.negative),
        }
    }

    pub fn power(a: Sign, n: i32) -> Sign {
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

    pub fn unary(f: Function, a: Sign) -> Sign {
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
