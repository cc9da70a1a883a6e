//! The exact solution of the 1D impact problem by characteristics, for general initial data.
//!
//! ```text
//! ρ u_tt − E u_xx = 0 on (0, L), t > 0,                 c = √(E/ρ)
//! far end x = L:  Clamped  u(L, t) = 0   |   Free  E u_x(L, t) = 0
//! x = 0, rigid obstacle at gap g ≥ 0:
//!   u(0, t) ≥ −g,   λ(t) = E u_x(0+, t) ≤ 0,   (u(0, t) + g) λ(t) = 0        (Signorini)
//! u(x, 0) = u⁰(x),  u_t(x, 0) = v⁰(x)
//! ```
//!
//! This generalises the paper's benchmark (§4.1, [`crate::exact::ImpactingBar`]: L = 1, c = 1,
//! clamped, g = 0, u⁰ = (L − x)/2, v⁰ = 0) and reproduces it, with the region I sign of
//! eq. (4.2) corrected as documented there.
//!
//! # d'Alembert waves
//! Every solution is `u = A(x − ct) + B(x + ct)`. At t = 0, `A + B = u⁰` and
//! `c(B' − A') = v⁰`, so with `W(x) = (1/c) ∫₀ˣ v⁰`:
//!
//! ```text
//! A₀ = (u⁰ − W)/2,   B₀ = (u⁰ + W)/2   on [0, L].
//! ```
//!
//! A (right-going) is needed on ξ ∈ [−ct_end, L], B (left-going) on η ∈ [0, L + ct_end];
//! the boundary conditions supply the rest, in s = ct:
//!
//! * **Clamped end**: `A(L − s) + B(L + s) = 0`, so `B(L + s) = −A(L − s)`: odd reflection.
//!   A non-zero u⁰(L) would make the displacement jump at x = L for t > 0; it is rejected
//!   ([`CharacteristicsError::ClampedEndDisplaced`]) beyond 64 ulps of the data's scale, and
//!   within that the end is held at its initial round-off value, so B stays continuous.
//! * **Free end**: `A'(L − s) + B'(L + s) = 0`, so `B(L + s) = A(L − s) + B₀(L) − A₀(L)`: even
//!   reflection, the constant keeping B continuous at η = L.
//! * **x = 0, free**: `A'(−s) + B'(s) = 0`, so `A(−s) = B(s) + k`, with k fixed by continuity
//!   of A where the phase began (k = A₀(0) − B₀(0) = 0 at t = 0). Then u(0, t) = 2B(s) + k.
//! * **x = 0, contact**: `u(0, t) = −g`, so `A(−s) = −g − B(s)`; differentiating,
//!   `A'(−s) = B'(s)` and `λ(t) = E(A'(−s) + B'(s)) = 2E B'(s)`.
//!
//! **Switching rule at x = 0** (persistent contact). In a free phase contact begins at the first
//! s where the free motion would pass the obstacle, i.e. where `2B(s) + k + g` goes from ≥ 0
//! to < 0 (a grazing touch, ≥ 0 on both sides, is not a contact). In contact, the incoming wave
//! decides: the contact holds while `λ = 2E B'(s) ≤ 0` and is released at the first s where
//! B' > 0; the next free phase takes `k = −g − 2B(s)`. Both switches keep A continuous, and
//! the energy `E ∫ (A'² + B'²)` is unchanged because `A'(−s) = ∓B'(s)` in both phases.
//! The switches are found by `search.rs`: a Taylor-bounded bisection that cannot miss a dip
//! below −tol between samples, tol being 64 ulps of the magnitudes involved.
//!
//! # Representation and accuracy
//! Each reflection maps the argument by `±arg + shift`, so every piece of A or B is
//! `offset + sign · F(dir · arg + shift)` with F ∈ {A₀, B₀} (`wave.rs`), and A₀, B₀ are
//! Chebyshev series on panels of [0, L] (`base.rs`).
//!
//! * **Piecewise-linear data** (nodal u⁰, v⁰): u⁰ is linear and W, the integral of the linear
//!   v⁰, is *quadratic* on each element, so the waves are piecewise quadratic (piecewise linear
//!   when v⁰ is constant) with breakpoints at the images of the nodes and of the switches.
//!   Values, slopes, switch times, λ, energies and L² norms are exact up to round-off: a few
//!   ulps per reflection, plus the m-term sum that makes W(x_m).
//! * **Smooth closures**: degree-31 Chebyshev interpolants on adaptive panels, accepted when the
//!   trailing coefficients are below 1e−14 of the data's scale (`base::TAIL_TOL`), with
//!   round-off coefficients dropped; for data analytic near [0, L] (polynomials, sin, cos, exp
//!   on O(1) intervals) this is one to a few panels, and u is then exact to ~1e−14 of the data's
//!   scale, slopes to ~1e−13 (differentiation of the interpolant). Switch times are simple roots
//!   (of u(0,t) + g at a contact start, of B' at a release) located to round-off, and the
//!   release is where u(0,t) + g has a double zero, so even an error δ there moves u by O(δ²).
//!   Measured against piecewise-linear samplings of the same data, whose differences from this
//!   solution fall exactly as h² (1.7e−11 → 1.0e−12 for 2¹⁶ → 2¹⁸ elements, see
//!   `tests/characteristics.rs`), u(0,t) and the L² distance agree to 1e−12–5e−12, far below
//!   the 1e−10 and 5e−10 asked for. The price is one Clenshaw sum of ≤ 33 terms per evaluation;
//!   a fine piecewise-linear sampling would need ~10⁵ nodes for 1e−10 and would put a
//!   breakpoint (and an L² cell) at every one of them.
//!
//! # Conventions
//! * Evaluations take 0 ≤ x ≤ L and 0 ≤ t ≤ t_end and return NaN outside ([`Characteristics::check_time`]
//!   reports the error instead). Slopes at a kink are the right limits in x (left at x = L).
//! * λ(t) is the right limit in t: `2E B'(ct+)` on `[start, end)` of each contact phase, 0
//!   elsewhere; between switches it equals `E u_x(0+, t)`.
//! * [`Characteristics::contact_intervals`] ends with `(start, t_end)` if the last contact is
//!   still on at t_end.

