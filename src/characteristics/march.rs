//! Building the two travelling waves by marching the boundary reflections in s = ct.
//!
//! A is known on ξ ∈ [0, L] and B on η ∈ [0, L] from the initial data. B beyond L comes from
//! A by the far-end reflection `B(L + σ) = ±A(L − σ) + κ`, and A below 0 from B by the
//! obstacle rule at x = 0 (free or contact). Each needs the other only at least 0 behind
//! (B(L + σ) needs A(L − σ), i.e. the x = 0 rule at s = σ − L), so the two sweeps alternate
//! and each pass advances by at least L until s_end = c·t_end.

use super::base::{Base, Which};
use super::search::first_descent;
use super::wave::{Map, Piece, Wave};
use super::{CharacteristicsError, FarEnd};

/// Relative round-off allowance of the switching tests: 64 ulps of the magnitudes involved.
const SWITCH_ULPS: f64 = 64.0 * f64::EPSILON;
/// More switches than this inside one panel means the data defeat the search.
const MAX_SWITCHES_PER_PANEL: usize = 1000;

pub(super) struct Params {
    pub length: f64,
    pub gap: f64,
    pub wave_speed: f64,
    pub far_end: FarEnd,
    /// c · t_end.
    pub s_end: f64,
}

pub(super) struct Marched {
    pub a: Wave,
    pub b: Wave,
    /// Contact phases in s = ct.
    pub contacts: Vec<(f64, f64)>,
    /// The last contact phase is still on at s_end.
    pub open: bool,
}

#[derive(Debug, Clone, Copy)]
enum Phase {
    /// `A(−s) = B(s) + k`.
    Free { k: f64 },
    /// `A(−s) = −g − B(s)`, since s = `since`.
    Contact { since: f64 },
}

/// The sweep at x = 0: turns B on [0, s] into A on [−s, 0].
struct Obstacle<'a> {
    base: &'a Base,
    gap: f64,
    wave_speed: f64,
    /// Swept up to here.
    s: f64,
    /// Start of the A piece being formed (a phase switch or a B piece boundary).
    seg_start: f64,
    phase: Phase,
    contacts: Vec<(f64, f64)>,
}

impl Obstacle<'_> {
    /// Close the A piece `[−s1, −seg_start]`, the image of B piece `b` under the current phase.
    fn emit(&mut self, b: &Map, s1: f64, out: &mut Vec<Piece>) {
        if s1 > self.seg_start {
            let map = match self.phase {
                Phase::Free { k } => b.reflect(0.0, 1.0, k),
                Phase::Contact { .. } => b.reflect(0.0, -1.0, -self.gap),
            };
            out.push(Piece { lo: -s1, hi: -self.seg_start, map });
        }
        self.seg_start = s1;
    }

    /// Sweep B piece `b` from `self.s` to `q`, panel by panel, appending A pieces to `out`.
    fn sweep(&mut self, b: &Piece, q: f64, out: &mut Vec<Piece>) -> Result<(), CharacteristicsError> {
        let (base, map) = (self.base, b.map);
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
            self.panel(&map, j, sb, out)?;
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
    fn panel(&mut self, map: &Map, j: usize, sb: f64, out: &mut Vec<Piece>) -> Result<(), CharacteristicsError> {
        let (base, g, w) = (self.base, self.gap, map.w);
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

pub(super) fn march(base: &Base, p: &Params) -> Result<Marched, CharacteristicsError> {
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
    let mut obstacle = Obstacle {
        base,
        gap: p.gap,
        wave_speed: p.wave_speed,
        s: 0.0,
        seg_start: 0.0,
        phase: Phase::Free { k: k0 },
        contacts: Vec::new(),
    };
    // A pieces in decreasing ξ, B pieces in increasing η: the order in which they are made.
    let mut a_seq = vec![Piece { lo: 0.0, hi: l, map: Map::identity(Which::A) }];
    let mut b_seq = vec![Piece { lo: 0.0, hi: l, map: Map::identity(Which::B) }];
    let (mut ia, mut ib, mut xi_done) = (0, 0, l);
    let xi_end = l - p.s_end;
    loop {
        let mut progressed = false;
        while obstacle.s < p.s_end && ib < b_seq.len() {
            let piece = b_seq[ib];
            let q = piece.hi.min(p.s_end);
            obstacle.sweep(&piece, q, &mut a_seq)?;
            progressed = true;
            ib += 1;
        }
        while xi_done > xi_end && ia < a_seq.len() {
            let piece = a_seq[ia];
            let lo = piece.lo.max(xi_end);
            if lo < xi_done {
                let map = piece.map.reflect(2.0 * l, sigma, kappa);
                b_seq.push(Piece { lo: 2.0 * l - xi_done, hi: 2.0 * l - lo, map });
                xi_done = lo;
                progressed = true;
            }
            ia += 1;
        }
        if obstacle.s >= p.s_end && xi_done <= xi_end {
            break;
        }
        if !progressed {
            return Err(CharacteristicsError::SwitchSearch { t: obstacle.s / p.wave_speed });
        }
    }
    let mut contacts = obstacle.contacts;
    let open = match obstacle.phase {
        Phase::Contact { since } if since < p.s_end => {
            contacts.push((since, p.s_end));
            true
        }
        _ => false,
    };
    a_seq.reverse();
    Ok(Marched { a: Wave { pieces: a_seq }, b: Wave { pieces: b_seq }, contacts, open })
}
