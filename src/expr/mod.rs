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
//! # Compilation
//! A small front end (lexer and recursive-descent parser, `parse.rs`) validates the text, locates
//! every error by its 1-based character column, checks names against the caller's lists
//! ([`ExprError::UnknownName`] lists what is allowed) and compiles the expression into a postfix
//! program, folding operations on numbers into their values; [`Expr::eval`] runs it on a stack
//! buffer. Parsing is linear in the text (one token and at most one instruction per step; no
//! token list, no intermediate strings): 100 000 terms parse in milliseconds. Until issue 22 the
//! front end wrote a fully parenthesised text for the exmex crate to parse again, which took
//! super-quadratic time (45 s for 100 000 terms); the evaluation order and the f64 operations are
//! the ones exmex performed, so every value is unchanged.

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
}

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
    /// The value when no variable occurs.
    constant: Option<f64>,
    /// The postfix program (`parse.rs`), and the stack height it reaches.
    program: Vec<Op>,
    height: usize,
}

/// Stack buffer of [`Expr::eval`]: a program that needs more (nesting is at most
/// [`MAX_DEPTH`] deep, and each level holds at most four pending operands) runs on the heap.
const STACK: usize = 512;

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
        let fail = |f: parse::Failure| f.into_error(key, text, vars, consts);
        check_tokens(text).map_err(fail)?;
        let mut parser = Parser::new(text, vars, consts).map_err(fail)?;
        parser.parse().map_err(fail)?;
        let Parser { used, mut program, max_height: height, .. } = parser;
        program.shrink_to_fit();
        let constant = if !used.contains(&true) {
            let value = run(&program, height, &[]);
            if !value.is_finite() {
                return Err(ExprError::ConstantNotFinite { key: key.into(), text: text.into(), value });
            }
            Some(value)
        } else {
            None
        };
        let vars = vars.iter().map(|v| v.to_string()).collect();
        Ok(Expr { key: key.into(), text: text.into(), vars, used, constant, program, height })
    }

    /// The value at `args`, one value per variable in the order given to [`Expr::parse`]. Does not
    /// allocate (unless nested beyond the stack buffer, see [`STACK`]). May be infinite or NaN: [`Expr::eval_into`] and
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
        run(&self.program, self.height, args)
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

    /// Rejects the first value at the quadrature points of a load integral that is not finite,
    /// naming the point's number and coordinates (a force finite at every node may still be
    /// infinite between them, where the load is integrated).
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

    /// Whether the variable `var` occurs in the text (false for a name that is not a variable).
    pub fn depends_on(&self, var: &str) -> bool {
        self.vars.iter().zip(&self.used).any(|(name, used)| name == var && *used)
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

/// Runs a postfix program that reaches stack height `height` with the variables `args`.
#[inline]
fn run(program: &[Op], height: usize, args: &[f64]) -> f64 {
    if height <= STACK {
        run_on(program, args, &mut [0.0; STACK])
    } else {
        run_on(program, args, &mut vec![0.0; height])
    }
}

/// The stack machine: leaves push, unary operations replace the top, binary ones pop the right
/// operand into the left. A program from the parser is well formed, so `stack` (at least its
/// height long) never under- or overflows.
fn run_on(program: &[Op], args: &[f64], stack: &mut [f64]) -> f64 {
    let mut top = 0;
    for &op in program {
        match op {
            Op::Num(v) => {
                stack[top] = v;
                top += 1;
            }
            Op::Var(i) => {
                stack[top] = args[i];
                top += 1;
            }
            Op::Neg | Op::Call(_) => stack[top - 1] = op.unary(stack[top - 1]),
            _ => {
                top -= 1;
                stack[top - 1] = op.binary(stack[top - 1], stack[top]);
            }
        }
    }
    stack[0]
}

// ---------------------------------------------------------------------------------------------
// The front end: tokens with their columns, and a recursive-descent parser that emits the
// canonical form.

mod parse;

use parse::{Op, Parser, check_tokens};

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

    #[test]
    fn programs_are_postfix_with_numbers_folded() {
        let compile = |text| {
            let mut parser = Parser::new(text, &["x"], &[("pi", std::f64::consts::PI)]).unwrap();
            parser.parse().unwrap();
            format!("{:?}", parser.program)
        };
        // -(x^2) + min(1e-3, pi): the min of two numbers is folded.
        assert_eq!(compile("-x^2 + min(1e-3, pi)"), "[Var(0), Num(2.0), Pow, Neg, Num(0.001), Add]");
        // (x - 1) - 2, left to right: nothing to fold (x - (1 + 2) would round differently).
        assert_eq!(compile("x - 1 - 2"), "[Var(0), Num(1.0), Sub, Num(2.0), Sub]");
        assert_eq!(compile("2^3^2"), "[Num(512.0)]");
    }
}

/// Two expressions are equal when they were written the same for the same key and variables
/// (what a resolved scene reading back to itself needs).
impl PartialEq for Expr {
    fn eq(&self, other: &Self) -> bool {
        self.key == other.key && self.text == other.text && self.vars == other.vars
    }
}
