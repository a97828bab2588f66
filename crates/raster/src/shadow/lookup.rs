//! The shadow lookup written once over [`Lanes`]: the light's view, the bias and the
//! percentage-closer weights in lanes, only the reads of the 4 x 4 texels per lane. The map is
//! stored with [`PAD`] texels of "no caster" around it, so a footprint that reaches past the
//! edge reads them instead of testing each texel's position. [`ShadowMap::visibility`] is the
//! one-lane case, so every lane width gives its bits.
//!
//! Most points are wholly lit or wholly in shadow, so the map also keeps, per texel, the least
//! and greatest distance of the footprint that starts there ([`footprint_ranges`]). Where no
//! lane's footprint straddles its point's distance, the lookup reads those two values per lane
//! instead of sixteen, and gives the same bits: the tent weights summed in the same order, or
//! zero.

use glam::Vec3;
use phosphor_lighting::{F32x1, Lanes, Vec3s};

use super::{BIAS_CONSTANT, BIAS_SLOPE, MAX_BIAS_SLOPE, Projection, ShadowMap};
use crate::texture::floor;

/// Texels of padding on every side of a stored map, each `f32::MAX` (no caster, so always
/// lit): the footprint of any point the lookup accepts (texel coordinates within
/// `(-3, size + 2)`, taps one before to two after) stays inside the padded array.
pub(super) const PAD: usize = 5;

/// All ones in every lane.
#[inline(always)]
fn ones<L: Lanes>(like: L) -> L {
    let zero = like.splat(0.0);
    zero.cmp_eq(zero)
}

/// `x > c` per lane as a mask, for a finite `c` (false for NaN): `x >= ` the next float
/// after `c`, exactly.
#[inline(always)]
fn above<L: Lanes>(x: L, c: f32) -> L {
    x.cmp_ge(x.splat(next_toward(c, f32::INFINITY)))
}

/// `x < c` per lane as a mask, for a finite `c` (false for NaN).
#[inline(always)]
fn below<L: Lanes>(x: L, c: f32) -> L {
    x.cmp_le(x.splat(next_toward(c, f32::NEG_INFINITY)))
}

/// The float next to a finite `c` in the direction of `to` (an infinity).
fn next_toward(c: f32, to: f32) -> f32 {
    if c == 0.0 {
        return f32::from_bits(1).copysign(to);
    }
    // Away from zero where `c` and `to` share a sign: one more in the magnitude's bits.
    let away = (c > 0.0) == (to > 0.0);
    f32::from_bits(if away {
        c.to_bits() + 1
    } else {
        c.to_bits() - 1
    })
}

/// Whether each lane is finite, as a mask.
#[inline(always)]
fn finite<L: Lanes>(x: L) -> L {
    x.abs().cmp_le(x.splat(f32::MAX))
}

impl ShadowMap {
    /// How much of the light reaches world point `p` with surface normal `n` (not necessarily
    /// unit): 1 fully lit, 0 in shadow, the PCF fraction between. Points outside the map,
    /// behind a perspective light or with a non-finite position are lit.
    #[must_use]
    pub fn visibility(&self, p: Vec3, n: Vec3) -> f32 {
        let like = F32x1(0.0);
        self.visibility_lanes(Vec3s::broadcast(like, p), Vec3s::broadcast(like, n))
            .0
    }

