//! Numbers as the scene file writes them, shared by the scene and motion writers.

/// `x` as the shortest decimal that reads back as the same `f32` (`0.2`, not the
/// `0.20000000298023224` that widening to `f64` first would write). Rust's `Display` for
/// floats is that shortest round-tripping form, and it parses as an `f64` that narrows back
/// to `x` exactly; `inf` and `nan` pass through as TOML's own.
pub(crate) fn shortest(x: f32) -> f64 {
    x.to_string().parse::<f64>().unwrap_or(f64::from(x))
}
