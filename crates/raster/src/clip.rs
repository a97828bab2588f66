//! Homogeneous clipping (Sutherland-Hodgman in clip space, before the perspective divide).
//!
//! Always against the near plane `z >= -w` (OpenGL) and `w >= W_MIN`; against a guard band
//! `|x|, |y| <= g w` only when a vertex leaves it, so that every screen coordinate stays far
//! inside the fixed-point range ([`phosphor_math::fixed::MAX_FIXED_COORD`]). Attributes are
//! linear in homogeneous space, so clipped vertices interpolate them with the same `t`.

use glam::{DVec4, Vec4};

/// Vertex attributes carried through clipping and interpolation: a shader's varyings.
pub const MAX_ATTRS: usize = crate::shader::MAX_VARYINGS;

/// Attribute storage of one vertex.
pub type Attrs = [f32; MAX_ATTRS];

/// Guard band half-width in pixels beyond the viewport edges.
pub const GUARD_BAND_PX: f32 = 65536.0;

/// Smallest `w` kept: a safety plane behind the near plane for arbitrary matrices.
pub const W_MIN: f32 = 1e-7;

/// A vertex in clip space with its attributes.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ClipVertex {
    /// Homogeneous clip-space position.
    pub pos: Vec4,
    /// Attributes (first `n` used).
    pub attrs: Attrs,
}

/// Most vertices a triangle clipped by 6 planes can have (3 + 6).
pub const MAX_POLY: usize = 9;

/// A convex polygon of clipped vertices, allocation-free.
#[derive(Debug, Clone, Copy)]
pub struct Polygon {
    verts: [ClipVertex; MAX_POLY],
    len: usize,
}

impl Polygon {
    fn empty() -> Polygon {
        Polygon {
            verts: [ClipVertex {
                pos: Vec4::ZERO,
                attrs: [0.0; MAX_ATTRS],
            }; MAX_POLY],
            len: 0,
        }
    }

    fn push(&mut self, v: ClipVertex) {
        if self.len < MAX_POLY {
            self.verts[self.len] = v;
            self.len += 1;
        }
    }

    /// The vertices, in the input winding order.
    #[must_use]
    pub fn vertices(&self) -> &[ClipVertex] {
        &self.verts[..self.len]
    }
}

/// Guard-band factors in NDC for a viewport of `width` x `height` pixels.
#[must_use]
pub fn guard_band(width: u32, height: u32) -> (f32, f32) {
    (
        1.0 + 2.0 * GUARD_BAND_PX / width.max(1) as f32,
        1.0 + 2.0 * GUARD_BAND_PX / height.max(1) as f32,
    )
}

/// The six clip planes `p` (a point is inside when `p . pos + plane_offset(i) >= 0`).
#[inline]
fn clip_planes((gx, gy): (f32, f32)) -> [Vec4; 6] {
    [
        Vec4::new(0.0, 0.0, 1.0, 1.0), // near: z + w >= 0
        Vec4::new(0.0, 0.0, 0.0, 1.0), // w >= W_MIN
        Vec4::new(-1.0, 0.0, 0.0, gx), // x <= gx w
        Vec4::new(1.0, 0.0, 0.0, gx),  // x >= -gx w
        Vec4::new(0.0, -1.0, 0.0, gy), // y <= gy w
        Vec4::new(0.0, 1.0, 0.0, gy),  // y >= -gy w
    ]
}

/// The constant term of plane `i` of [`clip_planes`].
#[inline]
fn offset(i: usize) -> f32 {
    if i == 1 { -W_MIN } else { 0.0 }
}

/// True when `pos` is inside all six clip planes: a triangle of such vertices is not changed
/// by [`clip_triangle`].
#[inline]
#[must_use]
pub fn inside_clip_volume(pos: Vec4, guard: (f32, f32)) -> bool {
    clip_planes(guard)
        .iter()
        .enumerate()
        .all(|(i, p)| p.dot(pos) + offset(i) >= 0.0)
}

