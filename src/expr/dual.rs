//! Exact first derivatives of an expression (forward-mode automatic differentiation): the
//! canonical form the front end hands exmex (fully parenthesised: a literal, `{v<i>}`,
//! `(a∘b)` for ∘ in `+ - * / ^`, `(-a)`, `f(a)`, `(a min b)`, `(a max b)`) is read back into a
//! tree once and evaluated on dual numbers `(v, ∇v)`, each operation with its derivative rule:
//!
//! ```text
//! (a·b)' = a'b + ab',   (a/b)' = (a'b − ab')/b²,   (aᵇ)' = b aᵇ⁻¹ a'   (b constant)
//!                                                   (aᵇ)' = aᵇ (b' ln a + b a'/a)   (else),
//! sin' = cos, cos' = −sin, tan' = 1 + tan², exp' = exp, log' = 1/a, sqrt' = 1/(2 sqrt),
//! abs' = sign(a) (0 at 0),   min/max: the derivative of the argument taken (the first on a tie).
//! ```
//!
//! The derivative is the expression's own, to round-off: no finite difference (issue 30: a
//! level-set obstacle's normal is ∇φ/|∇φ|). Where the expression is not differentiable (|a| at
//! 0, min/max on a tie) the one-sided rule above is taken; where a rule's value is not finite
//! (√a at 0, aᵇ at a = 0 with b < 1) the gradient is not finite and the caller refuses it.

use super::MAX_VARS;

/// A node of the canonical tree.
#[derive(Debug, Clone)]
enum Node {
    Number(f64),
    Var(usize),
    Neg(Box<Node>),
    Binary(u8, Box<Node>, Box<Node>),
    Call(&'static str, Box<Node>),
}

/// The canonical tree of an expression (built once by [`Expr::parse`](super::Expr::parse)).
#[derive(Debug, Clone)]
pub(super) struct Tree(Node);

/// Reads the canonical text (module docs) into a tree. The text is the front end's own output,
/// so a malformed one is a bug of this module: it panics.
pub(super) fn tree(canonical: &str) -> Tree {
    let mut reader = Reader { s: canonical.as_bytes(), at: 0 };
    let node = reader.node();
    assert_eq!(reader.at, reader.s.len(), "trailing text in the canonical form {canonical:?}");
    Tree(node)
}

struct Reader<'a> {
    s: &'a [u8],
    at: usize,
}

impl Reader<'_> {
    fn eat(&mut self, b: u8) {
        assert_eq!(self.s.get(self.at), Some(&b), "canonical form: expected {:?} at {}", b as char, self.at);
        self.at += 1;
    }

    fn node(&mut self) -> Node {
        match self.s[self.at] {
            b'(' => {
                self.at += 1;
                if self.s[self.at] == b'-' {
                    self.at += 1;
                    let inner = self.node();
                    self.eat(b')');
                    return Node::Neg(Box::new(inner));
                }
                let left = self.node();
                let op = if self.s[self.at] == b' ' {
                    // ` min ` or ` max `.
                    let op = if &self.s[self.at..self.at + 5] == b" min " { b'm' } else { b'M' };
                    self.at += 5;
                    op
                } else {
                    self.at += 1;
                    self.s[self.at - 1]
                };
                let right = self.node();
                self.eat(b')');
                Node::Binary(op, Box::new(left), Box::new(right))
            }
            b'{' => {
                self.at += 2; // `{v`
                let start = self.at;
                while self.s[self.at].is_ascii_digit() {
                    self.at += 1;
                }
                let i = std::str::from_utf8(&self.s[start..self.at]).expect("ascii").parse().expect("a variable index");
                self.eat(b'}');
                Node::Var(i)
            }
            c if c.is_ascii_digit() => {
                let start = self.at;
                while self.at < self.s.len()
                    && (self.s[self.at].is_ascii_alphanumeric() || b".-".contains(&self.s[self.at]))
                {
                    // A literal is `{:e}`: digits, '.', 'e', a '-' only right after the 'e'.
                    if self.s[self.at] == b'-' && self.s[self.at - 1] != b'e' {
                        break;
                    }
                    self.at += 1;
                }
                let text = std::str::from_utf8(&self.s[start..self.at]).expect("ascii");
                Node::Number(text.parse().expect("a literal in {:e} form"))
            }
            _ => {
                let start = self.at;
                while self.s[self.at].is_ascii_alphabetic() {
                    self.at += 1;
                }
                let name = std::str::from_utf8(&self.s[start..self.at]).expect("ascii");
                let name = super::FUNCTIONS.iter().map(|(f, _)| *f).find(|f| *f == name).expect("a function");
                self.eat(b'(');
                let inner = self.node();
                self.eat(b')');
                Node::Call(name, Box::new(inner))
            }
        }
    }
}

