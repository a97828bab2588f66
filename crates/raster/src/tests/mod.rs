//! Scenario tests of the whole pipeline (unit tests of single stages sit beside their code).

mod antialias;
mod coverage;
mod interpolation;
mod modes;
mod simd;
mod stability;
pub(crate) mod support;
mod variants;
