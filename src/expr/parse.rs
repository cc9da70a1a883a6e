//! The front end of [`super::Expr`]: a lexer and a recursive-descent parser that check a scene
//! expression, locate errors by column, and compile it into a postfix program (module docs of
//! [`super`]). Both are linear in the length of the text.

use super::*;

#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Kind {
    Number(f64),
    Name,
    Plus,
    Minus,
    Star,
    Slash,
    Power,
    Open,
    Close,
    Comma,
    End,
}

#[derive(Clone, Copy, Debug)]
pub(super) struct Token {
    kind: Kind,
    /// 1-based character column of the first character.
    column: usize,
    /// Byte range in the text.
    start: usize,
    end: usize,
}

/// A failure before the key and text are attached.
#[derive(Debug)]
pub(super) enum Failure {
    Parse { position: usize, message: String },
    Unknown { position: usize, name: String },
}

impl Failure {
    pub(super) fn into_error(self, key: &str, text: &str, vars: &[&str], consts: &[(&str, f64)]) -> ExprError {
        let (key, text) = (key.to_string(), text.to_string());
        match self {
            Failure::Parse { position, message } => ExprError::Parse { key, text, position, message },
            Failure::Unknown { position, name } => {
                let allowed = vars
                    .iter()
                    .copied()
                    .chain(consts.iter().map(|(name, _)| *name))
                    .chain(FUNCTIONS.iter().map(|(name, _)| *name))
                    .map(String::from)
                    .collect();
                ExprError::UnknownName { key, text, name, position, allowed }
            }
        }
    }
}

fn parse_failure(position: usize, message: impl Into<String>) -> Failure {
    Failure::Parse { position, message: message.into() }
}

/// The tokens of `text`, one at a time: the parser reads them as it goes, so no list of tokens
/// is ever held (a 16 MB scene is millions of them).
pub(super) struct Lexer<'a> {
    text: &'a str,
    /// Byte offset and 0-based character index of the next character.
    pos: usize,
    col: usize,
    done: bool,
}

impl<'a> Lexer<'a> {
    pub(super) fn new(text: &'a str) -> Self {
        Lexer { text, pos: 0, col: 0, done: false }
    }

    fn peek_char(&self) -> Option<char> {
        self.text[self.pos..].chars().next()
    }

    fn peek_second(&self) -> Option<char> {
        self.text[self.pos..].chars().nth(1)
    }

    fn advance(&mut self) {
        if let Some(c) = self.peek_char() {
            self.pos += c.len_utf8();
            self.col += 1;
        }
    }

    fn digits(&mut self) -> usize {
        let from = self.col;
        while self.peek_char().is_some_and(|c| c.is_ascii_digit()) {
            self.advance();
        }
        self.col - from
    }

    /// The next token; `End` (at column `characters + 1`) when the text is used up.
    pub(super) fn next_token(&mut self) -> Result<Token, Failure> {
        while self.peek_char().is_some_and(char::is_whitespace) {
            self.advance();
        }
        let (first, start) = (self.col, self.pos);
        let Some(c) = self.peek_char() else {
            self.done = true;
            return Ok(Token { kind: Kind::End, column: first + 1, start, end: start });
        };
        let kind = match c {
            '0'..='9' | '.' => self.number(first, start)?,
            _ if is_name_start(c) => {
                while self.peek_char().is_some_and(is_name_continue) {
                    self.advance();
                }
                Kind::Name
            }
            '*' if self.peek_second() == Some('*') => {
                self.advance();
                self.advance();
                Kind::Power
            }
            '+' | '-' | '*' | '/' | '^' | '(' | ')' | ',' => {
                self.advance();
                match c {
                    '+' => Kind::Plus,
                    '-' => Kind::Minus,
                    '*' => Kind::Star,
                    '/' => Kind::Slash,
                    '^' => Kind::Power,
                    '(' => Kind::Open,
                    ')' => Kind::Close,
                    _ => Kind::Comma,
                }
            }
            _ => return Err(parse_failure(first + 1, format!("unexpected character '{c}'"))),
        };
        Ok(Token { kind, column: first + 1, start, end: self.pos })
    }

