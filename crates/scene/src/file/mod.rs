//! Scene files: TOML in ([`load`]), TOML out ([`save`]), through a field-aware reader.

pub(crate) mod bump_image;
mod camera;
pub mod gltf_nodes;
pub mod load;
mod motion;
mod number;
mod read;
pub mod save;
