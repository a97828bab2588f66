//! Phosphor viewer (placeholder until the apps issue lands).
fn main() {}
