//! A travelling wave (A of ξ = x − ct, or B of η = x + ct) as contiguous pieces, each an image
//! `offset + sign · F(dir · arg + shift)` of one initial wave F ∈ {A₀, B₀} (see [`super::base`]).
//!
//! Every reflection maps the argument by `arg ↦ −arg` (at x = 0) or `arg ↦ 2L − arg`
//! (at x = L), so compositions stay of the form `±arg + shift` and a piece never needs
//! re-fitting: it keeps pointing at the initial data, and its values are exact to round-off.

use super::base::{Base, Which};

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Map {
    pub w: Which,
    pub sign: f64,
    pub dir: f64,
    pub shift: f64,
    pub offset: f64,
}

impl Map {
    pub fn identity(w: Which) -> Self {
        Map { w, sign: 1.0, dir: 1.0, shift: 0.0, offset: 0.0 }
    }

    /// The argument of the initial wave.
    #[inline]
    pub fn y(&self, arg: f64) -> f64 {
        self.dir * arg + self.shift
    }

    /// The k-th derivative (k ≤ 2) at `arg`, evaluated with panel j of the initial wave:
    /// `d^k/darg^k [offset + sign F(dir arg + shift)] = sign dir^k F^{(k)} (+ offset if k = 0)`.
    #[inline]
    pub fn eval(&self, base: &Base, j: usize, k: usize, arg: f64) -> f64 {
        let f = self.sign * base.eval(j, self.w, k, self.y(arg));
        match k {
            0 => self.offset + f,
            1 => self.dir * f,
            _ => f,
        }
    }

    /// The image under `arg ↦ mirror − arg`, scaled by `sign` and raised by `lift`:
    /// `G(arg) = lift + sign · self(mirror − arg)`.
    pub fn reflect(&self, mirror: f64, sign: f64, lift: f64) -> Self {
        Map {
            w: self.w,
            sign: sign * self.sign,
            dir: -self.dir,
            shift: self.shift + self.dir * mirror,
            offset: lift + sign * self.offset,
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Piece {
    pub lo: f64,
    pub hi: f64,
    pub map: Map,
}

/// Contiguous pieces in increasing argument; outside `[first.lo, last.hi]` the end pieces
/// extend (only round-off ever asks there).
#[derive(Debug, Clone)]
pub(super) struct Wave {
    pub pieces: Vec<Piece>,
}

impl Wave {
    /// The piece holding `arg`: starting at or before it (`right`) or ending at or after it.
    pub fn locate(&self, arg: f64, right: bool) -> usize {
        let k = if right {
            self.pieces.partition_point(|p| p.lo <= arg)
        } else {
            self.pieces.partition_point(|p| p.lo < arg)
        };
        k.saturating_sub(1)
    }

    /// (piece, panel) of the one-sided limit at `arg` from the right (`right`) or the left.
    pub fn find(&self, base: &Base, arg: f64, right: bool) -> (usize, usize) {
        let i = self.locate(arg, right);
        let map = &self.pieces[i].map;
        // Moving right in arg moves y in the direction of dir.
        (i, base.locate(map.y(arg), right == (map.dir > 0.0)))
    }

    pub fn eval(&self, base: &Base, k: usize, arg: f64, right: bool) -> f64 {
        let (i, j) = self.find(base, arg, right);
        self.pieces[i].map.eval(base, j, k, arg)
    }

    pub fn walk<'a>(&'a self, base: &'a Base, lo: f64, hi: f64) -> Walker<'a> {
        let (piece, panel) = self.find(base, lo, true);
        Walker { wave: self, base, end: hi, pos: lo, piece, panel, starts_piece: false, done: false }
    }
}

/// A stretch of a wave on which it is one polynomial: one piece, one panel.
#[derive(Debug, Clone, Copy)]
pub(super) struct Segment {
    pub lo: f64,
    pub hi: f64,
    pub piece: usize,
    pub panel: usize,
    /// `lo` is a boundary between two pieces (not only between two panels).
    pub starts_piece: bool,
    /// The segment ends the walk; `hi` is then the walk's end.
    pub last: bool,
}

/// The segments of a wave over `[pos, end]`, in increasing argument.
pub(super) struct Walker<'a> {
    wave: &'a Wave,
    base: &'a Base,
    end: f64,
    pos: f64,
    piece: usize,
    panel: usize,
    starts_piece: bool,
    done: bool,
}

impl Iterator for Walker<'_> {
    type Item = Segment;

    fn next(&mut self) -> Option<Segment> {
        while !self.done {
            let pieces = &self.wave.pieces;
            let map = pieces[self.piece].map;
            let forward = map.dir > 0.0;
            let has_next_panel = if forward { self.panel + 1 < self.base.panels() } else { self.panel > 0 };
            let panel_hi = if has_next_panel {
                let y_end = self.base.breaks[if forward { self.panel + 1 } else { self.panel }];
                map.dir * (y_end - map.shift)
            } else {
                f64::INFINITY
            };
            let piece_hi = if self.piece + 1 < pieces.len() { pieces[self.piece].hi } else { f64::INFINITY };
            let hi = panel_hi.min(piece_hi).min(self.end);
            let seg = Segment {
                lo: self.pos,
                hi,
                piece: self.piece,
                panel: self.panel,
                starts_piece: self.starts_piece,
                last: hi >= self.end,
            };
            let mut new_piece = false;
            if seg.last {
                self.done = true;
            } else if panel_hi < piece_hi {
                self.panel = if forward { self.panel + 1 } else { self.panel - 1 };
            } else {
                self.piece += 1;
                let next = pieces[self.piece].map;
                self.panel = self.base.locate(next.y(hi), next.dir > 0.0);
                new_piece = true;
            }
            if hi > self.pos || seg.last {
                self.pos = hi;
                self.starts_piece = new_piece;
                return Some(seg);
            }
            // An empty segment (boundaries equal to round-off): its piece boundary carries over.
            self.starts_piece |= new_piece;
        }
        None
    }
}
