//! Analytic primitives with exact normals (the normal of the true surface at each vertex, not an
//! average), for tests and scenes. The caller chooses the tessellation; counts are clamped to
//! sane ranges (at least 3 segments, at most 4096 per direction) and a size that is not a
//! positive finite number is replaced by 1, so no argument can produce NaN or panic.
//!
//! A 4096 x 4096 sphere holds 17 million vertices and 34 million triangles, about 2.7 GB while
//! it is built, so where a file sets the counts the `try_` builders check the mesh's
//! [`Footprint`] against a limit before allocating anything, and turn a failed allocation into
//! an error rather than an abort:
//!
//! ```
//! use phosphor_mesh::primitives::{self, PrimitiveError};
//!
//! let small = primitives::try_uv_sphere(1.0, 32, 16, 1 << 30)?;
//! assert!(small.is_consistent());
//! let err = primitives::try_uv_sphere(1.0, 4096, 2048, 1 << 30).unwrap_err();
//! assert_eq!(err.field(), "segments");
//! assert!(err.to_string().contains("needs 1.3 GB"));
//! # Ok::<(), PrimitiveError>(())
//! ```
//!
//! All primitives are centred on the origin, counter-clockwise seen from outside. Sphere,
//! cylinder, torus, plane and cube carry uvs and tangents; the tangents are the uv gradient,
//! which on these smooth parametrisations agrees with MikkTSpace (what [`crate::tangents`]
//! computes for meshes from files) to within the tessellation, in memory the footprint counts.

use std::collections::TryReserveError;
use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec2, Vec3};
use thiserror::Error;

use crate::mesh::Mesh;
use crate::normals::triangle_normal_f64;
use crate::tangents;

const MAX_TESSELLATION: u32 = 4096;

fn size(x: f32) -> f32 {
    if x.is_finite() && x > 0.0 { x } else { 1.0 }
}

fn count(n: u32, min: u32) -> u32 {
    n.clamp(min, MAX_TESSELLATION)
}

/// The memory a mesh whose size a file sets may take, checked before it is allocated: the
/// primitives of a scene share it (`phosphor_scene::PRIMITIVE_BUDGET_BYTES` is this figure),
/// and so do the copies of the meshes a glTF file's nodes place.
pub const MEMORY_BUDGET_BYTES: u64 = 4_000_000_000;

/// Bytes per vertex at the peak of a build: position, normal, uv and tangent (48) plus the
/// tangent pass's two f64 sums (48).
pub const BYTES_PER_VERTEX: u64 = 96;

/// Bytes per triangle: three indices and the surface, material and smoothing-group ids.
pub const BYTES_PER_TRIANGLE: u64 = 24;

/// The size of a primitive's mesh, known from its counts before anything is allocated.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Footprint {
    /// Vertices.
    pub vertices: u64,
    /// Triangles (an upper bound: zero-area ones at the poles are dropped while building).
    pub triangles: u64,
    /// The parameter that sizes the mesh, the larger count where two do (`segments`, `rings`,
    /// `sides`, `subdivisions`; `shape` for the cube, which has none).
    pub field: &'static str,
}

impl Footprint {
    /// Peak bytes while the mesh is built (mesh and tangent pass).
    #[must_use]
    pub fn bytes(self) -> u64 {
        self.vertices
            .saturating_mul(BYTES_PER_VERTEX)
            .saturating_add(self.triangles.saturating_mul(BYTES_PER_TRIANGLE))
    }

    /// `Err(TooLarge)` naming [`Footprint::field`] when [`Footprint::bytes`] is over
    /// `limit_bytes`.
    pub fn check(self, limit_bytes: u64) -> Result<(), PrimitiveError> {
        let needs_bytes = self.bytes();
        if needs_bytes > limit_bytes {
            return Err(PrimitiveError::TooLarge {
                field: self.field,
                needs_bytes,
                limit_bytes,
                footprint: self,
            });
        }
        Ok(())
    }
}

/// [`uv_sphere`]'s footprint (counts clamped as it clamps them).
#[must_use]
pub fn uv_sphere_footprint(segments: u32, rings: u32) -> Footprint {
    let (s, r) = (count(segments, 3), count(rings, 2));
    let (s64, r64) = (u64::from(s), u64::from(r));
    Footprint {
        vertices: (s64 + 1) * (r64 + 1),
        triangles: 2 * s64 * r64,
        field: if r > s { "rings" } else { "segments" },
    }
}