/// A value with its gradient over the expression's variables.
#[derive(Debug, Clone, Copy)]
struct Dual {
    v: f64,
    g: [f64; MAX_VARS],
}

impl Dual {
    fn constant(v: f64) -> Self {
        Dual { v, g: [0.0; MAX_VARS] }
    }

    /// `f(a)` with `f'(a) = slope`.
    fn chain(v: f64, slope: f64, a: &Dual) -> Self {
        Dual { v, g: a.g.map(|g| slope * g) }
    }
}

impl Tree {
    /// The value and the gradient at `args` (one value per variable, in the caller's order).
    pub(super) fn gradient(&self, args: &[f64]) -> (f64, [f64; MAX_VARS]) {
        let d = eval(&self.0, args);
        (d.v, d.g)
    }
}

fn eval(node: &Node, args: &[f64]) -> Dual {
    match node {
        Node::Number(v) => Dual::constant(*v),
        Node::Var(i) => {
            let mut d = Dual::constant(args[*i]);
            d.g[*i] = 1.0;
            d
        }
        Node::Neg(a) => {
            let a = eval(a, args);
            Dual { v: -a.v, g: a.g.map(|g| -g) }
        }
        Node::Binary(op, a, b) => {
            let (a, b) = (eval(a, args), eval(b, args));
            let mut g = [0.0; MAX_VARS];
            let v = match op {
                b'+' => {
                    for k in 0..MAX_VARS {
                        g[k] = a.g[k] + b.g[k];
                    }
                    a.v + b.v
                }
                b'-' => {
                    for k in 0..MAX_VARS {
                        g[k] = a.g[k] - b.g[k];
                    }
                    a.v - b.v
                }
                b'*' => {
                    for k in 0..MAX_VARS {
                        g[k] = a.g[k] * b.v + a.v * b.g[k];
                    }
                    a.v * b.v
                }
                b'/' => {
                    for k in 0..MAX_VARS {
                        g[k] = (a.g[k] * b.v - a.v * b.g[k]) / (b.v * b.v);
                    }
                    a.v / b.v
                }
                b'^' => {
                    let v = a.v.powf(b.v);
                    let constant_exponent = b.g.iter().all(|&x| x == 0.0);
                    for k in 0..MAX_VARS {
                        g[k] = if constant_exponent {
                            if a.g[k] == 0.0 { 0.0 } else { b.v * a.v.powf(b.v - 1.0) * a.g[k] }
                        } else {
                            v * (b.g[k] * a.v.ln() + b.v * a.g[k] / a.v)
                        };
                    }
                    v
                }
                b'm' | b'M' => {
                    let first = if *op == b'm' { !(b.v < a.v) } else { !(b.v > a.v) };
                    // f64::min/max return the other argument when one is NaN.
                    let first = if a.v.is_nan() {
                        false
                    } else if b.v.is_nan() {
                        true
                    } else {
                        first
                    };
                    return if first { a } else { b };
                }
                _ => unreachable!("canonical operators are + - * / ^ min max"),
            };
            Dual { v, g }
        }
        Node::Call(f, a) => {
            let a = eval(a, args);
            let (v, slope) = match *f {
                "sin" => (a.v.sin(), a.v.cos()),
                "cos" => (a.v.cos(), -a.v.sin()),
                "tan" => {
                    let t = a.v.tan();
                    (t, 1.0 + t * t)
                }
                "exp" => {
                    let e = a.v.exp();
                    (e, e)
                }
                "log" => (a.v.ln(), 1.0 / a.v),
                "sqrt" => {
                    let s = a.v.sqrt();
                    (s, 0.5 / s)
                }
                "abs" => (
                    a.v.abs(),
                    if a.v > 0.0 {
                        1.0
                    } else if a.v < 0.0 {
                        -1.0
                    } else {
                        0.0
                    },
                ),
                _ => unreachable!("canonical functions of one argument"),
            };
            if a.g.iter().all(|&x| x == 0.0) {
                return Dual::constant(v);
            }
            Dual::chain(v, slope, &a)
        }
    }
}