/// Clips triangle `tri` (attributes `0..n`) against the near plane, `w >= W_MIN` and the guard
/// band `(gx, gy)`. Returns an empty polygon when nothing is left.
#[must_use]
pub fn clip_triangle(tri: &[ClipVertex; 3], n: usize, guard: (f32, f32)) -> Polygon {
    let (gx, gy) = guard;
    let planes = clip_planes(guard);
    let mut poly = Polygon::empty();
    for v in tri {
        poly.push(*v);
    }
    if tri.iter().all(|v| inside_clip_volume(v.pos, guard)) {
        return poly;
    }
    // Clipped vertices are computed in f64, from the endpoint nearer the plane, and put
    // exactly on the plane. Interpolating `a + (b - a) t` in f32 between corners 1e12 apart
    // loses ~1e5 to cancellation (f64 still ~1e4 at 1e20), which threw guard-band vertices
    // out of the fixed-point range or across the screen: a screen-filling triangle showed a
    // crack. From the nearer endpoint the error scales with the distance to the plane, and
    // the choice does not depend on the edge's direction, so two triangles sharing an edge
    // get the same bits.
    let mut pos = [DVec4::ZERO; MAX_POLY];
    let mut attrs = [[0.0; MAX_ATTRS]; MAX_POLY];
    for (k, v) in tri.iter().enumerate() {
        pos[k] = v.pos.as_dvec4();
        attrs[k] = v.attrs;
    }
    let mut len = 3;
    for (i, plane) in planes.iter().enumerate() {
        let (plane, off) = (plane.as_dvec4(), f64::from(offset(i)));
        let dist = |p: DVec4| plane.dot(p) + off;
        if pos[..len].iter().all(|p| dist(*p) >= 0.0) {
            continue;
        }
        let (mut out_pos, mut out_attrs, mut out_len) = (pos, attrs, 0);
        let mut emit = |p: DVec4, a: Attrs| {
            if out_len < MAX_POLY {
                out_pos[out_len] = p;
                out_attrs[out_len] = a;
                out_len += 1;
            }
        };
        for k in 0..len {
            let next = (k + 1) % len;
            let (da, db) = (dist(pos[k]), dist(pos[next]));
            if da >= 0.0 {
                emit(pos[k], attrs[k]);
            }
            if (da >= 0.0) != (db >= 0.0) {
                let a_first = da.abs() < db.abs()
                    || (da.abs() == db.abs() && pos[k].to_array() < pos[next].to_array());
                let (from, to) = if a_first { (k, next) } else { (next, k) };
                let (df, dt) = if a_first { (da, db) } else { (db, da) };
                let t = df / (df - dt);
                let mut p = pos[from] + (pos[to] - pos[from]) * t;
                match i {
                    0 => p.z = -p.w,
                    1 => p.w = f64::from(W_MIN),
                    2 => p.x = f64::from(gx) * p.w,
                    3 => p.x = -f64::from(gx) * p.w,
                    4 => p.y = f64::from(gy) * p.w,
                    _ => p.y = -f64::from(gy) * p.w,
                }
                let (a, b) = (&attrs[from], &attrs[to]);
                let mut v = *a;
                let tf = t as f32;
                for j in 0..n {
                    v[j] = a[j] + (b[j] - a[j]) * tf;
                }
                emit(p, v);
            }
        }
        (pos, attrs, len) = (out_pos, out_attrs, out_len);
        if len < 3 {
            return Polygon::empty();
        }
    }
    let mut poly = Polygon::empty();
    for k in 0..len {
        poly.push(ClipVertex {
            pos: pos[k].as_vec4(),
            attrs: attrs[k],
        });
    }
    poly
}

#[cfg(test)]
mod tests {
    use super::*;

    fn v(x: f32, y: f32, z: f32, w: f32) -> ClipVertex {
        ClipVertex {
            pos: Vec4::new(x, y, z, w),
            attrs: [x; MAX_ATTRS],
        }
    }

    #[test]
    fn triangle_behind_the_near_plane_vanishes_and_crossing_one_becomes_a_quad() {
        let g = guard_band(100, 100);
        let behind = [
            v(0.0, 0.0, -2.0, 1.0),
            v(1.0, 0.0, -2.0, 1.0),
            v(0.0, 1.0, -3.0, 1.0),
        ];
        assert_eq!(clip_triangle(&behind, 1, g).vertices().len(), 0);
        let crossing = [
            v(0.0, 0.0, -2.0, 1.0),
            v(1.0, 0.0, 0.0, 1.0),
            v(0.0, 1.0, 0.0, 1.0),
        ];
        let p = clip_triangle(&crossing, 1, g);
        assert_eq!(p.vertices().len(), 4);
        for c in p.vertices() {
            assert!(c.pos.z + c.pos.w >= -1e-6);
            assert_eq!(c.attrs[0], c.pos.x, "attributes follow the position");
        }
    }

    #[test]
    fn triangles_up_to_1e30_across_clip_to_exactly_the_guard_band() {
        // `a + (b - a) t` lost ~1e5 to cancellation at 1e12 in f32 (and ~1e4 at 1e20 in f64),
        // which threw guard-band vertices out of range or across the screen: a crack.
        let g = guard_band(64, 48);
        for s in [1e6f32, 1e12, 1e20, 1e30] {
            let huge = [
                v(-2.4 * s, -1.8 * s, 0.0, 3.0),
                v(2.4 * s, -1.8 * s, 0.0, 3.0),
                v(0.0, 1.8 * s, 0.0, 3.0),
            ];
            let p = clip_triangle(&huge, 0, g);
            assert!(p.vertices().len() >= 3, "{s}");
            // The whole guard band is covered: its four corners are the polygon.
            let mut corners: Vec<(f32, f32)> = p
                .vertices()
                .iter()
                .map(|c| (c.pos.x / c.pos.w, c.pos.y / c.pos.w))
                .collect();
            corners.dedup();
            assert_eq!(corners.len(), 4, "{s}: {corners:?}");
            for (x, y) in corners {
                assert!(
                    (x.abs() - g.0).abs() <= g.0 * 1e-6 && (y.abs() - g.1).abs() <= g.1 * 1e-6,
                    "{s}: ({x}, {y})"
                );
            }
        }
    }

    #[test]
    fn guard_band_keeps_screen_coordinates_in_fixed_point_range() {
        let g = guard_band(64, 64);
        let huge = [
            v(-1e9, -1e9, 0.0, 1.0),
            v(1e9, -1e9, 0.0, 1.0),
            v(0.0, 1e9, 0.0, 1.0),
        ];
        let p = clip_triangle(&huge, 0, g);
        assert!(p.vertices().len() >= 3);
        for c in p.vertices() {
            let sx = (c.pos.x / c.pos.w + 1.0) * 32.0;
            assert!(sx.abs() < phosphor_math::fixed::MAX_FIXED_COORD);
        }
    }
}