/// [`cube`]'s footprint.
#[must_use]
pub fn cube_footprint() -> Footprint {
    Footprint {
        vertices: 24,
        triangles: 12,
        field: "shape",
    }
}

/// [`cylinder`]'s footprint.
#[must_use]
pub fn cylinder_footprint(segments: u32) -> Footprint {
    let s = u64::from(count(segments, 3));
    Footprint {
        vertices: 2 * (s + 1) + 2 * (s + 2),
        triangles: 4 * s,
        field: "segments",
    }
}

/// [`torus`]'s footprint.
#[must_use]
pub fn torus_footprint(segments: u32, sides: u32) -> Footprint {
    let (s, k) = (count(segments, 3), count(sides, 3));
    let (s64, k64) = (u64::from(s), u64::from(k));
    Footprint {
        vertices: (s64 + 1) * (k64 + 1),
        triangles: 2 * s64 * k64,
        field: if k > s { "sides" } else { "segments" },
    }
}

/// [`plane`]'s footprint.
#[must_use]
pub fn plane_footprint(subdivisions: u32) -> Footprint {
    let n = u64::from(count(subdivisions, 1));
    Footprint {
        vertices: (n + 1) * (n + 1),
        triangles: 2 * n * n,
        field: "subdivisions",
    }
}

/// A primitive that may not be built. `field` is the count that sized it (the larger one
/// where two do), as the primitive's parameter is named.
#[derive(Clone, Debug, Error, PartialEq, Eq)]
pub enum PrimitiveError {
    /// The footprint is over the caller's limit; nothing was allocated.
    #[error("{field}: {}", too_large(*.needs_bytes, *.limit_bytes, .footprint))]
    TooLarge {
        /// The parameter that sized the mesh.
        field: &'static str,
        /// The footprint's bytes.
        needs_bytes: u64,
        /// The caller's limit.
        limit_bytes: u64,
        /// Vertices and triangles.
        footprint: Footprint,
    },
    /// The system refused the memory.
    #[error("{field}: out of memory: the mesh needs {} GB", gigabytes(*.needs_bytes))]
    OutOfMemory {
        /// The parameter that sized the mesh.
        field: &'static str,
        /// The footprint's bytes.
        needs_bytes: u64,
    },
}

impl PrimitiveError {
    /// The parameter that sized the mesh (`segments`, `rings`, `sides`, `subdivisions`).
    #[must_use]
    pub fn field(&self) -> &'static str {
        match self {
            PrimitiveError::TooLarge { field, .. } | PrimitiveError::OutOfMemory { field, .. } => {
                field
            }
        }
    }

    /// The message without the field, for callers that name the field themselves.
    #[must_use]
    pub fn what(&self) -> String {
        let full = self.to_string();
        full.strip_prefix(self.field())
            .and_then(|s| s.strip_prefix(": "))
            .map_or(full.clone(), str::to_owned)
    }
}

/// Bytes in GB (10^9) with one decimal, rounded up so a figure never understates a need:
/// `gigabytes(2_700_000_001)` is `"2.8"`.
#[must_use]
pub fn gigabytes(bytes: u64) -> String {
    let tenths = bytes.div_ceil(100_000_000);
    format!("{}.{}", tenths / 10, tenths % 10)
}

fn too_large(needs: u64, limit: u64, f: &Footprint) -> String {
    format!(
        "the mesh needs {} GB ({} vertices, {} triangles), over the {} GB limit",
        gigabytes(needs),
        f.vertices,
        f.triangles,
        gigabytes(limit)
    )
}

/// Accumulates vertices and triangles; triangles are oriented so their face normal agrees with
/// the vertex normals (outward), and zero-area ones (at sphere poles) are dropped.
#[derive(Default)]
struct Builder {
    mesh: Mesh,
    uvs: Vec<Vec2>,
    /// Allocate through `try_reserve` (the `try_` builders) rather than aborting on failure.
    fallible: bool,
}

/// Reserves exactly `n` more, fallibly or not.
fn reserve<T>(v: &mut Vec<T>, n: u64, fallible: bool) -> Result<(), TryReserveError> {
    let n = usize::try_from(n).unwrap_or(usize::MAX);
    if fallible {
        v.try_reserve_exact(n)
    } else {
        v.reserve_exact(n);
        Ok(())
    }
}

