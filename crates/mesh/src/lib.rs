//! `phosphor-mesh`: triangle meshes for Phosphor. OBJ loading (through tobj, plus a light line
//! scan for smoothing groups and line-numbered errors), face normals robust for slivers,
//! vertex normals averaged only within a surface (seeds: `N_v = sum N_k / |sum N_k|`),
//! tangents, and analytic primitives with exact normals. Knows nothing of light or pixels.
//!
//! ```
//! use phosphor_mesh::primitives;
//!
//! // Primitives carry exact normals, uvs and tangents.
//! let sphere = primitives::uv_sphere(1.0, 32, 16);
//! assert!(sphere.is_consistent());
//! ```
//!
//! # Vertex normals: measured accuracy
//!
//! Normals averaged from a UV sphere's welded positions (no authored normals, crease 180)
//! against the exact radial normals, `cargo test -p phosphor-mesh --test normals_accuracy -- --nocapture`:
//!
//! MEASUREMENTS_PLACEHOLDER

pub mod build;
pub mod error;
pub mod mesh;
pub mod normals;
pub mod primitives;
pub mod stats;
pub mod tangents;

pub use build::TriangleSoup;
pub use error::MeshError;
pub use mesh::{Mesh, MtlMaterial, fallback_tangent};
pub use normals::{NormalOptions, NormalSource, Weighting, triangle_normal_f64};
pub use stats::MeshStats;
