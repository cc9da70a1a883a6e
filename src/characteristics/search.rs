//! The first time a function goes below zero: the contact start (u(0,t) + g < 0 under free
//! reflection) and the release (λ > 0 under contact) of [`super::march`].
//!
//! On one panel the function f(s) is a polynomial with a known bound `|f''| ≤ m2`, so on
//! `[m − h, m + h]` Taylor's theorem gives `f ≥ f(m) − |f'(m)| h − m2 h²/2`. A depth-first
//! bisection visits the left half first and discards every interval this bound clears, so it
//! returns the *first* sub-interval of round-off width where f is negative, and never misses a
//! dip between samples (the weakness of plain sampling). It costs O(log(width/ulp)) evaluations
//! for a transversal crossing or a tangency.
//!
//! "Negative" means below `−tol`, with tol a few hundred ulps of the magnitudes that make up f:
//! a dip shallower than that is round-off (e.g. f(s_release) = 0 computed as −1e−17) and is not
//! a switch. Once the first point with `f < −tol` is known, the switch is put at the last zero
//! crossing before it, by bisection to the last representable point with `f ≥ 0`.

/// More evaluations than any polynomial of degree ≤ 32 needs; reaching it means the bound is
/// useless (non-finite data slipped through), and the caller reports an error.
const BUDGET: usize = 200_000;

/// The search budget was spent.
#[derive(Debug)]
pub(super) struct Exhausted;

struct Search<'a> {
    f: &'a dyn Fn(f64) -> (f64, f64),
    m2: f64,
    evals: usize,
}

impl Search<'_> {
    fn f(&mut self, s: f64) -> Result<(f64, f64), Exhausted> {
        self.evals += 1;
        if self.evals > BUDGET { Err(Exhausted) } else { Ok((self.f)(s)) }
    }

    /// The first point (to round-off) of [lo, hi] where `f < thr` (`below`), or the last one
    /// where `f ≥ thr` (`!below`, searching from the right).
    fn extreme(&mut self, lo: f64, hi: f64, thr: f64, below: bool) -> Result<Option<f64>, Exhausted> {
        let hits = |v: f64| if below { v < thr } else { v >= thr };
        let (m, h) = (0.5 * (lo + hi), 0.5 * (hi - lo));
        let (fm, dm) = self.f(m)?;
        let reach = dm.abs() * h + 0.5 * self.m2 * h * h;
        let cleared = if below { fm - reach >= thr } else { fm + reach < thr };
        if cleared {
            return Ok(None);
        }
        if !(m > lo && m < hi) || h <= 2.0 * f64::EPSILON * lo.abs().max(hi.abs()) {
            let order = if below { [lo, m, hi] } else { [hi, m, lo] };
            for s in order {
                if hits(self.f(s)?.0) {
                    return Ok(Some(s));
                }
            }
            return Ok(None);
        }
        let halves = if below { [(lo, m), (m, hi)] } else { [(m, hi), (lo, m)] };
        for (a, b) in halves {
            if let Some(s) = self.extreme(a, b, thr, below)? {
                return Ok(Some(s));
            }
        }
        Ok(None)
    }
}

/// The first s in [lo, hi] where f (value, derivative; `|f''| ≤ m2`) goes from ≥ 0 to < 0,
/// counting only dips below −tol; `lo` if f is already negative there.
pub(super) fn first_descent(
    f: &dyn Fn(f64) -> (f64, f64),
    m2: f64,
    lo: f64,
    hi: f64,
    tol: f64,
) -> Result<Option<f64>, Exhausted> {
    if hi <= lo || hi.is_nan() || lo.is_nan() {
        return Ok(None);
    }
    let mut search = Search { f, m2, evals: 0 };
    let s1 = if search.f(lo)?.0 < -tol {
        lo
    } else {
        match search.extreme(lo, hi, -tol, true)? {
            Some(s) => s,
            None => return Ok(None),
        }
    };
    let Some(mut a) = search.extreme(lo, s1, 0.0, false)? else { return Ok(Some(lo)) };
    // f(a) ≥ 0 > f(b): bisect to adjacent floats, keep the last non-negative point.
    let mut b = s1;
    loop {
        let m = 0.5 * (a + b);
        if !(m > a && m < b) {
            return Ok(Some(a));
        }
        if search.f(m)?.0 < 0.0 {
            b = m;
        } else {
            a = m;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_first_of_several_crossings_and_skips_a_tangency() {
        // f = (s − 1)² (s − 2)(s − 3): touches 0 at 1, negative on (2, 3).
        let f = |s: f64| {
            let v = (s - 1.0).powi(2) * (s - 2.0) * (s - 3.0);
            let d = 2.0 * (s - 1.0) * (s - 2.0) * (s - 3.0) + (s - 1.0).powi(2) * (2.0 * s - 5.0);
            (v, d)
        };
        // |f''| = |12s² − 42s + 34| ≤ 34 + 42·4 + 12·16 on [0, 4].
        let s = first_descent(&f, 400.0, 0.0, 4.0, 1e-14).unwrap();
        assert_eq!(s, Some(2.0));
        // A linear descent from a positive value: root to the last ulp.
        let g = |s: f64| (0.3 - s, -1.0);
        let r = first_descent(&g, 0.0, 0.0, 1.0, 1e-15).unwrap().unwrap();
        assert!(g(r).0 >= 0.0 && g(r.next_up()).0 < 0.0, "{r}");
        // Positive throughout, even with a shallow dip to −1e−16 (round-off): none.
        let h = |s: f64| ((s - 0.5).powi(2) - 1e-16, 2.0 * (s - 0.5));
        assert_eq!(first_descent(&h, 2.0, 0.0, 1.0, 1e-14).unwrap(), None);
    }
}
