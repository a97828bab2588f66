//! Cross-module tests: the lecture notes' equations by hand, numeric edge cases, the Effects
//! equivalence for every subset, and property tests of the bounds.

mod effects_equivalence;
mod lights;
mod numerics;
mod properties;
mod notes_equations;
mod support;
mod wide4;