    /// [`ShadowMap::visibility`] per lane: every step is the one-lane step lane by lane, so
    /// each lane has the same bits at every width.
    #[inline(always)]
    #[must_use]
    pub fn visibility_lanes<L: Lanes>(&self, p: Vec3s<L>, n: Vec3s<L>) -> L {
        let like = p.x;
        let (zero, one, half) = (like.splat(0.0), like.splat(1.0), like.splat(0.5));
        let light = &self.light;
        // World to light view, in the order of glam's `Mat4::transform_point3`.
        let m = &light.view;
        let row = |r: usize| {
            let s = |c: glam::Vec4| like.splat(c[r]);
            ((s(m.x_axis) * p.x + s(m.y_axis) * p.y) + s(m.z_axis) * p.z) + s(m.w_axis)
        };
        let (vx, vy, vz) = (row(0), row(1), row(2));
        let dist = zero - vz;
        let toward = Vec3s::broadcast(like, light.toward);
        let (sx, sy, texel, mut valid, to_light) = match light.projection {
            Projection::Orthographic { half_width } => {
                let h = like.splat(half_width);
                (vx / h, vy / h, like.splat(self.texel), ones(like), toward)
            }
            Projection::Perspective { tan_half } => {
                let k = dist * like.splat(tan_half);
                // glam's `normalize_or_zero` of the way to the light.
                let d = toward - p;
                let rcp = one / d.length_squared().sqrt();
                let unit = finite(rcp) & above(rcp, 0.0);
                let dir = Vec3s::select(unit, d * rcp, Vec3s::broadcast(like, Vec3::ZERO));
                let texel = like.splat(self.texel) * dist;
                (vx / k, vy / k, texel, above(dist, 0.0), dir)
            }
        };
        valid = valid & finite(sx) & finite(sy) & finite(dist);
        // tan(theta) from the normal: sqrt(1 - c^2) / c, capped.
        let len2 = n.length_squared();
        let usable = above(len2, 0.0) & finite(len2);
        let c = usable.blend(n.dot(to_light) / len2.sqrt(), one);
        let cap = like.splat(MAX_BIAS_SLOPE);
        let tan = (one - c * c).max_c(zero).sqrt() / c;
        let slope = above(c, 0.0).blend(tan.min_c(cap), cap);
        let compare = dist - texel * (like.splat(BIAS_CONSTANT) + like.splat(BIAS_SLOPE) * slope);
        let size = self.size as f32;
        let s = like.splat(size);
        // Texel coordinates with centres at integers (the rasterizer's pixel centres).
        let fx = (sx + one) * half * s - half;
        let fy = (one - sy) * half * s - half;
        valid = valid
            & above(fx, -3.0)
            & above(fy, -3.0)
            & below(fx, size + 2.0)
            & below(fy, size + 2.0);
        let (fx, fy) = (valid.blend(fx, zero), valid.blend(fy, zero));
        let (x0, y0) = (floor(fx), floor(fy));
        let (tx, ty) = (fx - x0, fy - y0);
        // A 3 x 3 box of bilinear taps at offsets -1, 0, 1: tent weights over texels
        // x0 - 1 ..= x0 + 2, rows y0 - 1 ..= y0 + 2 (padded: slot `i + PAD` holds texel `i`).
        let (x0, y0) = (x0.to_lanes(), y0.to_lanes());
        let mut first = [0usize; 8];
        let (mut least, mut most) = ([f32::MAX; 8], [f32::MAX; 8]);
        for k in 0..L::N {
            // Whole numbers in `[-3, size + 1]` (or 0): through `i32`, whose conversion is a
            // single instruction where `usize`'s is a branchy sequence.
            let row = (y0[k] as i32 + (PAD as i32 - 1)).max(0) as usize;
            let col = (x0[k] as i32 + (PAD as i32 - 1)).max(0) as usize;
            first[k] = row * self.stride + col;
            [least[k], most[k]] = self.ranges.get(first[k]).copied().unwrap_or([f32::MAX; 2]);
        }
        let wx = [one - tx, one, one, tx];
        let wy = [one - ty, one, one, ty];
        // A lane whose footprint is wholly nearer than its point (or wholly not) has all 16
        // comparisons true (false): its weights summed as below, term by term (or zero). When
        // no valid lane is partly lit, that is the result, with the same bits.
        let whole = compare.cmp_le(like.with_lanes(least));
        let reaches = compare.cmp_le(like.with_lanes(most));
        let partial = valid.mask_bits() & reaches.mask_bits() & !whole.mask_bits();
        if partial == 0 {
            let mut row = zero;
            for wx in wx {
                row = row + wx;
            }
            let mut lit = zero;
            for w in wy {
                lit = lit + row * w;
            }
            let lit = (lit / like.splat(9.0)).max_c(zero).min_c(one) & whole;
            return valid.blend(lit, one);
        }
        let (mut upper, mut lower) = ([[0.0; 8]; 8], [[0.0; 8]; 8]);
        for k in 0..L::N {
            let at = |j: usize| -> [f32; 4] {
                let s = first[k] + j * self.stride;
                self.distance
                    .get(s..s + 4)
                    .and_then(|r| r.try_into().ok())
                    .unwrap_or([f32::MAX; 4])
            };
            let (r0, r1, r2, r3) = (at(0), at(1), at(2), at(3));
            upper[k] = [r0[0], r0[1], r0[2], r0[3], r1[0], r1[1], r1[2], r1[3]];
            lower[k] = [r2[0], r2[1], r2[2], r2[3], r3[0], r3[1], r3[2], r3[3]];
        }
        let (u, l) = (like.columns(&upper), like.columns(&lower));
        let mut lit = zero;
        for (j, w) in wy.iter().enumerate() {
            let taps = if j < 2 { &u } else { &l };
            let base = (j % 2) * 4;
            let mut row = zero;
            for (i, wx) in wx.iter().enumerate() {
                row = row + (compare.cmp_le(taps[base + i]) & *wx);
            }
            lit = lit + row * *w;
        }
        let lit = (lit / like.splat(9.0)).max_c(zero).min_c(one);
        valid.blend(lit, one)
    }
}

