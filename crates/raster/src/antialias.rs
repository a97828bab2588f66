//! Anti-aliasing by supersampling (SSAA) and multisampling (MSAA). Either way the frame is
//! drawn into a sample image `k` times the width and the height, each sample exactly as a
//! pixel of that larger image (the same integer edge functions and top-left rule, so coverage
//! and depth stay watertight at every sample), and each pixel of the output is the mean of its
//! `k x k` samples in linear light (a box filter).
//!
//! - **Supersampling** shades every sample: its cost grows with the pixels (about `k * k`
//!   times).
//! - **Multisampling** shades once per pixel and triangle: in the per-pixel modes (`phong`,
//!   `fast-phong`) the samples of a pixel that one triangle owns are shaded together at their
//!   centroid (the pixel centre when it owns them all, always a point inside the triangle, so
//!   attributes are never extrapolated) and the colour is written to each of them. Only pixels
//!   on an edge are shaded more than once, so the shading cost grows with the edges, not with
//!   the samples; coverage and depth still cost `k * k` times. A pixel whose samples all show
//!   one colour keeps it once, in a layer of one colour per pixel beside the samples: its
//!   samples' colours are neither written, cleared nor averaged, and the resolve copies it. Modes that shade during
//!   traversal (`flat`, `gouraud`, `reference`, the incremental interpolation) shade each
//!   sample: for flat and Gouraud a sample's colour is one plane step, as cheap as its
//!   coverage test, and `reference` is the per-sample truth the others are measured against.
//!
//! Every shading mode, `reference` included, sees the same samples, so an accuracy comparison
//! between modes stays meaningful with anti-aliasing on. The resolve sums the samples of a
//! pixel in one fixed order, so the picture is byte-identical for any thread count.

use std::fmt;
use std::str::FromStr;

use glam::Vec3;

use crate::framebuffer::layer::{WHOLE, columns_over};
use crate::framebuffer::{CLEAN_ROW, Framebuffer, MAX_SIDE, fill_rows, same_color};

/// How edges are anti-aliased; names as used by the CLI and scene files.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Default)]
pub enum Antialias {
    /// One sample per pixel, at its centre.
    #[default]
    Off,
    /// 4 samples per pixel on a 2 x 2 grid, shaded once per pixel and triangle.
    Msaa4,
    /// 4 samples per pixel on a 2 x 2 grid, each shaded.
    Ssaa4,
    /// 16 samples per pixel on a 4 x 4 grid, shaded once per pixel and triangle.
    Msaa16,
    /// 16 samples per pixel on a 4 x 4 grid, each shaded.
    Ssaa16,
}

impl Antialias {
    /// Every choice, cheapest first.
    pub const ALL: [Antialias; 5] = [
        Antialias::Off,
        Antialias::Msaa4,
        Antialias::Ssaa4,
        Antialias::Msaa16,
        Antialias::Ssaa16,
    ];

    /// Samples along each side of a pixel: 1, 2 or 4.
    #[must_use]
    pub const fn factor(self) -> u32 {
        match self {
            Antialias::Off => 1,
            Antialias::Msaa4 | Antialias::Ssaa4 => 2,
            Antialias::Msaa16 | Antialias::Ssaa16 => 4,
        }
    }

    /// Samples per pixel: 1, 4 or 16.
    #[must_use]
    pub const fn samples(self) -> u32 {
        self.factor() * self.factor()
    }

    /// Whether the per-pixel modes shade once per pixel and triangle instead of once per
    /// sample (multisampling).
    #[must_use]
    pub const fn multisample(self) -> bool {
        matches!(self, Antialias::Msaa4 | Antialias::Msaa16)
    }

