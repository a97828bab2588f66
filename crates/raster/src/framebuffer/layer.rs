//! The pixel layer of a multisampled sample image: one colour per output pixel, kept there
//! while every sample of the pixel shows that colour, and in the samples only once an edge
//! splits the pixel.
//!
//! Multisampling shades a pixel that one triangle owns once, at its centre, and every sample
//! of it gets that colour. Writing the colour `k * k` times, clearing `k * k` colours per pixel
//! and averaging `k * k` equal colours back in the resolve costs memory traffic for nothing:
//! most pixels are not on an edge. So such a pixel keeps one colour in the layer, and its
//! samples' colours are not written, not cleared and not read. A pixel becomes split when a
//! draw shows several triangles in it: its colour is copied to the samples the draw does not
//! write, and the draw's triangles write the others. The resolve averages split pixels and
//! copies the others; the sums of `k * k` equal colours give that colour back exactly (see
//! [`crate::antialias`]), so either way the picture is the same.
//!
//! The samples' depths are kept for every sample as before: coverage and the depth test need
//! them.

use glam::Vec3;

/// [`PixelLayer::split`] of a pixel whose samples hold its colours.
pub(crate) const SPLIT: u8 = 1;
/// [`PixelLayer::split`] of a pixel whose colour is the layer's.
pub(crate) const WHOLE: u8 = 0;

/// The pixel layer of a sample image `k` times as wide and as tall as `width` x `height`
/// pixels.
#[derive(Debug, Clone)]
pub(crate) struct PixelLayer {
    /// Samples per pixel side.
    pub k: usize,
    /// Pixels per row.
    pub width: usize,
    /// Per pixel, row-major: its colour while it is [`WHOLE`].
    pub color: Vec<Vec3>,
    /// Per pixel: [`WHOLE`] or [`SPLIT`].
    pub split: Vec<u8>,
}

impl PixelLayer {
    /// A layer over a sample image whose samples already hold every colour: every pixel
    /// [`SPLIT`], so the image means what it meant without the layer.
    pub fn over_samples(k: usize, width: usize, height: usize) -> PixelLayer {
        PixelLayer {
            k,
            width,
            color: vec![Vec3::ZERO; width * height],
            split: vec![SPLIT; width * height],
        }
    }

    /// All its rows.
    pub fn all(&mut self) -> LayerRows<'_> {
        LayerRows {
            k: self.k,
            width: self.width,
            color: &mut self.color,
            split: &mut self.split,
        }
    }

    /// Its rows in bands of `rows` pixel rows, in order.
    pub fn bands(&mut self, rows: usize) -> impl Iterator<Item = LayerRows<'_>> {
        let (k, width) = (self.k, self.width);
        let n = (rows * width).max(1);
        let colors = self.color.chunks_mut(n);
        colors
            .zip(self.split.chunks_mut(n))
            .map(move |(color, split)| LayerRows {
                k,
                width,
                color,
                split,
            })
    }
}

/// A band's share of a [`PixelLayer`]: its pixel rows, whose samples are the band's sample
/// rows (`k` per pixel row, `k * width` samples each).
pub(crate) struct LayerRows<'a> {
    /// Samples per pixel side.
    pub k: usize,
    /// Pixels per row.
    pub width: usize,
    /// The rows' colours.
    pub color: &'a mut [Vec3],
    /// The rows' [`WHOLE`] / [`SPLIT`] marks.
    pub split: &'a mut [u8],
}

