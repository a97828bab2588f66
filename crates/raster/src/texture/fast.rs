//! The `f32` lookup the shading modes use, written once over [`Lanes`]: the same filter as
//! [`Texture::sample_f64`], every step in lanes but the reads of the texels. Each coordinate
//! is folded into the wrap's period before it is scaled to texels, so that texel indices come
//! from comparisons; a row's two texels are one read (see the chain's padding); the mip level
//! comes from the squared scale factor by comparisons with powers of 4 and a series for the
//! fraction, with no square root and no `log2` call. [`Texture::sample`] is the one-lane case,
//! so every lane width gives its bits.

use glam::Vec3;
use phosphor_lighting::{F32x1, Lanes, Vec3s};

use super::{Filter, Texture, Wrap};

/// Largest coordinate magnitude the lookup takes: past it `f32` keeps no fraction of a texel,
/// and below 2^22 the rounding in [`floor`] is exact.
const LIMIT: f32 = 4.0e6;

/// `x` with NaN as 0 and magnitudes capped at [`LIMIT`].
#[inline(always)]
fn finite<L: Lanes>(x: L) -> L {
    let zero = x.splat(0.0);
    x.cmp_eq(x)
        .blend(x, zero)
        .max_c(x.splat(-LIMIT))
        .min_c(x.splat(LIMIT))
}

/// `floor(x)` for `|x| <= 2^22`: adding and taking away `1.5 * 2^23` rounds to the nearest
/// integer, one less where that went up.
#[inline(always)]
pub(crate) fn floor<L: Lanes>(x: L) -> L {
    let magic = x.splat(12_582_912.0);
    let r = (x + magic) - magic;
    r.cmp_le(x).blend(r, r - x.splat(1.0))
}

/// `t` folded into one period of `wrap`: `[0, 1]` for repeat and mirror (mirror reflects
/// every other copy), and `[-1, 2]` for clamp, past which every index clamps alike.
#[inline(always)]
fn fold<L: Lanes>(t: L, wrap: Wrap) -> L {
    let one = t.splat(1.0);
    match wrap {
        Wrap::Repeat => t - floor(t),
        Wrap::Mirror => {
            let half = t * t.splat(0.5);
            let f = (half - floor(half)) * t.splat(2.0);
            f.cmp_le(one).blend(f, t.splat(2.0) - f)
        }
        Wrap::Clamp => t.max_c(t.splat(-1.0)).min_c(t.splat(2.0)),
    }
}

/// `2 / (k ln 2)` for `k = 1, 3, .., 11`: the series of `log2 m = (2 / ln 2) atanh s`.
const ATANH: [f32; 6] = {
    let l = std::f32::consts::LN_2;
    [
        2.0 / l,
        2.0 / (3.0 * l),
        2.0 / (5.0 * l),
        2.0 / (7.0 * l),
        2.0 / (9.0 * l),
        2.0 / (11.0 * l),
    ]
};

/// `a + (b - a) t`.
#[inline(always)]
fn lerp<L: Lanes>(a: L, b: L, t: L) -> L {
    a + (b - a) * t
}

/// Channel `c` of the four texels in the transposed row pairs `t` (top) and `b` (bottom),
/// blended by `fx` along the rows and `fy` between them.
#[inline(always)]
fn blend4<L: Lanes>(t: &[L; 8], b: &[L; 8], c: usize, fx: L, fy: L) -> L {
    lerp(lerp(t[c], t[c + 4], fx), lerp(b[c], b[c + 4], fx), fy)
}

/// The texel nearest folded `t` on an axis of `n` texels, per lane.
#[inline(always)]
fn nearest<L: Lanes>(t: L, n: usize, wrap: Wrap) -> [f32; 8] {
    let (zero, n) = (t.splat(0.0), t.splat(n as f32));
    let i = floor(t * n);
    let i = match wrap {
        Wrap::Repeat => i.cmp_ge(n).blend(zero, i),
        Wrap::Clamp | Wrap::Mirror => i,
    };
    i.max_c(zero).min_c(n - t.splat(1.0)).to_lanes()
}

/// Which level each lane reads, and its size in lanes.
struct Levels<L> {
    index: [usize; 8],
    width: L,
    height: L,
    /// First slot of each lane's level, and slots per row (exact while the chain has at most
    /// [`EXACT_SLOTS`] slots).
    offset: L,
    stride: L,
}

/// Slot positions below this are exact in `f32` and sit in its mantissa once [`MANTISSA`] is
/// added: a chain of at most this many slots (an image up to about 2,500 texels square) has
/// its addresses computed in lanes.
const EXACT_SLOTS: usize = 1 << 23;

/// `2^23`, [`EXACT_SLOTS`] as an `f32`.
const MANTISSA: f32 = 8_388_608.0;