mod base;
mod cheb;
mod march;
mod search;
mod store;
mod wave;

use base::{Base, Which};
pub use store::MAX_LISTED_CONTACTS;
#[doc(hidden)]
pub use store::StoreLimits;
use store::{Store, Window};
use wave::{Segment, Wave};

/// Boundary condition at x = L.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum FarEnd {
    /// u(L, t) = 0.
    Clamped,
    /// E u_x(L, t) = 0.
    Free,
}

/// The bar: length L, density ρ, Young's modulus E, far end, gap g to the obstacle at x = 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BarData {
    pub length: f64,
    pub density: f64,
    pub modulus: f64,
    pub far_end: FarEnd,
    pub gap: f64,
}

/// Initial displacement u⁰ and velocity v⁰.
#[derive(Clone, Copy)]
pub enum InitialData<'a> {
    /// Nodal values at `0 = x_0 < … < x_m = L`, linear in between.
    PiecewiseLinear { x: &'a [f64], u: &'a [f64], v: &'a [f64] },
    /// Closures on [0, L], resolved to ~1e−14 (see the module documentation).
    Smooth { u: &'a dyn Fn(f64) -> f64, v: &'a dyn Fn(f64) -> f64 },
}

impl std::fmt::Debug for InitialData<'_> {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            InitialData::PiecewiseLinear { x, u, v } => {
                f.debug_struct("PiecewiseLinear").field("x", x).field("u", u).field("v", v).finish()
            }
            InitialData::Smooth { .. } => f.write_str("Smooth { .. }"),
        }
    }
}

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum CharacteristicsError {
    #[error("{what} must be finite and > 0, got {value}")]
    NotPositive { what: &'static str, value: f64 },
    #[error("{what} must be finite and ≥ 0, got {value}")]
    Negative { what: &'static str, value: f64 },
    #[error("piecewise-linear data need x, u, v of one length ≥ 2, got {x}, {u}, {v}")]
    DataLengths { x: usize, u: usize, v: usize },
    #[error("nodes must run from x_0 = 0 to x_m = L = {length} (8 ulps allowed at x_m), got {first} … {last}")]
    NodeEnds { first: f64, last: f64, length: f64 },
    #[error("nodes must increase strictly, but x[{index}] = {value} ≤ x[{index} − 1] = {previous}")]
    NodesNotIncreasing { index: usize, value: f64, previous: f64 },
    #[error("initial {what} is not finite at x = {x}")]
    NonFinite { what: &'static str, x: f64 },
    #[error("u⁰(0) = {u0} is below the obstacle at −g = {limit} (round-off allowance {tol})")]
    InitialPenetration { u0: f64, limit: f64, tol: f64 },
    #[error("a clamped far end needs u⁰(L) = 0, got {value} (round-off allowance {tol})")]
    ClampedEndDisplaced { value: f64, tol: f64 },
    #[error(
        "smooth initial data not resolved to 1e-14 by degree-31 Chebyshev panels near x = {x}: panel width {width} reached the minimum {min_width}"
    )]
    SmoothDataUnresolved { x: f64, width: f64, min_width: f64 },
    #[error("the contact switching search failed near t = {t}")]
    SwitchSearch { t: f64 },
    #[error("t = {t} is outside [0, t_end = {t_end}]")]
    TimeOutOfRange { t: f64, t_end: f64 },
    #[error(
        "tracing the waves up to t_end = {t_end} takes c·t_end/L = {crossings:.3e} crossings of the bar (c = √(E/ρ) = {wave_speed:e}, L = {length}): at most {max:e} are traced (about 5 s here); shorten time.end or lower the wave speed"
    )]
    TooManyCrossings { crossings: f64, max: f64, wave_speed: f64, length: f64, t_end: f64 },
}