impl Builder {
    /// A builder with room for `f` reserved up front: one allocation per array, none while
    /// building, so a refused allocation happens here where it can be reported.
    fn new(f: Footprint, fallible: bool) -> Result<Builder, TryReserveError> {
        let mut b = Builder {
            fallible,
            ..Builder::default()
        };
        let m = &mut b.mesh;
        reserve(&mut m.positions, f.vertices, fallible)?;
        reserve(&mut m.normals, f.vertices, fallible)?;
        reserve(&mut b.uvs, f.vertices, fallible)?;
        reserve(&mut m.indices, f.triangles, fallible)?;
        reserve(&mut m.surface_ids, f.triangles, fallible)?;
        reserve(&mut m.smoothing_groups, f.triangles, fallible)?;
        reserve(&mut m.material_ids, f.triangles, fallible)?;
        Ok(b)
    }

    fn vertex(&mut self, p: DVec3, n: DVec3, uv: Vec2) -> u32 {
        self.mesh.positions.push(p.as_vec3());
        self.mesh
            .normals
            .push(phosphor_math::safe_normalize(n.as_vec3(), Vec3::Y));
        self.uvs.push(uv);
        (self.mesh.positions.len() - 1) as u32
    }

    fn triangle(&mut self, t: [u32; 3], surface: u32, group: u32) {
        let p = t.map(|i| self.mesh.positions[i as usize]);
        let Some((face, _)) = triangle_normal_f64(p[0], p[1], p[2]) else {
            return;
        };
        let avg: Vec3 = t.iter().map(|&i| self.mesh.normals[i as usize]).sum();
        let t = if face.dot(avg.as_dvec3()) < 0.0 {
            [t[0], t[2], t[1]]
        } else {
            t
        };
        self.mesh.indices.push(t);
        self.mesh.surface_ids.push(surface);
        self.mesh.smoothing_groups.push(group);
        self.mesh.material_ids.push(0);
    }

    /// Quads of a `(nu + 1) x (nv + 1)` vertex grid starting at `first`, row-major in u, split
    /// into two triangles each with checkerboard-alternating diagonals.
    fn grid(&mut self, first: u32, nu: u32, nv: u32, surface: u32, group: u32) {
        let at = |i: u32, j: u32| first + j * (nu + 1) + i;
        for j in 0..nv {
            for i in 0..nu {
                let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                // Diagonals alternate like a checkerboard, so the triangles around every vertex
                // are mirror-symmetric and averaged normals carry no azimuthal bias (with one
                // diagonal everywhere the sphere's first ring was 10x worse, see crate docs).
                if (i + j) % 2 == 0 {
                    self.triangle([a, b, c], surface, group);
                    self.triangle([a, c, d], surface, group);
                } else {
                    self.triangle([a, b, d], surface, group);
                    self.triangle([b, c, d], surface, group);
                }
            }
        }
    }

    fn finish(mut self) -> Result<Mesh, TryReserveError> {
        let m = &mut self.mesh;
        m.tangents = Some(if self.fallible {
            tangents::try_gradient_tangents(&m.positions, &m.normals, &self.uvs, &m.indices)?
        } else {
            tangents::gradient_tangents(&m.positions, &m.normals, &self.uvs, &m.indices)
        });
        m.uvs = Some(self.uvs);
        Ok(self.mesh)
    }
}

/// Unit direction at polar angle `theta` from +Y and azimuth `phi`, exact at the poles and
/// the seam (`phi` given by its step so that the last column repeats the first bit for bit).
fn sphere_dir(i: u32, rings: u32, j: u32, segments: u32) -> DVec3 {
    if i == 0 {
        return DVec3::Y;
    }
    if i == rings {
        return DVec3::NEG_Y;
    }
    let theta = PI * f64::from(i) / f64::from(rings);
    let phi = TAU * f64::from(j % segments) / f64::from(segments);
    DVec3::new(
        theta.sin() * phi.cos(),
        theta.cos(),
        -theta.sin() * phi.sin(),
    )
}

/// UV sphere of `radius` with `segments` around the Y axis and `rings` from pole to pole.
/// Normals are the exact radial directions; u runs around (0 to 1), v from the south pole (0)
/// to the north pole (1). Seam and pole vertices are duplicated (one per uv), bit-identical.
#[must_use]
pub fn uv_sphere(radius: f32, segments: u32, rings: u32) -> Mesh {
    // Infallible: without `fallible` no step returns an error.
    sphere(radius, segments, rings, false).unwrap_or_default()
}

