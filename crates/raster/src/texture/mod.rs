//! Texture maps: an image in linear RGB with its mipmap chain, sampled with wrap modes and a
//! filter, in `f32` for the shading modes, in lanes for a shader's pixel stage, and in `f64`
//! for the reference.
//!
//! Conventions (those of OpenGL 1.x and of OBJ files): `(u, v) = (0, 0)` is the image's
//! bottom-left corner and `(1, 1)` its top-right; texel `(i, j)` (column `i`, row `j` from
//! the top) has its centre at `u = (i + 0.5) / width`, `v = 1 - (j + 0.5) / height`. A glTF
//! file's `v` runs the other way; its loader flips it.
//!
//! The mip level follows the footprint of a pixel in texels, from the screen-space
//! derivatives of `(u, v)` (OpenGL's scale factor):
//! `rho = max(|d(u W, v H)/dx|, |d(u W, v H)/dy|)`, level `log2(rho)`, clamped to the chain.
//! Trilinear filtering blends the bilinear samples of the two levels around it.
//!
//! ```
//! use glam::Vec3;
//! use phosphor_raster::texture::{Filter, Texture, Wrap};
//!
//! // A 2x2 checkerboard, black and white.
//! let texels = vec![Vec3::ZERO, Vec3::ONE, Vec3::ONE, Vec3::ZERO];
//! let t = Texture::new(2, 2, texels)?.with_filter(Filter::Trilinear);
//! assert_eq!(t.levels(), 2);
//! // One texel per pixel: level 0, the texel under the point.
//! assert_eq!(t.sample(0.25, 0.75, [0.5, 0.0, 0.0, 0.5]), Vec3::ZERO);
//! // Two texels per pixel: level 1, the mean.
//! assert_eq!(t.sample(0.25, 0.75, [1.0, 0.0, 0.0, 1.0]), Vec3::splat(0.5));
//! // Wrapping: `u = 1.25` repeats `u = 0.25`.
//! assert_eq!(t.with_wrap(Wrap::Repeat, Wrap::Repeat).sample(1.25, 0.75, [0.5, 0.0, 0.0, 0.5]), Vec3::ZERO);
//! # Ok::<(), phosphor_raster::texture::TextureError>(())
//! ```

use glam::{DVec3, Vec3};

mod chain;
mod fast;

pub(crate) use fast::floor;

use chain::Chain;

/// Largest side of a texture, in texels (the image crate's and most GPUs' limit).
pub const MAX_TEXTURE_SIDE: u32 = 16384;

/// What a lookup does with a coordinate outside `[0, 1]`, per axis.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Wrap {
    /// The image tiles.
    #[default]
    Repeat,
    /// The edge texel extends outwards.
    Clamp,
    /// The image tiles, every other copy mirrored.
    Mirror,
}

/// How texels are combined.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub enum Filter {
    /// The nearest texel of level 0.
    Nearest,
    /// The four nearest texels of level 0, weighted by distance.
    Bilinear,
    /// Bilinear in the two mip levels around the pixel's footprint, blended.
    #[default]
    Trilinear,
}

/// A texture that cannot be made.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum TextureError {
    /// A side is 0 or over [`MAX_TEXTURE_SIDE`].
    Size {
        /// Width asked for.
        width: u32,
        /// Height asked for.
        height: u32,
    },
    /// The texels are not `width * height`.
    Texels {
        /// Texels expected.
        expected: usize,
        /// Texels given.
        got: usize,
    },
}

impl std::fmt::Display for TextureError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            TextureError::Size { width, height } => write!(
                f,
                "texture of {width}x{height}: each side must be 1 to {MAX_TEXTURE_SIDE}"
            ),
            TextureError::Texels { expected, got } => {
                write!(f, "texture needs {expected} texels, got {got}")
            }
        }
    }
}

impl std::error::Error for TextureError {}

/// An RGB image in linear values with its mipmap chain, built once.
#[derive(Debug, Clone)]
pub struct Texture {
    chain: Chain,
    wrap: (Wrap, Wrap),
    filter: Filter,
}

/// Texel index `i` on an axis of `n` texels, wrapped.
#[inline(always)]
fn wrap_index(i: i64, n: usize, wrap: Wrap) -> usize {
    let n = n as i64;
    let k = match wrap {
        Wrap::Repeat => i.rem_euclid(n),
        Wrap::Clamp => i.clamp(0, n - 1),
        Wrap::Mirror => {
            let m = i.rem_euclid(2 * n);
            if m < n { m } else { 2 * n - 1 - m }
        }
    };
    k as usize
}

/// `x` with NaN as 0 and infinities as the largest finite values: a coordinate the filter
/// can take.
#[inline(always)]
fn finite(x: f64) -> f64 {
    if x.is_nan() {
        0.0
    } else {
        x.clamp(-1e15, 1e15)
    }
}

