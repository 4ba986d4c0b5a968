//! Parameter expressions of parametric L-systems (The Algorithmic Beauty of Plants notation):
//! arithmetic on the predecessor's parameters, compiled to a small stack program and evaluated
//! in 32-bit floats.
//!
//! Grammar, loosest binding first: `||`, `&&`, comparisons (`< > <= >= == !=`), `+ -`, `* /`,
//! unary `-` and `!`, `^` (power, right-associative), and primaries: numbers, parameter names,
//! parenthesised expressions and the functions `sqrt abs min max floor sin cos` (angles in
//! degrees). Comparisons and logic give 1.0 for true and 0.0 for false.

use std::fmt;

/// One instruction of a compiled expression.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Op {
    /// Push a constant.
    Const(f32),
    /// Push the predecessor's parameter with this index.
    Param(u8),
    /// Pop two values, push their sum (and so on for the other binary operators).
    Add,
    /// Subtraction.
    Sub,
    /// Multiplication.
    Mul,
    /// Division.
    Div,
    /// Power.
    Pow,
    /// Less than.
    Lt,
    /// Greater than.
    Gt,
    /// Less than or equal.
    Le,
    /// Greater than or equal.
    Ge,
    /// Equal.
    Eq,
    /// Not equal.
    Ne,
    /// Logical and.
    And,
    /// Logical or.
    Or,
    /// Negation.
    Neg,
    /// Logical not.
    Not,
    /// Minimum of two values.
    Min,
    /// Maximum of two values.
    Max,
    /// Square root.
    Sqrt,
    /// Absolute value.
    Abs,
    /// Floor.
    Floor,
    /// Sine of an angle in degrees.
    Sin,
    /// Cosine of an angle in degrees.
    Cos,
}

/// A compiled expression.
#[derive(Clone, Debug, PartialEq)]
pub struct Expr {
    /// The stack program.
    pub ops: Vec<Op>,
}

/// Why an expression did not parse.
#[derive(Debug, Clone, PartialEq)]
pub struct ExprError(pub String);

impl fmt::Display for ExprError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for ExprError {}

impl Expr {
    /// Compiles `text`, where `names` are the parameter names in order.
    pub fn parse(text: &str, names: &[String]) -> Result<Expr, ExprError> {
        let mut p = Parser { s: text.as_bytes(), i: 0, names, ops: Vec::new(), nest: 0 };
        p.or()?;
        p.ws();
        if p.i < p.s.len() {
            return Err(ExprError(format!("expression '{text}': unexpected '{}'", p.s[p.i] as char)));
        }
        if p.ops.is_empty() {
            return Err(ExprError(format!("expression '{text}' is empty")));
        }
        // The evaluator's stack holds 32 values.
        let mut depth = 0i32;
        for op in &p.ops {
            depth += match op {
                Op::Const(_) | Op::Param(_) => 1,
                Op::Neg | Op::Not | Op::Sqrt | Op::Abs | Op::Floor | Op::Sin | Op::Cos => 0,
                _ => -1,
            };
            if depth > 32 {
                return Err(ExprError(format!("expression '{text}' nests too deeply (at most 32 pending values)")));
            }
        }
        Ok(Expr { ops: p.ops })
    }

    /// Whether the expression uses no parameter.
    pub fn is_constant(&self) -> bool {
        !self.ops.iter().any(|o| matches!(o, Op::Param(_)))
    }

    /// Evaluates the expression with the predecessor's parameters `args`.
    pub fn eval(&self, args: &[f32]) -> f32 {
        let mut st = [0.0f32; 32];
        let mut n = 0usize;
        for op in &self.ops {
            match *op {
                Op::Const(c) => {
                    st[n] = c;
                    n += 1;
                }
                Op::Param(i) => {
                    st[n] = args.get(i as usize).copied().unwrap_or(0.0);
                    n += 1;
                }
                Op::Neg => st[n - 1] = -st[n - 1],
                Op::Not => st[n - 1] = b(st[n - 1] == 0.0),
                Op::Sqrt => st[n - 1] = st[n - 1].sqrt(),
                Op::Abs => st[n - 1] = st[n - 1].abs(),
                Op::Floor => st[n - 1] = st[n - 1].floor(),
                Op::Sin => st[n - 1] = st[n - 1].to_radians().sin(),
                Op::Cos => st[n - 1] = st[n - 1].to_radians().cos(),
                bin => {
                    let (x, y) = (st[n - 2], st[n - 1]);
                    n -= 1;
                    st[n - 1] = match bin {
                        Op::Add => x + y,
                        Op::Sub => x - y,
                        Op::Mul => x * y,
                        Op::Div => x / y,
                        Op::Pow => x.powf(y),
                        Op::Lt => b(x < y),
                        Op::Gt => b(x > y),
                        Op::Le => b(x <= y),
                        Op::Ge => b(x >= y),
                        Op::Eq => b(x == y),
                        Op::Ne => b(x != y),
                        Op::And => b(x != 0.0 && y != 0.0),
                        Op::Or => b(x != 0.0 || y != 0.0),
                        Op::Min => x.min(y),
                        Op::Max => x.max(y),
                        _ => unreachable!("unary operators are handled above"),
                    };
                }
            }
        }
        st[0]
    }
}

