//! The marched waves in bounded memory.
//!
//! A march over [0, s_end] makes about `2 + switches` pieces per crossing of the bar, so
//! `c·t_end / L` crossings (10⁸ for a 1 m steel bar over a day, or a stiff bar over a few steps)
//! would need memory in proportion. The [`Store`] keeps the whole march only while it holds at
//! most [`StoreLimits::resident`] pieces (every shipped scene and test: the evaluation is then
//! exactly the one-march evaluation). Beyond that it keeps
//!
//! * checkpoints: march states ([`Marcher`], trimmed to what marching on from there needs), one
//!   every `spacing` pieces made, at most [`StoreLimits::checkpoints`] of them (when full, every
//!   other one is dropped and the spacing doubles), plus the finished march;
//! * a few windows: the pieces an evaluation at s ∈ [s_lo, s_hi] can touch (A on
//!   [−s_hi − L, L − s_lo + L], B on [s_lo − L, s_hi + 2L], the contact phases around),
//!   re-marched from the last checkpoint at or before s_lo, or from a window's march state when
//!   that is further on (evaluations at increasing times, as a run makes them, then cost one
//!   march in all). A window holds about [`StoreLimits::window`] pieces.
//!
//! Re-marching makes the same pieces bit for bit (module docs of [`super::march`]), and a window
//! holds every piece (and one more on each side) that a locate or walk at its times visits in
//! the whole wave, so every value is the one the whole march gives; `tests/exact_memory.rs`
//! checks that at random times against the resident store.

use super::CharacteristicsError;
use super::base::Base;
use super::march::{Marcher, Params};
use super::wave::Wave;
use std::collections::VecDeque;
use std::sync::{Arc, Mutex};

/// The contact phases listed by `contact_intervals`: the first this many.
pub const MAX_LISTED_CONTACTS: usize = 1 << 16;
/// Windows kept for reuse.
const CACHED_WINDOWS: usize = 4;

/// Sizes of the bounded store (pieces of 56 bytes).
#[doc(hidden)]
#[derive(Debug, Clone, Copy)]
pub struct StoreLimits {
    /// The whole march is kept while it holds at most this many pieces (3.7 MB).
    pub resident: usize,
    /// Pieces made per window (and the first checkpoint spacing).
    pub window: usize,
    /// Checkpoints kept at most.
    pub checkpoints: usize,
}

impl StoreLimits {
    pub const DEFAULT: StoreLimits = StoreLimits { resident: 1 << 16, window: 1 << 14, checkpoints: 256 };
}

/// The pieces of both waves that evaluations at s = ct ∈ [s_lo, s_hi] need, and the contact
/// phases (in t) that can hold such a t.
#[derive(Debug)]
pub(super) struct Window {
    s_lo: f64,
    s_hi: f64,
    pub a: Wave,
    pub b: Wave,
    /// `[start, end)` in t; a phase still on past the window ends at +∞.
    contacts: Vec<(f64, f64)>,
    /// The last phase listed is the march's last and still on at t_end: `[start, t_end]`.
    open_last: bool,
}

impl Window {
    fn new(m: &Marcher, s_lo: f64, s_hi: f64, c: f64, t_end: f64) -> Self {
        let (a, b, closed, on) = m.pieces();
        let mut contacts: Vec<(f64, f64)> = closed.iter().map(|&p| to_t(p, c, t_end)).collect();
        if let Some(since) = on {
            contacts.push((since / c, f64::INFINITY));
        }
        Window {
            s_lo,
            s_hi,
            a: Wave { pieces: a },
            b: Wave { pieces: b },
            contacts,
            open_last: m.finished() == Some(true),
        }
    }

    fn covers(&self, s: f64) -> bool {
        self.s_lo <= s && s <= self.s_hi
    }

    /// Whether t lies in a contact phase `[start, end)` (or `[start, t_end]` if still on).
    pub fn in_contact(&self, t: f64) -> bool {
        let i = self.contacts.partition_point(|c| c.0 <= t);
        i > 0 && {
            let end = self.contacts[i - 1].1;
            t < end || (self.open_last && i == self.contacts.len() && t <= end)
        }
    }
}

/// A contact phase `(start, end)` in s as times, the end clipped to t_end.
fn to_t((a, b): (f64, f64), c: f64, t_end: f64) -> (f64, f64) {
    (a / c, (b / c).min(t_end))
}

/// A window, borrowed from a resident store or shared from the cache.
pub(super) enum WindowRef<'a> {
    Resident(&'a Window),
    Cached(Arc<Window>),
}

impl std::ops::Deref for WindowRef<'_> {
    type Target = Window;
    fn deref(&self) -> &Window {
        match self {
            WindowRef::Resident(w) => w,
            WindowRef::Cached(w) => w,
        }
    }
}