/// Fills `ranges` (whole rows from row `first_row` on) with, at each texel, the least and
/// greatest of the 4 x 4 values of `distance` (rows of `stride`) whose top-left it is,
/// clipped to the array.
pub(super) fn footprint_ranges(
    distance: &[f32],
    stride: usize,
    first_row: usize,
    ranges: &mut [[f32; 2]],
) {
    // Written as selects, not `f32::min`, so that they run in vectors (no NaN is stored).
    let min = |a: f32, b: f32| if b < a { b } else { a };
    let max = |a: f32, b: f32| if b > a { b } else { a };
    let (mut least, mut most) = (vec![0.0; stride], vec![0.0; stride]);
    let rows: Vec<&[f32]> = distance.chunks_exact(stride).collect();
    for (r, out) in ranges.chunks_exact_mut(stride).enumerate() {
        let r = first_row + r;
        if r >= rows.len() {
            break;
        }
        // Down the columns, then along the row.
        least.copy_from_slice(rows[r]);
        most.copy_from_slice(rows[r]);
        for below in rows.iter().skip(r + 1).take(3) {
            for ((lo, hi), &d) in least.iter_mut().zip(most.iter_mut()).zip(below.iter()) {
                *lo = min(*lo, d);
                *hi = max(*hi, d);
            }
        }
        // Four columns at a time where they fit, then the last three by what is left.
        let lows = least
            .iter()
            .zip(&least[1..])
            .zip(&least[2..])
            .zip(&least[3..]);
        let highs = most.iter().zip(&most[1..]).zip(&most[2..]).zip(&most[3..]);
        for (out, ((((&l0, &l1), &l2), &l3), (((&h0, &h1), &h2), &h3))) in
            out.iter_mut().zip(lows.zip(highs))
        {
            *out = [min(min(l0, l1), min(l2, l3)), max(max(h0, h1), max(h2, h3))];
        }
        for c in stride.saturating_sub(3)..stride {
            let lo = least[c..].iter().fold(f32::MAX, |a, &b| min(a, b));
            let hi = most[c..].iter().fold(f32::MIN, |a, &b| max(a, b));
            out[c] = [lo, hi];
        }
    }
}

#[cfg(test)]
mod tests {
    use super::next_toward;

    #[test]
    fn footprint_ranges_bound_each_block() {
        let stride = 7;
        let distance: Vec<f32> = (0..stride * stride)
            .map(|i| ((i * 37 % 23) as f32) - 5.0)
            .collect();
        let mut ranges = vec![[0.0; 2]; stride * stride];
        super::footprint_ranges(&distance, stride, 0, &mut ranges[..3 * stride]);
        super::footprint_ranges(&distance, stride, 3, &mut ranges[3 * stride..]);
        for r in 0..stride {
            for c in 0..stride {
                let block: Vec<f32> = (r..(r + 4).min(stride))
                    .flat_map(|y| (c..(c + 4).min(stride)).map(move |x| (y, x)))
                    .map(|(y, x)| distance[y * stride + x])
                    .collect();
                let lo = block.iter().copied().fold(f32::INFINITY, f32::min);
                let hi = block.iter().copied().fold(f32::NEG_INFINITY, f32::max);
                assert_eq!(
                    ranges[r * stride + c],
                    [lo, hi],
                    "block at row {r}, column {c}"
                );
            }
        }
    }

    #[test]
    fn next_toward_steps_one_float() {
        for c in [-3.0f32, 2.0, 1026.0, 4098.0, 0.0, -0.5] {
            let up = next_toward(c, f32::INFINITY);
            let down = next_toward(c, f32::NEG_INFINITY);
            assert!(up > c && down < c, "{c}: {down} {up}");
            // Nothing lies strictly between: the midpoint rounds to one of the ends.
            let (mu, md) = ((c as f64 + up as f64) / 2.0, (c as f64 + down as f64) / 2.0);
            assert!(mu as f32 == c || mu as f32 == up, "{c}");
            assert!(md as f32 == c || md as f32 == down, "{c}");
        }
    }
}
