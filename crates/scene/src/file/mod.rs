//! Scene files: TOML in ([`load`]), TOML out ([`save`]), through a field-aware reader.

pub mod load;
mod read;
pub mod save;
