//! The framebuffer: linear f32 RGB clamped to `[0, 1]` (or, for high-dynamic-range output, to
//! `[0, HDR_MAX]`) plus a depth buffer, its coverage, and its encodings.

use glam::Vec3;

pub(crate) mod layer;
pub(crate) mod readout;
pub use readout::{Shown, WindowBuffer};

use layer::PixelLayer;

/// Errors of the raster crate; each names the value at fault.
#[derive(Debug, thiserror::Error)]
pub enum RasterError {
    /// A framebuffer of zero (or absurd) size was asked for.
    #[error("framebuffer size {width}x{height}: {what}")]
    BadSize {
        /// Requested width.
        width: u32,
        /// Requested height.
        height: u32,
        /// Why it was refused.
        what: &'static str,
    },
    /// A bump-map parameter is unusable.
    #[error("bump map: {0}")]
    BadBump(String),
}

/// Largest accepted side: keeps every screen coordinate far inside the fixed-point range.
pub const MAX_SIDE: u32 = 1 << 15;

/// Depth of an empty pixel: the far plane, which is not drawn (the test is `depth < stored`).
pub const FAR_DEPTH: f32 = 1.0;

/// The largest intensity a high-dynamic-range framebuffer keeps ([`Framebuffer::set_hdr`]):
/// the largest finite half-precision float, so that an image stays finite when stored as
/// 16-bit floats (OpenEXR's `half`), and 16 samples of it still sum to a finite `f32` in the
/// anti-aliasing resolve.
pub const HDR_MAX: f32 = 65504.0;

/// Linear RGB intensities (row 0 at the top) and depth in `[0, 1]` (0 = near plane). The
/// intensities are clamped to `[0, 1]` as they are written, or to `[0, HDR_MAX]` with
/// [`Framebuffer::set_hdr`].
#[derive(Debug, Clone)]
pub struct Framebuffer {
    width: u32,
    height: u32,
    pub(crate) color: Vec<Vec3>,
    pub(crate) depth: Vec<f32>,
    /// A clear the renderer has deferred to its band jobs (each clears its own rows, in
    /// parallel, just before drawing them); never left set when `render` returns.
    pub(crate) pending_clear: Option<Vec3>,
    /// The colour of the last clear, or `None` when unknown. Every pixel outside `dirty` holds
    /// it (clamped) and the far depth, so the next clear to the same colour only rewrites the
    /// dirty columns: a frame of a small object no longer pays for rewriting the whole image.
    pub(crate) clean: Option<Vec3>,
    /// Per row, the columns `[lo, hi)` written since the last clear ([`CLEAN_ROW`] for none).
    /// Only the band jobs write pixels, and they widen this to each span they draw.
    pub(crate) dirty: Vec<(u32, u32)>,
    /// The sample image of the last anti-aliased frame ([`crate::Antialias`]), kept so that
    /// the next frame of the same size and choice reuses it instead of allocating again.
    pub(crate) samples: Option<Box<Framebuffer>>,
    /// A multisampled sample image's colour per output pixel ([`layer`]): where a pixel is
    /// not split by an edge, its colour is here and its samples' colours mean nothing.
    pub(crate) layer: Option<PixelLayer>,
    /// The largest intensity a pixel keeps: 1, or [`HDR_MAX`] ([`Framebuffer::set_hdr`]).
    pub(crate) ceiling: f32,
    /// Per pixel, the share of what lies under the overlays that shows through them: the
    /// product of `1 - w` over the strokes [`Framebuffer::blend`] drew since the last clear,
    /// so that [`Framebuffer::alpha`] counts a grid line over a transparent background as
    /// opaque. `None` until an overlay is drawn.
    pub(crate) overlay: Option<Vec<f32>>,
}

/// A row with no pixel written since the last clear (see [`Framebuffer`]'s `dirty`).
pub(crate) const CLEAN_ROW: (u32, u32) = (u32::MAX, 0);

/// Clamps to `[0, 1]`, NaN and `-0.0` to `+0.0`: the one gate every colour passes on its way
/// to a pixel.
///
/// Written as two selects per channel, `x > 0 ? x : 0` then `x < 1 ? x : 1`: NaN fails the
/// first comparison, so no separate NaN test is needed, and each select is one SSE `maxss` /
/// `minss` (or half of a `maxps` / `minps` over two channels). `x.max(0.0).min(1.0)` gives the
/// same values except the sign of a zero, but is lowered with extra compares and masks for
/// NaN in both steps (13 instructions against 4 on x86-64); this runs once per shaded pixel.
#[inline]
#[must_use]
pub fn clamp_color(c: Vec3) -> Vec3 {
    clamp_color_to(c, 1.0)
}

