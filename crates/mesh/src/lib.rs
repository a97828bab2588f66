//! `phosphor-mesh`: triangle meshes for Phosphor. OBJ loading (through tobj, plus a light line
//! scan for smoothing groups and line-numbered errors), PLY, STL and glTF 2.0 loading chosen by
//! extension ([`load_mesh`]), face normals robust for slivers,
//! vertex normals averaged only within a surface (the lecture notes' `N_v = sum N_k / |sum N_k|`),
//! MikkTSpace tangents ([`tangents`]), analytic primitives with exact normals, and a render order
//! ([`Mesh::sort_spatially`]: triangles along a Morton curve, so neighbours in memory are
//! neighbours in space). Knows nothing of light or pixels.
//!
//! Vertex colours (PLY `red green blue`, glTF `COLOR_0`, OBJ `v x y z r g b`) arrive in
//! [`Mesh::colors`] as linear RGB. Texture maps arrive as references in each [`MtlMaterial`]
//! (`kd_map`, `ks_map`, `normal_map`): a [`TextureRef`] names a file or holds the encoded bytes
//! embedded in a glTF, with its [`Wrap`]s; this crate decodes no image, and reads one only
//! when asked ([`TextureSource::bytes`], through [`open`] with [`MAX_IMAGE_BYTES`]).
//!
//! ```
//! use phosphor_mesh::{parse_obj, primitives, NormalOptions};
//!
//! // A unit cube as OBJ text without normals: the default 60-degree crease keeps it flat.
//! let obj = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nv 0 0 1\nv 1 0 1\nv 1 1 1\nv 0 1 1\n\
//!            f 1 4 3 2\nf 5 6 7 8\nf 1 2 6 5\nf 2 3 7 6\nf 3 4 8 7\nf 4 1 5 8\n";
//! let mesh = parse_obj(obj, "cube.obj", None, &NormalOptions::default())?;
//! assert_eq!(mesh.indices.len(), 12);
//! assert_eq!(mesh.positions.len(), 24); // split at every edge: one normal per face corner
//! assert_eq!(mesh.stats().surfaces, 6);
//!
//! // Errors name the file and line.
//! let bad = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 0\n";
//! let err = parse_obj(bad, "bad.obj", None, &NormalOptions::default()).unwrap_err();
//! assert!(err.to_string().starts_with("bad.obj:4: "));
//!
//! // Primitives carry exact normals, uvs and tangents.
//! let sphere = primitives::uv_sphere(1.0, 32, 16);
//! assert!(sphere.is_consistent());
//!
//! // Render order: the same triangles, stored for memory locality.
//! let mut sorted = sphere.clone();
//! sorted.sort_spatially();
//! assert_eq!(sorted.indices.len(), sphere.indices.len());
//! assert!(sorted.is_consistent());
//! # Ok::<(), phosphor_mesh::MeshError>(())
//! ```
//!
//! # Bounds on work and memory
//!
//! Loading is near-linear in the file whatever its shape: edges shared by many faces, vertices
//! shared by many faces ([`normals`] documents the rule at vertices where more than 256 corners
//! meet) and polygons of many corners ([`triangulate`]). Every file is opened as a regular
//! file only, without blocking, and read up to a cap ([`open`]): [`MAX_MESH_FILE_BYTES`] for a
//! mesh and for a glTF file's buffers together, [`MAX_MTL_BYTES`] for an MTL file (a bad MTL
//! only costs the material, with a warning). Lines of text formats are at most
//! [`MAX_LINE_BYTES`]. The files a glTF names, buffers and images alike, stay in its folder
//! ([`assets`]); the images embedded in a glTF are copied at most once each and at most
//! [`MAX_MESH_FILE_BYTES`] together. Warnings are one
//! line of at most [`MAX_WARNING_CHARS`] characters, and every quote of a file's text in a
//! message has its control characters escaped ([`sanitize`]). Primitives whose counts come
//! from a file, and the triangles a glTF file's nodes place, are checked against a memory
//! limit before anything is allocated ([`primitives::try_uv_sphere`] and its siblings,
//! [`primitives::MEMORY_BUDGET_BYTES`]).
//!
//! # Vertex normals: measured accuracy
//!
//! Normals averaged from a UV sphere's and a torus' welded positions (no authored normals,
//! crease 180) against the exact normals of the true surfaces,
//! `cargo test -p phosphor-mesh --test normals_accuracy -- --nocapture`. Sphere of radius 1
//! (`segments x rings`), exact normal radial:
//!
//! | tessellation | weighting | mean error | max error | max within 60 deg of equator |
//! |---|---|---|---|---|
//! | 64x32   | Uniform | 5.05e-4 rad | 1.64e-2 rad | 3.14e-6 rad |
//! | 64x32   | Area    | 2.22e-3 rad | 2.45e-2 rad | 3.61e-3 rad |
//! | 64x32   | Angle   | 9.26e-4 rad | 1.53e-3 rad | 1.27e-3 rad |
//! | 128x64  | Uniform | 1.27e-4 rad | 8.18e-3 rad | 7.09e-7 rad |
//! | 128x64  | Area    | 6.88e-4 rad | 1.23e-2 rad | 1.01e-3 rad |
//! | 128x64  | Angle   | 2.38e-4 rad | 3.83e-4 rad | 3.29e-4 rad |
//! | 512x256 | Uniform | 8.90e-6 rad | 2.05e-3 rad | 3.21e-6 rad |
//! | 512x256 | Area    | 6.02e-5 rad | 3.07e-3 rad | 6.45e-5 rad |
//! | 512x256 | Angle   | 1.52e-5 rad | 2.59e-5 rad | 2.21e-5 rad |
//!
//! Angle weighting is within 1e-3 rad everywhere from 128x64 on. Uniform and area weighting are
//! within 1e-3 rad on average, but their maximum sits on the ring next to each pole, where the
//! pole's fan triangles meet split quads (2 triangles above a vertex, 2 or 4 below) and the
//! triangles are long and thin; that error halves with each doubling of the tessellation
//! (first order), while elsewhere it is second order. The primitive grids alternate their
//! diagonals (checkerboard) so every vertex sees a mirror-symmetric fan: with one diagonal
//! everywhere, uniform weighting measured mean 2.7e-4 rad and 2e-4 rad away from the poles
//! at 128x64 (against 1.3e-4 and 7e-7 now), max 4.9e-3 rad.
//!
//! Torus of radii 1 and 0.3 (`segments x sides`), exact normal away from the tube's centre
//! circle:
//!
//! | tessellation | weighting | mean error | max error |
//! |---|---|---|---|
//! | 64x32   | Uniform | 7.06e-6 rad | 1.23e-5 rad |
//! | 64x32   | Area    | 9.14e-4 rad | 3.00e-3 rad |
//! | 64x32   | Angle   | 1.88e-3 rad | 3.06e-3 rad |
//! | 128x64  | Uniform | 5.42e-7 rad | 2.19e-6 rad |
//! | 128x64  | Area    | 2.34e-4 rad | 7.57e-4 rad |
//! | 128x64  | Angle   | 4.80e-4 rad | 7.67e-4 rad |
//! | 512x256 | Uniform | 1.28e-6 rad | 7.68e-6 rad |
//! | 512x256 | Area    | 1.56e-5 rad | 4.91e-5 rad |
//! | 512x256 | Angle   | 3.05e-5 rad | 4.90e-5 rad |
//!
//! With no poles every vertex of the torus sees the same regular, mirror-symmetric fan, and uniform
//! weighting (the lecture notes' formula) is the most accurate: its error is at the rounding of the
//! f32 positions (it stops falling at 512x256, where edges are 7e-3 long). Area and angle weighting
//! converge at second order (a quarter per doubling) but their max error stays 6 to 350 times
//! larger; likely because the torus' quads are trapezoids (outer edge longer than inner), so area
//! and angle weights differ around a vertex and break the symmetry that cancels uniform weighting's
//! first-order error. What accuracy costs, then: on regular grids the cheapest weighting is also
//! the most accurate; angle weighting pays off where fans are irregular (the sphere's pole rings,
//! where its max error is 10 to 80 times below uniform's).