impl Texture {
    /// A texture of `width x height` linear RGB texels, rows from the top, repeating, with
    /// trilinear filtering; its mip levels are built here (each the 2x2 mean of the one
    /// above, down to 1x1). Non-finite or negative values are read as 0.
    ///
    /// # Errors
    /// A side of 0 or over [`MAX_TEXTURE_SIDE`], or a texel count that is not
    /// `width * height`.
    pub fn new(width: u32, height: u32, mut texels: Vec<Vec3>) -> Result<Texture, TextureError> {
        if width == 0 || height == 0 || width > MAX_TEXTURE_SIDE || height > MAX_TEXTURE_SIDE {
            return Err(TextureError::Size { width, height });
        }
        let expected = width as usize * height as usize;
        if texels.len() != expected {
            return Err(TextureError::Texels {
                expected,
                got: texels.len(),
            });
        }
        for t in &mut texels {
            *t = Vec3::select(t.cmpge(Vec3::ZERO) & t.is_finite_mask(), *t, Vec3::ZERO);
        }
        Ok(Texture {
            chain: Chain::build(width as usize, height as usize, &texels, Wrap::Repeat),
            wrap: (Wrap::Repeat, Wrap::Repeat),
            filter: Filter::Trilinear,
        })
    }

    /// A texture from 8-bit sRGB-encoded texels (`channels` of 1 grey, 2 grey and alpha, 3
    /// RGB or 4 RGBA per texel, rows from the top), decoded to linear values; alpha is
    /// ignored.
    ///
    /// # Errors
    /// As [`Texture::new`]; a `channels` outside 1..=4 counts as a wrong texel count.
    pub fn from_srgb8(
        width: u32,
        height: u32,
        channels: usize,
        bytes: &[u8],
    ) -> Result<Texture, TextureError> {
        let table: [f32; 256] = std::array::from_fn(|i| srgb_to_linear(i as f32 / 255.0));
        let expected = width as usize * height as usize;
        if !(1..=4).contains(&channels) || bytes.len() != expected * channels {
            return Err(TextureError::Texels {
                expected,
                got: bytes.len() / channels.clamp(1, 4),
            });
        }
        let texels = bytes
            .chunks_exact(channels)
            .map(|c| {
                let l = |k: usize| table[c[k] as usize];
                if channels >= 3 {
                    Vec3::new(l(0), l(1), l(2))
                } else {
                    Vec3::splat(l(0))
                }
            })
            .collect();
        Texture::new(width, height, texels)
    }

    /// Bytes a texture of `width x height` takes with its chain: for a caller to check
    /// before it decodes an image.
    #[must_use]
    pub fn bytes_for(width: u32, height: u32) -> u64 {
        Chain::bytes_for(width, height)
    }

    /// The same texture with wrap modes `u` and `v`.
    #[must_use]
    pub fn with_wrap(mut self, u: Wrap, v: Wrap) -> Texture {
        self.wrap = (u, v);
        self.chain.pad(u);
        self
    }

    /// The same texture with every texel, in every level, multiplied by `factor` (a
    /// material's colour factor: glTF's `baseColorFactor`, MTL's `Kd` under `map_Kd`); a
    /// non-finite or negative factor component is read as 0. The chain stays the mean of the
    /// level above, since scaling is linear.
    #[must_use]
    pub fn tinted(mut self, factor: Vec3) -> Texture {
        let f = Vec3::select(
            factor.cmpge(Vec3::ZERO) & factor.is_finite_mask(),
            factor,
            Vec3::ZERO,
        );
        self.chain.scale(f);
        self
    }

    /// The same texture with `filter`.
    #[must_use]
    pub fn with_filter(mut self, filter: Filter) -> Texture {
        self.filter = filter;
        self
    }

    /// The filter.
    #[must_use]
    pub fn filter(&self) -> Filter {
        self.filter
    }

    /// Mip levels, level 0 included.
    #[must_use]
    pub fn levels(&self) -> usize {
        self.chain.levels.len()
    }

    /// Width and height of level 0.
    #[must_use]
    pub fn size(&self) -> (u32, u32) {
        (
            self.chain.levels[0].width as u32,
            self.chain.levels[0].height as u32,
        )
    }

    /// Texel `(i, j)` of `level` (column, row from the top), wrapped as the texture wraps.
    #[must_use]
    pub fn texel(&self, level: usize, i: i64, j: i64) -> Vec3 {
        let level = level.min(self.chain.levels.len() - 1);
        let l = &self.chain.levels[level];
        self.chain.at(
            level,
            wrap_index(i, l.width, self.wrap.0),
            wrap_index(j, l.height, self.wrap.1),
        )
    }

    /// The mip level for the screen derivatives `d = [du/dx, dv/dx, du/dy, dv/dy]`:
    /// `log2` of the footprint in level-0 texels, clamped to the chain (0 when magnified).
    #[must_use]
    pub fn level_of(&self, d: [f64; 4]) -> f64 {
        let (w, h) = (
            self.chain.levels[0].width as f64,
            self.chain.levels[0].height as f64,
        );
        let d = d.map(finite);
        let x = (d[0] * w).hypot(d[1] * h);
        let y = (d[2] * w).hypot(d[3] * h);
        let rho = x.max(y);
        if rho > 1.0 {
            rho.log2().min((self.chain.levels.len() - 1) as f64)
        } else {
            0.0
        }
    }