/// [`uv_sphere`] checked against `limit_bytes` before anything is allocated (the error names
/// `segments` or `rings`, whichever is larger), and `OutOfMemory` instead of an abort when
/// the system refuses the memory.
pub fn try_uv_sphere(
    radius: f32,
    segments: u32,
    rings: u32,
    limit_bytes: u64,
) -> Result<Mesh, PrimitiveError> {
    let f = uv_sphere_footprint(segments, rings);
    f.check(limit_bytes)?;
    sphere(radius, segments, rings, true).map_err(|_| out_of_memory(f))
}

fn out_of_memory(f: Footprint) -> PrimitiveError {
    PrimitiveError::OutOfMemory {
        field: f.field,
        needs_bytes: f.bytes(),
    }
}

fn sphere(radius: f32, segments: u32, rings: u32, fallible: bool) -> Result<Mesh, TryReserveError> {
    let r = f64::from(size(radius));
    let (s, rg) = (count(segments, 3), count(rings, 2));
    let mut b = Builder::new(uv_sphere_footprint(segments, rings), fallible)?;
    for i in 0..=rg {
        for j in 0..=s {
            let d = sphere_dir(i, rg, j, s);
            let uv = Vec2::new(j as f32 / s as f32, 1.0 - i as f32 / rg as f32);
            b.vertex(d * r, d, uv);
        }
    }
    b.grid(0, s, rg, 0, 1);
    b.finish()
}

/// Axis-aligned cube from `-half_size` to `half_size`: 24 vertices (four per face, each with
/// its face normal), 12 triangles, six surfaces (flat, smoothing group 0).
#[must_use]
pub fn cube(half_size: f32) -> Mesh {
    let h = f64::from(size(half_size));
    let mut b = Builder::default();
    let faces = [
        (DVec3::X, DVec3::NEG_Z),
        (DVec3::NEG_X, DVec3::Z),
        (DVec3::Y, DVec3::X),
        (DVec3::NEG_Y, DVec3::X),
        (DVec3::Z, DVec3::X),
        (DVec3::NEG_Z, DVec3::NEG_X),
    ];
    for (surface, (n, u)) in faces.into_iter().enumerate() {
        let v = n.cross(u);
        let first = b.mesh.positions.len() as u32;
        for (du, dv) in [(-1.0, -1.0), (1.0, -1.0), (-1.0, 1.0), (1.0, 1.0)] {
            let p = (n + u * du + v * dv) * h;
            let uv = Vec2::new((du as f32 + 1.0) * 0.5, (dv as f32 + 1.0) * 0.5);
            b.vertex(p, n, uv);
        }
        b.grid(first, 1, 1, surface as u32, 0);
    }
    // Infallible: a default builder is not `fallible`.
    b.finish().unwrap_or_default()
}

/// Cylinder around the Y axis, `y` from `-height/2` to `height/2`, with both caps. The rims are
/// split (side vertices carry radial normals, cap vertices +/-Y), so they stay sharp. Surfaces:
/// side 0, top 1, bottom 2 (smoothing groups 1, 2, 3).
#[must_use]
pub fn cylinder(radius: f32, height: f32, segments: u32) -> Mesh {
    // Infallible: without `fallible` no step returns an error.
    cylinder_mesh(radius, height, segments, false).unwrap_or_default()
}

/// [`cylinder`] checked against `limit_bytes` before anything is allocated; see
/// [`try_uv_sphere`].
pub fn try_cylinder(
    radius: f32,
    height: f32,
    segments: u32,
    limit_bytes: u64,
) -> Result<Mesh, PrimitiveError> {
    let f = cylinder_footprint(segments);
    f.check(limit_bytes)?;
    cylinder_mesh(radius, height, segments, true).map_err(|_| out_of_memory(f))
}

fn cylinder_mesh(
    radius: f32,
    height: f32,
    segments: u32,
    fallible: bool,
) -> Result<Mesh, TryReserveError> {
    let r = f64::from(size(radius));
    let hh = f64::from(size(height)) * 0.5;
    let s = count(segments, 3);
    let dir = |j: u32| {
        let phi = TAU * f64::from(j % s) / f64::from(s);
        DVec3::new(phi.cos(), 0.0, -phi.sin())
    };
    let mut b = Builder::new(cylinder_footprint(segments), fallible)?;
    for (row, y) in [-hh, hh].into_iter().enumerate() {
        for j in 0..=s {
            let d = dir(j);
            b.vertex(
                d * r + DVec3::Y * y,
                d,
                Vec2::new(j as f32 / s as f32, row as f32),
            );
        }
    }
    b.grid(0, s, 1, 0, 1);
    for (surface, y) in [(1u32, hh), (2, -hh)] {
        let n = DVec3::Y * y.signum();
        let centre = b.vertex(DVec3::Y * y, n, Vec2::splat(0.5));
        let first = b.mesh.positions.len() as u32;
        for j in 0..=s {
            let d = dir(j);
            let uv = Vec2::new(
                (d.x * 0.5 + 0.5) as f32,
                (0.5 - d.z * 0.5 * y.signum()) as f32,
            );
            b.vertex(d * r + DVec3::Y * y, n, uv);
        }
        for j in 0..s {
            b.triangle([centre, first + j, first + j + 1], surface, surface + 1);
        }
    }
    b.finish()
}