/// The most bar crossings `c·t_end/L` a solution traces. Marching costs about 0.5 µs per
/// crossing here (`check` of a 6-element bar, T = 1: 0.81 s at c = 10⁶, 6.5 s at 10⁷, 54 s at
/// 10⁸): 10⁷ crossings bound the set-up to a few seconds. The paper's longest run (T = 3000,
/// c = L = 1) is 3000 crossings; a 1 m steel bar (c ≈ 5000 m/s) over 1000 s is 5·10⁶.
pub const MAX_CROSSINGS: f64 = 1e7;

/// The exact solution on [0, L] × [0, t_end]; see the module documentation.
#[derive(Debug, Clone)]
pub struct Characteristics {
    length: f64,
    modulus: f64,
    wave_speed: f64,
    t_end: f64,
    smooth: bool,
    base: Base,
    /// The marched waves, whole or in windows (`store.rs`).
    store: Store,
    /// Gauss–Legendre rule for the cell integrals: 3 points (exact for the quartic e² of
    /// piecewise-linear data), 8 points (degree 15) for smooth data.
    gauss: Vec<(f64, f64)>,
    /// Slope jumps at most this large are round-off, not kinks.
    kink_tol: f64,
}

/// Relative round-off allowance of the validation tests, in ulps of the data's scale.
const DATA_ULPS: f64 = 64.0 * f64::EPSILON;
/// The last node may differ from L by this many ulps of L.
const END_ULPS: f64 = 8.0 * f64::EPSILON;
/// Smooth data: a slope jump below this fraction of the slope scale is not a kink (a release
/// leaves a jump 2|B'(s_release)| ~ 1e−15 relative; a genuine kink is O(1)).
const SMOOTH_KINK_REL: f64 = 1e-10;

fn positive(what: &'static str, value: f64) -> Result<f64, CharacteristicsError> {
    if value.is_finite() && value > 0.0 { Ok(value) } else { Err(CharacteristicsError::NotPositive { what, value }) }
}

