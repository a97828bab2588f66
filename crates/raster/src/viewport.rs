//! The image a draw is projected onto and how it is split into bands: what every stage
//! needs to know of the target, in one place.

use glam::Vec4;

use phosphor_math::fixed::{MAX_FIXED_COORD, SUBPIXEL_ONE};

#[cfg(test)]
use crate::clip::inside_clip_volume;
use crate::clip::{ClipVertex, W_MIN, guard_band};
#[cfg(test)]
use crate::setup::project;
use crate::setup::{ScreenPos, ScreenVertex, attr_scale, to_screen};

/// Pixel rows per band. A multisampled image's bands hold this many rows of pixels, `block`
/// sample rows each ([`band_rows`]): bands of the same pixel rows keep the same split of the
/// work over threads, and a triangle is set up in no more bands than without multisampling.
pub const BAND_ROWS: u32 = 16;

/// Scan lines per band of an image with `block x block` samples per pixel (1: none).
#[must_use]
pub const fn band_rows(block: u32) -> u32 {
    BAND_ROWS * block
}

/// Vertices per call of [`Viewport::screen_pos_lanes`].
pub(crate) const LANES: usize = 8;

/// `phosphor_math::fixed::to_fixed` of one lane, with no branch: the fixed-point value (an
/// `i32`, as `ScreenPos` keeps it) and whether `v` is in range. The rounding is the same:
/// half away from zero, from the truncation and the exact remainder.
#[inline(always)]
fn fixed_lane(v: f32) -> (i32, bool) {
    let ok = v.is_finite() & (v.abs() <= MAX_FIXED_COORD);
    let d = f64::from(v) * SUBPIXEL_ONE as f64;
    let t = d.trunc();
    let rest = d - t;
    let up = f64::from(u8::from(rest >= 0.5)) - f64::from(u8::from(rest <= -0.5));
    // |t + up| <= 2^28 when `ok` (otherwise the value is dropped): added to 1.5 * 2^52 it
    // is exact, and the low 32 bits of the sum's mantissa are it in two's complement. A
    // conversion by `as` would test for overflow lane by lane.
    const MAGIC: f64 = 6_755_399_441_055_744.0;
    (((t + up) + MAGIC).to_bits() as u32 as i32, ok)
}

/// The image a draw is projected onto.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Viewport {
    /// Image width in pixels (or samples).
    pub width: u32,
    /// Image height.
    pub height: u32,
    /// The guard band's extent in clip space ([`guard_band`]).
    pub guard: (f32, f32),
    /// Whether attributes are divided by `w` (perspective-correct interpolation).
    pub perspective: bool,
    /// Scan lines per band ([`band_rows`]).
    pub band_rows: u32,
}

impl Viewport {
    /// A `width` x `height` image with `block x block` samples per pixel (1: one).
    pub fn new(width: u32, height: u32, perspective: bool, block: u32) -> Viewport {
        Viewport {
            width,
            height,
            guard: guard_band(width, height),
            perspective,
            band_rows: band_rows(block),
        }
    }

    /// Whether `pos` is finite and inside every clip plane (a triangle of three such
    /// vertices is not changed by clipping).
    #[cfg(test)]
    fn inside(&self, pos: Vec4) -> bool {
        pos.is_finite() && inside_clip_volume(pos, self.guard)
    }

    /// Divide and viewport of `cv` with `n` attributes, with no clip-volume test (for the
    /// corners clipping made, which lie on its planes).
    #[inline]
    pub fn project(&self, cv: &ClipVertex, n: usize) -> Option<ScreenVertex> {
        to_screen(cv, self.width, self.height, n, self.perspective)
    }

    /// The screen position of a vertex inside the clip volume and the scale of its
    /// attributes (`1/w` when perspective-correct, else 1): the bits of [`to_screen`]. The
    /// reference that [`Viewport::screen_pos_lanes`] is tested against.
    #[cfg(test)]
    pub(crate) fn screen_pos(&self, pos: Vec4) -> Option<(ScreenPos, f32)> {
        if !self.inside(pos) {
            return None;
        }
        let (p, rhw) = project(pos, self.width, self.height, self.perspective)?;
        Some((p, attr_scale(rhw, self.perspective)))
    }