/// Torus around the Y axis: tube centre circle of radius `major`, tube radius `minor`,
/// `segments` around the axis and `sides` around the tube; exact normals.
#[must_use]
pub fn torus(major: f32, minor: f32, segments: u32, sides: u32) -> Mesh {
    // Infallible: without `fallible` no step returns an error.
    torus_mesh(major, minor, segments, sides, false).unwrap_or_default()
}

/// [`torus`] checked against `limit_bytes` before anything is allocated (the error names
/// `segments` or `sides`, whichever is larger); see [`try_uv_sphere`].
pub fn try_torus(
    major: f32,
    minor: f32,
    segments: u32,
    sides: u32,
    limit_bytes: u64,
) -> Result<Mesh, PrimitiveError> {
    let f = torus_footprint(segments, sides);
    f.check(limit_bytes)?;
    torus_mesh(major, minor, segments, sides, true).map_err(|_| out_of_memory(f))
}

fn torus_mesh(
    major: f32,
    minor: f32,
    segments: u32,
    sides: u32,
    fallible: bool,
) -> Result<Mesh, TryReserveError> {
    let big = f64::from(size(major));
    let small = f64::from(size(minor));
    let (s, k) = (count(segments, 3), count(sides, 3));
    let mut b = Builder::new(torus_footprint(segments, sides), fallible)?;
    for i in 0..=k {
        let psi = TAU * f64::from(i % k) / f64::from(k);
        for j in 0..=s {
            let phi = TAU * f64::from(j % s) / f64::from(s);
            let radial = DVec3::new(phi.cos(), 0.0, -phi.sin());
            let n = radial * psi.cos() + DVec3::Y * psi.sin();
            let uv = Vec2::new(j as f32 / s as f32, i as f32 / k as f32);
            b.vertex(radial * big + n * small, n, uv);
        }
    }
    b.grid(0, s, k, 0, 1);
    b.finish()
}

/// Square in the XZ plane from `-half_size` to `half_size`, normal +Y, split into
/// `subdivisions` x `subdivisions` quads; u along +X, v along -Z, tangent +X with `w = +1`.
#[must_use]
pub fn plane(half_size: f32, subdivisions: u32) -> Mesh {
    // Infallible: without `fallible` no step returns an error.
    plane_mesh(half_size, subdivisions, false).unwrap_or_default()
}

/// [`plane`] checked against `limit_bytes` before anything is allocated; see
/// [`try_uv_sphere`].
pub fn try_plane(
    half_size: f32,
    subdivisions: u32,
    limit_bytes: u64,
) -> Result<Mesh, PrimitiveError> {
    let f = plane_footprint(subdivisions);
    f.check(limit_bytes)?;
    plane_mesh(half_size, subdivisions, true).map_err(|_| out_of_memory(f))
}

