//! Scene expressions: initial data and forces written as formulas in the scene, e.g.
//! `force = "sin(pi*x/L)*exp(-t)"`, parsed once and evaluated at every node (and time step).
//!
//! # Language
//! - numbers: `2`, `0.5`, `.5`, `1e-3`, `2.5E+2` (no sign: `-1` is unary minus applied to `1`);
//! - the variables the caller lists (`["x", "t"]` for a bar's force, `["x", "y"]` for a plate's
//!   data) and the constants it binds by name (`L`, `H`, `pi`), both plain identifiers;
//! - `+ - * /`, unary `-` and `+`, powers `^` and its synonym `**`, parentheses;
//! - functions `sin cos tan exp log sqrt abs` (one argument, `log` is the natural logarithm) and
//!   `min max` (two arguments, written `min(a, b)`; like [`f64::min`] they return the other argument
//!   when one is NaN).
//!
//! Precedence is the mathematical one, as in Python and Fortran: `^` binds tighter than unary minus
//! and is right-associative, so `-x^2` is `-(x^2)` (−9 at x = 3), `2^3^2` is `2^(3^2)` = 512, and an
//! exponent may carry its own sign (`2^-x^2` is `2^(-(x^2))`). `*`, `/`, `+`, `-` are
//! left-associative. There is no implicit multiplication (`2x` is an error at the `x`).
//!
//! # The crate behind it
//! [exmex] 0.21 compiles and evaluates the expression. Chosen among the candidates because it is
//! actively developed, MIT/Apache-2.0 like this crate, brings only `regex` (already in our tree)
//! and `smallvec`, and parses once into a flat representation, folding constant sub-expressions,
//! whose evaluation `eval(&[f64])` works on a stack buffer (no allocation up to 32 operands).
//! The others: evalexpr 13 is AGPL-3.0 (incompatible with our licence), meval 0.2 (2017, on nom 1)
//! and fasteval 0.2 (2020) are unmaintained.
//!
//! exmex lacks four things this module supplies with a small front end (tokenizer and
//! recursive-descent parser, below) that validates the text and hands exmex a canonical, fully
//! parenthesised form of it:
//! - exmex's unary operators bind tighter than `^` (`-1^2 == 1` in its docs, so `-x^2` would be 9):
//!   the canonical form puts every operation in its own parentheses, so exmex evaluates exactly
//!   the tree parsed here, with the convention above;
//! - its errors are messages without a position: here every error carries the 1-based character
//!   column of the offending token in the scene's text;
//! - its numbers have no exponent (`1e-3` reads as `1` next to Euler's `e`) and its constants are
//!   fixed at compile time (`π`, `E`, ...): numbers and the caller's constants reach exmex as
//!   literals in Rust's round-trip scientific form (`{:e}`), read back exactly by a literal matcher
//!   of our own; exmex's own constants and functions are not offered (only the list above is);
//! - it orders variables alphabetically and accepts any name: here names are checked against the
//!   caller's lists ([`ExprError::UnknownName`] lists what is allowed), and [`Expr::eval`] takes the
//!   caller's order.
//!
//! exmex has `^` only; `**` is accepted by the front end as the same operator.

use exmex::{BinOp, Express, FlatEx, MakeOperators, MatchLiteral, Operator};

/// Most variables an expression may take (x, y, z, t with room to spare); [`Expr::eval`] gathers
/// them on the stack.
const MAX_VARS: usize = 8;

/// Deepest nesting of parentheses, signs and powers accepted; keeps the recursive parser's stack
/// bounded on hostile input such as ten thousand `(`.
const MAX_DEPTH: usize = 100;

/// The functions of the language with their number of arguments.
const FUNCTIONS: [(&str, usize); 9] =
    [("sin", 1), ("cos", 1), ("tan", 1), ("exp", 1), ("log", 1), ("sqrt", 1), ("abs", 1), ("min", 2), ("max", 2)];