    /// Bilinear sample of one level at `(u, v)`, in `f64`.
    fn bilinear(&self, level: usize, u: f64, v: f64) -> DVec3 {
        let l = &self.chain.levels[level];
        let x = u * l.width as f64 - 0.5;
        let y = (1.0 - v) * l.height as f64 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let (i, j) = (x0 as i64, y0 as i64);
        let t = |di: i64, dj: i64| {
            self.chain
                .at(
                    level,
                    wrap_index(i + di, l.width, self.wrap.0),
                    wrap_index(j + dj, l.height, self.wrap.1),
                )
                .as_dvec3()
        };
        let top = t(0, 0) * (1.0 - fx) + t(1, 0) * fx;
        let bottom = t(0, 1) * (1.0 - fx) + t(1, 1) * fx;
        top * (1.0 - fy) + bottom * fy
    }

    /// The filtered colour at `(u, v)` with screen derivatives `d` (see
    /// [`Texture::level_of`]), in `f64`: the reference's lookup, and the definition the
    /// `f32` and lane forms follow.
    #[must_use]
    pub fn sample_f64(&self, u: f64, v: f64, d: [f64; 4]) -> DVec3 {
        let (u, v) = (finite(u), finite(v));
        match self.filter {
            Filter::Nearest => {
                let l = &self.chain.levels[0];
                let i = (u * l.width as f64).floor() as i64;
                let j = ((1.0 - v) * l.height as f64).floor() as i64;
                self.texel(0, i, j).as_dvec3()
            }
            Filter::Bilinear => self.bilinear(0, u, v),
            Filter::Trilinear => {
                let lod = self.level_of(d);
                let lo = lod.floor();
                let f = lod - lo;
                let lo = lo as usize;
                let a = self.bilinear(lo, u, v);
                if f > 0.0 && lo + 1 < self.chain.levels.len() {
                    a * (1.0 - f) + self.bilinear(lo + 1, u, v) * f
                } else {
                    a
                }
            }
        }
    }
}

/// The sRGB transfer function's inverse (IEC 61966-2-1): an encoded value in `[0, 1]` to
/// linear light.
#[must_use]
pub fn srgb_to_linear(c: f32) -> f32 {
    if c <= 0.04045 {
        c / 12.92
    } else {
        ((c + 0.055) / 1.055).powf(2.4)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn checker(n: u32) -> Texture {
        let texels = (0..n * n)
            .map(|k| {
                if (k % n + k / n).is_multiple_of(2) {
                    Vec3::ONE
                } else {
                    Vec3::ZERO
                }
            })
            .collect();
        Texture::new(n, n, texels).unwrap()
    }

    #[test]
    fn a_chain_goes_down_to_one_texel_and_keeps_the_mean() {
        let t = checker(8);
        assert_eq!(t.levels(), 4);
        for level in 1..4 {
            assert_eq!(t.texel(level, 0, 0), Vec3::splat(0.5), "{level}");
        }
        let odd = Texture::new(5, 3, vec![Vec3::ONE; 15]).unwrap();
        assert_eq!(odd.levels(), 3); // 5x3, 2x1, 1x1
        assert_eq!(odd.texel(2, 0, 0), Vec3::ONE);
    }

    #[test]
    fn wrap_modes_fold_indices() {
        assert_eq!(wrap_index(-1, 4, Wrap::Repeat), 3);
        assert_eq!(wrap_index(5, 4, Wrap::Repeat), 1);
        assert_eq!(wrap_index(-1, 4, Wrap::Clamp), 0);
        assert_eq!(wrap_index(9, 4, Wrap::Clamp), 3);
        assert_eq!(wrap_index(4, 4, Wrap::Mirror), 3);
        assert_eq!(wrap_index(-1, 4, Wrap::Mirror), 0);
        assert_eq!(wrap_index(8, 4, Wrap::Mirror), 0);
    }

    #[test]
    fn bad_sizes_and_values_are_refused_or_zeroed() {
        assert!(Texture::new(0, 4, vec![]).is_err());
        assert!(Texture::new(2, 2, vec![Vec3::ONE; 3]).is_err());
        assert!(Texture::from_srgb8(2, 2, 5, &[0; 20]).is_err());
        let t = Texture::new(1, 1, vec![Vec3::new(f32::NAN, -1.0, f32::INFINITY)]).unwrap();
        assert_eq!(t.texel(0, 0, 0), Vec3::ZERO);
        let c = t.sample(f32::NAN, f32::INFINITY, [f32::NAN; 4]);
        assert!(c.is_finite());
    }

    #[test]
    fn srgb_bytes_decode_to_linear() {
        let t = Texture::from_srgb8(1, 1, 3, &[255, 128, 0]).unwrap();
        let c = t.texel(0, 0, 0);
        assert_eq!(c.x, 1.0);
        assert!((c.y - 0.2158605).abs() < 1e-6, "{c}");
        assert_eq!(c.z, 0.0);
    }
}
