//! What both fast-Phong methods check before a triangle's quadratics are accepted: the
//! tolerance at the check points, and that no highlight narrower than the triangle can hide
//! between them.

use glam::Vec3;
use phosphor_lighting::{lobe_sharpness, specular_upper_bound};

use super::Lit;

/// Largest error (per channel, on the `[0, 1]` intensity) the fit may show at the check
/// points before the triangle falls back to `phong`: one 8-bit code.
pub const FAST_PHONG_TOLERANCE: f32 = 1.0 / 255.0;

/// Lobes up to this [`phosphor_lighting::lobe_sharpness`] (`n_s` times the squared
/// angular extent of the triangle) are at least as wide as the triangle: they vary smoothly
/// across the ten samples, whose checks see any misfit. Sharper ones are checked against the
/// bound.
pub const MAX_SMOOTH_LOBE_SHARPNESS: f32 = 1.0;

/// Whether a triangle's specular highlight cannot peak between the points a method checked:
/// its lobes are smooth over the triangle, or their upper bound stays within
/// [`FAST_PHONG_TOLERANCE`] of `seen`, the largest specular the checks saw. `nodes` are the
/// surface points and normals at the corners (0, 1, 2) and at the midpoints of edges 01, 12,
/// 20 (3, 4, 5). The bound is loose on a large triangle, so where it fails it is retried on
/// the four half-size triangles of the nodes (spreads halve).
pub(crate) fn highlight_is_sampled<const FX: u32>(
    lit: &Lit,
    nodes: &[(Vec3, Vec3); 6],
    seen: Vec3,
) -> bool {
    let (set, mat, eye) = (lit.set, &lit.mat, lit.eye);
    let fits = |corners: [usize; 3]| {
        let p = corners.map(|i| nodes[i].0);
        let n = corners.map(|i| nodes[i].1);
        lobe_sharpness::<FX>(set, mat, p, n, eye) <= MAX_SMOOTH_LOBE_SHARPNESS
            || (specular_upper_bound::<FX>(set, mat, p, n, eye) - seen).max_element()
                <= FAST_PHONG_TOLERANCE
    };
    fits([0, 1, 2])
        || [[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]]
            .into_iter()
            .all(fits)
}