/// Errors of parsing or evaluating a scene expression. Each message starts with
/// `key = "text": ` so that it points into the scene file.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ExprError {
    /// The text is not an expression; `position` is the 1-based character column in `text` of the
    /// offending token (`text.chars().count() + 1` when the text ends too early).
    #[error("{key} = {text:?}: parse error at column {position}: {message}\n{}", caret(text, *position))]
    Parse { key: String, text: String, position: usize, message: String },
    /// A name that is neither one of the caller's variables or constants nor a function.
    #[error("{key} = {text:?}: unknown name '{name}' at column {position}; allowed: {}", allowed.join(", "))]
    UnknownName { key: String, text: String, name: String, position: usize, allowed: Vec<String> },
    /// An expression without variables whose value is infinite or NaN (e.g. `1/0`).
    #[error("{key} = {text:?}: evaluates to {}, which is not finite", sci(*value))]
    ConstantNotFinite { key: String, text: String, value: f64 },
    /// The value at point number `node` (0-based, in the order of the points given), with
    /// coordinates `at` (one per variable in `vars`), is infinite or NaN.
    #[error("{key} = {text:?}: evaluates to {} at node {node} ({}), which is not finite", sci(*value), coordinates(vars, at))]
    NotFinite { key: String, text: String, node: usize, vars: Vec<String>, at: Vec<f64>, value: f64 },
    /// The value at quadrature point number `point` of the load integral (0-based, three per
    /// element for a bar), with coordinates `at`, is infinite or NaN.
    #[error("{key} = {text:?}: evaluates to {} at quadrature point {point} of the load integral ({}), which is not finite", sci(*value), coordinates(vars, at))]
    NotFiniteAtLoadPoint { key: String, text: String, point: usize, vars: Vec<String>, at: Vec<f64>, value: f64 },
    /// More tokens than [`MAX_TOKENS`] (the text is not repeated: it may be megabytes).
    #[error(
        "{key}: the expression has {tokens} tokens (numbers, names, operators, parentheses); at most {limit} are allowed"
    )]
    TooLong { key: String, tokens: usize, limit: usize },
    /// More bytes than [`MAX_BYTES`] (checked before tokenizing, which holds the characters).
    #[error("{key}: the expression is {bytes} bytes long; at most {limit} are allowed")]
    TooManyBytes { key: String, bytes: usize, limit: usize },
}

/// Most tokens an expression may have. exmex parses its input in a time that grows faster than
/// the length (issue 22, D4: 30 000 terms took 1.5 s, 100 000 terms 45 s), and no scene needs
/// more than a few hundred; at this bound a worst-case expression parses in a fraction of a
/// second (see tests/expr.rs).
pub const MAX_TOKENS: usize = 20_000;

/// Most bytes an expression may have: [`MAX_TOKENS`] tokens of the longest numbers
/// (`-1.2345678901234567e-300` is 24 bytes) and their spaces fit in 1 MiB.
pub const MAX_BYTES: usize = 1 << 20;

/// A number in short scientific form: at most 5 significant digits, trailing zeros dropped
/// (`1.5e0`, `0e0`, `-3.3333e-1`, `inf`, `NaN`).
pub fn sci(value: f64) -> String {
    if !value.is_finite() {
        return format!("{value}");
    }
    let full = format!("{value:.4e}");
    let (mantissa, exponent) = full.split_once('e').expect("{:e} writes an exponent");
    let mantissa = if mantissa.contains('.') { mantissa.trim_end_matches('0').trim_end_matches('.') } else { mantissa };
    format!("{mantissa}e{exponent}")
}

fn coordinates(vars: &[String], at: &[f64]) -> String {
    let pairs: Vec<String> = vars.iter().zip(at).map(|(name, value)| format!("{name} = {}", sci(*value))).collect();
    pairs.join(", ")
}

/// The text again with a `^` under column `position`, indented by four spaces.
fn caret(text: &str, position: usize) -> String {
    format!("    {text}\n    {}^", " ".repeat(position.saturating_sub(1)))
}

