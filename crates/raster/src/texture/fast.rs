//! The `f32` lookup the shading modes use: the same filter as [`Texture::sample_f64`], with
//! the coordinate folded into the wrap's period before it is scaled to texels, so that the
//! texel indices come from comparisons instead of divisions, and the footprint's level from
//! the squared scale factor (`log2 rho = log2(rho^2) / 2`) instead of a square root. A lane
//! lookup is this lookup per lane, so every lane width gives the scalar's bits.

use glam::Vec3;
use phosphor_lighting::{Lanes, Vec3s};

use super::{Filter, Level, Texture, Wrap};

/// `x` with NaN as 0 and magnitudes capped where `f32` keeps no fraction: a coordinate the
/// fold can take.
#[inline(always)]
fn finite(x: f32) -> f32 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(-8.0e6, 8.0e6)
    }
}

/// `t` folded into one period of `wrap`: `[0, 1]` for repeat and mirror (mirror reflects
/// every other copy), and `[-1, 2]` for clamp, past which every index clamps alike.
#[inline(always)]
fn fold(t: f32, wrap: Wrap) -> f32 {
    match wrap {
        Wrap::Repeat => t - t.floor(),
        Wrap::Mirror => {
            let half = t * 0.5;
            let f = (half - half.floor()) * 2.0;
            if f > 1.0 { 2.0 - f } else { f }
        }
        Wrap::Clamp => t.clamp(-1.0, 2.0),
    }
}

/// For a folded coordinate `t` on an axis of `n` texels: the two texels whose centres
/// bracket it, wrapped, and the weight of the second.
#[inline(always)]
fn bracket(t: f32, n: usize, wrap: Wrap) -> (usize, usize, f32) {
    let x = t * n as f32 - 0.5;
    let x0 = x.floor();
    let f = x - x0;
    let (i, last) = (x0 as i64, n as i64 - 1);
    let (a, b) = match wrap {
        // A folded coordinate puts `i` in `-1..=last`: only the seam wraps.
        Wrap::Repeat => (
            if i < 0 { last } else { i.min(last) },
            if i >= last { 0 } else { (i + 1).max(0) },
        ),
        // Mirror's seams repeat the edge texel, as clamp does.
        Wrap::Mirror | Wrap::Clamp => (i.clamp(0, last), (i + 1).clamp(0, last)),
    };
    (a as usize, b as usize, f)
}

/// The texel nearest the folded coordinate `t` on an axis of `n` texels.
#[inline(always)]
fn nearest(t: f32, n: usize, wrap: Wrap) -> usize {
    let (i, last) = ((t * n as f32).floor() as i64, n as i64 - 1);
    let k = match wrap {
        Wrap::Repeat if i > last => 0,
        _ => i.clamp(0, last),
    };
    k as usize
}

impl Level {
    #[inline(always)]
    fn bilinear(&self, u: f32, v: f32, wrap: (Wrap, Wrap)) -> Vec3 {
        let (i0, i1, fx) = bracket(u, self.width, wrap.0);
        let (j0, j1, fy) = bracket(v, self.height, wrap.1);
        let top = self.at(i0, j0).lerp(self.at(i1, j0), fx);
        let bottom = self.at(i0, j1).lerp(self.at(i1, j1), fx);
        top.lerp(bottom, fy)
    }
}

impl Texture {
    /// The filtered colour at `(u, v)` with screen derivatives `d` (see
    /// [`Texture::level_of`]), in `f32`: [`Texture::sample_f64`]'s filter, within `f32`
    /// rounding of it (a few units in the last place of the coordinates and the level).
    #[must_use]
    #[inline]
    pub fn sample(&self, u: f32, v: f32, d: [f32; 4]) -> Vec3 {
        // Rows run from the top, `v` from the bottom.
        let (u, v) = (
            fold(finite(u), self.wrap.0),
            fold(1.0 - finite(v), self.wrap.1),
        );
        let base = &self.levels[0];
        match self.filter {
            Filter::Nearest => base.at(
                nearest(u, base.width, self.wrap.0),
                nearest(v, base.height, self.wrap.1),
            ),
            Filter::Bilinear => base.bilinear(u, v, self.wrap),
            Filter::Trilinear => {
                let lod = self.level_of_f32(d);
                let lo = lod.floor();
                let f = lod - lo;
                let lo = lo as usize;
                let a = self.levels[lo].bilinear(u, v, self.wrap);
                match self.levels.get(lo + 1) {
                    Some(next) if f > 0.0 => a.lerp(next.bilinear(u, v, self.wrap), f),
                    _ => a,
                }
            }
        }
    }

    /// [`Texture::level_of`] in `f32`.
    #[inline(always)]
    fn level_of_f32(&self, d: [f32; 4]) -> f32 {
        let (w, h) = (self.levels[0].width as f32, self.levels[0].height as f32);
        let d = d.map(finite);
        let (ux, vx, uy, vy) = (d[0] * w, d[1] * h, d[2] * w, d[3] * h);
        let rho2 = (ux * ux + vx * vx).max(uy * uy + vy * vy);
        if rho2 > 1.0 {
            (0.5 * rho2.log2()).min((self.levels.len() - 1) as f32)
        } else {
            0.0
        }
    }

    /// [`Texture::sample`] per lane: a pixel stage's lookup.
    #[inline]
    #[must_use]
    pub fn sample_lanes<L: Lanes>(&self, u: L, v: L, d: [L; 4]) -> Vec3s<L> {
        let like = u;
        let (u, v) = (u.to_lanes(), v.to_lanes());
        let d = d.map(Lanes::to_lanes);
        let (mut r, mut g, mut b) = ([0.0; 8], [0.0; 8], [0.0; 8]);
        for k in 0..L::N {
            let c = self.sample(u[k], v[k], [d[0][k], d[1][k], d[2][k], d[3][k]]);
            (r[k], g[k], b[k]) = (c.x, c.y, c.z);
        }
        Vec3s::new(like.with_lanes(r), like.with_lanes(g), like.with_lanes(b))
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
