//! The classic illumination models as pure functions over plain data (being built).
