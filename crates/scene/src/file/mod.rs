//! Scene files: TOML in ([`load`]), TOML out ([`save`]), through a field-aware reader.

mod camera;
pub mod load;
mod read;
pub mod save;