/// [`clamp_color`] to `[0, ceiling]` instead: NaN and `-0.0` to `+0.0`, `+inf` to `ceiling`.
/// The renderer's gate takes the framebuffer's ceiling (1, or [`HDR_MAX`]) as a value, so
/// that either range costs the same two selects per channel.
#[inline]
#[must_use]
pub fn clamp_color_to(c: Vec3, ceiling: f32) -> Vec3 {
    let clamp = |x: f32| {
        let x = if x > 0.0 { x } else { 0.0 };
        if x < ceiling { x } else { ceiling }
    };
    Vec3::new(clamp(c.x), clamp(c.y), clamp(c.z))
}

impl Framebuffer {
    /// A black framebuffer with every depth at the far plane. Zero or above [`MAX_SIDE`] is an error.
    pub fn new(width: u32, height: u32) -> Result<Framebuffer, RasterError> {
        let bad = |what| {
            Err(RasterError::BadSize {
                width,
                height,
                what,
            })
        };
        if width == 0 || height == 0 {
            return bad("zero size");
        }
        if width > MAX_SIDE || height > MAX_SIDE {
            return bad("side above 32768");
        }
        let n = width as usize * height as usize;
        Ok(Framebuffer {
            width,
            height,
            color: vec![Vec3::ZERO; n],
            depth: vec![FAR_DEPTH; n],
            pending_clear: None,
            clean: Some(Vec3::ZERO),
            dirty: vec![CLEAN_ROW; height as usize],
            samples: None,
            layer: None,
            ceiling: 1.0,
            overlay: None,
        })
    }

    /// Keeps intensities above 1 (up to [`HDR_MAX`]) from the next frame on, for output
    /// that holds them (OpenEXR, tone mapping); `false` (the default) clamps every pixel to
    /// `[0, 1]` as it is written. Either way no NaN or infinity is stored. A framebuffer
    /// drawn with anti-aliasing averages what it keeps: clamped samples in `[0, 1]`, or the
    /// samples' own intensities.
    pub fn set_hdr(&mut self, hdr: bool) {
        let ceiling = if hdr { HDR_MAX } else { 1.0 };
        if ceiling != self.ceiling {
            self.ceiling = ceiling;
            // The pixels hold the last clear clamped to the old range: rewrite them all.
            self.clean = None;
            self.samples = None;
        }
    }

    /// Whether intensities above 1 are kept ([`Framebuffer::set_hdr`]).
    #[must_use]
    pub fn hdr(&self) -> bool {
        self.ceiling > 1.0
    }

    /// Per pixel (row-major from the top), the share of its samples that the last frame drew
    /// a triangle on: 1 or 0 without anti-aliasing, `j / (k * k)` with `k x k` samples per
    /// pixel. A sample is drawn where its depth is nearer than the far plane (every drawn
    /// depth is, the depth test being `depth < stored`), so this costs nothing while drawing;
    /// it reads the sample image an anti-aliased frame keeps, or the pixels' own depths.
    #[must_use]
    pub fn coverage(&self) -> Vec<f32> {
        let width = self.width as usize;
        let (depth, k) = match &self.samples {
            Some(s)
                if s.width / self.width > 1
                    && s.width == self.width * (s.width / self.width)
                    && s.height == self.height * (s.width / self.width) =>
            {
                (&s.depth, (s.width / self.width) as usize)
            }
            _ => (&self.depth, 1),
        };
        let stride = width * k;
        let scale = 1.0 / (k * k) as f32;
        let mut out = Vec::with_capacity(self.depth.len());
        for y in 0..self.height as usize {
            for x in 0..width {
                let mut drawn = 0u32;
                for sy in 0..k {
                    let row = &depth[(y * k + sy) * stride + x * k..][..k];
                    drawn += row.iter().filter(|&&d| d < FAR_DEPTH).count() as u32;
                }
                out.push(drawn as f32 * scale);
            }
        }
        out
    }

