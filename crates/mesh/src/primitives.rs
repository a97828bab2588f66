//! Analytic primitives with exact normals (the normal of the true surface at each vertex, not an
//! average), for tests and scenes. The caller chooses the tessellation; counts are clamped to
//! sane ranges (at least 3 segments, at most 4096 per direction) and a size that is not a
//! positive finite number is replaced by 1, so no argument can produce NaN or panic.
//!
//! All primitives are centred on the origin, counter-clockwise seen from outside. Sphere,
//! cylinder, torus, plane and cube carry uvs and tangents.

use std::f64::consts::{PI, TAU};

use glam::{DVec3, Vec2, Vec3};

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

/// Accumulates vertices and triangles; triangles are oriented so their face normal agrees with
/// the vertex normals (outward), and zero-area ones (at sphere poles) are dropped.
#[derive(Default)]
struct Builder {
    mesh: Mesh,
    uvs: Vec<Vec2>,
}

impl Builder {
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

    fn finish(mut self) -> Mesh {
        let m = &mut self.mesh;
        m.tangents = Some(tangents::compute(
            &m.positions,
            &m.normals,
            &self.uvs,
            &m.indices,
        ));
        m.uvs = Some(self.uvs);
        self.mesh
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
    let r = f64::from(size(radius));
    let (s, rg) = (count(segments, 3), count(rings, 2));
    let mut b = Builder::default();
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
    b.finish()
}

/// Cylinder around the Y axis, `y` from `-height/2` to `height/2`, with both caps. The rims are
/// split (side vertices carry radial normals, cap vertices +/-Y), so they stay sharp. Surfaces:
/// side 0, top 1, bottom 2 (smoothing groups 1, 2, 3).
#[must_use]
pub fn cylinder(radius: f32, height: f32, segments: u32) -> Mesh {
    let r = f64::from(size(radius));
    let hh = f64::from(size(height)) * 0.5;
    let s = count(segments, 3);
    let dir = |j: u32| {
        let phi = TAU * f64::from(j % s) / f64::from(s);
        DVec3::new(phi.cos(), 0.0, -phi.sin())
    };
    let mut b = Builder::default();
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
    let big = f64::from(size(major));
    let small = f64::from(size(minor));
    let (s, k) = (count(segments, 3), count(sides, 3));
    let mut b = Builder::default();
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
    let h = f64::from(size(half_size));
    let n = count(subdivisions, 1);
    let mut b = Builder::default();
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
    fn cube_has_24_vertices_12_triangles_6_surfaces() {
        let c = cube(1.0);
        assert_eq!(
            (c.positions.len(), c.indices.len(), c.stats().surfaces),
            (24, 12, 6)
        );
    }
}
