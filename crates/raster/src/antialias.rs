//! Anti-aliasing by supersampling (SSAA): the frame is drawn at `k` times the width and the
//! height, each sample exactly as a pixel of that larger image (the same integer edge
//! functions and top-left rule, so coverage stays watertight at every sample), and each pixel
//! of the output is the mean of its `k x k` samples in linear light (a box filter).
//!
//! Every shading mode, `reference` included, sees the same samples, so an accuracy comparison
//! between modes stays meaningful with anti-aliasing on. The resolve sums the samples of a
//! pixel in one fixed order, so the picture is byte-identical for any thread count.
//!
//! Supersampling shades every sample: its cost grows with the pixels (about `k * k` times),
//! not with the edges as multisampling's would.

use std::fmt;
use std::str::FromStr;

use glam::Vec3;

use crate::framebuffer::{Framebuffer, MAX_SIDE};

/// How edges are anti-aliased; names as used by the CLI and scene files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Antialias {
    /// One sample per pixel, at its centre.
    #[default]
    Off,
    /// 4 samples per pixel on a 2 x 2 grid.
    Ssaa4,
    /// 16 samples per pixel on a 4 x 4 grid.
    Ssaa16,
}

impl Antialias {
    /// Every choice, cheapest first.
    pub const ALL: [Antialias; 3] = [Antialias::Off, Antialias::Ssaa4, Antialias::Ssaa16];

    /// Samples along each side of a pixel: 1, 2 or 4.
    #[must_use]
    pub const fn factor(self) -> u32 {
        match self {
            Antialias::Off => 1,
            Antialias::Ssaa4 => 2,
            Antialias::Ssaa16 => 4,
        }
    }

    /// Samples per pixel: 1, 4 or 16.
    #[must_use]
    pub const fn samples(self) -> u32 {
        self.factor() * self.factor()
    }

    /// The name: `off`, `ssaa4`, `ssaa16`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Antialias::Off => "off",
            Antialias::Ssaa4 => "ssaa4",
            Antialias::Ssaa16 => "ssaa16",
        }
    }

    /// The next choice, wrapping (the viewer's key).
    #[must_use]
    pub const fn next(self) -> Antialias {
        match self {
            Antialias::Off => Antialias::Ssaa4,
            Antialias::Ssaa4 => Antialias::Ssaa16,
            Antialias::Ssaa16 => Antialias::Off,
        }
    }

    /// Whether an image of `width` x `height` can be drawn with this choice: the sample image
    /// must itself be a valid framebuffer (sides up to 32768).
    #[must_use]
    pub const fn fits(self, width: u32, height: u32) -> bool {
        let k = self.factor() as u64;
        width as u64 * k <= MAX_SIDE as u64 && height as u64 * k <= MAX_SIDE as u64
    }
}

impl fmt::Display for Antialias {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An unknown anti-aliasing name.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown anti-aliasing '{0}' (expected off, ssaa4 or ssaa16)")]
pub struct UnknownAntialias(pub String);

impl FromStr for Antialias {
    type Err = UnknownAntialias;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Antialias::ALL
            .into_iter()
            .find(|a| a.name() == s)
            .ok_or_else(|| UnknownAntialias(s.to_string()))
    }
}

/// Box-filters `samples` (exactly `k` times `out`'s width and height) into `out`: each pixel's
/// colour is the mean of its `k x k` samples, its depth the nearest of them. Rows are spread
/// over `threads` (0 = all cores); the sums run in one fixed order, so the result does not
/// depend on the thread count.
///
/// # Panics
/// If the sizes do not match (a caller's bug, not an input error).
pub(crate) fn resolve(samples: &Framebuffer, out: &mut Framebuffer, k: u32, threads: usize) {
    assert!(
        samples.width() == out.width() * k && samples.height() == out.height() * k,
        "sample image is not {k} times the output"
    );
    let width = out.width() as usize;
    let k = k as usize;
    let sample_width = width * k;
    let scale = 1.0 / (k * k) as f32;
    let rows_per_task = 16;
    crate::bands::for_each_chunk_pair(
        threads,
        &mut out.color,
        &mut out.depth,
        (rows_per_task * width, 1),
        |first, color, depth| {
            let y0 = first / width;
            for (dy, (color, depth)) in color
                .chunks_mut(width)
                .zip(depth.chunks_mut(width))
                .enumerate()
            {
                let y = y0 + dy;
                for x in 0..width {
                    let mut sum = Vec3::ZERO;
                    let mut nearest = f32::INFINITY;
                    for sy in 0..k {
                        let row = (y * k + sy) * sample_width + x * k;
                        for s in row..row + k {
                            sum += samples.color[s];
                            nearest = nearest.min(samples.depth[s]);
                        }
                    }
                    // Samples are clamped to [0, 1], so their mean is too.
                    color[x] = sum * scale;
                    depth[x] = nearest;
                }
            }
        },
    );
    out.mark_all_written();
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_factors_match_samples() {
        for a in Antialias::ALL {
            assert_eq!(a.name().parse::<Antialias>().unwrap(), a);
            assert_eq!(a.samples(), a.factor() * a.factor());
        }
        assert_eq!(Antialias::Ssaa4.samples(), 4);
        assert_eq!(Antialias::Ssaa16.samples(), 16);
        assert!("msaa4".parse::<Antialias>().is_err());
        assert_eq!(Antialias::Ssaa16.next(), Antialias::Off);
    }

    #[test]
    fn sample_images_over_the_largest_side_do_not_fit() {
        assert!(Antialias::Ssaa16.fits(8192, 8192));
        assert!(!Antialias::Ssaa16.fits(8193, 10));
        assert!(!Antialias::Ssaa4.fits(10, 16385));
        assert!(Antialias::Off.fits(32768, 32768));
    }

    #[test]
    fn resolve_averages_each_block_and_keeps_the_nearest_depth() {
        let mut hi = Framebuffer::new(4, 2).unwrap();
        // Left output pixel: one sample of four lit; right: all four at 0.5.
        hi.color[0] = Vec3::ONE;
        hi.depth[0] = 0.25;
        for s in [2, 3, 6, 7] {
            hi.color[s] = Vec3::splat(0.5);
            hi.depth[s] = 0.75;
        }
        let mut lo = Framebuffer::new(2, 1).unwrap();
        resolve(&hi, &mut lo, 2, 1);
        assert_eq!(lo.pixel(0, 0), Vec3::splat(0.25));
        assert_eq!(lo.pixel(1, 0), Vec3::splat(0.5));
        assert_eq!(lo.depth_at(0, 0), 0.25);
        assert_eq!(lo.depth_at(1, 0), 0.75);
    }
}