/// A parsed expression: its scene key and source text, the variable names in evaluation order,
/// and the compiled form. Cheap to share between threads (`Send + Sync`); evaluation does not
/// mutate it.
#[derive(Clone, Debug)]
pub struct Expr {
    key: String,
    text: String,
    vars: Vec<String>,
    /// `used[i]`: variable `vars[i]` occurs in the text.
    used: Vec<bool>,
    /// exmex's variable slot `j` takes the caller's variable `slots[j]`.
    slots: Vec<usize>,
    /// The value when no variable occurs.
    constant: Option<f64>,
    /// The canonical form (module docs), read again by [`Expr::derivative`].
    canonical: String,
    /// Boxed: exmex keeps its nodes inline (a few kB), and scenes, errors and their `Result`s
    /// carry expressions by value; unboxed, validation frames overflowed a 2 MB thread stack in
    /// debug builds (`reproduce` runs scenes on rayon's threads).
    compiled: Box<FlatEx<f64, Ops, CanonicalLiteral>>,
}

impl Expr {
    /// Parses `text`. `key` is the scene key (e.g. `"bar.initial.velocity"`) repeated in errors,
    /// `vars` the variable names in the order [`Expr::eval`] takes their values, `consts` the
    /// named constants (e.g. `[("L", 1.0), ("pi", PI)]`).
    ///
    /// # Panics
    /// If the caller's names are not identifiers, collide with each other or with a function, a
    /// constant is not finite, or there are more than 8 variables: these are bugs of the caller, not
    /// of the scene.
    pub fn parse(key: &str, text: &str, vars: &[&str], consts: &[(&str, f64)]) -> Result<Expr, ExprError> {
        check_names(vars, consts);
        if text.len() > MAX_BYTES {
            return Err(ExprError::TooManyBytes { key: key.into(), bytes: text.len(), limit: MAX_BYTES });
        }
        let tokens = tokenize(text).map_err(|f| f.into_error(key, text, vars, consts))?;
        if tokens.len() > MAX_TOKENS {
            return Err(ExprError::TooLong { key: key.into(), tokens: tokens.len(), limit: MAX_TOKENS });
        }
        let mut parser = Parser { text, tokens, next: 0, vars, consts, used: vec![false; vars.len()], depth: 0 };
        let canonical = parser.parse().map_err(|f| f.into_error(key, text, vars, consts))?;
        let used = parser.used;
        let compiled = FlatEx::<f64, Ops, CanonicalLiteral>::parse(&canonical)
            .unwrap_or_else(|e| panic!("exmex rejected the canonical form {canonical:?} of {text:?}: {e}"));
        let slots: Vec<usize> = compiled
            .var_names()
            .iter()
            .map(|name| name.strip_prefix('v').and_then(|i| i.parse().ok()).expect("canonical variables are v<index>"))
            .collect();
        debug_assert_eq!(slots.len(), used.iter().filter(|u| **u).count());
        let constant = if slots.is_empty() {
            let value = compiled.eval(&[]).expect("no variable, no value needed");
            if !value.is_finite() {
                return Err(ExprError::ConstantNotFinite { key: key.into(), text: text.into(), value });
            }
            Some(value)
        } else {
            None
        };
        let vars = vars.iter().map(|v| v.to_string()).collect();
        let compiled = Box::new(compiled);
        Ok(Expr { key: key.into(), text: text.into(), vars, used, slots, constant, canonical, compiled })
    }

    /// The value at `args`, one value per variable in the order given to [`Expr::parse`]. Does not
    /// allocate for up to 32 operands. May be infinite or NaN: [`Expr::eval_into`] and
    /// [`Expr::eval_at_nodes`] check.
    ///
    /// # Panics
    /// If `args` has not one value per variable.
    #[inline]
    pub fn eval(&self, args: &[f64]) -> f64 {
        assert_eq!(args.len(), self.vars.len(), "{}: one value per variable {:?}", self.key, self.vars);
        if let Some(value) = self.constant {
            return value;
        }
        let mut values = [0.0; MAX_VARS];
        for (value, &i) in values.iter_mut().zip(&self.slots) {
            *value = args[i];
        }
        self.compiled.eval(&values[..self.slots.len()]).expect("one value per exmex variable")
    }