    /// A number starting at character `first` (byte `start`).
    fn number(&mut self, first: usize, start: usize) -> Result<Kind, Failure> {
        let mut count = self.digits();
        if self.peek_char() == Some('.') {
            self.advance();
            count += self.digits();
        }
        if count == 0 {
            return Err(parse_failure(first + 1, "a '.' without digits is not a number"));
        }
        if matches!(self.peek_char(), Some('e' | 'E')) {
            self.advance();
            if matches!(self.peek_char(), Some('+' | '-')) {
                self.advance();
            }
            if self.digits() == 0 {
                let written = &self.text[start..self.pos];
                return Err(parse_failure(
                    first + 1,
                    format!("malformed number '{written}' (exponent without digits)"),
                ));
            }
        }
        let written = &self.text[start..self.pos];
        // Digits, at most one '.', an optional exponent with digits: always a valid f64 literal.
        let value: f64 =
            written.parse().map_err(|_| parse_failure(first + 1, format!("malformed number '{written}'")))?;
        if !value.is_finite() {
            return Err(parse_failure(first + 1, format!("number {written} is too large for f64")));
        }
        Ok(Kind::Number(value))
    }
}

/// Lexes the whole text once, so that a bad character or number anywhere is reported before
/// any grammar error (holds no tokens).
pub(super) fn check_tokens(text: &str) -> Result<(), Failure> {
    let mut lexer = Lexer::new(text);
    while !lexer.done {
        lexer.next_token()?;
    }
    Ok(())
}

/// One instruction of the compiled form: a postfix program run on a stack
/// ([`super::Expr::eval`]). Binary operators pop the right operand, then the left.
#[derive(Clone, Copy, Debug)]
pub(super) enum Op {
    Num(f64),
    /// The caller's variable number i.
    Var(usize),
    Neg,
    Add,
    Sub,
    Mul,
    Div,
    Pow,
    Min,
    Max,
    /// A one-argument function of [`FUNCTIONS`].
    Call(fn(f64) -> f64),
}

impl Op {
    /// The value of a unary operation (`Neg`, `Call`) on `a`.
    #[inline]
    pub(super) fn unary(self, a: f64) -> f64 {
        match self {
            Op::Neg => -a,
            Op::Call(f) => f(a),
            _ => f64::NAN,
        }
    }

    /// The value of a binary operation on `a` (left) and `b` (right).
    #[inline]
    pub(super) fn binary(self, a: f64, b: f64) -> f64 {
        match self {
            Op::Add => a + b,
            Op::Sub => a - b,
            Op::Mul => a * b,
            Op::Div => a / b,
            Op::Pow => a.powf(b),
            Op::Min => a.min(b),
            Op::Max => a.max(b),
            _ => f64::NAN,
        }
    }
}

/// Grammar (lowest precedence first):
/// ```text
/// sum     = product { ("+" | "-") product }
/// product = signed { ("*" | "/") signed }
/// signed  = ("-" | "+") signed | power
/// power   = primary [ ("^" | "**") signed ]
/// primary = number | variable | constant | function "(" sum { "," sum } ")" | "(" sum ")"
/// ```
/// Each rule appends its postfix code to `program`, folding an operation whose operands are
/// numbers into its value (the same f64 operation, done once). Every step is O(1) (one token,
/// one instruction), so parsing is linear in the text.
pub(super) struct Parser<'a> {
    pub(super) text: &'a str,
    pub(super) lexer: Lexer<'a>,
    /// The next token (read ahead).
    pub(super) current: Token,
    pub(super) vars: &'a [&'a str],
    pub(super) consts: &'a [(&'a str, f64)],
    pub(super) used: Vec<bool>,
    pub(super) depth: usize,
    /// `(` consumed and not yet closed.
    open: usize,
    pub(super) program: Vec<Op>,
    /// Stack height the program reaches so far, and its maximum.
    height: usize,
    pub(super) max_height: usize,
}

