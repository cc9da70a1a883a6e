//! Building the two travelling waves by marching the boundary reflections in s = ct.
//!
//! A is known on ξ ∈ [0, L] and B on η ∈ [0, L] from the initial data. B beyond L comes from
//! A by the far-end reflection `B(L + σ) = ±A(L − σ) + κ`, and A below 0 from B by the
//! obstacle rule at x = 0 (free or contact). Each needs the other only at least 0 behind
//! (B(L + σ) needs A(L − σ), i.e. the x = 0 rule at s = σ − L), so the two sweeps alternate
//! and each pass advances by at least L until s_end = c·t_end.
//!
//! The march is incremental ([`Marcher::step`]) and forgets what is behind it
//! ([`Marcher::trim`]): a piece is made from its predecessor and the sweep's state alone, and
//! each sweep clips at the same s_end, so marching in bounded stretches from a saved state
//! makes the very pieces (bit for bit) that one march over [0, s_end] makes.

use super::base::{Base, Which};
use super::search::first_descent;
use super::wave::{Map, Piece};
use super::{CharacteristicsError, FarEnd};
use std::collections::VecDeque;

/// Relative round-off allowance of the switching tests: 64 ulps of the magnitudes involved.
const SWITCH_ULPS: f64 = 64.0 * f64::EPSILON;
/// More switches than this inside one panel means the data defeat the search.
const MAX_SWITCHES_PER_PANEL: usize = 1000;

#[derive(Debug, Clone, Copy)]
pub(super) struct Params {
    pub length: f64,
    pub gap: f64,
    pub wave_speed: f64,
    pub far_end: FarEnd,
    /// c · t_end.
    pub s_end: f64,
}

#[derive(Debug, Clone, Copy)]
enum Phase {
    /// `A(−s) = B(s) + k`.
    Free { k: f64 },
    /// `A(−s) = −g − B(s)`, since s = `since`.
    Contact { since: f64 },
}

/// The sweep at x = 0: turns B on [0, s] into A on [−s, 0].
#[derive(Debug, Clone)]
struct Obstacle {
    gap: f64,
    wave_speed: f64,
    /// Swept up to here.
    s: f64,
    /// Start of the A piece being formed (a phase switch or a B piece boundary).
    seg_start: f64,
    phase: Phase,
    /// Closed contact phases found by the sweep, not yet taken by the marcher.
    contacts: Vec<(f64, f64)>,
}

impl Obstacle {
    /// Close the A piece `[−s1, −seg_start]`, the image of B piece `b` under the current phase.
    fn emit(&mut self, b: &Map, s1: f64, out: &mut VecDeque<Piece>) {
        if s1 > self.seg_start {
            let map = match self.phase {
                Phase::Free { k } => b.reflect(0.0, 1.0, k),
                Phase::Contact { .. } => b.reflect(0.0, -1.0, -self.gap),
            };
            out.push_back(Piece { lo: -s1, hi: -self.seg_start, map });
        }
        self.seg_start = s1;
    }

    /// Sweep B piece `b` from `self.s` to `q`, panel by panel, appending A pieces to `out`.
    fn sweep(&mut self, base: &Base, b: &Piece, q: f64, out: &mut VecDeque<Piece>) -> Result<(), CharacteristicsError> {
        let map = b.map;
        let forward = map.dir > 0.0;
        let mut j = base.locate(map.y(self.s), forward);
        loop {
            let has_next = if forward { j + 1 < base.panels() } else { j > 0 };
            let panel_end = if has_next {
                map.dir * (base.breaks[if forward { j + 1 } else { j }] - map.shift)
            } else {
                f64::INFINITY
            };
            let sb = panel_end.min(q);
            self.panel(base, &map, j, sb, out)?;
            if sb >= q {
                break;
            }
            j = if forward { j + 1 } else { j - 1 };
        }
        self.emit(&map, q, out);
        self.s = q;
        Ok(())
    }

