//! The two initial waves on [0, L], `A₀ = (u⁰ − W)/2` and `B₀ = (u⁰ + W)/2` with
//! `W(x) = (1/c) ∫₀ˣ v⁰`, stored as Chebyshev series on panels `[y_j, y_{j+1}]`.
//!
//! * Piecewise-linear data: one panel per element. u⁰ is linear there and W is the exact
//!   integral of the linear v⁰, a quadratic, so A₀, B₀ are exact quadratics (3 coefficients).
//! * Smooth closures: adaptive panels carrying degree-31 interpolants of u⁰ and v⁰ at the zeros
//!   of T_32; a panel is halved until the last three coefficients of both are below
//!   [`TAIL_TOL`] times the data's scale (the chebfun "plateau" test, Aurentz & Trefethen,
//!   *ACM TOMS* 43 (2017)). W is then the exact integral of the v⁰ interpolant.

use super::CharacteristicsError;
use super::cheb;

/// Samples per smooth panel (degree 31).
const SMOOTH_POINTS: usize = 32;
/// Relative size of the three trailing Chebyshev coefficients at which a smooth panel is
/// accepted; 100 ulps, above the round-off floor of the sampled coefficients (~ε·scale).
pub(super) const TAIL_TOL: f64 = 1e-14;
/// Coefficients below this many ulps of the data's scale are round-off and are dropped: the
/// naive transform sums 32 samples, so its noise is up to ~32 ulps of the scale.
const CHOP_ULPS: f64 = 64.0 * f64::EPSILON;
/// A smooth panel is never narrower than L·2⁻²⁰; data still unresolved there are rejected.
const MAX_DEPTH: u32 = 20;

/// Which initial wave a piece of a travelling wave is an image of.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Which {
    A,
    B,
}

#[derive(Debug, Clone)]
pub(super) struct Base {
    /// Panel boundaries `0 = y_0 < … < y_n = L`.
    pub breaks: Vec<f64>,
    /// Coefficients per series.
    len: usize,
    /// Per panel, six series in y-derivatives: `[A₀, B₀, A₀', B₀', A₀'', B₀'']`.
    coef: Vec<f64>,
    /// Per panel, `sup|F^{(k)}|` (y-derivatives, k = 0..=3) at index `2k + w`.
    sup: Vec<[f64; 8]>,
}

impl Base {
    /// From u⁰ and v⁰ series per panel (in the panel's z ∈ [−1, 1]) and the wave speed c.
    fn from_series(breaks: Vec<f64>, u: &[Vec<f64>], v: &[Vec<f64>], c: f64) -> Self {
        let len = u.iter().map(Vec::len).chain(v.iter().map(|s| s.len() + 1)).max().unwrap_or(1);
        let panels = breaks.len() - 1;
        let mut coef = Vec::with_capacity(6 * len * panels);
        let mut sup = Vec::with_capacity(panels);
        let mut w_left = 0.0;
        for (j, (uj, vj)) in u.iter().zip(v).enumerate() {
            let h = breaks[j + 1] - breaks[j];
            // W on the panel: W(y_j) + (h/2c) ∫_{−1}^{z} v⁰ dz'   (dy = h/2 dz).
            let mut w: Vec<f64> = cheb::antiderivative(vj).iter().map(|f| f * h / (2.0 * c)).collect();
            w[0] += w_left;
            w_left = w.iter().sum(); // W(y_{j+1}): T_k(1) = 1.
            let at = |s: &[f64], k: usize| s.get(k).copied().unwrap_or(0.0);
            let a: Vec<f64> = (0..len).map(|k| 0.5 * (at(uj, k) - at(&w, k))).collect();
            let b: Vec<f64> = (0..len).map(|k| 0.5 * (at(uj, k) + at(&w, k))).collect();
            // d/dy = (2/h) d/dz.
            let d = |s: &[f64]| -> Vec<f64> { cheb::derivative(s).iter().map(|x| x * 2.0 / h).collect() };
            let (da, db) = (d(&a), d(&b));
            let (dda, ddb) = (d(&da), d(&db));
            let (ddda, dddb) = (d(&dda), d(&ddb));
            let mut s = [0.0; 8];
            for (k, series) in [&a, &b, &da, &db, &dda, &ddb, &ddda, &dddb].into_iter().enumerate() {
                s[k] = cheb::sup_bound(series);
            }
            sup.push(s);
            for series in [a, b, da, db, dda, ddb] {
                coef.extend_from_slice(&series);
            }
        }
        Base { breaks, len, coef, sup }
    }

    /// Piecewise-linear nodal data (validated by the caller): one panel per element.
    pub fn piecewise_linear(x: &[f64], u: &[f64], v: &[f64], c: f64) -> Self {
        let lin = |f: &[f64], j: usize| vec![0.5 * (f[j] + f[j + 1]), 0.5 * (f[j + 1] - f[j])];
        let us: Vec<_> = (0..x.len() - 1).map(|j| lin(u, j)).collect();
        let vs: Vec<_> = (0..x.len() - 1).map(|j| lin(v, j)).collect();
        Self::from_series(x.to_vec(), &us, &vs, c)
    }