    /// [`Viewport::screen_pos`] of up to [`LANES`] vertices `pos` at once, bit for bit: each
    /// step is one IEEE operation per lane, with no branch, so that a caller compiled for
    /// AVX2 runs it in vectors (per vertex the scalar path takes a dozen branches). Writes
    /// `out[j]` and `scale[j]` only for the vertices that have a screen position, and returns
    /// whether one does.
    #[inline(always)]
    pub(crate) fn screen_pos_lanes(
        &self,
        pos: &[Vec4],
        out: &mut [ScreenPos],
        scale: &mut [f32; LANES],
    ) -> bool {
        let len = pos.len().min(LANES).min(out.len());
        if len == 0 {
            return false;
        }
        // Lanes past `len` repeat the last vertex; their results are dropped. A whole group
        // is read in place, without a bound per lane.
        let padded: [Vec4; LANES];
        let all = match pos.first_chunk::<LANES>() {
            Some(all) => all,
            None => {
                padded = std::array::from_fn(|j| pos[j.min(len - 1)]);
                &padded
            }
        };
        let lane = |f: fn(&Vec4) -> f32| -> [f32; LANES] { std::array::from_fn(|j| f(&all[j])) };
        let (x, y, z, w) = (lane(|p| p.x), lane(|p| p.y), lane(|p| p.z), lane(|p| p.w));
        let (gx, gy) = self.guard;
        let (width, height) = (f64::from(self.width), f64::from(self.height));
        let mut ok = [false; LANES];
        let (mut fx, mut fy) = ([0i32; LANES], [0i32; LANES]);
        let (mut depth, mut rhw) = ([0.0f64; LANES], [0.0f64; LANES]);
        for j in 0..LANES {
            let (x, y, z, w) = (x[j], y[j], z[j], w[j]);
            // `inside_clip_volume`: each plane's dot product has at most two terms that are
            // not zero, so its one rounding is the same as here.
            let finite = x.is_finite() & y.is_finite() & z.is_finite() & w.is_finite();
            let inside = (z + w >= 0.0)
                & (w - W_MIN >= 0.0)
                & (gx * w - x >= 0.0)
                & (gx * w + x >= 0.0)
                & (gy * w - y >= 0.0)
                & (gy * w + y >= 0.0);
            // `project`.
            let wd = f64::from(w);
            let inv = 1.0 / wd;
            let sx = (f64::from(x) * inv + 1.0) * 0.5 * width;
            let sy = (1.0 - f64::from(y) * inv) * 0.5 * height;
            let d = (f64::from(z) * inv) * 0.5 + 0.5;
            let (px, x_ok) = fixed_lane(sx as f32);
            let (py, y_ok) = fixed_lane(sy as f32);
            ok[j] = finite & inside & (wd > 0.0) & (wd < f64::INFINITY) & x_ok & y_ok;
            ok[j] &= d.is_finite();
            (fx[j], fy[j], depth[j]) = (px, py, d);
            rhw[j] = inv;
        }
        let mut any = false;
        for j in 0..len {
            if ok[j] {
                out[j] = ScreenPos {
                    fx: fx[j],
                    fy: fy[j],
                    depth: depth[j],
                    inv_w: if self.perspective { rhw[j] } else { 1.0 },
                };
                scale[j] = attr_scale(rhw[j], self.perspective);
                any = true;
            }
        }
        any
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Every vertex's lane result equals the one-vertex path's, bit for bit: on and near each
    /// clip plane, at the edges of the fixed-point range, at rounding ties, and for values
    /// that are not finite.
    #[test]
    fn screen_positions_in_lanes_match_one_vertex_at_a_time() {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let special = [
            0.0,
            -0.0,
            1.0,
            -1.0,
            W_MIN,
            0.5,
            1e-30,
            3e38,
            f32::INFINITY,
            f32::NEG_INFINITY,
            f32::NAN,
            f32::MAX,
            f32::MIN_POSITIVE,
        ];
        let value = |next: &mut dyn FnMut() -> u64, w: f32| -> f32 {
            let r = next();
            match r % 8 {
                0 => special[(r >> 8) as usize % special.len()],
                // On a plane of the guard band or the near plane.
                1 => w * [1.0, -1.0, 1.0001, 0.9999][(r >> 8) as usize % 4],
                // Pixel positions that round at a half sub-pixel.
                2 => ((r >> 8) % 4096) as f32 / 2048.0 - 1.0 + 1.0 / 1024.0,
                _ => (((r >> 8) % 2_000_000) as f32 / 1_000_000.0 - 1.0) * w * 1.2,
            }
        };
        let mut checked = 0;
        for (width, height, perspective) in [(1920, 1080, true), (7, 3, false), (1, 1, true)] {
            let view = Viewport::new(width, height, perspective, 1);
            for _ in 0..20_000 {
                let pos: Vec<Vec4> = (0..1 + next() as usize % LANES)
                    .map(|_| {
                        let w = if next() % 6 == 0 {
                            value(&mut next, 1.0)
                        } else {
                            (next() % 1000) as f32 / 100.0 + 0.01
                        };
                        let w = if next() % 50 == 0 { w * 1e6 } else { w };
                        let (x, y, z) = (
                            value(&mut next, w),
                            value(&mut next, w),
                            value(&mut next, w),
                        );
                        Vec4::new(x, y, z, w)
                    })
                    .collect();
                let mut out = vec![ScreenPos::NONE; pos.len()];
                let mut scale = [f32::NAN; LANES];
                let any = view.screen_pos_lanes(&pos, &mut out, &mut scale);
                let mut some = false;
                for (j, p) in pos.iter().enumerate() {
                    let want = view.screen_pos(*p);
                    some |= want.is_some();
                    match want {
                        Some((sp, s)) => {
                            assert_eq!(out[j], sp, "{p}");
                            assert_eq!(scale[j].to_bits(), s.to_bits(), "{p}");
                            checked += 1;
                        }
                        None => assert!(out[j].is_none(), "{p}: {:?}", out[j]),
                    }
                }
                assert_eq!(any, some);
            }
        }
        // Most vertices land on screen (a test of mostly refusals would prove little).
        assert!(checked > 100_000, "{checked}");
    }
}