    /// The name: `off`, `msaa4`, `ssaa4`, `msaa16`, `ssaa16`.
    #[must_use]
    pub const fn name(self) -> &'static str {
        match self {
            Antialias::Off => "off",
            Antialias::Msaa4 => "msaa4",
            Antialias::Ssaa4 => "ssaa4",
            Antialias::Msaa16 => "msaa16",
            Antialias::Ssaa16 => "ssaa16",
        }
    }

    /// The next choice, wrapping, in the order of [`Antialias::ALL`] (the viewer's key).
    #[must_use]
    pub const fn next(self) -> Antialias {
        match self {
            Antialias::Off => Antialias::Msaa4,
            Antialias::Msaa4 => Antialias::Ssaa4,
            Antialias::Ssaa4 => Antialias::Msaa16,
            Antialias::Msaa16 => Antialias::Ssaa16,
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
#[error("unknown anti-aliasing '{0}' (expected off, msaa4, ssaa4, msaa16 or ssaa16)")]
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
/// Only the pixels over samples drawn this frame are filtered: every other sample holds the
/// clear colour and the far depth (the sample image's dirty columns say which), so such a
/// pixel is the clear colour itself, and `out` keeps the same record of what it drew.
///
/// # Panics
/// If the sizes do not match (a caller's bug, not an input error).
pub(crate) fn resolve(samples: &Framebuffer, out: &mut Framebuffer, k: u32, threads: usize) {
    let rule = ResolveRule::new(samples, out, k);
    let width = rule.width;
    let drawn: Vec<(u32, u32)> = samples
        .dirty
        .chunks(rule.k)
        .map(|r| rule.drawn(r))
        .collect();
    // Per output row: the columns that may not hold `clean` now.
    let stale: Vec<(u32, u32)> = out.dirty.iter().map(|&d| rule.stale(d)).collect();
    let rows_per_task = 16;
    let samples_of = SampleRows::of(samples, rule.k);
    crate::parallel::for_each_chunk_pair(
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
                rule.row((drawn[y], stale[y]), samples_of.row(y), (color, depth));
            }
        },
    );
    rule.finish(out);
    out.dirty = drawn;
}

/// The resolve of one frame, row by row: what [`resolve`] does over the whole image, and a
/// band's draw over its own rows while their samples are still in cache (then the frame's
/// end has nothing left to resolve). Either way each output row gets the same values.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ResolveRule {
    /// Samples per pixel side.
    pub k: usize,
    /// Output pixels per row.
    pub width: usize,
    /// The clear colour every undrawn sample holds, if known.
    clean: Option<Vec3>,
    /// Whether the output's dirty columns say where it may not hold `clean` (else every
    /// column may not).
    stale_known: bool,
}

impl ResolveRule {
    /// The resolve of `samples` (exactly `k` times `out`'s width and height) into `out`,
    /// given what `out` holds now.
    ///
    /// # Panics
    /// If the sizes do not match (a caller's bug, not an input error).
    pub fn new(samples: &Framebuffer, out: &Framebuffer, k: u32) -> ResolveRule {
        assert!(
            samples.width() == out.width() * k && samples.height() == out.height() * k,
            "sample image is not {k} times the output"
        );
        let clean = samples.clean;
        ResolveRule {
            k: k as usize,
            width: out.width() as usize,
            clean,
            stale_known: matches!(clean, Some(bg) if same_color(out.clean, bg))
                && out.pending_clear.is_none(),
        }
    }

    /// The output columns over drawn samples of one output row, from its `k` sample rows'
    /// dirty columns (all of them when no clear is known).
    pub fn drawn(&self, sample_rows: &[(u32, u32)]) -> (u32, u32) {
        if self.clean.is_none() {
            return (0, self.width as u32);
        }
        match columns_over(sample_rows, self.k, self.width) {
            (lo, hi) if lo < hi => (lo as u32, hi as u32),
            _ => CLEAN_ROW,
        }
    }

    /// The columns of an output row that may not hold the clear colour now, from the row's
    /// dirty columns in the output.
    pub fn stale(&self, dirty: (u32, u32)) -> (u32, u32) {
        if self.stale_known {
            dirty
        } else {
            (0, self.width as u32)
        }
    }

    /// Resolves one output row (`color`, `depth`, `width` long) from its samples: the columns
    /// `drawn` filtered, and those of `stale` outside them cleared.
    pub fn row(
        &self,
        (drawn, stale): ((u32, u32), (u32, u32)),
        samples: RowSamples,
        (color, depth): (&mut [Vec3], &mut [f32]),
    ) {
        let width = self.width;
        let (lo, hi) = drawn;
        let (lo, hi) = (lo as usize, (hi as usize).max(lo as usize));
        if let Some(bg) = self.clean {
            let (slo, shi) = (stale.0 as usize, (stale.1 as usize).min(width));
            for (a, b) in [(slo, shi.min(lo)), (slo.max(hi), shi)] {
                if a < b {
                    fill_rows(&mut color[a..b], &mut depth[a..b], bg);
                }
            }
        }
        if lo < hi {
            let (color, depth) = (&mut color[lo..hi], &mut depth[lo..hi]);
            match self.k {
                2 => resolve_row::<2>(samples, width, lo, color, depth),
                4 => resolve_row::<4>(samples, width, lo, color, depth),
                _ => resolve_row::<1>(samples, width, lo, color, depth),
            }
        }
    }