fn plane_mesh(half_size: f32, subdivisions: u32, fallible: bool) -> Result<Mesh, TryReserveError> {
    let h = f64::from(size(half_size));
    let n = count(subdivisions, 1);
    let mut b = Builder::new(plane_footprint(subdivisions), fallible)?;
    for j in 0..=n {
        for i in 0..=n {
            let (fu, fv) = (f64::from(i) / f64::from(n), f64::from(j) / f64::from(n));
            let p = DVec3::new(-h + 2.0 * h * fu, 0.0, h - 2.0 * h * fv);
            b.vertex(p, DVec3::Y, Vec2::new(fu as f32, fv as f32));
        }
    }
    b.grid(0, n, n, 0, 1);
    b.finish()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn check_outward(m: &Mesh) {
        assert!(m.is_consistent());
        for t in 0..m.indices.len() {
            let n = m
                .face_normal(t)
                .expect("primitives drop degenerate triangles");
            for &i in &m.indices[t] {
                assert!(
                    n.dot(m.normals[i as usize]) > 0.0,
                    "triangle {t} faces inward"
                );
            }
        }
    }

    #[test]
    fn every_primitive_is_consistent_and_faces_outward() {
        for m in [
            uv_sphere(1.0, 16, 8),
            cube(0.5),
            cylinder(1.0, 2.0, 12),
            torus(1.0, 0.3, 16, 8),
            plane(1.0, 3),
            uv_sphere(f32::NAN, 0, 0),
            cylinder(-1.0, f32::INFINITY, 1),
        ] {
            check_outward(&m);
            assert!(m.uvs.is_some() && m.tangents.is_some());
        }
    }

    #[test]
    fn sphere_normals_are_exact_radial_directions() {
        let m = uv_sphere(2.0, 24, 12);
        for (p, n) in m.positions.iter().zip(&m.normals) {
            assert!((*p / 2.0 - *n).length() < 1e-6);
        }
    }

    #[test]
    fn tangents_are_perpendicular_to_normals() {
        for m in [
            uv_sphere(1.0, 16, 8),
            torus(1.0, 0.3, 16, 8),
            plane(1.0, 2),
            cylinder(1.0, 1.0, 8),
        ] {
            let ts = m.tangents.as_ref().expect("primitives have tangents");
            for (t, n) in ts.iter().zip(&m.normals) {
                assert!(t.truncate().dot(*n).abs() < 1e-5);
            }
        }
        let p = plane(1.0, 2);
        let ts = p.tangents.as_ref().expect("plane has tangents");
        assert!(
            ts.iter()
                .all(|t| (t.truncate() - Vec3::X).length() < 1e-6 && t.w == 1.0)
        );
    }

    #[test]
    fn counts_over_the_limit_are_refused_naming_the_count_before_allocating() {
        let gb = 1_000_000_000;
        let e = try_uv_sphere(1.0, 4096, 4096, gb).expect_err("2.4 GB is over 1 GB");
        assert_eq!(
            e.to_string(),
            "segments: the mesh needs 2.5 GB (16785409 vertices, 33554432 triangles), \
             over the 1.0 GB limit"
        );
        assert_eq!(e.field(), "segments");
        assert!(e.what().starts_with("the mesh needs 2.5 GB"));
        let e = try_uv_sphere(1.0, 8, 4096, 1_000_000).expect_err("over");
        assert_eq!(e.field(), "rings");
        let e = try_torus(1.0, 0.3, 100, 4096, 1_000_000).expect_err("over");
        assert_eq!(e.field(), "sides");
        let e = try_torus(1.0, 0.3, 4096, 100, 1_000_000).expect_err("over");
        assert_eq!(e.field(), "segments");
        let e = try_cylinder(1.0, 1.0, 4096, 1000).expect_err("over");
        assert_eq!(e.field(), "segments");
        let e = try_plane(1.0, 4096, gb).expect_err("over");
        assert_eq!(e.field(), "subdivisions");
        // Counts past the clamp are sized as clamped.
        assert_eq!(
            uv_sphere_footprint(u32::MAX, 0),
            uv_sphere_footprint(4096, 2)
        );
    }

    #[test]
    fn checked_builders_within_the_limit_match_the_plain_ones() {
        let sphere = uv_sphere_footprint(16, 8);
        assert_eq!(
            try_uv_sphere(1.0, 16, 8, sphere.bytes()).expect("fits"),
            uv_sphere(1.0, 16, 8)
        );
        assert_eq!(
            try_torus(1.0, 0.3, 12, 6, u64::MAX).expect("fits"),
            torus(1.0, 0.3, 12, 6)
        );
        assert_eq!(
            try_cylinder(1.0, 2.0, 9, u64::MAX).expect("fits"),
            cylinder(1.0, 2.0, 9)
        );
        assert_eq!(try_plane(1.0, 3, u64::MAX).expect("fits"), plane(1.0, 3));
        assert!(try_uv_sphere(1.0, 16, 8, sphere.bytes() - 1).is_err());
        assert_eq!(gigabytes(2_700_000_001), "2.8");
        assert_eq!(gigabytes(0), "0.0");
    }

    #[test]
    fn cube_has_24_vertices_12_triangles_6_surfaces() {
        let c = cube(1.0);
        assert_eq!(
            (c.positions.len(), c.indices.len(), c.stats().surfaces),
            (24, 12, 6)
        );
    }
}