    /// Writes the value at each point into `out` (one point per entry), rejecting the first value
    /// that is not finite with its node index and coordinates. Allocates nothing unless it fails.
    ///
    /// # Panics
    /// If `N` is not the number of variables or the points do not fill `out` exactly.
    pub fn eval_into<const N: usize>(
        &self,
        points: impl IntoIterator<Item = [f64; N]>,
        out: &mut [f64],
    ) -> Result<(), ExprError> {
        let mut count = 0;
        for (node, point) in points.into_iter().enumerate() {
            assert!(node < out.len(), "{}: more points than output slots ({})", self.key, out.len());
            let value = self.eval(&point);
            if !value.is_finite() {
                return Err(self.not_finite(node, &point, value));
            }
            out[node] = value;
            count = node + 1;
        }
        assert_eq!(count, out.len(), "{}: fewer points than output slots", self.key);
        Ok(())
    }

    /// The value at each point, rejecting the first value that is not finite with its node index
    /// and coordinates.
    ///
    /// # Panics
    /// If a point does not hold one value per variable.
    pub fn eval_at_nodes<P: AsRef<[f64]>>(&self, points: impl IntoIterator<Item = P>) -> Result<Vec<f64>, ExprError> {
        points
            .into_iter()
            .enumerate()
            .map(|(node, point)| {
                let point = point.as_ref();
                let value = self.eval(point);
                if value.is_finite() { Ok(value) } else { Err(self.not_finite(node, point, value)) }
            })
            .collect()
    }

    /// Refuses a value that is not finite at a quadrature point of a load integral (points in
    /// the order the assembly visits them), naming the point and its coordinates.
    pub fn check_at_load_points<const N: usize>(
        &self,
        points: impl IntoIterator<Item = [f64; N]>,
    ) -> Result<(), ExprError> {
        for (point, at) in points.into_iter().enumerate() {
            let value = self.eval(&at);
            if !value.is_finite() {
                let (key, text, vars) = (self.key.clone(), self.text.clone(), self.vars.clone());
                return Err(ExprError::NotFiniteAtLoadPoint { key, text, point, vars, at: at.to_vec(), value });
            }
        }
        Ok(())
    }

    fn not_finite(&self, node: usize, point: &[f64], value: f64) -> ExprError {
        ExprError::NotFinite {
            key: self.key.clone(),
            text: self.text.clone(),
            node,
            vars: self.vars.clone(),
            at: point.to_vec(),
            value,
        }
    }

    /// The source text, as written in the scene.
    pub fn text(&self) -> &str {
        &self.text
    }

    /// The scene key given to [`Expr::parse`].
    pub fn key(&self) -> &str {
        &self.key
    }

    /// The variable names, in evaluation order.
    pub fn vars(&self) -> &[String] {
        &self.vars
    }

    /// `Some(value)` when no variable occurs in the text (so a constant force stays on the fast
    /// path); the value is finite. Syntactic: `x - x` depends on `x`.
    pub fn is_constant(&self) -> Option<f64> {
        self.constant
    }

    /// The expression's exact first derivatives ([`dual`]): [`Derivative::at`] gives the value
    /// and the gradient over the variables (in the order given to [`Expr::parse`]).
    pub fn derivative(&self) -> Derivative {
        Derivative { tree: dual::tree(&self.canonical), n: self.vars.len() }
    }

    /// Whether the variable `var` occurs in the text (false for a name that is not a variable).
    pub fn depends_on(&self, var: &str) -> bool {
        self.vars.iter().zip(&self.used).any(|(name, used)| name == var && *used)
    }
}

/// An expression ready for its exact gradient ([`Expr::derivative`]).
#[derive(Debug, Clone)]
pub struct Derivative {
    tree: dual::Tree,
    n: usize,
}

