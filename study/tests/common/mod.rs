//! Helpers shared by the study's tests (one home: `tests/common` of the solver holds the solver's).

/// Half a unit of the last digit printed in `cell` (`0.9978` → 5e-5, `13515` → 0.5, `2.4e4` →
/// 500), the rounding error of a printed number.
pub fn half_last_place(cell: &str) -> f64 {
    let (mantissa, exponent) = cell.split_once('e').map_or((cell, 0), |(m, e)| (m, e.parse::<i32>().unwrap()));
    let decimals = mantissa.split_once('.').map_or(0, |(_, d)| d.len()) as i32;
    0.5 * 10f64.powi(exponent - decimals)
}