fn non_negative(what: &'static str, value: f64) -> Result<f64, CharacteristicsError> {
    if value.is_finite() && value >= 0.0 { Ok(value) } else { Err(CharacteristicsError::Negative { what, value }) }
}

/// Checks nodal data and returns the nodes with x_m snapped to L.
fn nodes(x: &[f64], u: &[f64], v: &[f64], length: f64) -> Result<Vec<f64>, CharacteristicsError> {
    let m = x.len();
    if m < 2 || u.len() != m || v.len() != m {
        return Err(CharacteristicsError::DataLengths { x: m, u: u.len(), v: v.len() });
    }
    for (what, f) in [("x", x), ("u⁰", u), ("v⁰", v)] {
        if let Some(i) = f.iter().position(|y| !y.is_finite()) {
            return Err(CharacteristicsError::NonFinite { what, x: x[i] });
        }
    }
    if x[0] != 0.0 || (x[m - 1] - length).abs() > END_ULPS * length {
        return Err(CharacteristicsError::NodeEnds { first: x[0], last: x[m - 1], length });
    }
    for i in 1..m {
        if x[i] <= x[i - 1] {
            return Err(CharacteristicsError::NodesNotIncreasing { index: i, value: x[i], previous: x[i - 1] });
        }
    }
    let mut x = x.to_vec();
    x[m - 1] = length;
    Ok(x)
}

/// One cell of an integration over [0, L]: inside one mesh element and one segment of each wave.
struct Cell {
    element: usize,
    p: f64,
    q: f64,
    a: Segment,
    b: Segment,
}

impl Characteristics {
    /// The solution for `data` and `initial` on [0, t_end].
    pub fn new(data: &BarData, initial: InitialData<'_>, t_end: f64) -> Result<Self, CharacteristicsError> {
        Self::with_limits(data, initial, t_end, StoreLimits::DEFAULT)
    }

    /// [`Self::new`] with the store's sizes chosen (tests force the windowed store with them).
    #[doc(hidden)]
    pub fn with_limits(
        data: &BarData,
        initial: InitialData<'_>,
        t_end: f64,
        limits: StoreLimits,
    ) -> Result<Self, CharacteristicsError> {
        let length = positive("length", data.length)?;
        let density = positive("density", data.density)?;
        let modulus = positive("modulus", data.modulus)?;
        let gap = non_negative("gap", data.gap)?;
        let t_end = non_negative("t_end", t_end)?;
        let c = (modulus / density).sqrt();
        let crossings = c * t_end / length;
        if !(crossings <= MAX_CROSSINGS) {
            return Err(CharacteristicsError::TooManyCrossings {
                crossings,
                max: MAX_CROSSINGS,
                wave_speed: c,
                length,
                t_end,
            });
        }
        let (base, smooth) = match initial {
            InitialData::PiecewiseLinear { x, u, v } => {
                (Base::piecewise_linear(&nodes(x, u, v, length)?, u, v, c), false)
            }
            InitialData::Smooth { u, v } => (Base::smooth(u, v, length, c)?, true),
        };
        let u_at = |j: usize, y: f64| base.eval(j, Which::A, 0, y) + base.eval(j, Which::B, 0, y);
        let scale = 2.0 * base.scale(0);
        let u00 = u_at(0, 0.0);
        let tol = DATA_ULPS * (scale + gap);
        if u00 < -gap - tol {
            return Err(CharacteristicsError::InitialPenetration { u0: u00, limit: -gap, tol });
        }
        let u0l = u_at(base.panels() - 1, length);
        if data.far_end == FarEnd::Clamped && u0l.abs() > DATA_ULPS * scale {
            return Err(CharacteristicsError::ClampedEndDisplaced { value: u0l, tol: DATA_ULPS * scale });
        }
        let params = march::Params { length, gap, wave_speed: c, far_end: data.far_end, s_end: c * t_end };
        let store = Store::march(&base, params, t_end, limits)?;
        let kink_tol = if smooth { SMOOTH_KINK_REL } else { DATA_ULPS } * base.scale(1);
        Ok(Characteristics {
            length,
            modulus,
            wave_speed: c,
            t_end,
            smooth,
            base,
            store,
            gauss: cheb::gauss_legendre(if smooth { 8 } else { 3 }),
            kink_tol,
        })
    }