impl Derivative {
    /// The value and the gradient at `args` (one value per variable): `grad[k] = ∂f/∂vars[k]`
    /// (entries beyond the number of variables are 0).
    pub fn at(&self, args: &[f64]) -> (f64, [f64; MAX_VARS]) {
        assert_eq!(args.len(), self.n, "one value per variable");
        self.tree.gradient(args)
    }
}

/// Caller bugs, not scene errors: see the panics of [`Expr::parse`].
fn check_names(vars: &[&str], consts: &[(&str, f64)]) {
    assert!(vars.len() <= MAX_VARS, "at most {MAX_VARS} variables, got {vars:?}");
    let names: Vec<&str> = vars.iter().copied().chain(consts.iter().map(|(name, _)| *name)).collect();
    for (i, name) in names.iter().enumerate() {
        let mut chars = name.chars();
        let identifier = chars.next().is_some_and(is_name_start) && chars.all(is_name_continue);
        assert!(identifier, "{name:?} is not an identifier");
        assert!(!FUNCTIONS.iter().any(|(f, _)| f == name), "{name:?} is a function");
        assert!(!names[..i].contains(name), "{name:?} is bound twice");
    }
    for (name, value) in consts {
        assert!(value.is_finite(), "constant {name} = {value} is not finite");
    }
}

fn is_name_start(c: char) -> bool {
    c.is_alphabetic() || c == '_'
}

fn is_name_continue(c: char) -> bool {
    c.is_alphanumeric() || c == '_'
}

// ---------------------------------------------------------------------------------------------
// The exmex side: operators and the literal form of the canonical text.

/// The operators of the canonical form. Priorities follow exmex's defaults but do not matter: the
/// canonical form parenthesises every operation.
#[derive(Clone, Debug)]
struct Ops;

impl MakeOperators<f64> for Ops {
    fn make<'a>() -> Vec<Operator<'a, f64>> {
        let bin = |apply: fn(f64, f64) -> f64, prio, is_commutative| BinOp { apply, prio, is_commutative };
        vec![
            Operator::make_bin("^", bin(f64::powf, 4, false)),
            Operator::make_bin("*", bin(|a, b| a * b, 2, true)),
            Operator::make_bin("/", bin(|a, b| a / b, 3, false)),
            Operator::make_bin_unary("+", bin(|a, b| a + b, 0, true), |a| a),
            Operator::make_bin_unary("-", bin(|a, b| a - b, 1, false), |a| -a),
            Operator::make_bin("min", bin(f64::min, 0, true)),
            Operator::make_bin("max", bin(f64::max, 0, true)),
            Operator::make_unary("sin", f64::sin),
            Operator::make_unary("cos", f64::cos),
            Operator::make_unary("tan", f64::tan),
            Operator::make_unary("exp", f64::exp),
            Operator::make_unary("log", f64::ln),
            Operator::make_unary("sqrt", f64::sqrt),
            Operator::make_unary("abs", f64::abs),
        ]
    }
}

/// Literals of the canonical form: Rust's `{:e}` of a finite non-negative f64 (`2.5e0`,
/// `1e-3`), which `f64::from_str` reads back exactly.
#[derive(Clone, Debug)]
struct CanonicalLiteral;

impl MatchLiteral for CanonicalLiteral {
    fn is_literal(text: &str) -> Option<&str> {
        let bytes = text.as_bytes();
        let digits = |from: usize| bytes[from..].iter().take_while(|b| b.is_ascii_digit()).count();
        let mut end = digits(0);
        if end == 0 {
            return None;
        }
        if bytes.get(end) == Some(&b'.') {
            end += 1 + digits(end + 1);
        }
        if bytes.get(end) == Some(&b'e') {
            let sign = usize::from(bytes.get(end + 1) == Some(&b'-'));
            end += 1 + sign + digits(end + 1 + sign);
        }
        Some(&text[..end])
    }
}

