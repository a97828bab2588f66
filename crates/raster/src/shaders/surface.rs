//! What several modes compute alike from a vertex or a triangle: the per-pixel modes'
//! varyings, the bump-mapped normal and a flat face's facet. Kept apart from the modes so
//! that each mode and the tinted variants import it one way.

use glam::{Vec2, Vec3, Vec4};
use phosphor_lighting::{Lanes, Vec3s};

use crate::bump::BumpMap;
use crate::shader::{MAX_VARYINGS, TriangleLanes, Varyings, VertexLanes, put_vec3};

/// The varyings of the per-pixel modes: world position 0..3, normal 3..6, and with a tangent
/// frame uv 6..8 and tangent 8..12.
#[inline(always)]
pub fn surface_varyings<L: Lanes>(v: &VertexLanes<L>, frame: bool) -> Varyings<L> {
    let mut out = [v.position.x.splat(0.0); MAX_VARYINGS];
    put_vec3(&mut out, 0, v.position);
    put_vec3(&mut out, 3, v.normal);
    if frame {
        out[6] = v.uv[0];
        out[7] = v.uv[1];
        out[8..12].copy_from_slice(&v.tangent);
    }
    out
}

/// The normals `n` perturbed by `map` at the lanes' uvs and tangents (varyings 6..12).
#[inline(always)]
pub fn perturbed<L: Lanes>(map: &BumpMap, n: Vec3s<L>, v: &Varyings<L>) -> Vec3s<L> {
    let (u, w) = (v[6].to_lanes(), v[7].to_lanes());
    let t = [v[8], v[9], v[10], v[11]].map(Lanes::to_lanes);
    let n0 = n.to_vecs();
    let out: [Vec3; 8] = std::array::from_fn(|i| {
        if i < L::N {
            let tangent = Vec4::new(t[0][i], t[1][i], t[2][i], t[3][i]);
            map.perturb(n0[i], tangent, Vec2::new(u[i], w[i]))
        } else {
            Vec3::ZERO
        }
    });
    Vec3s::from_vecs(n.x, out)
}

/// The facet of each lane's triangle: its centroid and face normal, as the scalar
/// `(a + b + c) / 3` and `safe_normalize((b - a) x (c - a))` compute them (counter-clockwise
/// is front, so the normal points outwards).
#[inline(always)]
pub(crate) fn facet<L: Lanes>(t: &TriangleLanes<L>) -> (Vec3s<L>, Vec3s<L>) {
    let [a, b, c] = t.corners.map(|c| c.position);
    let like = a.x;
    let centroid = Vec3s::new(
        (a.x + b.x + c.x) / like.splat(3.0),
        (a.y + b.y + c.y) / like.splat(3.0),
        (a.z + b.z + c.z) / like.splat(3.0),
    );
    let n = (b - a)
        .cross(c - a)
        .safe_normalize(Vec3s::broadcast(like, Vec3::ZERO));
    (centroid, n)
}