    pub fn length(&self) -> f64 {
        self.length
    }

    pub fn wave_speed(&self) -> f64 {
        self.wave_speed
    }

    pub fn t_end(&self) -> f64 {
        self.t_end
    }

    /// `Ok` iff 0 ≤ t ≤ t_end, where the evaluations are defined.
    pub fn check_time(&self, t: f64) -> Result<(), CharacteristicsError> {
        if (0.0..=self.t_end).contains(&t) {
            Ok(())
        } else {
            Err(CharacteristicsError::TimeOutOfRange { t, t_end: self.t_end })
        }
    }

    fn inside(&self, x: f64, t: f64) -> bool {
        (0.0..=self.length).contains(&x) && (0.0..=self.t_end).contains(&t)
    }

    /// Displacement u(x, t) = A(x − ct) + B(x + ct).
    pub fn u(&self, x: f64, t: f64) -> f64 {
        if !self.inside(x, t) {
            return f64::NAN;
        }
        let s = self.wave_speed * t;
        let Some(w) = self.window(s) else { return f64::NAN };
        w.a.eval(&self.base, 0, x - s, true) + w.b.eval(&self.base, 0, x + s, true)
    }

    /// The waves' pieces for evaluations at s = ct (`store.rs`).
    fn window(&self, s: f64) -> Option<store::WindowRef<'_>> {
        self.store.window(&self.base, s)
    }

    /// Whether only windows of the waves are kept (the march made more than
    /// `StoreLimits::resident` pieces; `store.rs`).
    #[doc(hidden)]
    pub fn is_windowed(&self) -> bool {
        self.store.windowed()
    }

    /// (A'(x − ct), B'(x + ct)), right limits in x (left limits at x = L).
    fn slopes(&self, x: f64, t: f64) -> (f64, f64) {
        let (s, right) = (self.wave_speed * t, x < self.length);
        let Some(w) = self.window(s) else { return (f64::NAN, f64::NAN) };
        (w.a.eval(&self.base, 1, x - s, right), w.b.eval(&self.base, 1, x + s, right))
    }

    /// Velocity u_t = c(−A' + B').
    pub fn u_t(&self, x: f64, t: f64) -> f64 {
        if !self.inside(x, t) {
            return f64::NAN;
        }
        let (da, db) = self.slopes(x, t);
        self.wave_speed * (db - da)
    }

    /// Strain u_x = A' + B'.
    pub fn u_x(&self, x: f64, t: f64) -> f64 {
        if !self.inside(x, t) {
            return f64::NAN;
        }
        let (da, db) = self.slopes(x, t);
        da + db
    }

    /// u(0, t).
    pub fn u0(&self, t: f64) -> f64 {
        self.u(0.0, t)
    }

    /// Whether t lies in a contact phase `[start, end)` (or `[start, t_end]` if still on).
    pub fn in_contact(&self, t: f64) -> bool {
        // Outside [0, t_end] (or NaN) no phase holds t: they lie in [0, t_end].
        (0.0..=self.t_end).contains(&t) && self.window(self.wave_speed * t).is_some_and(|w| w.in_contact(t))
    }

    /// Contact force λ(t) = E u_x(0+, t) = 2E B'(ct+) in contact, 0 otherwise (≤ 0).
    pub fn lambda(&self, t: f64) -> f64 {
        if self.check_time(t).is_err() {
            return f64::NAN;
        }
        let s = self.wave_speed * t;
        let Some(w) = self.window(s) else { return f64::NAN };
        if !w.in_contact(t) {
            return 0.0;
        }
        2.0 * self.modulus * w.b.eval(&self.base, 1, s, true)
    }

    /// The contact phases `[start, end)` up to t_end, in increasing time.
    /// Only the first [`MAX_LISTED_CONTACTS`] are listed (memory stays bounded however long
    /// t_end is); [`Self::contact_count`] counts them all.
    pub fn contact_intervals(&self) -> &[(f64, f64)] {
        &self.store.listed
    }

    /// The number of contact phases up to t_end.
    pub fn contact_count(&self) -> usize {
        self.store.count
    }

    fn at(&self, wave: &Wave, seg: &Segment, k: usize, arg: f64) -> f64 {
        wave.pieces[seg.piece].map.eval(&self.base, seg.panel, k, arg)
    }

    /// `∫_p^q f` by the Gauss–Legendre rule of this solution.
    fn quad(&self, p: f64, q: f64, mut f: impl FnMut(f64) -> f64) -> f64 {
        let (m, h) = (0.5 * (p + q), 0.5 * (q - p));
        h * self.gauss.iter().map(|(z, w)| w * f(m + h * z)).sum::<f64>()
    }

    /// Calls `visit` on the cells that split [0, L] at the mesh nodes and at every breakpoint
    /// of A(· − ct) and B(· + ct), in increasing x; u(·, t) is one polynomial on each.
    fn cells(&self, w: &Window, nodes: &[f64], s: f64, mut visit: impl FnMut(&Cell)) {
        let l = self.length;
        let mut wa = w.a.walk(&self.base, -s, l - s);
        let mut wb = w.b.walk(&self.base, s, l + s);
        let (Some(mut sa), Some(mut sb)) = (wa.next(), wb.next()) else { return };
        for (element, x) in nodes.windows(2).enumerate() {
            let mut p = x[0];
            loop {
                let xa = if sa.last { f64::INFINITY } else { sa.hi + s };
                let xb = if sb.last { f64::INFINITY } else { sb.hi - s };
                let q = x[1].min(xa).min(xb);
                if q > p {
                    visit(&Cell { element, p, q, a: sa, b: sb });
                    p = q;
                }
                if xa <= q {
                    sa = wa.next().unwrap_or(Segment { last: true, ..sa });
                }
                if xb <= q {
                    sb = wb.next().unwrap_or(Segment { last: true, ..sb });
                }
                if q >= x[1] {
                    break;
                }
            }
        }
    }

    /// Energy `½∫ρ u_t² + ½∫E u_x² = E ∫₀ᴸ (A'(x − ct)² + B'(x + ct)²) dx` (ρc² = E),
    /// integrated cell by cell (exactly for piecewise-linear data: A'² is quadratic).
    pub fn energy(&self, t: f64) -> f64 {
        if self.check_time(t).is_err() {
            return f64::NAN;
        }
        let s = self.wave_speed * t;
        let Some(w) = self.window(s) else { return f64::NAN };
        let mut sum = 0.0;
        self.cells(&w, &[0.0, self.length], s, |c| {
            sum += self.quad(c.p, c.q, |x| {
                let (da, db) = (self.at(&w.a, &c.a, 1, x - s), self.at(&w.b, &c.b, 1, x + s));
                da * da + db * db
            });
        });
        self.modulus * sum
    }

    /// The x in (0, L), sorted, where u(·, t) has a slope discontinuity: the images of the
    /// waves' breakpoints where the wave's slope jumps by more than round-off (64 ulps of the
    /// slope scale; 1e−10 of it for smooth data, whose panel joins are not kinks). An A and a B
    /// kink meeting at one x are reported once, even if their jumps cancel.
    pub fn kinks(&self, t: f64, out: &mut Vec<f64>) {
        out.clear();
        if self.check_time(t).is_err() {
            return;
        }
        let (l, s) = (self.length, self.wave_speed * t);
        let Some(w) = self.window(s) else { return };
        for (wave, lo, to_x) in [(&w.a, -s, s), (&w.b, s, -s)] {
            let mut prev: Option<Segment> = None;
            for seg in wave.walk(&self.base, lo, lo + l) {
                if let Some(p) = prev
                    && (seg.starts_piece || !self.smooth)
                {
                    let jump = self.at(wave, &seg, 1, seg.lo) - self.at(wave, &p, 1, seg.lo);
                    let x = seg.lo + to_x;
                    if jump.abs() > self.kink_tol && x > 0.0 && x < l {
                        out.push(x);
                    }
                }
                prev = Some(seg);
            }
        }
        out.sort_unstable_by(f64::total_cmp);
        out.dedup_by(|a, b| (*a - *b).abs() <= END_ULPS * l);
    }

    fn mesh_ok(&self, nodes: &[f64]) -> bool {
        nodes.len() >= 2
            && nodes[0] == 0.0
            && (nodes[nodes.len() - 1] - self.length).abs() <= END_ULPS * self.length
            && nodes.windows(2).all(|w| w[1] > w[0])
    }

    /// `‖u_h − u(·, t)‖_{L²(0,L)}` for the P1 function with `values` at `nodes` (0 = x_0 < … <
    /// x_m = L). Integrated cell by cell (mesh refined by all breakpoints of the waves) with the
    /// Gauss–Legendre rule: 3 points for piecewise-linear data, exact since u_h − u is a
    /// quadratic on each cell; 8 points (degree 15) for smooth data, on cells no longer than a
    /// mesh element or a Chebyshev panel. NaN for a bad mesh or t outside [0, t_end].
    pub fn l2_error_p1(&self, nodes: &[f64], values: &[f64], t: f64) -> f64 {
        if values.len() != nodes.len() {
            return f64::NAN;
        }
        self.integrate(nodes, t, |j, x, u| {
            let (x0, x1, v0, v1) = (nodes[j], nodes[j + 1], values[j], values[j + 1]);
            let e = v0 + (v1 - v0) * (x - x0) / (x1 - x0) - u;
            e * e
        })
        .sqrt()
    }

    /// `∫₀ᴸ g(j, x, u(x, t)) dx`, with j the element of the 1D mesh `nodes` (0 = x_0 < … <
    /// x_m = L) that holds x: integrated cell by cell, the mesh refined at every breakpoint of
    /// the waves (u(·, t) is one polynomial on each cell), by this solution's Gauss–Legendre
    /// rule: 3 points (exact for degree ≤ 5: u is piecewise quadratic for piecewise-linear data)
    /// or 8 points (degree 15) for smooth data. NaN for a bad mesh or t outside [0, t_end].
    /// A plate's L² error against the plane wave is this with g the integral over y of the
    /// squared error across the cells over element j (`crate::plate::norms`).
    pub fn integrate(&self, nodes: &[f64], t: f64, mut g: impl FnMut(usize, f64, f64) -> f64) -> f64 {
        if !self.mesh_ok(nodes) || self.check_time(t).is_err() {
            return f64::NAN;
        }
        let s = self.wave_speed * t;
        let Some(w) = self.window(s) else { return f64::NAN };
        let mut sum = 0.0;
        self.cells(&w, nodes, s, |c| {
            sum += self.quad(c.p, c.q, |x| {
                let u = self.at(&w.a, &c.a, 0, x - s) + self.at(&w.b, &c.b, 0, x + s);
                g(c.element, x, u)
            });
        });
        sum
    }

    /// `‖I_h u(·, t)‖_{L²(0,L)}` of the nodal interpolant, exactly:
    /// `Σ_j h_j (a² + ab + b²)/3` with a, b the end values. NaN as [`Self::l2_error_p1`].
    pub fn l2_norm_interpolant(&self, nodes: &[f64], t: f64) -> f64 {
        if !self.mesh_ok(nodes) || self.check_time(t).is_err() {
            return f64::NAN;
        }
        let mut a = self.u(0.0, t);
        let mut sum = 0.0;
        for w in nodes.windows(2) {
            let b = self.u(w[1].min(self.length), t);
            sum += (w[1] - w[0]) * (a * a + a * b + b * b) / 3.0;
            a = b;
        }
        sum.sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_solution_can_be_shared_across_threads() {
        fn shareable<T: Clone + std::fmt::Debug + Send + Sync>() {}
        shareable::<Characteristics>();
        shareable::<CharacteristicsError>();
    }
}
