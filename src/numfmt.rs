//! Number formatting shared by every writer and message (a leaf module).

/// Shortest representation that reads back to the same f64 (Rust's `Display`/`LowerExp` are
/// both shortest round-trip); plain notation for moderate magnitudes, exponent otherwise.
pub fn fmt_f64(x: f64) -> String {
    let a = x.abs();
    if x == 0.0 || (1e-4..1e15).contains(&a) || !x.is_finite() { format!("{x}") } else { format!("{x:e}") }
}