impl Texture {
    /// The levels `lo` (one index per lane, as exact small integers) name.
    #[inline(always)]
    fn levels_at<L: Lanes>(&self, lo: L) -> Levels<L> {
        let levels = &self.chain.levels;
        let at = lo.to_lanes();
        // Neighbouring pixels mostly share a level: one look-up for all.
        if lo.cmp_eq(lo.splat(at[0])).all() {
            let i = (at[0] as usize).min(levels.len() - 1);
            let l = &levels[i];
            return Levels {
                index: [i; 8],
                width: lo.splat(l.width as f32),
                height: lo.splat(l.height as f32),
                offset: lo.splat(l.offset as f32),
                stride: lo.splat(l.stride() as f32),
            };
        }
        let mut index = [0; 8];
        let (mut w, mut h, mut o, mut s) = ([0.0; 8], [0.0; 8], [0.0; 8], [0.0; 8]);
        for k in 0..L::N {
            let i = (at[k] as usize).min(levels.len() - 1);
            let l = &levels[i];
            index[k] = i;
            (w[k], h[k]) = (l.width as f32, l.height as f32);
            (o[k], s[k]) = (l.offset as f32, l.stride() as f32);
        }
        Levels {
            index,
            width: lo.with_lanes(w),
            height: lo.with_lanes(h),
            offset: lo.with_lanes(o),
            stride: lo.with_lanes(s),
        }
    }

    /// The bilinear sample of the levels `at` names, at folded `(u, v)` (`v` from the top).
    #[inline(always)]
    fn bilinear_lanes<L: Lanes>(&self, at: &Levels<L>, u: L, v: L, exact: bool) -> Vec3s<L> {
        let (zero, one) = (u.splat(0.0), u.splat(1.0));
        let half = u.splat(0.5);
        // Along a row: texel `i` and the next, read together; the padding holds the texel
        // each wrap puts past either end, so only the range is clamped.
        let x = u * at.width - half;
        let x0 = floor(x);
        let fx = x - x0;
        let i = x0.max_c(u.splat(-1.0)).min_c(at.width - one);
        // Down the columns: rows `j0` and `j1`, wrapped.
        let y = v * at.height - half;
        let y0 = floor(y);
        let fy = y - y0;
        let last = at.height - one;
        let (j0, j1) = match self.wrap.1 {
            Wrap::Repeat => (
                y0.cmp_ge(zero).blend(y0.min_c(last), last),
                y0.cmp_ge(last).blend(zero, (y0 + one).max_c(zero)),
            ),
            Wrap::Mirror | Wrap::Clamp => (
                y0.max_c(zero).min_c(last),
                (y0 + one).max_c(zero).min_c(last),
            ),
        };
        // Slot `i + 1` of a row holds texel `i` (`i >= -1`).
        let (top, bottom) = if exact {
            // Slots are integers below 2^23: adding 2^23 leaves each in the low mantissa
            // bits, read per lane without a conversion.
            let s = at.offset + i + one + u.splat(MANTISSA);
            let (s0, s1) = (
                (s + j0 * at.stride).to_lanes(),
                (s + j1 * at.stride).to_lanes(),
            );
            let mask = EXACT_SLOTS as u32 - 1;
            let (mut top, mut bottom) = ([[0.0; 8]; 8], [[0.0; 8]; 8]);
            for k in 0..L::N {
                top[k] = self.chain.pair((s0[k].to_bits() & mask) as usize);
                bottom[k] = self.chain.pair((s1[k].to_bits() & mask) as usize);
            }
            (top, bottom)
        } else {
            let (mut top, mut bottom) = ([[0.0; 8]; 8], [[0.0; 8]; 8]);
            let (i, j0, j1) = (i.to_lanes(), j0.to_lanes(), j1.to_lanes());
            for k in 0..L::N {
                let l = &self.chain.levels[at.index[k]];
                let s = l.offset + (i[k] + 1.0) as usize;
                top[k] = self.chain.pair(s + j0[k] as usize * l.stride());
                bottom[k] = self.chain.pair(s + j1[k] as usize * l.stride());
            }
            (top, bottom)
        };
        let (t, b) = (u.columns(&top), u.columns(&bottom));
        Vec3s::new(
            blend4(&t, &b, 0, fx, fy),
            blend4(&t, &b, 1, fx, fy),
            blend4(&t, &b, 2, fx, fy),
        )
    }