    /// What the output records once every row is resolved (its dirty columns are each
    /// row's `drawn`, set by the caller).
    pub fn finish(&self, out: &mut Framebuffer) {
        out.clean = self.clean;
        out.pending_clear = None;
        out.overlay = None;
    }
}

/// A sample image's rows as the resolve reads them: colours, depths, and the pixel layer
/// (colours and split marks) when it has one of `k x k` samples.
pub(crate) struct SampleRows<'a> {
    k: usize,
    /// Output pixels per row.
    width: usize,
    color: &'a [Vec3],
    depth: &'a [f32],
    layer: Option<(&'a [Vec3], &'a [u8])>,
}

impl<'a> SampleRows<'a> {
    /// All of `samples`' rows.
    fn of(samples: &'a Framebuffer, k: usize) -> SampleRows<'a> {
        let layer = samples.layer.as_ref().filter(|l| l.k == k);
        SampleRows {
            k,
            width: samples.width() as usize / k,
            color: &samples.color,
            depth: &samples.depth,
            layer: layer.map(|l| (&l.color[..], &l.split[..])),
        }
    }

    /// A band's rows: its sample rows and its pixel layer's rows (`k` sample rows of
    /// `width * k` per pixel row).
    pub fn band(
        k: usize,
        width: usize,
        (color, depth): (&'a [Vec3], &'a [f32]),
        layer: Option<(&'a [Vec3], &'a [u8])>,
    ) -> SampleRows<'a> {
        SampleRows {
            k,
            width,
            color,
            depth,
            layer,
        }
    }

    /// The samples of output row `y` (counted from the first of these rows).
    pub fn row(&self, y: usize) -> RowSamples<'a> {
        let (k, width) = (self.k, self.width);
        let n = k * width * k;
        let at = (y * n).min(self.color.len())..((y + 1) * n).min(self.color.len());
        let dat = (y * n).min(self.depth.len())..((y + 1) * n).min(self.depth.len());
        let layer = self.layer.and_then(|(c, s)| {
            let at = y * width..(y + 1) * width;
            Some((c.get(at.clone())?, s.get(at)?))
        });
        (&self.color[at], &self.depth[dat], layer)
    }
}

/// One output row's samples: `K` rows of colours and of depths (`width * K` samples each),
/// and the row of the image's pixel layer (colours, split marks), if it has one.
pub(crate) type RowSamples<'a> = (&'a [Vec3], &'a [f32], Option<(&'a [Vec3], &'a [u8])>);

/// Filters output pixels `lo..lo + color.len()` of one row from its `K` rows of samples. The
/// sums are pairwise (the same tree for every pixel), so that `K x K` equal samples give that
/// value back exactly: a pixel the layer holds whole takes the layer's colour, which is what
/// its samples would sum to.
#[inline(always)]
fn resolve_row<const K: usize>(
    (rows, depths, layer): RowSamples,
    width: usize,
    lo: usize,
    color: &mut [Vec3],
    depth: &mut [f32],
) {
    let stride = width * K;
    let n = color.len();
    nearest_rows::<K>(depths, stride, lo, depth);
    let layer =
        layer.and_then(|(colors, split)| Some((colors.get(lo..lo + n)?, split.get(lo..lo + n)?)));
    let Some((colors, split)) = layer else {
        for (i, c) in color.iter_mut().enumerate() {
            *c = mean_of::<K>(rows, stride, (lo + i) * K);
        }
        return;
    };
    // Every colour the layer holds, then the split pixels' means over them.
    color.copy_from_slice(colors);
    for (i, (c, _)) in color
        .iter_mut()
        .zip(split)
        .enumerate()
        .filter(|(_, (_, s))| **s != WHOLE)
    {
        *c = mean_of::<K>(rows, stride, (lo + i) * K);
    }
}