    /// The phase switches of `B(s) = map(s)` (panel j) on `[self.s, sb]`.
    ///
    /// Free phase: u(0, t) = B(s) + A(−s) = 2B(s) + k, so contact starts where
    /// `f = 2B + k + g` first goes negative (the free motion would pass the obstacle).
    /// Contact phase: λ = E u_x(0+) = E(A'(−s) + B'(s)) = 2E B'(s) (A(−s) = −g − B(s) gives
    /// A'(−s) = B'(s)), so the contact is released where `−B'` first goes negative.
    fn panel(
        &mut self,
        base: &Base,
        map: &Map,
        j: usize,
        sb: f64,
        out: &mut VecDeque<Piece>,
    ) -> Result<(), CharacteristicsError> {
        let (g, w) = (self.gap, map.w);
        let at = |k: usize, s: f64| map.eval(base, j, k, s);
        for _ in 0..MAX_SWITCHES_PER_PANEL {
            if self.s >= sb {
                return Ok(());
            }
            let found = match self.phase {
                Phase::Free { k } => {
                    let f = |s: f64| (2.0 * at(0, s) + k + g, 2.0 * at(1, s));
                    let size = 2.0 * (map.offset.abs() + base.sup(j, w, 0)) + k.abs() + g;
                    first_descent(&f, 2.0 * base.sup(j, w, 2), self.s, sb, SWITCH_ULPS * size)
                }
                Phase::Contact { .. } => {
                    let f = |s: f64| (-at(1, s), -at(2, s));
                    first_descent(&f, base.sup(j, w, 3), self.s, sb, SWITCH_ULPS * base.sup(j, w, 1))
                }
            };
            let found = found.map_err(|_| CharacteristicsError::SwitchSearch { t: self.s / self.wave_speed })?;
            let Some(s) = found else {
                self.s = sb;
                return Ok(());
            };
            self.emit(map, s, out);
            self.phase = match self.phase {
                Phase::Free { .. } => Phase::Contact { since: s },
                Phase::Contact { since } => {
                    if s > since {
                        self.contacts.push((since, s));
                    }
                    // Continuity of A at −s: B(s) + k = −g − B(s).
                    Phase::Free { k: -g - 2.0 * at(0, s) }
                }
            };
            self.s = s;
        }
        Err(CharacteristicsError::SwitchSearch { t: self.s / self.wave_speed })
    }
}

/// A march in progress: the pieces it still needs and the pieces evaluations from its current
/// position on may ask for, each sequence with the global index of its first element.
#[derive(Debug, Clone)]
pub(super) struct Marcher {
    p: Params,
    /// Far-end reflection `B(L + σ) = sigma · A(L − σ) + kappa`.
    sigma: f64,
    kappa: f64,
    obstacle: Obstacle,
    /// A pieces in decreasing ξ, B pieces in increasing η: the order in which they are made.
    a: VecDeque<Piece>,
    a_first: usize,
    b: VecDeque<Piece>,
    b_first: usize,
    /// Next A piece to reflect at x = L, next B piece to sweep at x = 0 (global indices).
    ia: usize,
    ib: usize,
    xi_done: f64,
    /// Closed contact phases in s, the first being number `contacts_first` of the march.
    contacts: VecDeque<(f64, f64)>,
    contacts_first: usize,
    /// Pieces made so far (both waves).
    made: usize,
    /// `Some(open)` once the march reached s_end; `open`: the last contact is still on there.
    finished: Option<bool>,
}

impl Marcher {
    /// The march at s = 0.
    pub fn new(base: &Base, p: Params) -> Self {
        let l = p.length;
        let last = base.panels() - 1;
        let end = |w| base.eval(last, w, 0, l);
        // Far end, u = A(L − s) + B(L + s):
        //   clamped u(L, t) = u⁰(L):  B(L + σ) = −A(L − σ) + (A₀(L) + B₀(L))   (odd reflection),
        //   free    u_x(L, t) = 0:    B'(L + σ) = −A'(L − σ), so B(L + σ) = A(L − σ) + (B₀(L) − A₀(L))
        //                             (even reflection; the constant makes B continuous at L).
        let (sigma, kappa) = match p.far_end {
            FarEnd::Clamped => (-1.0, end(Which::A) + end(Which::B)),
            FarEnd::Free => (1.0, end(Which::B) - end(Which::A)),
        };
        // Free reflection at x = 0 from t = 0: A(−s) = B(s) + k, continuous at s = 0.
        let k0 = base.eval(0, Which::A, 0, 0.0) - base.eval(0, Which::B, 0, 0.0);
        let obstacle = Obstacle {
            gap: p.gap,
            wave_speed: p.wave_speed,
            s: 0.0,
            seg_start: 0.0,
            phase: Phase::Free { k: k0 },
            contacts: Vec::new(),
        };
        Marcher {
            p,
            sigma,
            kappa,
            obstacle,
            a: VecDeque::from([Piece { lo: 0.0, hi: l, map: Map::identity(Which::A) }]),
            a_first: 0,
            b: VecDeque::from([Piece { lo: 0.0, hi: l, map: Map::identity(Which::B) }]),
            b_first: 0,
            ia: 0,
            ib: 0,
            xi_done: l,
            contacts: VecDeque::new(),
            contacts_first: 0,
            made: 2,
            finished: None,
        }
    }