    /// Per pixel, its opacity over a background of opacity `background` (clamped to
    /// `[0, 1]`, NaN as 0): `a = c + (1 - c) * background` for the pixel's
    /// [`Framebuffer::coverage`] `c`, and under overlay strokes of weights `w` (the wireframe,
    /// the grid, the axes) `1 - (1 - a) * product(1 - w)`, as they are blended over it. Drawn over a background cleared to its colour times
    /// its opacity, the pixels then hold colours premultiplied by this alpha, as the
    /// resolve averages colour and coverage alike: a pixel half covered over a transparent
    /// background has alpha 0.5 and half the surface's colour.
    #[must_use]
    #[allow(
        clippy::manual_clamp,
        reason = "max/min map NaN to a bound, clamp() keeps it"
    )]
    pub fn alpha(&self, background: f32) -> Vec<f32> {
        let b = background.max(0.0).min(1.0);
        let mut alpha = self.coverage();
        for a in &mut alpha {
            *a += (1.0 - *a) * b;
        }
        if let Some(through) = &self.overlay {
            for (a, t) in alpha.iter_mut().zip(through) {
                *a = 1.0 - (1.0 - *a) * t;
            }
        }
        alpha
    }

    /// Width in pixels.
    #[must_use]
    pub fn width(&self) -> u32 {
        self.width
    }

    /// Height in pixels.
    #[must_use]
    pub fn height(&self) -> u32 {
        self.height
    }

    /// Fills the colour with `background` (clamped to the framebuffer's range) and resets
    /// depth to the far plane. When the last clear had the same colour, only the pixels
    /// written since are rewritten.
    pub fn clear(&mut self, background: Vec3) {
        let bg = clamp_color_to(background, self.ceiling);
        let only_dirty = same_color(self.clean, bg);
        let width = self.width;
        // With a pixel layer the samples' colours mean nothing until a pixel is split.
        let color: &mut [Vec3] = match &mut self.layer {
            Some(layer) => {
                layer.all().clear(bg, only_dirty.then_some(&self.dirty[..]));
                &mut []
            }
            None => &mut self.color,
        };
        clear_rows(
            (color, &mut self.depth, &mut self.dirty),
            width,
            bg,
            only_dirty,
        );
        self.clean = Some(bg);
        self.pending_clear = None;
        self.overlay = None;
    }

    /// Defers [`Framebuffer::clear`] to the next banded draw (the renderer's own use).
    pub(crate) fn defer_clear(&mut self, background: Vec3) {
        self.pending_clear = Some(clamp_color_to(background, self.ceiling));
        self.overlay = None;
    }

    /// Gives this sample image a pixel layer of `k x k` samples per pixel ([`layer`]), for
    /// multisampled draws, or with `k == 1` takes it away, first writing the colour of every
    /// pixel it held to the pixel's samples: either way the image shows what it showed.
    pub(crate) fn set_layer(&mut self, k: u32) {
        if self.layer.as_ref().is_some_and(|l| l.k == k as usize) {
            return;
        }
        if let Some(mut layer) = self.layer.take() {
            layer.all().split_all(&mut self.color);
        }
        let (w, h) = (self.width / k.max(1), self.height / k.max(1));
        if k > 1 && w * k == self.width && h * k == self.height {
            let (k, w, h) = (k as usize, w as usize, h as usize);
            self.layer = Some(PixelLayer::over_samples(k, w, h));
        }
    }

    /// Drops the sample image an anti-aliased frame keeps for reuse.
    pub fn release_samples(&mut self) {
        self.samples = None;
    }

    /// Carries out a deferred clear that no draw took.
    pub(crate) fn finish_clear(&mut self) {
        if let Some(bg) = self.pending_clear {
            self.clear(bg);
        }
    }

    /// The colour at `(x, y)`, row 0 at the top; black outside the image.
    #[must_use]
    pub fn pixel(&self, x: u32, y: u32) -> Vec3 {
        if x >= self.width || y >= self.height {
            return Vec3::ZERO;
        }
        self.color[y as usize * self.width as usize + x as usize]
    }

    /// The depth at `(x, y)` in `[0, 1]`; [`FAR_DEPTH`] where nothing was drawn or outside.
    #[must_use]
    pub fn depth_at(&self, x: u32, y: u32) -> f32 {
        if x >= self.width || y >= self.height {
            return FAR_DEPTH;
        }
        self.depth[y as usize * self.width as usize + x as usize]
    }

    /// All colours, row-major from the top row, each channel in `[0, 1]` (in `[0, HDR_MAX]`
    /// with [`Framebuffer::set_hdr`]).
    #[must_use]
    pub fn color(&self) -> &[Vec3] {
        &self.color
    }

    /// Blends `color` over pixel `(x, y)` (inside the image) with weight `w` in `[0, 1]`,
    /// clamped to the framebuffer's range, and counts the pixel as written since the last
    /// clear: an overlay drawn over the background must survive the next partial clear and
    /// the background fill of [`Framebuffer::write_0rgb`]. Depth is left as drawn, and so is
    /// coverage; the stroke's opacity is kept for [`Framebuffer::alpha`].
    pub(crate) fn blend(&mut self, x: usize, y: usize, color: Vec3, w: f32) {
        let at = y * self.width as usize + x;
        let n = self.color.len();
        let through = self.overlay.get_or_insert_with(|| vec![1.0; n]);
        through[at] *= 1.0 - w;
        // Exactly `color` at `w = 1` (and the pixel at `w = 0`), as `c + (color - c) * w` is not.
        let c = self.color[at];
        self.color[at] = clamp_color_to(c * (1.0 - w) + color * w, self.ceiling);
        let d = &mut self.dirty[y];
        d.0 = d.0.min(x as u32);
        d.1 = d.1.max(x as u32 + 1);
    }

    /// All depths, row-major, in `[0, 1]`.
    #[must_use]
    pub fn depth(&self) -> &[f32] {
        &self.depth
    }
}