/// The nearest depth of each of the `K x K` samples of output pixels `lo..lo + depth.len()`,
/// into `depth`, from the `K` rows of depths `stride` long: row by row over whole slices, so
/// that the minimum runs in vector lanes; each pixel's samples are taken rows first, then
/// columns.
#[inline(always)]
fn nearest_rows<const K: usize>(depths: &[f32], stride: usize, lo: usize, depth: &mut [f32]) {
    depth.fill(f32::INFINITY);
    for sy in 0..K {
        let start = sy * stride + lo * K;
        let Some(row) = depths.get(start..start + depth.len() * K) else {
            return;
        };
        for (d, samples) in depth.iter_mut().zip(row.chunks_exact(K)) {
            for &s in samples {
                // The minimum as a select: one vector minimum per four pixels, where
                // `f32::min`'s NaN rule added a NaN test and a blend to each. A NaN sample
                // is skipped either way.
                *d = if s < *d { s } else { *d };
            }
        }
    }
}

/// The mean colour of the `K x K` samples whose first is `x`, in rows `stride` long: each
/// row's `K` samples summed pairwise, then the row sums pairwise (the tree of a pairwise sum
/// over the samples in row order), so that equal samples give their value back exactly.
#[inline(always)]
fn mean_of<const K: usize>(rows: &[Vec3], stride: usize, x: usize) -> Vec3 {
    let mut row_sums = [Vec3::ZERO; K];
    for (sy, sum) in row_sums.iter_mut().enumerate() {
        let at = sy * stride + x;
        if let Some(samples) = rows.get(at..at + K) {
            *sum = pairwise(std::array::from_fn::<Vec3, K, _>(|sx| samples[sx]));
        }
    }
    // Samples are clamped to [0, 1] (or [0, HDR_MAX]), so their mean is too, and the sum of
    // 16 of them is finite.
    pairwise(row_sums) * (1.0 / (K * K) as f32)
}

/// The sum of `v` as a pairwise tree: neighbours first, then neighbouring sums (`M` a power
/// of two).
#[inline(always)]
fn pairwise<const M: usize>(mut v: [Vec3; M]) -> Vec3 {
    let mut n = M;
    while n > 1 {
        n /= 2;
        for j in 0..n {
            v[j] = v[2 * j] + v[2 * j + 1];
        }
    }
    v[0]
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
        assert_eq!(Antialias::Msaa4.samples(), 4);
        assert!(Antialias::Msaa16.multisample() && !Antialias::Ssaa16.multisample());
        assert!("msaa8".parse::<Antialias>().is_err());
        // The viewer's key visits every choice once.
        let mut a = Antialias::Off;
        for want in Antialias::ALL.into_iter().cycle().skip(1).take(5) {
            a = a.next();
            assert_eq!(a, want);
        }
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
        // Written here, not drawn: no clear colour is known to hold anywhere.
        hi.clean = None;
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

    #[test]
    fn resolve_fills_undrawn_pixels_with_the_clear_and_keeps_the_record() {
        let bg = Vec3::new(0.1, 0.2, 0.3);
        let mut hi = Framebuffer::new(8, 4).unwrap();
        hi.clear(bg);
        // A draw wrote samples (2..4, 0..2), and said so in the dirty columns.
        for y in 0..2 {
            for x in 2..4 {
                hi.color[y * 8 + x] = Vec3::ONE;
                hi.depth[y * 8 + x] = 0.5;
            }
            hi.dirty[y] = (2, 4);
        }
        let mut lo = Framebuffer::new(4, 2).unwrap();
        lo.color.fill(Vec3::splat(0.9));
        resolve(&hi, &mut lo, 2, 1);
        assert_eq!(lo.pixel(1, 0), Vec3::ONE);
        assert_eq!(lo.depth_at(1, 0), 0.5);
        // Every other pixel is the clear colour exactly, though the output held another.
        for (x, y) in [(0, 0), (2, 0), (3, 0), (0, 1), (1, 1), (3, 1)] {
            assert_eq!(lo.pixel(x, y), bg, "({x}, {y})");
            assert_eq!(lo.depth_at(x, y), 1.0, "({x}, {y})");
        }
        assert_eq!(lo.dirty, vec![(1, 2), CLEAN_ROW]);
        assert_eq!(lo.clean, Some(bg));
    }
}