    /// Smooth closures on [0, L], resolved adaptively (see the module documentation).
    pub fn smooth(
        u: &dyn Fn(f64) -> f64,
        v: &dyn Fn(f64) -> f64,
        length: f64,
        c: f64,
    ) -> Result<Self, CharacteristicsError> {
        // Scales from 513 equispaced samples; they only set the acceptance threshold.
        let scale = |f: &dyn Fn(f64) -> f64, what: &'static str| {
            (0..=512).try_fold(0.0f64, |m, i| {
                let x = length * i as f64 / 512.0;
                let y = f(x);
                if y.is_finite() { Ok(m.max(y.abs())) } else { Err(CharacteristicsError::NonFinite { what, x }) }
            })
        };
        let scales = [scale(u, "u⁰")?, scale(v, "v⁰")?];
        let mut fit = Fit { f: [u, v], scales, length, breaks: vec![0.0], series: [Vec::new(), Vec::new()] };
        fit.panel(0.0, length, 0)?;
        let Fit { breaks, series: [us, vs], .. } = fit;
        Ok(Self::from_series(breaks, &us, &vs, c))
    }

    pub fn panels(&self) -> usize {
        self.breaks.len() - 1
    }

    /// The panel holding y: the one starting at or before y (`upper`), or the one ending at or
    /// after it (`!upper`); they differ only at panel boundaries. Clamped to the panels.
    pub fn locate(&self, y: f64, upper: bool) -> usize {
        let k = if upper { self.breaks.partition_point(|&b| b <= y) } else { self.breaks.partition_point(|&b| b < y) };
        k.saturating_sub(1).min(self.panels() - 1)
    }

    /// The k-th y-derivative (k ≤ 2) of A₀ or B₀ at y, with panel j's polynomial.
    pub fn eval(&self, j: usize, w: Which, k: usize, y: f64) -> f64 {
        let (a, b) = (self.breaks[j], self.breaks[j + 1]);
        let z = (2.0 * y - a - b) / (b - a);
        let idx = (6 * j + 2 * k + w as usize) * self.len;
        cheb::eval(&self.coef[idx..idx + self.len], z)
    }

    /// A bound of `|F^{(k)}|` (k ≤ 3) on panel j.
    pub fn sup(&self, j: usize, w: Which, k: usize) -> f64 {
        self.sup[j][2 * k + w as usize]
    }

    /// `max_j sup|F^{(k)}|` over both waves: the scale of displacements (k = 0), strains (k = 1).
    pub fn scale(&self, k: usize) -> f64 {
        self.sup.iter().map(|s| s[2 * k].max(s[2 * k + 1])).fold(0.0, f64::max)
    }
}

/// State of the adaptive fit of the smooth closures.
struct Fit<'a> {
    f: [&'a dyn Fn(f64) -> f64; 2],
    scales: [f64; 2],
    length: f64,
    breaks: Vec<f64>,
    series: [Vec<Vec<f64>>; 2],
}

impl Fit<'_> {
    fn panel(&mut self, a: f64, b: f64, depth: u32) -> Result<(), CharacteristicsError> {
        let mut fits = [Vec::new(), Vec::new()];
        let mut resolved = true;
        for (i, what) in ["u⁰", "v⁰"].into_iter().enumerate() {
            let mut vals = Vec::with_capacity(SMOOTH_POINTS);
            for z in cheb::points(SMOOTH_POINTS) {
                let x = 0.5 * (a + b) + 0.5 * (b - a) * z;
                let y = (self.f[i])(x);
                if !y.is_finite() {
                    return Err(CharacteristicsError::NonFinite { what, x });
                }
                vals.push(y);
            }
            let mut c = cheb::interpolate(&vals);
            let tail = c[SMOOTH_POINTS - 3..].iter().fold(0.0f64, |m, c| m.max(c.abs()));
            resolved &= tail <= TAIL_TOL * self.scales[i];
            // Drop trailing coefficients at the round-off floor of the samples: they carry no
            // information, and differentiation would amplify them by up to k² ≈ 10³.
            let floor = CHOP_ULPS * self.scales[i];
            let keep = c.iter().rposition(|c| c.abs() > floor).map_or(1, |k| k + 1);
            c.truncate(keep);
            fits[i] = c;
        }
        if resolved {
            self.breaks.push(b);
            let [u, v] = fits;
            self.series[0].push(u);
            self.series[1].push(v);
            return Ok(());
        }
        if depth == MAX_DEPTH {
            return Err(CharacteristicsError::SmoothDataUnresolved {
                x: 0.5 * (a + b),
                width: b - a,
                min_width: self.length / f64::from(1u32 << MAX_DEPTH),
            });
        }
        let m = 0.5 * (a + b);
        self.panel(a, m, depth + 1)?;
        self.panel(m, b, depth + 1)
    }
}
