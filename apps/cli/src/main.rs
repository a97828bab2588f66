//! Phosphor command line (placeholder until the apps issue lands).
fn main() {}