pub mod assets;
pub mod build;
pub mod error;
mod formats;
mod loader;
pub mod mesh;
mod mtl;
pub mod normals;
pub mod open;
mod order;
pub mod primitives;
pub mod sanitize;
mod scan;
pub mod stats;
pub mod tangents;
pub mod texture_ref;
pub mod topology;
pub mod triangulate;

pub use assets::{allow_outside_assets, asset_path, read_asset};
pub use build::TriangleSoup;
pub use error::MeshError;
pub use formats::{
    MeshFormat, gltf_uri_bytes, load_mesh, load_mesh_with_warnings, parse_mesh_bytes,
};
pub use loader::{
    MAX_MTL_BYTES, MAX_WARNING_CHARS, load_obj, load_obj_with_warnings, parse_obj,
    parse_obj_with_warnings,
};
pub use mesh::{Mesh, MtlMaterial, unit_fit};
pub use normals::{NormalOptions, NormalSource, Weighting, triangle_normal_f64};
pub use open::{MAX_LINE_BYTES, MAX_MESH_FILE_BYTES, read_file, read_text};
pub use stats::MeshStats;
pub use tangents::fallback_tangent;
pub use texture_ref::{MAX_IMAGE_BYTES, TextureRef, TextureSource, Wrap};
pub use topology::is_closed_solid;