fn b(v: bool) -> f32 {
    if v { 1.0 } else { 0.0 }
}

struct Parser<'a> {
    s: &'a [u8],
    i: usize,
    names: &'a [String],
    ops: Vec<Op>,
    nest: usize,
}

impl Parser<'_> {
    fn text(&self) -> String {
        String::from_utf8_lossy(self.s).into_owned()
    }

    fn err<T>(&self, what: &str) -> Result<T, ExprError> {
        Err(ExprError(format!("expression '{}': {what}", self.text())))
    }

    fn ws(&mut self) {
        while self.i < self.s.len() && self.s[self.i].is_ascii_whitespace() {
            self.i += 1;
        }
    }

    fn eat(&mut self, t: &str) -> bool {
        self.ws();
        if self.s[self.i..].starts_with(t.as_bytes()) {
            self.i += t.len();
            true
        } else {
            false
        }
    }

    fn push(&mut self, op: Op) -> Result<(), ExprError> {
        // The evaluator's stack holds 32 values; a deeper expression is refused here.
        if self.ops.len() >= 256 {
            return self.err("too long (at most 256 operations)");
        }
        self.ops.push(op);
        Ok(())
    }

    fn or(&mut self) -> Result<(), ExprError> {
        self.and()?;
        while self.eat("||") {
            self.and()?;
            self.push(Op::Or)?;
        }
        Ok(())
    }

    fn and(&mut self) -> Result<(), ExprError> {
        self.cmp()?;
        while self.eat("&&") {
            self.cmp()?;
            self.push(Op::And)?;
        }
        Ok(())
    }

    fn cmp(&mut self) -> Result<(), ExprError> {
        self.add()?;
        let ops = [("<=", Op::Le), (">=", Op::Ge), ("==", Op::Eq), ("!=", Op::Ne), ("<", Op::Lt), (">", Op::Gt)];
        if let Some(&(_, op)) = ops.iter().find(|(t, _)| self.eat(t)) {
            self.add()?;
            self.push(op)?;
        }
        Ok(())
    }

    fn add(&mut self) -> Result<(), ExprError> {
        self.mul()?;
        loop {
            if self.eat("+") {
                self.mul()?;
                self.push(Op::Add)?;
            } else if self.eat("-") {
                self.mul()?;
                self.push(Op::Sub)?;
            } else {
                return Ok(());
            }
        }
    }

    fn mul(&mut self) -> Result<(), ExprError> {
        self.unary()?;
        loop {
            if self.eat("*") {
                self.unary()?;
                self.push(Op::Mul)?;
            } else if self.eat("/") {
                self.unary()?;
                self.push(Op::Div)?;
            } else {
                return Ok(());
            }
        }
    }

    fn unary(&mut self) -> Result<(), ExprError> {
        self.nest += 1;
        if self.nest > 64 {
            return self.err("nests too deeply");
        }
        let r = self.unary_inner();
        self.nest -= 1;
        r
    }

    fn unary_inner(&mut self) -> Result<(), ExprError> {
        if self.eat("-") {
            self.unary()?;
            self.push(Op::Neg)
        } else if self.s[self.i..].starts_with(b"!") && !self.s[self.i..].starts_with(b"!=") {
            self.i += 1;
            self.unary()?;
            self.push(Op::Not)
        } else {
            self.power()
        }
    }

    fn power(&mut self) -> Result<(), ExprError> {
        self.primary()?;
        if self.eat("^") {
            self.unary()?;
            self.push(Op::Pow)?;
        }
        Ok(())
    }

    fn primary(&mut self) -> Result<(), ExprError> {
        self.ws();
        // Bounded recursion: parentheses, unary operators and calls nest at most 64 deep.
        self.nest += 1;
        if self.nest > 64 {
            return self.err("nests too deeply");
        }
        let r = self.primary_inner();
        self.nest -= 1;
        r
    }

    fn primary_inner(&mut self) -> Result<(), ExprError> {
        let Some(&c) = self.s.get(self.i) else {
            return self.err("ends too early");
        };
        if c == b'(' {
            self.i += 1;
            self.or()?;
            if !self.eat(")") {
                return self.err("missing ')'");
            }
            return Ok(());
        }
        if c.is_ascii_digit() || c == b'.' {
            let start = self.i;
            while self.i < self.s.len() && (self.s[self.i].is_ascii_digit() || self.s[self.i] == b'.') {
                self.i += 1;
            }
            // An exponent such as 1e-3.
            if self.i < self.s.len() && (self.s[self.i] == b'e' || self.s[self.i] == b'E') {
                let save = self.i;
                self.i += 1;
                if self.i < self.s.len() && (self.s[self.i] == b'-' || self.s[self.i] == b'+') {
                    self.i += 1;
                }
                if self.i < self.s.len() && self.s[self.i].is_ascii_digit() {
                    while self.i < self.s.len() && self.s[self.i].is_ascii_digit() {
                        self.i += 1;
                    }
                } else {
                    self.i = save;
                }
            }
            let t = std::str::from_utf8(&self.s[start..self.i]).unwrap_or("");
            return match t.parse::<f32>() {
                Ok(v) => self.push(Op::Const(v)),
                Err(_) => self.err(&format!("'{t}' is not a number")),
            };
        }
        if c.is_ascii_alphabetic() || c == b'_' {
            let start = self.i;
            while self.i < self.s.len() && (self.s[self.i].is_ascii_alphanumeric() || self.s[self.i] == b'_') {
                self.i += 1;
            }
            let name = std::str::from_utf8(&self.s[start..self.i]).unwrap_or("").to_string();
            let funcs: [(&str, usize, Op); 7] = [
                ("sqrt", 1, Op::Sqrt),
                ("abs", 1, Op::Abs),
                ("floor", 1, Op::Floor),
                ("sin", 1, Op::Sin),
                ("cos", 1, Op::Cos),
                ("min", 2, Op::Min),
                ("max", 2, Op::Max),
            ];
            self.ws();
            if self.s.get(self.i) == Some(&b'(') {
                let Some(&(_, argc, op)) = funcs.iter().find(|(f, _, _)| *f == name) else {
                    return self.err(&format!("unknown function '{name}'"));
                };
                self.i += 1;
                for k in 0..argc {
                    if k > 0 && !self.eat(",") {
                        return self.err(&format!("{name} takes {argc} arguments"));
                    }
                    self.or()?;
                }
                if !self.eat(")") {
                    return self.err(&format!("missing ')' after the arguments of {name}"));
                }
                return self.push(op);
            }
            return match self.names.iter().position(|n| *n == name) {
                Some(i) => self.push(Op::Param(i as u8)),
                None => self.err(&format!("unknown name '{name}'")),
            };
        }
        self.err(&format!("unexpected '{}'", c as char))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn e(t: &str, names: &[&str], args: &[f32]) -> f32 {
        let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
        Expr::parse(t, &names).unwrap().eval(args)
    }

    #[test]
    fn precedence_and_functions() {
        assert_eq!(e("1+2*3", &[], &[]), 7.0);
        assert_eq!(e("(1+2)*3", &[], &[]), 9.0);
        assert_eq!(e("-2^2", &[], &[]), -4.0);
        assert_eq!(e("l*0.5", &["l"], &[3.0]), 1.5);
        assert_eq!(e("x>1 && y<=2", &["x", "y"], &[2.0, 2.0]), 1.0);
        assert_eq!(e("max(a, 2) - min(a, 2)", &["a"], &[5.0]), 3.0);
        assert_eq!(e("1e-1*10", &[], &[]), 1.0);
    }

    #[test]
    fn errors_are_reported() {
        for bad in ["1+", "l*", "(1", "q", "foo(1)", "1 2", ""] {
            assert!(Expr::parse(bad, &["l".to_string()]).is_err(), "{bad}");
        }
    }
}
