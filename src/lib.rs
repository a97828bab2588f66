//! Phosphor: an ECS-based scene engine whose renderer is a CPU scan-line rasterizer for the
//! classic illumination and shading models (ambient, Lambert, Phong/Blinn specular with Fresnel,
//! attenuation; flat, Gouraud, Phong and fast Phong shading; bump mapping).
//!
//! This package is a facade: it re-exports the library crates so that `tests/` and `benches/`
//! (and users who want everything) depend on one name.
//!
//! ```
//! use phosphor::math::safe_normalize;
//! use phosphor::math::glam::Vec3;
//! assert_eq!(safe_normalize(Vec3::ZERO, Vec3::Z), Vec3::Z);
//! ```

pub use phosphor_lighting as lighting;
pub use phosphor_math as math;
pub use phosphor_mesh as mesh;
pub use phosphor_raster as raster;
pub use phosphor_scene as scene;
