//! One case from its base state and its perturbed copies: the round-off check behind every
//! digit the report prints (issue 22), written once (issue 28).
//!
//! A section gives [`replicate`] the run of one case as a function of the [`Copy`] (the base
//! state, or perturbed copy k of [`super::band::PERTURBATIONS`]; how a copy perturbs its initial
//! data is the section's: U⁰ relatively ([`super::band::perturbed`]), V⁰ by a velocity pattern,
//! …) and gets back the runs, base first; the report then prints of each quantity the digits all
//! runs share, else their band ([`super::band::stable_digits`]).
//!
//! **Which copies run** ([`Copies`]). `All` runs every copy. `WherePrinted` runs the base and the
//! first copy, and the other copies only if a printed digit could still change: the rule is that
//! every quantity the section prints of the case ([`Printed`]: a value and its significant
//! digits, or a count) must print the same over the whole interval `x₀ ± K·|x₁ − x₀|` (x₀ the
//! base value, x₁ the first copy's, K = [`MARGIN`]), and counts must be equal. All copies
//! perturb the initial data by the same size (≤ 1e-13), so where the response is linear their
//! deviations from x₀ are of the order of |x₁ − x₀|; K = 100 leaves two decades for their
//! spread. A run that amplifies round-off (the chattering standard mass, long Paoli–Schatzman
//! runs, a diverging scheme) moves x₁ far from x₀, the interval crosses a rounding boundary and
//! every copy runs.
//!
//! **Where the rule does not hold.** A time read off the step grid (a first impact, a contact
//! duration) moves by whole steps: base and first copy may agree exactly while a third copy
//! lands one step later, which no interval around x₀ predicts. Compared with the five-run report
//! (`reproduce` full at 014a145 against 517e9f6, 2026-11-27): the bodies section printed every
//! number the same, but the dropped disc of the method comparison printed `0.5000` where the
//! five runs give `0.50–0.51` (8 of its rows): that section runs [`Copies::All`]. A section
//! whose printed values are step-quantized events uses `All` unless such a comparison shows
//! the rule holds for it.

use super::band::{PERTURBATIONS, sig};
use rayon::prelude::*;

/// Spread allowance of the copies not run (module docs).
pub const MARGIN: f64 = 100.0;

/// A run of a case: the base state or perturbed copy `k` (0 ≤ k < [`PERTURBATIONS`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Copy {
    Base,
    Perturbed(usize),
}

impl Copy {
    /// Every run of a case, base first.
    pub fn all() -> impl Iterator<Item = Copy> {
        std::iter::once(Copy::Base).chain((0..PERTURBATIONS).map(Copy::Perturbed))
    }

    /// The copy's index, None for the base run.
    pub fn index(self) -> Option<usize> {
        match self {
            Copy::Base => None,
            Copy::Perturbed(k) => Some(k),
        }
    }
}

/// Which copies [`replicate`] runs (module docs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Copies {
    All,
    WherePrinted,
}

/// A quantity the report prints of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Printed {
    /// A value shown with at most this many significant digits (None: the run has none).
    Value(Option<f64>, usize),
    /// A count, shown as it is.
    Count(usize),
}

/// Whether copy values `b` print as the base values `a` over the margin interval (module docs).
pub fn settled(a: &[Printed], b: &[Printed]) -> bool {
    a.len() == b.len()
        && a.iter().zip(b).all(|(x, y)| match (*x, *y) {
            (Printed::Count(p), Printed::Count(q)) => p == q,
            (Printed::Value(None, _), Printed::Value(None, _)) => true,
            (Printed::Value(Some(x0), d), Printed::Value(Some(x1), _)) => {
                let reach = MARGIN * (x1 - x0).abs();
                x0.is_finite() && x1.is_finite() && {
                    let shown = sig(x0, d);
                    sig(x0 - reach, d) == shown && sig(x0 + reach, d) == shown
                }
            }
            _ => false,
        })
}

/// Runs a case from its base state and its perturbed copies (which: `copies`, module docs),
/// in parallel (rayon); the runs come back base first, then the copies that ran, in order.
/// `printed` lists what the report prints of a run (used by [`Copies::WherePrinted`]).
pub fn replicate<T: Send>(
    copies: Copies,
    run: impl Fn(Copy) -> T + Sync,
    printed: impl Fn(&T) -> Vec<Printed>,
) -> Vec<T> {
    match copies {
        Copies::All => Copy::all().collect::<Vec<_>>().into_par_iter().map(&run).collect(),
        Copies::WherePrinted => {
            let (base, first) = rayon::join(|| run(Copy::Base), || run(Copy::Perturbed(0)));
            let mut out = vec![base, first];
            if !settled(&printed(&out[0]), &printed(&out[1])) {
                let rest: Vec<T> = (1..PERTURBATIONS).into_par_iter().map(|k| run(Copy::Perturbed(k))).collect();
                out.extend(rest);
            }
            out
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_digit_within_reach_of_the_spread_runs_every_copy() {
        let v = |x: f64| vec![Printed::Value(Some(x), 4)];
        // 0.123410 ± 100·1e-9 stays 0.1234; 0.123449 ± 100·2e-8 reaches 0.123451, printed 0.1235
        // (± 100·1e-8 would end on 0.123450 itself, a rounding tie decided by the last bit).
        assert!(settled(&v(0.123_410), &v(0.123_410 + 1e-9)));
        assert!(!settled(&v(0.123_449), &v(0.123_449 + 2e-8)));
        assert!(!settled(&[Printed::Count(3)], &[Printed::Count(4)]));
        assert!(!settled(&[Printed::Value(None, 4)], &v(1.0)));
        let calls = std::sync::atomic::AtomicUsize::new(0);
        let runs = replicate(
            Copies::WherePrinted,
            |c| {
                calls.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                // 1.5, not 1.0: below a power of ten `sig` shows one decimal more (0.99…→"1.0000")
                if c == Copy::Base { 1.5 } else { 1.5 + 1e-15 }
            },
            |x| vec![Printed::Value(Some(*x), 4)],
        );
        assert_eq!((runs.len(), calls.into_inner()), (2, 2));
        let runs = replicate(
            Copies::WherePrinted,
            |c| c.index().map_or(0.5, |k| 0.5 + 1e-3 * k as f64 + 1e-3),
            |x| vec![Printed::Value(Some(*x), 4)],
        );
        assert_eq!(runs.len(), 1 + PERTURBATIONS);
    }
}