impl LayerRows<'_> {
    /// These rows, borrowed for a shorter while.
    pub fn reborrow<'b>(&'b mut self) -> LayerRows<'b> {
        LayerRows {
            k: self.k,
            width: self.width,
            color: &mut *self.color,
            split: &mut *self.split,
        }
    }

    /// Makes every pixel of these rows [`SPLIT`], copying the colour of each [`WHOLE`] one to
    /// its samples (`samples`: the band's sample rows): for a draw that writes samples one by
    /// one (a mode that shades during traversal, the visible pass).
    pub fn split_all(&mut self, samples: &mut [Vec3]) {
        let (k, width) = (self.k, self.width);
        let stride = width * k;
        for (p, (s, &c)) in self.split.iter_mut().zip(self.color.iter()).enumerate() {
            if *s == WHOLE {
                let base = (p / width) * k * stride + (p % width) * k;
                fill_block(samples, stride, base, k, c);
                *s = SPLIT;
            }
        }
    }

    /// Clears these rows to `bg` (every pixel [`WHOLE`] of colour `bg`), or with `dirty` (per
    /// sample row, the columns written since the last clear) only the pixels over those
    /// columns: the others already are.
    pub fn clear(&mut self, bg: Vec3, dirty: Option<&[(u32, u32)]>) {
        let (k, width) = (self.k, self.width);
        let Some(dirty) = dirty else {
            crate::framebuffer::fill_colors(self.color, bg);
            self.split.fill(WHOLE);
            return;
        };
        let rows = self
            .color
            .chunks_mut(width)
            .zip(self.split.chunks_mut(width));
        for ((color, split), sample_rows) in rows.zip(dirty.chunks(k)) {
            let (lo, hi) = columns_over(sample_rows, k, width);
            if lo < hi {
                crate::framebuffer::fill_colors(&mut color[lo..hi], bg);
                split[lo..hi].fill(WHOLE);
            }
        }
    }
}

/// The pixels `[lo, hi)` (empty when `lo >= hi`) of a row `width` pixels long over the
/// columns `[lo, hi)` of its `k` sample rows.
pub(crate) fn columns_over(sample_rows: &[(u32, u32)], k: usize, width: usize) -> (usize, usize) {
    let (lo, hi) = sample_rows
        .iter()
        .fold((u32::MAX, 0), |(lo, hi), &(l, h)| (lo.min(l), hi.max(h)));
    (lo as usize / k, (hi as usize).div_ceil(k).min(width))
}

/// Writes `c` to the `k x k` samples whose first is `base`, in rows `stride` samples long.
#[inline(always)]
pub(crate) fn fill_block(samples: &mut [Vec3], stride: usize, base: usize, k: usize, c: Vec3) {
    for sy in 0..k {
        let row = base + sy * stride;
        if let Some(row) = samples.get_mut(row..row + k) {
            row.fill(c);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_all_copies_whole_pixels_to_their_samples_and_keeps_split_ones() {
        // 2 x 1 pixels of 2 x 2 samples: pixel 0 whole, pixel 1 split with its own samples.
        let mut layer = PixelLayer::over_samples(2, 2, 1);
        layer.color[0] = Vec3::splat(0.5);
        layer.split[0] = WHOLE;
        let mut samples: Vec<Vec3> = (0..8).map(|i| Vec3::splat(i as f32)).collect();
        layer.all().split_all(&mut samples);
        assert_eq!(layer.split, vec![SPLIT, SPLIT]);
        for s in [0, 1, 4, 5] {
            assert_eq!(samples[s], Vec3::splat(0.5), "sample {s}");
        }
        for s in [2, 3, 6, 7] {
            assert_eq!(samples[s], Vec3::splat(s as f32), "sample {s}");
        }
    }

    #[test]
    fn a_clear_of_the_dirty_columns_covers_every_pixel_over_them() {
        // 4 x 2 pixels of 2 x 2 samples, all split; sample row 1 wrote columns 3..5 (pixels
        // 1 and 2 of pixel row 0), sample row 3 nothing.
        let mut layer = PixelLayer::over_samples(2, 4, 2);
        let bg = Vec3::new(0.1, 0.2, 0.3);
        let dirty = [(u32::MAX, 0), (3, 5), (u32::MAX, 0), (u32::MAX, 0)];
        layer.all().clear(bg, Some(&dirty));
        assert_eq!(
            layer.split,
            vec![SPLIT, WHOLE, WHOLE, SPLIT, SPLIT, SPLIT, SPLIT, SPLIT]
        );
        assert_eq!(layer.color[1], bg);
        assert_eq!(layer.color[2], bg);
        layer.all().clear(bg, None);
        assert!(layer.split.iter().all(|&s| s == WHOLE));
        assert!(layer.color.iter().all(|&c| c == bg));
    }
}
