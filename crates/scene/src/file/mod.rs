//! Scene files: TOML in ([`load`]), TOML out ([`save`]), through a field-aware reader.

mod bump_image;
mod camera;
pub mod load;
mod read;
pub mod save;
