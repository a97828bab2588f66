//! The uv gradient per vertex, for the analytic primitives (whose size a scene file sets).
//!
//! Per triangle, the tangent `T` and bitangent `B` solve `e1 = du1 T + dv1 B`,
//! `e2 = du2 T + dv2 B` (the uv derivatives of position, Lengyel 2001). They are summed at each
//! vertex (vertices are already split per surface, so this averages like the normals), then
//! `T` is made perpendicular to the vertex normal (Gram-Schmidt) and `w = sign((N x T) . B)`.
//! On a primitive's smooth parametrisation this is the surface's `dP/du` direction, which
//! MikkTSpace approaches too; unlike MikkTSpace its memory is two sums per vertex, which the
//! primitives' footprint counts, and every allocation can be refused without an abort.
//!
//! Fallback: a vertex whose triangles have degenerate uvs (zero uv area) or whose summed tangent
//! is parallel to the normal gets [`fallback_tangent`] (a unit vector perpendicular to
//! the normal, `w = +1`).

use std::collections::TryReserveError;

use glam::{DVec3, Vec2, Vec3, Vec4};

use super::fallback_tangent;

/// One tangent per vertex; see the module docs. Inputs must have equal lengths (`normals` and
/// `uvs` per position) and indices in range; entries out of range are skipped.
pub(crate) fn compute(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[[u32; 3]],
) -> Vec<Vec4> {
    let n = positions.len().min(normals.len()).min(uvs.len());
    let mut out = Vec::with_capacity(positions.len());
    fill(
        positions,
        normals,
        uvs,
        indices,
        vec![DVec3::ZERO; n],
        vec![DVec3::ZERO; n],
        &mut out,
    );
    out
}

/// [`compute`], reporting a failed allocation instead of aborting (for meshes whose size a
/// scene file sets).
pub(crate) fn try_compute(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[[u32; 3]],
) -> Result<Vec<Vec4>, TryReserveError> {
    let n = positions.len().min(normals.len()).min(uvs.len());
    let zeros = |n: usize| -> Result<Vec<DVec3>, TryReserveError> {
        let mut v = Vec::new();
        v.try_reserve_exact(n)?;
        v.resize(n, DVec3::ZERO);
        Ok(v)
    };
    let (t_sum, b_sum) = (zeros(n)?, zeros(n)?);
    let mut out = Vec::new();
    out.try_reserve_exact(positions.len())?;
    fill(positions, normals, uvs, indices, t_sum, b_sum, &mut out);
    Ok(out)
}

/// Sums each triangle's tangent and bitangent into `t_sum` and `b_sum` (one per vertex up to
/// the shortest input) and pushes one tangent per position onto `out`.
fn fill(
    positions: &[Vec3],
    normals: &[Vec3],
    uvs: &[Vec2],
    indices: &[[u32; 3]],
    mut t_sum: Vec<DVec3>,
    mut b_sum: Vec<DVec3>,
    out: &mut Vec<Vec4>,
) {
    let n = t_sum.len().min(b_sum.len());
    for tri in indices {
        if tri.iter().any(|&i| i as usize >= n) {
            continue;
        }
        let [i0, i1, i2] = tri.map(|i| i as usize);
        let (p0, p1, p2) = (
            positions[i0].as_dvec3(),
            positions[i1].as_dvec3(),
            positions[i2].as_dvec3(),
        );
        let (w0, w1, w2) = (uvs[i0].as_dvec2(), uvs[i1].as_dvec2(), uvs[i2].as_dvec2());
        let (e1, e2) = (p1 - p0, p2 - p0);
        let (d1, d2) = (w1 - w0, w2 - w0);
        let det = d1.x * d2.y - d2.x * d1.y;
        if det == 0.0 || !det.is_finite() {
            continue;
        }
        let r = 1.0 / det;
        let t = (e1 * d2.y - e2 * d1.y) * r;
        let b = (e2 * d1.x - e1 * d2.x) * r;
        if !(t.is_finite() && b.is_finite()) {
            continue;
        }
        // Area weighting comes for free: the triangle's T and B are not normalized.
        for i in [i0, i1, i2] {
            t_sum[i] += t;
            b_sum[i] += b;
        }
    }
    out.extend((0..positions.len()).map(|i| {
        let Some(&nf) = normals.get(i) else {
            return Vec4::new(1.0, 0.0, 0.0, 1.0);
        };
        if i >= n {
            return fallback_tangent(nf);
        }
        let nn = nf.as_dvec3();
        let t = t_sum[i] - nn * nn.dot(t_sum[i]);
        let len = t.length();
        if len <= 1e-12 * t_sum[i].length() || !len.is_finite() || len == 0.0 {
            return fallback_tangent(nf);
        }
        let t = t / len;
        let w = if nn.cross(t).dot(b_sum[i]) < 0.0 {
            -1.0
        } else {
            1.0
        };
        let t32 = phosphor_math::safe_normalize(t.as_vec3(), Vec3::X);
        t32.extend(w)
    }));
}