    /// The level of detail per lane for derivatives `d` (see [`Texture::level_of`]): its
    /// integer part, as a float, and its fraction, 0 where the chain ends or the texture is
    /// magnified.
    #[inline(always)]
    fn lod_lanes<L: Lanes>(&self, d: [L; 4]) -> (L, L) {
        let like = d[0];
        let (zero, one) = (like.splat(0.0), like.splat(1.0));
        let l0 = &self.chain.levels[0];
        let (w, h) = (like.splat(l0.width as f32), like.splat(l0.height as f32));
        let (ux, vx) = (finite(d[0]) * w, finite(d[1]) * h);
        let (uy, vy) = (finite(d[2]) * w, finite(d[3]) * h);
        let rho2 = (ux * ux + vx * vx).max_c(uy * uy + vy * vy);
        let magnified = rho2.cmp_le(one);
        if magnified.all() {
            // Level 0 everywhere, no blend: what the steps below give these lanes.
            return (zero, zero);
        }
        // `lo` counts the powers 4^k (k >= 1) at most rho^2, up to the last level; `p` is
        // the largest of them (or 1).
        let last = self.chain.levels.len() - 1;
        let (mut lo, mut p, mut q) = (zero, one, 4.0f32);
        for _ in 0..last {
            let reached = rho2.cmp_ge(like.splat(q));
            if !reached.any() {
                break;
            }
            lo = lo + (reached & one);
            p = reached.blend(like.splat(q), p);
            q *= 4.0;
        }
        // rho^2 = p m with m in [1, 4): the fraction is log2(m) / 2. With m = 2^e m', m' in
        // [1, 2): log2 m' = (2 / ln 2) atanh(s), s = (m' - 1) / (m' + 1) <= 1/3, whose series
        // to s^11 is within 1e-6.
        let m = rho2 / p;
        let e = m.cmp_ge(like.splat(2.0));
        let m = e.blend(m * like.splat(0.5), m);
        let s = (m - one) / (m + one);
        let s2 = s * s;
        let mut series = like.splat(ATANH[5]);
        for k in (0..5).rev() {
            series = like.splat(ATANH[k]) + s2 * series;
        }
        let series = s * series;
        let f = ((e & one) + series) * like.splat(0.5);
        let f = f.max_c(zero).min_c(one);
        let ends = lo.cmp_ge(like.splat(last as f32));
        (lo, (magnified | ends).blend(zero, f))
    }

    /// The filtered colour at `(u, v)` with screen derivatives `d` (see
    /// [`Texture::level_of`]), in `f32`: [`Texture::sample_f64`]'s filter, within `f32`
    /// rounding of it (a few units in the last place of the coordinates and the level).
    #[must_use]
    #[inline]
    pub fn sample(&self, u: f32, v: f32, d: [f32; 4]) -> Vec3 {
        let c = self.sample_lanes(F32x1(u), F32x1(v), d.map(F32x1));
        Vec3::new(c.x.0, c.y.0, c.z.0)
    }

    /// [`Texture::sample`] in lanes: a pixel stage's lookup. Lane `i` has the bits of
    /// [`Texture::sample`] at lane `i`'s arguments.
    #[inline(always)]
    #[must_use]
    pub fn sample_lanes<L: Lanes>(&self, u: L, v: L, d: [L; 4]) -> Vec3s<L> {
        self.lookup(u, v, d, self.chain.slots() <= EXACT_SLOTS)
    }

