//! The front end of [`super::Expr`]: a tokenizer and a recursive-descent parser that check a
//! scene expression, locate errors by column, and write the canonical, fully parenthesised form
//! handed to exmex (module docs of [`super`]).

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

pub(super) fn tokenize(text: &str) -> Result<Vec<Token>, Failure> {
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let byte_at = |i: usize| chars.get(i).map_or(text.len(), |(b, _)| *b);
    let char_at = |i: usize| chars.get(i).map(|(_, c)| *c);
    let mut tokens = Vec::new();
    let mut i = 0;
    while let Some(c) = char_at(i) {
        let first = i;
        let kind = match c {
            _ if c.is_whitespace() => {
                i += 1;
                continue;
            }
            '0'..='9' | '.' => {
                let digits = |i: &mut usize| {
                    let from = *i;
                    while char_at(*i).is_some_and(|c| c.is_ascii_digit()) {
                        *i += 1;
                    }
                    *i - from
                };
                let mut count = digits(&mut i);
                if char_at(i) == Some('.') {
                    i += 1;
                    count += digits(&mut i);
                }
                if count == 0 {
                    return Err(parse_failure(first + 1, "a '.' without digits is not a number"));
                }
                if matches!(char_at(i), Some('e' | 'E')) {
                    i += 1;
                    if matches!(char_at(i), Some('+' | '-')) {
                        i += 1;
                    }
                    if digits(&mut i) == 0 {
                        let written = &text[byte_at(first)..byte_at(i)];
                        return Err(parse_failure(
                            first + 1,
                            format!("malformed number '{written}' (exponent without digits)"),
                        ));
                    }
                }
                let written = &text[byte_at(first)..byte_at(i)];
                let value: f64 = written.parse().expect("digits, one '.', an exponent: a valid f64 literal");
                if !value.is_finite() {
                    return Err(parse_failure(first + 1, format!("number {written} is too large for f64")));
                }
                Kind::Number(value)
            }
            _ if is_name_start(c) => {
                while char_at(i).is_some_and(is_name_continue) {
                    i += 1;
                }
                Kind::Name
            }
            '*' if char_at(i + 1) == Some('*') => {
                i += 2;
                Kind::Power
            }
            '+' | '-' | '*' | '/' | '^' | '(' | ')' | ',' => {
                i += 1;
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
        tokens.push(Token { kind, column: first + 1, start: byte_at(first), end: byte_at(i) });
    }
    tokens.push(Token { kind: Kind::End, column: chars.len() + 1, start: text.len(), end: text.len() });
    Ok(tokens)
}

/// Grammar (lowest precedence first):
/// ```text
/// sum     = product { ("+" | "-") product }
/// product = signed { ("*" | "/") signed }
/// signed  = ("-" | "+") signed | power
/// power   = primary [ ("^" | "**") signed ]
/// primary = number | variable | constant | function "(" sum { "," sum } ")" | "(" sum ")"
/// ```
/// Each rule returns its canonical text: a literal, `{v<i>}`, or a parenthesised operation.
pub(super) struct Parser<'a> {
    pub(super) text: &'a str,
    pub(super) tokens: Vec<Token>,
    pub(super) next: usize,
    pub(super) vars: &'a [&'a str],
    pub(super) consts: &'a [(&'a str, f64)],
    pub(super) used: Vec<bool>,
    pub(super) depth: usize,
}