/// The byte layout of one 8-bit pixel ([`Framebuffer::write_row`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PixelLayout {
    /// Red, green, blue: 3 bytes.
    Rgb8,
    /// Red, green, blue, alpha (always 255: the framebuffer is opaque): 4 bytes.
    Rgba8,
}

impl PixelLayout {
    /// Bytes per pixel.
    #[must_use]
    pub fn bytes(self) -> usize {
        match self {
            PixelLayout::Rgb8 => 3,
            PixelLayout::Rgba8 => 4,
        }
    }
}

/// Whether `clean` holds exactly the colour `bg` (bit for bit: a clear to a different colour,
/// however close, rewrites every pixel).
pub(crate) fn same_color(clean: Option<Vec3>, bg: Vec3) -> bool {
    clean.is_some_and(|c| c.to_array().map(f32::to_bits) == bg.to_array().map(f32::to_bits))
}

/// Clears rows `width` pixels wide (`color`, `depth` and their `dirty` extents, one per row):
/// colour to `bg`, depth to the far plane, every row marked clean. With `only_dirty` (the rows
/// already hold `bg` outside their dirty columns) only the dirty columns are rewritten. An
/// empty `color` clears the depth alone.
pub(crate) fn clear_rows(
    (color, depth, dirty): (&mut [Vec3], &mut [f32], &mut [(u32, u32)]),
    width: u32,
    bg: Vec3,
    only_dirty: bool,
) {
    let width = width as usize;
    if !only_dirty {
        fill_rows(color, depth, bg);
    } else {
        for (y, (d, &(lo, hi))) in depth.chunks_mut(width).zip(dirty.iter()).enumerate() {
            let (lo, hi) = (lo as usize, (hi as usize).min(width));
            if lo < hi {
                let c = color
                    .get_mut(y * width + lo..y * width + hi)
                    .unwrap_or_default();
                fill_rows(c, &mut d[lo..hi], bg);
            }
        }
    }
    dirty.fill(CLEAN_ROW);
}

/// Clears rows: `color` to `bg`, `depth` to the far plane. Colours are written four at a time
/// (48 bytes, three full vector stores) rather than one 12-byte `Vec3` at a time, which is what
/// a plain `fill` compiles to; the clear touches every pixel of every frame.
pub(crate) fn fill_rows(color: &mut [Vec3], depth: &mut [f32], bg: Vec3) {
    fill_colors(color, bg);
    depth.fill(FAR_DEPTH);
}

