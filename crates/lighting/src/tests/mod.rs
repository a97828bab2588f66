//! Cross-module tests: the lecture notes' equations by hand, numeric edge cases, the Effects
//! equivalence for every subset, and property tests of the bounds.

mod effects_equivalence;
mod lights;
mod notes_equations;
mod numerics;
mod properties;
mod shade_wide;
mod support;