    /// [`Texture::sample_lanes`] with the texel addresses computed in lanes (`exact`, for
    /// chains of at most [`EXACT_SLOTS`] slots) or per lane in integers.
    #[inline(always)]
    fn lookup<L: Lanes>(&self, u: L, v: L, d: [L; 4], exact: bool) -> Vec3s<L> {
        // Rows run from the top, `v` from the bottom.
        let one = u.splat(1.0);
        let (u, v) = (
            fold(finite(u), self.wrap.0),
            fold(one - finite(v), self.wrap.1),
        );
        let zero = u.splat(0.0);
        match self.filter {
            Filter::Nearest => {
                let l0 = self.chain.levels[0];
                let (i, j) = (
                    nearest(u, l0.width, self.wrap.0),
                    nearest(v, l0.height, self.wrap.1),
                );
                let mut texel = [[0.0; 8]; 8];
                for k in 0..L::N {
                    texel[k] = self
                        .chain
                        .pair(l0.offset + j[k] as usize * l0.stride() + i[k] as usize + 1);
                }
                let t = u.columns(&texel);
                Vec3s::new(t[0], t[1], t[2])
            }
            Filter::Bilinear => self.bilinear_lanes(&self.levels_at(zero), u, v, exact),
            Filter::Trilinear => {
                let (lo, f) = self.lod_lanes(d);
                let a = self.bilinear_lanes(&self.levels_at(lo), u, v, exact);
                if f.cmp_eq(zero).all() {
                    return a;
                }
                let b = self.bilinear_lanes(&self.levels_at(lo + one), u, v, exact);
                Vec3s::new(lerp(a.x, b.x, f), lerp(a.y, b.y, f), lerp(a.z, b.z, f))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An `n x n` texture of distinct values, so that any wrong texel shows.
    fn ramp(n: u32) -> Texture {
        let texels = (0..n * n)
            .map(|k| Vec3::new(k as f32, (k % n) as f32, (k / n) as f32) / (n * n) as f32)
            .collect();
        Texture::new(n, n, texels).unwrap()
    }

    #[test]
    fn the_f32_lookup_follows_the_f64_definition() {
        // Coordinates across several copies, both signs, texel centres and seams; levels
        // from magnified to the last one.
        for wrap in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
            for filter in [Filter::Nearest, Filter::Bilinear, Filter::Trilinear] {
                let t = ramp(8).with_wrap(wrap, wrap).with_filter(filter);
                let mut checked = 0;
                for a in -40..=40 {
                    for b in [-17, -3, 0, 5, 22] {
                        let (u, v) = (a as f32 * 0.0613 + 0.004, b as f32 * 0.0917 + 0.011);
                        let s = 0.02 * (1 + (a + 40) % 7) as f32;
                        let d = [s, 0.3 * s, -0.2 * s, s];
                        let got = t.sample(u, v, d);
                        let want = t
                            .sample_f64(f64::from(u), f64::from(v), d.map(f64::from))
                            .as_vec3();
                        // Nearest is a step: one texel either way at an edge is rounding.
                        let tol = if filter == Filter::Nearest { 0.2 } else { 1e-4 };
                        assert!(
                            (got - want).abs().max_element() < tol,
                            "{wrap:?} {filter:?} ({u}, {v}): {got} vs {want}"
                        );
                        if (got - want).abs().max_element() < 1e-5 {
                            checked += 1;
                        }
                    }
                }
                assert!(checked > 380, "{wrap:?} {filter:?}: {checked} of 405 equal");
            }
        }
    }

    #[test]
    fn lanes_give_the_scalar_bits_with_mixed_levels_and_either_addressing() {
        // Each lane its own footprint (magnified to past the last level) and wrap copy, so
        // that lanes read different levels; addresses in lanes and in integers agree.
        for wrap in [Wrap::Repeat, Wrap::Clamp, Wrap::Mirror] {
            for filter in [Filter::Nearest, Filter::Bilinear, Filter::Trilinear] {
                let t = ramp(13).with_wrap(wrap, Wrap::Mirror).with_filter(filter);
                for round in 0..20 {
                    let r = round as f32;
                    let us: [f32; 4] = std::array::from_fn(|k| 0.37 * r - 2.1 + 0.61 * k as f32);
                    let vs: [f32; 4] = std::array::from_fn(|k| 1.3 - 0.29 * r + 0.17 * k as f32);
                    let ds: [f32; 4] =
                        std::array::from_fn(|k| 0.004 * 3f32.powi((k as i32 + round) % 7));
                    let l = |a: [f32; 4]| wide::f32x4::from(a);
                    let d = [
                        l(ds),
                        l(ds.map(|x| 0.5 * x)),
                        l(ds.map(|x| -0.25 * x)),
                        l(ds),
                    ];
                    for exact in [true, false] {
                        let got = t.lookup(l(us), l(vs), d, exact);
                        let (r, g, b) = (got.x.to_lanes(), got.y.to_lanes(), got.z.to_lanes());
                        for k in 0..4 {
                            let want =
                                t.sample(us[k], vs[k], [ds[k], 0.5 * ds[k], -0.25 * ds[k], ds[k]]);
                            assert_eq!(
                                Vec3::new(r[k], g[k], b[k]),
                                want,
                                "{wrap:?} {filter:?} {round} lane {k} exact {exact}"
                            );
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn lanes_give_the_scalar_bits() {
        let t = ramp(16);
        let us = [0.1f32, -0.7, 3.3, 0.5, 0.999, -0.001, 12.25, 0.0];
        let vs = [0.4f32, 0.2, -5.1, 0.5, 0.0, 1.0, 0.75, 0.3];
        let d = [0.01f32, 0.0, 0.0, 0.2];
        for half in [0, 4] {
            let lanes = |a: &[f32]| wide::f32x4::from([a[0], a[1], a[2], a[3]]);
            let (u, v) = (lanes(&us[half..]), lanes(&vs[half..]));
            let got = t.sample_lanes(u, v, d.map(wide::f32x4::splat));
            let (r, g, b) = (got.x.to_lanes(), got.y.to_lanes(), got.z.to_lanes());
            for k in 0..4 {
                let want = t.sample(us[half + k], vs[half + k], d);
                assert_eq!(Vec3::new(r[k], g[k], b[k]), want, "lane {}", half + k);
            }
        }
    }
}