/// `value` as a canonical literal, negative values as `(-literal)`.
fn literal(value: f64) -> String {
    if value.is_sign_negative() { format!("(-{:e})", -value) } else { format!("{value:e}") }
}

// ---------------------------------------------------------------------------------------------
// The front end: tokens with their columns, and a recursive-descent parser that emits the
// canonical form.

mod dual;
mod parse;

use parse::{Parser, tokenize};

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn short_scientific_form() {
        let cases = [(0.0, "0e0"), (1.5, "1.5e0"), (-1.0 / 3.0, "-3.3333e-1"), (1e-3, "1e-3"), (123456.0, "1.2346e5")];
        for (value, written) in cases {
            assert_eq!(sci(value), written);
        }
        assert_eq!(sci(f64::INFINITY), "inf");
        assert_eq!(sci(f64::NAN), "NaN");
    }

    /// Exact derivatives against hand-written ones at a point, to a few ulps (each rule is
    /// one or two roundings: 8 ε relative). mutation: the product rule without a·b' in
    /// dual.rs → this fails.
    #[test]
    fn derivatives_are_the_expressions_own() {
        let (x, y) = (0.7, -1.3);
        let cases: [(&str, f64, [f64; 2]); 9] = [
            ("y - 0.01*x^2", y - 0.01 * x * x, [-0.02 * x, 1.0]),
            (
                "sqrt(x^2 + y^2) - 2",
                (x * x + y * y).sqrt() - 2.0,
                [x / (x * x + y * y).sqrt(), y / (x * x + y * y).sqrt()],
            ),
            ("-x^3*y", -x * x * x * y, [-3.0 * x * x * y, -x * x * x]),
            (
                "sin(x)*exp(y)/cos(y)",
                x.sin() * y.exp() / y.cos(),
                [x.cos() * y.exp() / y.cos(), x.sin() * y.exp() * (1.0 + y.tan()) / y.cos()],
            ),
            ("log(x)*tan(x)", x.ln() * x.tan(), [x.tan() / x + x.ln() * (1.0 + x.tan() * x.tan()), 0.0]),
            ("x^y", x.powf(y), [y * x.powf(y - 1.0), x.powf(y) * x.ln()]),
            ("abs(y) + max(x, y)", -y + x, [1.0, -1.0]),
            ("min(x, 2*y) - 2^x", 2.0 * y - 2f64.powf(x), [-(2f64.powf(x)) * 2f64.ln(), 2.0]),
            ("3 + 0*x", 3.0, [0.0, 0.0]),
        ];
        for (text, value, grad) in cases {
            let e = Expr::parse("k", text, &["x", "y"], &[]).unwrap();
            let (v, g) = e.derivative().at(&[x, y]);
            let close = |a: f64, b: f64| (a - b).abs() <= 8.0 * f64::EPSILON * b.abs().max(1.0);
            assert!(close(v, value) && close(v, e.eval(&[x, y])), "{text}: {v} vs {value}");
            assert!(close(g[0], grad[0]) && close(g[1], grad[1]), "{text}: {g:?} vs {grad:?}");
        }
    }

    #[test]
    fn canonical_form_is_fully_parenthesised() {
        let mut parser = Parser {
            text: "-x^2 + min(1e-3, pi)",
            tokens: tokenize("-x^2 + min(1e-3, pi)").unwrap(),
            next: 0,
            vars: &["x"],
            consts: &[("pi", std::f64::consts::PI)],
            used: vec![false],
            depth: 0,
        };
        let canonical = parser.parse().unwrap();
        assert_eq!(canonical, "((-({v0}^2e0))+(1e-3 min 3.141592653589793e0))");
        assert_eq!(literal(-2.5), "(-2.5e0)");
    }
}

/// Two expressions are equal when they were written the same for the same key and variables
/// (what a resolved scene reading back to itself needs).
impl PartialEq for Expr {
    fn eq(&self, other: &Self) -> bool {
        self.key == other.key && self.text == other.text && self.vars == other.vars
    }
}