    /// Swept up to this s at x = 0.
    pub fn position(&self) -> f64 {
        self.obstacle.s
    }

    pub fn made(&self) -> usize {
        self.made
    }

    /// Pieces and contact phases held.
    pub fn held(&self) -> usize {
        self.a.len() + self.b.len() + self.contacts.len()
    }

    /// `Some(open)` once s_end is reached; see the field.
    pub fn finished(&self) -> Option<bool> {
        self.finished
    }

    /// Closed contact phases so far (held or forgotten): the number of the next one.
    pub fn contacts_made(&self) -> usize {
        self.contacts_first + self.contacts.len()
    }

    /// The closed contact phase number `i` (s units), if still held.
    pub fn contact(&self, i: usize) -> Option<(f64, f64)> {
        i.checked_sub(self.contacts_first).and_then(|k| self.contacts.get(k).copied())
    }

    fn done(&self) -> bool {
        self.obstacle.s >= self.p.s_end && self.xi_done <= self.p.length - self.p.s_end
    }

    /// One pass of both sweeps (each over every piece available to it); at s_end, closes the
    /// march instead. Does nothing once finished.
    pub fn step(&mut self, base: &Base) -> Result<(), CharacteristicsError> {
        if self.finished.is_some() {
            return Ok(());
        }
        if self.done() {
            let open = match self.obstacle.phase {
                Phase::Contact { since } if since < self.p.s_end => {
                    self.obstacle.contacts.push((since, self.p.s_end));
                    true
                }
                _ => false,
            };
            self.contacts.extend(self.obstacle.contacts.drain(..));
            self.finished = Some(open);
            return Ok(());
        }
        let (l, s_end, xi_end) = (self.p.length, self.p.s_end, self.p.length - self.p.s_end);
        let mut progressed = false;
        while self.obstacle.s < s_end && self.ib < self.b_first + self.b.len() {
            let piece = self.b[self.ib - self.b_first];
            let q = piece.hi.min(s_end);
            let before = self.a.len();
            self.obstacle.sweep(base, &piece, q, &mut self.a)?;
            self.made += self.a.len() - before;
            progressed = true;
            self.ib += 1;
        }
        self.contacts.extend(self.obstacle.contacts.drain(..));
        while self.xi_done > xi_end && self.ia < self.a_first + self.a.len() {
            let piece = self.a[self.ia - self.a_first];
            let lo = piece.lo.max(xi_end);
            if lo < self.xi_done {
                let map = piece.map.reflect(2.0 * l, self.sigma, self.kappa);
                self.b.push_back(Piece { lo: 2.0 * l - self.xi_done, hi: 2.0 * l - lo, map });
                self.made += 1;
                self.xi_done = lo;
                progressed = true;
            }
            self.ia += 1;
        }
        if !progressed && !self.done() {
            return Err(CharacteristicsError::SwitchSearch { t: self.obstacle.s / self.p.wave_speed });
        }
        Ok(())
    }

    /// Forgets what neither the march nor an evaluation at any s ≥ `s_lo` can need: A pieces
    /// above ξ = L − s_lo + margin, B pieces below η = s_lo − margin, contact phases ended
    /// before s_lo − margin, keeping one more of each beyond those bounds.
    pub fn trim(&mut self, s_lo: f64, margin: f64) {
        let (a_bound, b_bound) = (self.p.length - s_lo + margin, s_lo - margin);
        while self.a.len() >= 2 && self.a_first < self.ia && self.a[1].lo > a_bound {
            self.a.pop_front();
            self.a_first += 1;
        }
        while self.b.len() >= 2 && self.b_first < self.ib && self.b[1].hi < b_bound {
            self.b.pop_front();
            self.b_first += 1;
        }
        while self.contacts.len() >= 2 && self.contacts[1].1 < b_bound {
            self.contacts.pop_front();
            self.contacts_first += 1;
        }
    }

    /// The held pieces: A and B in increasing argument, the closed contact phases (s units),
    /// and the contact phase still on at the current position (its start), if any.
    pub fn pieces(&self) -> (Vec<Piece>, Vec<Piece>, Vec<(f64, f64)>, Option<f64>) {
        let on = match (self.finished, self.obstacle.phase) {
            (None, Phase::Contact { since }) => Some(since),
            _ => None,
        };
        (
            self.a.iter().rev().copied().collect(),
            self.b.iter().copied().collect(),
            self.contacts.iter().copied().collect(),
            on,
        )
    }
}
