//! Number formatting shared by every writer and message (a leaf module).

/// Shortest representation that reads back to the same f64 (Rust's `Display`/`LowerExp` are
/// both shortest round-trip); plain notation for moderate magnitudes, exponent otherwise.
pub fn fmt_f64(x: f64) -> String {
    Shortest(x).to_string()
}

/// [`fmt_f64`] as a `Display` value: written straight into a writer, without a `String`.
#[derive(Debug, Clone, Copy)]
pub struct Shortest(pub f64);

impl std::fmt::Display for Shortest {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let (x, a) = (self.0, self.0.abs());
        if x == 0.0 || (1e-4..1e15).contains(&a) || !x.is_finite() { write!(f, "{x}") } else { write!(f, "{x:e}") }
    }
}