impl<'a> Parser<'a> {
    pub(super) fn new(text: &'a str, vars: &'a [&'a str], consts: &'a [(&'a str, f64)]) -> Result<Self, Failure> {
        let mut lexer = Lexer::new(text);
        let current = lexer.next_token()?;
        Ok(Parser {
            text,
            lexer,
            current,
            vars,
            consts,
            used: vec![false; vars.len()],
            depth: 0,
            open: 0,
            program: Vec::new(),
            height: 0,
            max_height: 0,
        })
    }

    pub(super) fn parse(&mut self) -> Result<(), Failure> {
        if self.peek().kind == Kind::End {
            return Err(parse_failure(1, "empty expression"));
        }
        self.sum()?;
        let token = self.peek();
        match token.kind {
            Kind::End => Ok(()),
            Kind::Close => Err(parse_failure(token.column, "unbalanced parenthesis: ')' without a matching '('")),
            Kind::Comma => Err(parse_failure(token.column, "',' outside the arguments of min or max")),
            _ => Err(self.expected("an operator", token)),
        }
    }

    fn peek(&self) -> Token {
        self.current
    }

    fn bump(&mut self) -> Result<Token, Failure> {
        let token = self.current;
        match token.kind {
            Kind::Open => self.open += 1,
            Kind::Close => self.open = self.open.saturating_sub(1),
            _ => {}
        }
        if token.kind != Kind::End {
            self.current = self.lexer.next_token()?;
        }
        Ok(token)
    }

    /// Appends a leaf (number or variable).
    fn leaf(&mut self, op: Op) {
        self.program.push(op);
        self.height += 1;
        self.max_height = self.max_height.max(self.height);
    }

    /// Appends a unary operation, folded when its operand is a number.
    fn unary(&mut self, op: Op) {
        if let Some(Op::Num(a)) = self.program.last_mut() {
            *a = op.unary(*a);
        } else {
            self.program.push(op);
        }
    }

    /// Appends a binary operation, folded when both operands are numbers (a leaf that ends a
    /// complete operand is that whole operand).
    fn binary(&mut self, op: Op) {
        self.height -= 1;
        let n = self.program.len();
        if let [.., Op::Num(a), Op::Num(b)] = self.program[..] {
            self.program.truncate(n - 1);
            self.program[n - 2] = Op::Num(op.binary(a, b));
        } else {
            self.program.push(op);
        }
    }

    fn written(&self, token: Token) -> &str {
        &self.text[token.start..token.end]
    }

    fn expected(&self, what: &str, found: Token) -> Failure {
        let written =
            if found.kind == Kind::End { "the end".to_string() } else { format!("'{}'", self.written(found)) };
        parse_failure(found.column, format!("expected {what}, found {written}"))
    }

    fn sum(&mut self) -> Result<(), Failure> {
        self.left_associative(Self::product, |kind| match kind {
            Kind::Plus => Some(Op::Add),
            Kind::Minus => Some(Op::Sub),
            _ => None,
        })
    }

    fn product(&mut self) -> Result<(), Failure> {
        self.left_associative(Self::signed, |kind| match kind {
            Kind::Star => Some(Op::Mul),
            Kind::Slash => Some(Op::Div),
            _ => None,
        })
    }

    /// `operand { op operand }`, grouped from the left; `op` names the operation of a token of
    /// this level.
    fn left_associative(
        &mut self,
        operand: fn(&mut Self) -> Result<(), Failure>,
        op: fn(Kind) -> Option<Op>,
    ) -> Result<(), Failure> {
        operand(self)?;
        while let Some(op) = op(self.peek().kind) {
            self.bump()?;
            operand(self)?;
            self.binary(op);
        }
        Ok(())
    }

    /// Every level of nesting passes through here, so the depth is counted here.
    fn signed(&mut self) -> Result<(), Failure> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(parse_failure(self.peek().column, format!("nested more than {MAX_DEPTH} levels deep")));
        }
        match self.peek().kind {
            Kind::Minus => {
                self.bump()?;
                self.signed()?;
                self.unary(Op::Neg);
            }
            Kind::Plus => {
                self.bump()?;
                self.signed()?;
            }
            _ => self.power()?,
        }
        self.depth -= 1;
        Ok(())
    }

    fn power(&mut self) -> Result<(), Failure> {
        self.primary()?;
        if self.peek().kind != Kind::Power {
            return Ok(());
        }
        self.bump()?;
        // The exponent is `signed`, not `power`: right-associative, and `2^-1` is allowed.
        self.signed()?;
        self.binary(Op::Pow);
        Ok(())
    }

    fn primary(&mut self) -> Result<(), Failure> {
        let token = self.peek();
        match token.kind {
            Kind::Number(value) => {
                self.bump()?;
                self.leaf(Op::Num(value));
                Ok(())
            }
            Kind::Open => {
                self.bump()?;
                self.sum()?;
                self.close(token)
            }
            Kind::Name => {
                self.bump()?;
                self.name(token)
            }
            Kind::Close if self.open == 0 => {
                Err(parse_failure(token.column, "unbalanced parenthesis: ')' without a matching '('"))
            }
            _ => Err(self.expected("a number, a name or '('", token)),
        }
    }

    /// Consumes the `)` matching `open`.
    fn close(&mut self, open: Token) -> Result<(), Failure> {
        let token = self.peek();
        match token.kind {
            Kind::Close => {
                self.bump()?;
                Ok(())
            }
            Kind::End => Err(parse_failure(
                token.column,
                format!("unbalanced parenthesis: the '(' at column {} is not closed", open.column),
            )),
            _ => Err(self.expected("an operator or ')'", token)),
        }
    }

    fn name(&mut self, token: Token) -> Result<(), Failure> {
        let name = self.written(token);
        let call = self.peek().kind == Kind::Open;
        if let Some(i) = self.vars.iter().position(|v| *v == name) {
            if call {
                return Err(parse_failure(self.peek().column, format!("'{name}' is a variable, not a function")));
            }
            self.used[i] = true;
            self.leaf(Op::Var(i));
            return Ok(());
        }
        if let Some(&(_, value)) = self.consts.iter().find(|(c, _)| *c == name) {
            if call {
                return Err(parse_failure(self.peek().column, format!("'{name}' is a constant, not a function")));
            }
            self.leaf(Op::Num(value));
            return Ok(());
        }
        let Some(&(function, arity)) = FUNCTIONS.iter().find(|(f, _)| *f == name) else {
            return Err(Failure::Unknown { position: token.column, name: name.to_string() });
        };
        if !call {
            return Err(self.expected(&format!("'(' after the function '{function}'"), self.peek()));
        }
        let open = self.bump()?;
        self.sum()?;
        let mut args = 1;
        while self.peek().kind == Kind::Comma {
            let comma = self.bump()?;
            if args == arity {
                return Err(parse_failure(comma.column, format!("{function} takes {}", arguments(arity))));
            }
            self.sum()?;
            args += 1;
        }
        if args < arity && self.peek().kind == Kind::Close {
            return Err(parse_failure(self.peek().column, format!("{function} takes {}", arguments(arity))));
        }
        self.close(open)?;
        match function {
            "min" => self.binary(Op::Min),
            "max" => self.binary(Op::Max),
            _ => self.unary(Op::Call(unary_function(function))),
        }
        Ok(())
    }
}

fn arguments(arity: usize) -> String {
    if arity == 1 { "one argument".into() } else { format!("{arity} arguments") }
}

/// The one-argument function named `name` (one of [`FUNCTIONS`]; `log` is the natural logarithm).
fn unary_function(name: &str) -> fn(f64) -> f64 {
    match name {
        "sin" => f64::sin,
        "cos" => f64::cos,
        "tan" => f64::tan,
        "exp" => f64::exp,
        "log" => f64::ln,
        "sqrt" => f64::sqrt,
        _ => f64::abs,
    }
}