/// Fills `color` with `bg`, four at a time ([`fill_rows`]).
pub(crate) fn fill_colors(color: &mut [Vec3], bg: Vec3) {
    let four = [bg; 4];
    let mut quads = color.chunks_exact_mut(4);
    for q in &mut quads {
        q.copy_from_slice(&four);
    }
    quads.into_remainder().fill(bg);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::encode::{Encoding, encode};

    #[test]
    fn zero_size_is_an_error_not_a_panic() {
        assert!(Framebuffer::new(0, 4).is_err());
        assert!(Framebuffer::new(4, 0).is_err());
        assert!(Framebuffer::new(1 << 20, 1).is_err());
    }

    #[test]
    fn clamp_color_maps_every_float_into_the_unit_range_with_positive_zero() {
        let cases = [
            (f32::NAN, 0.0),
            (-f32::NAN, 0.0),
            (-0.0, 0.0),
            (0.0, 0.0),
            (-1e-30, 0.0),
            (f32::NEG_INFINITY, 0.0),
            (1e-40, 1e-40),
            (0.25, 0.25),
            (0.999_999_9, 0.999_999_9),
            (1.0, 1.0),
            (1.000_000_1, 1.0),
            (f32::INFINITY, 1.0),
        ];
        for (x, want) in cases {
            // Each case in each channel, the others holding different values.
            for c in [
                Vec3::new(x, 0.5, -3.0),
                Vec3::new(7.0, x, 0.5),
                Vec3::new(0.5, 2.0, x),
            ] {
                let got = clamp_color(c);
                let expect = c.to_array().map(|v| {
                    if v.to_bits() == x.to_bits() || (v.is_nan() && x.is_nan()) {
                        want
                    } else {
                        v.clamp(0.0, 1.0)
                    }
                });
                assert_eq!(
                    got.to_array().map(f32::to_bits),
                    expect.map(f32::to_bits),
                    "{c}"
                );
            }
        }
    }

    #[test]
    fn clear_clamps_and_encodings_agree() {
        let mut fb = Framebuffer::new(2, 1).unwrap();
        fb.clear(Vec3::new(2.0, f32::NAN, 0.5));
        assert_eq!(fb.pixel(1, 0), Vec3::new(1.0, 0.0, 0.5));
        let mut out = [0u32; 2];
        fb.write_0rgb(&mut out);
        assert_eq!(out[0] >> 8, 0xff00);
        assert_eq!(fb.to_rgb8(Encoding::Linear)[..3], [255, 0, 128]);
    }

    #[test]
    fn rgba8_and_rows_hold_the_rgb8_bytes_with_opaque_alpha() {
        let mut fb = Framebuffer::new(3, 2).unwrap();
        fb.clean = None;
        for (i, c) in fb.color.iter_mut().enumerate() {
            *c = Vec3::new(i as f32 / 5.0, 1.0 - i as f32 / 5.0, 0.5);
        }
        for encoding in [Encoding::Srgb, Encoding::Linear] {
            let rgb = fb.to_rgb8(encoding);
            let rgba = fb.to_rgba8(encoding);
            assert_eq!(rgba.len(), 3 * 2 * 4);
            for (p, q) in rgb.chunks_exact(3).zip(rgba.chunks_exact(4)) {
                assert_eq!(p, &q[..3]);
                assert_eq!(q[3], 255);
            }
            let mut row = [7u8; 9];
            fb.write_row(1, encoding, PixelLayout::Rgb8, &mut row);
            assert_eq!(row[..], rgb[9..18]);
            let mut short = [7u8; 5];
            fb.write_row(0, encoding, PixelLayout::Rgb8, &mut short);
            assert_eq!(short[..3], rgb[..3], "one whole pixel fits");
            assert_eq!(short[3..], [7, 7], "a partial pixel is left alone");
            fb.write_row(2, encoding, PixelLayout::Rgb8, &mut row);
            assert_eq!(row[..], rgb[9..18], "a row past the bottom writes nothing");
        }
        assert_ne!(fb.to_rgb8(Encoding::Srgb), fb.to_rgb8(Encoding::Linear));
    }

    #[test]
    fn presenting_on_several_threads_gives_the_same_bytes() {
        let mut fb = Framebuffer::new(37, 41).unwrap();
        // Written here behind the renderer's back: no pixel is known to hold a clear colour.
        fb.clean = None;
        for (i, c) in fb.color.iter_mut().enumerate() {
            let t = i as f32 * 0.37;
            *c = Vec3::new(t.sin(), (t * 0.5).cos(), (t * 0.01).fract() * 1.2 - 0.1);
        }
        fb.color[5] = Vec3::new(f32::NAN, f32::INFINITY, -1.0);
        let expected: Vec<u32> = fb
            .color
            .iter()
            .map(|c| {
                let [r, g, b] = [c.x, c.y, c.z].map(|v| u32::from(encode(v, Encoding::Srgb)));
                (r << 16) | (g << 8) | b
            })
            .collect();
        for threads in [1, 2, 3, 0] {
            let mut out = vec![0u32; fb.color.len()];
            fb.write_0rgb_threads(&mut out, threads);
            assert_eq!(out, expected, "{threads} threads");
        }
    }
}
