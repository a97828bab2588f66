//! Shading modes against each other.