#[derive(Debug)]
pub(super) struct Store {
    params: Params,
    t_end: f64,
    limits: StoreLimits,
    resident: Option<Window>,
    checkpoints: Vec<Marcher>,
    /// Most recently used first: a window and the march state it was cut from.
    cache: Mutex<VecDeque<(Arc<Window>, Marcher)>>,
    /// The first [`MAX_LISTED_CONTACTS`] contact phases, in t.
    pub listed: Vec<(f64, f64)>,
    /// Contact phases in all.
    pub count: usize,
}

impl Clone for Store {
    fn clone(&self) -> Self {
        Store {
            params: self.params,
            t_end: self.t_end,
            limits: self.limits,
            resident: self.resident.as_ref().map(|w| Window {
                s_lo: w.s_lo,
                s_hi: w.s_hi,
                a: w.a.clone(),
                b: w.b.clone(),
                contacts: w.contacts.clone(),
                open_last: w.open_last,
            }),
            checkpoints: self.checkpoints.clone(),
            cache: Mutex::new(VecDeque::new()),
            listed: self.listed.clone(),
            count: self.count,
        }
    }
}

impl Store {
    /// Marches over [0, s_end] once (so that every error shows here), keeping what the module
    /// documentation says.
    pub fn march(base: &Base, params: Params, t_end: f64, limits: StoreLimits) -> Result<Self, CharacteristicsError> {
        let (c, margin) = (params.wave_speed, params.length);
        let mut m = Marcher::new(base, params);
        let mut checkpoints = vec![m.clone()];
        let (mut spacing, mut trimming) = (limits.window.max(1), false);
        let mut next = spacing;
        let (mut listed, mut seen) = (Vec::new(), 0);
        while m.finished().is_none() {
            m.step(base)?;
            while seen < m.contacts_made() {
                if listed.len() < MAX_LISTED_CONTACTS
                    && let Some(p) = m.contact(seen)
                {
                    listed.push(to_t(p, c, t_end));
                }
                seen += 1;
            }
            trimming |= m.held() > limits.resident;
            if trimming {
                m.trim(m.position(), margin);
            }
            if m.made() >= next && m.finished().is_none() {
                let mut cp = m.clone();
                cp.trim(cp.position(), margin);
                checkpoints.push(cp);
                next = m.made() + spacing;
                if checkpoints.len() > limits.checkpoints.max(2) {
                    // Keep checkpoints 0, 2, 4, …: the spacing doubles.
                    let mut i = 0;
                    checkpoints.retain(|_| {
                        i += 1;
                        i % 2 == 1
                    });
                    spacing *= 2;
                }
            }
        }
        let resident = (!trimming).then(|| Window::new(&m, 0.0, f64::INFINITY, c, t_end));
        if trimming {
            checkpoints.push(m);
        } else {
            checkpoints.clear();
        }
        Ok(Store {
            params,
            t_end,
            limits,
            resident,
            checkpoints,
            cache: Mutex::new(VecDeque::new()),
            listed,
            count: seen,
        })
    }

    /// Whether only windows are kept (the march was longer than `limits.resident` pieces).
    pub fn windowed(&self) -> bool {
        self.resident.is_none()
    }

    /// The window for evaluations at s; `None` only if re-marching fails, which it cannot (it
    /// repeats a march that succeeded).
    pub fn window(&self, base: &Base, s: f64) -> Option<WindowRef<'_>> {
        if let Some(w) = &self.resident {
            return Some(WindowRef::Resident(w));
        }
        let mut cache = self.cache.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(i) = cache.iter().position(|(w, _)| w.covers(s)) {
            let entry = cache.remove(i)?;
            let w = entry.0.clone();
            cache.push_front(entry);
            return Some(WindowRef::Cached(w));
        }
        let k = self.checkpoints.partition_point(|m| m.position() <= s).saturating_sub(1);
        let from = self.checkpoints.get(k)?.position();
        // A cached march state behind s but past the checkpoint is the shorter way there.
        let cursor = cache.iter().position(|(w, m)| w.s_lo <= s && m.position() >= from);
        let start = match cursor {
            Some(i) => cache.remove(i)?.1,
            None => self.checkpoints[k].clone(),
        };
        let (window, marcher) = self.cut(base, start, s).ok()?;
        let window = Arc::new(window);
        cache.push_front((window.clone(), marcher));
        cache.truncate(CACHED_WINDOWS);
        Some(WindowRef::Cached(window))
    }

    /// Marches `m` on to cover s and about `limits.window` pieces beyond, and cuts the window.
    fn cut(&self, base: &Base, mut m: Marcher, s: f64) -> Result<(Window, Marcher), CharacteristicsError> {
        let margin = self.params.length;
        let budget = self.limits.window.max(1);
        let mut made = None;
        while m.finished().is_none() {
            if m.position() >= s + margin {
                let since = *made.get_or_insert(m.made());
                if m.made() - since >= budget {
                    break;
                }
            }
            m.step(base)?;
            if m.held() > 2 * budget {
                m.trim(m.position().min(s), margin);
            }
        }
        m.trim(s, margin);
        let s_hi = if m.finished().is_some() { f64::INFINITY } else { m.position() - margin };
        Ok((Window::new(&m, s, s_hi, self.params.wave_speed, self.t_end), m))
    }
}