impl Parser<'_> {
    pub(super) fn parse(&mut self) -> Result<String, Failure> {
        if self.peek().kind == Kind::End {
            return Err(parse_failure(1, "empty expression"));
        }
        let canonical = self.sum()?;
        let token = self.peek();
        match token.kind {
            Kind::End => Ok(canonical),
            Kind::Close => Err(parse_failure(token.column, "unbalanced parenthesis: ')' without a matching '('")),
            Kind::Comma => Err(parse_failure(token.column, "',' outside the arguments of min or max")),
            _ => Err(self.expected("an operator", token)),
        }
    }

    fn peek(&self) -> Token {
        self.tokens[self.next]
    }

    fn bump(&mut self) -> Token {
        let token = self.tokens[self.next];
        self.next += 1;
        token
    }

    fn written(&self, token: Token) -> &str {
        &self.text[token.start..token.end]
    }

    fn expected(&self, what: &str, found: Token) -> Failure {
        let written =
            if found.kind == Kind::End { "the end".to_string() } else { format!("'{}'", self.written(found)) };
        parse_failure(found.column, format!("expected {what}, found {written}"))
    }

    fn sum(&mut self) -> Result<String, Failure> {
        self.left_associative(Self::product, |kind| match kind {
            Kind::Plus => Some('+'),
            Kind::Minus => Some('-'),
            _ => None,
        })
    }

    fn product(&mut self) -> Result<String, Failure> {
        self.left_associative(Self::signed, |kind| match kind {
            Kind::Star => Some('*'),
            Kind::Slash => Some('/'),
            _ => None,
        })
    }

    /// `operand { op operand }`, grouped from the left; `op` names the operator of a token of this
    /// level.
    fn left_associative(
        &mut self,
        operand: fn(&mut Self) -> Result<String, Failure>,
        op: fn(Kind) -> Option<char>,
    ) -> Result<String, Failure> {
        let mut canonical = operand(self)?;
        while let Some(op) = op(self.peek().kind) {
            self.bump();
            let right = operand(self)?;
            canonical = format!("({canonical}{op}{right})");
        }
        Ok(canonical)
    }

    /// Every level of nesting passes through here, so the depth is counted here.
    fn signed(&mut self) -> Result<String, Failure> {
        self.depth += 1;
        if self.depth > MAX_DEPTH {
            return Err(parse_failure(self.peek().column, format!("nested more than {MAX_DEPTH} levels deep")));
        }
        let canonical = match self.peek().kind {
            Kind::Minus => {
                self.bump();
                format!("(-{})", self.signed()?)
            }
            Kind::Plus => {
                self.bump();
                self.signed()?
            }
            _ => self.power()?,
        };
        self.depth -= 1;
        Ok(canonical)
    }

    fn power(&mut self) -> Result<String, Failure> {
        let base = self.primary()?;
        if self.peek().kind != Kind::Power {
            return Ok(base);
        }
        self.bump();
        // The exponent is `signed`, not `power`: right-associative, and `2^-1` is allowed.
        let exponent = self.signed()?;
        Ok(format!("({base}^{exponent})"))
    }

    fn primary(&mut self) -> Result<String, Failure> {
        let token = self.peek();
        match token.kind {
            Kind::Number(value) => {
                self.bump();
                Ok(literal(value))
            }
            Kind::Open => {
                self.bump();
                let inner = self.sum()?;
                self.close(token)?;
                Ok(inner)
            }
            Kind::Name => {
                self.bump();
                self.name(token)
            }
            Kind::Close if !self.inside_parentheses() => {
                Err(parse_failure(token.column, "unbalanced parenthesis: ')' without a matching '('"))
            }
            _ => Err(self.expected("a number, a name or '('", token)),
        }
    }

    /// Whether an `(` before the current token is still open.
    fn inside_parentheses(&self) -> bool {
        let mut open = 0i64;
        for token in &self.tokens[..self.next] {
            match token.kind {
                Kind::Open => open += 1,
                Kind::Close => open -= 1,
                _ => {}
            }
        }
        open > 0
    }

    /// Consumes the `)` matching `open`.
    fn close(&mut self, open: Token) -> Result<(), Failure> {
        let token = self.peek();
        match token.kind {
            Kind::Close => {
                self.bump();
                Ok(())
            }
            Kind::End => Err(parse_failure(
                token.column,
                format!("unbalanced parenthesis: the '(' at column {} is not closed", open.column),
            )),
            _ => Err(self.expected("an operator or ')'", token)),
        }
    }

    fn name(&mut self, token: Token) -> Result<String, Failure> {
        let name = self.written(token);
        let call = self.peek().kind == Kind::Open;
        if let Some(i) = self.vars.iter().position(|v| *v == name) {
            if call {
                return Err(parse_failure(self.peek().column, format!("'{name}' is a variable, not a function")));
            }
            self.used[i] = true;
            return Ok(format!("{{v{i}}}"));
        }
        if let Some((_, value)) = self.consts.iter().find(|(c, _)| *c == name) {
            if call {
                return Err(parse_failure(self.peek().column, format!("'{name}' is a constant, not a function")));
            }
            return Ok(literal(*value));
        }
        let Some(&(function, arity)) = FUNCTIONS.iter().find(|(f, _)| *f == name) else {
            return Err(Failure::Unknown { position: token.column, name: name.to_string() });
        };
        if !call {
            return Err(self.expected(&format!("'(' after the function '{function}'"), self.peek()));
        }
        let open = self.bump();
        let mut args = vec![self.sum()?];
        while self.peek().kind == Kind::Comma {
            let comma = self.bump();
            if args.len() == arity {
                return Err(parse_failure(comma.column, format!("{function} takes {}", arguments(arity))));
            }
            args.push(self.sum()?);
        }
        if args.len() < arity && self.peek().kind == Kind::Close {
            return Err(parse_failure(self.peek().column, format!("{function} takes {}", arguments(arity))));
        }
        self.close(open)?;
        Ok(match args.as_slice() {
            [arg] => format!("{function}({arg})"),
            [a, b] => format!("({a} {function} {b})"),
            _ => unreachable!("arities are 1 and 2"),
        })
    }
}

fn arguments(arity: usize) -> String {
    if arity == 1 { "one argument".into() } else { format!("{arity} arguments") }
}
