//! The framebuffer read out as 8-bit pixels through an encoding table: softbuffer's
//! `0x00RRGGBB` words for a window, RGB or RGBA bytes for files and other callers, whole or a
//! row at a time.

use glam::Vec3;

use super::{Framebuffer, PixelLayout};
#[cfg(test)]
use crate::encode::LUT_SIZE;
use crate::encode::{Encoder, Encoding};

impl Framebuffer {
    /// Writes softbuffer's `0x00RRGGBB`, sRGB-encoded, into `out` (as many pixels as both hold).
    pub fn write_0rgb(&self, out: &mut [u32]) {
        self.write_0rgb_threads(out, 1);
    }

    /// [`Framebuffer::write_0rgb`] on `threads` threads (0 = all cores), by rows; the same bytes.
    ///
    /// Outside the columns written since the last clear every pixel holds the clear's colour,
    /// so those are filled with its one encoded value and only the written columns are
    /// converted pixel by pixel (a frame of a small object converts a fraction of the image).
    pub fn write_0rgb_threads(&self, out: &mut [u32], threads: usize) {
        self.write_0rgb_over(out, threads, None);
    }

    /// [`Framebuffer::write_0rgb_threads`] into a buffer that may still hold what an earlier
    /// call wrote: `held` is what that call returned, when the buffer holds those words
    /// unchanged (a window surface whose buffer age is 1). Where that frame and this one had
    /// the same clear colour and size, only the columns either of them wrote are rewritten,
    /// so a frame of a small object touches a fraction of the buffer. The buffer ends with
    /// the same words as `write_0rgb_threads` writes. Returns what it now holds, for the next
    /// call.
    pub fn write_0rgb_over(&self, out: &mut [u32], threads: usize, held: Option<&Shown>) -> Shown {
        let enc = Encoder::new(Encoding::Srgb);
        let width = self.width as usize;
        let n = out.len().min(self.color.len());
        let shown = self.shown(n);
        let before = shown.kept(held);
        let rows: Vec<usize> = (0..shown.written.len()).collect();
        crate::parallel::for_each_chunk(threads, &mut out[..n], &rows, (16, width), |dst, rows| {
            for (dst, &y) in dst.chunks_mut(width).zip(rows) {
                let src = &self.color[y * width..y * width + dst.len()];
                let before = before.and_then(|b| b.get(y)).copied();
                word_row(
                    enc,
                    (src, dst),
                    (shown.written[y], shown.background),
                    before,
                );
            }
        });
        shown
    }

    /// What [`Framebuffer::write_0rgb_over`] of this image's first `n` pixels leaves in a
    /// buffer: the background's word (when the clear colour is known) and each row's
    /// columns that are not the background.
    pub(crate) fn shown(&self, n: usize) -> Shown {
        let background = background_word(self.clean);
        let written = (0..n.div_ceil(self.width as usize))
            .map(|y| written_row(background, self.dirty.get(y).copied(), self.width))
            .collect();
        Shown {
            size: (self.width, self.height),
            len: n,
            background,
            written,
        }
    }

    /// Interleaved 8-bit RGB, row-major from the top, through the encoding table.
    #[must_use]
    pub fn to_rgb8(&self, encoding: Encoding) -> Vec<u8> {
        let enc = Encoder::new(encoding);
        let mut out = Vec::with_capacity(self.color.len() * 3);
        for c in &self.color {
            out.extend([enc.encode(c.x), enc.encode(c.y), enc.encode(c.z)]);
        }
        out
    }

    /// Interleaved 8-bit RGBA (alpha 255), row-major from the top, through the encoding
    /// table: the layout of most GPU textures, image crates and HTML canvases, for callers
    /// that put the picture somewhere other than a PNG file or a softbuffer window.
    #[must_use]
    pub fn to_rgba8(&self, encoding: Encoding) -> Vec<u8> {
        let mut out = vec![0; self.color.len() * 4];
        for y in 0..self.height {
            let w = self.width as usize * 4;
            let row = &mut out[y as usize * w..(y as usize + 1) * w];
            self.write_row(y, encoding, PixelLayout::Rgba8, row);
        }
        out
    }

    /// Writes row `y` (0 at the top) into `out` as 8-bit pixels in `layout`, through the
    /// encoding table: as many whole pixels as both hold (`width * layout.bytes()` bytes is
    /// the full row). A row past the bottom writes nothing. The same bytes as the matching
    /// row of [`Framebuffer::to_rgb8`] / [`Framebuffer::to_rgba8`], without holding a copy of
    /// the whole image (a streaming encoder, a texture upload row by row).
    pub fn write_row(&self, y: u32, encoding: Encoding, layout: PixelLayout, out: &mut [u8]) {
        if y >= self.height {
            return;
        }
        let enc = Encoder::new(encoding);
        let w = self.width as usize;
        let src = &self.color[y as usize * w..(y as usize + 1) * w];
        for (d, c) in out.chunks_exact_mut(layout.bytes()).zip(src) {
            d[0] = enc.encode(c.x);
            d[1] = enc.encode(c.y);
            d[2] = enc.encode(c.z);
            if let Some(a) = d.get_mut(3) {
                *a = u8::MAX;
            }
        }
    }
}

/// What [`Framebuffer::write_0rgb_over`] left in a buffer: the background's word and, per
/// row, the columns holding anything else. Hand it to the next call while the buffer holds
/// those words unchanged.
#[derive(Debug, Clone, Default)]
pub struct Shown {
    size: (u32, u32),
    len: usize,
    background: Option<u32>,
    written: Vec<(u32, u32)>,
}

impl Shown {
    /// What a readout of `len` words of an image of `size` with the background's word
    /// `background` compares a held buffer's [`Shown`] against ([`Shown::kept`]).
    pub(crate) fn new(size: (u32, u32), len: usize, background: Option<u32>) -> Shown {
        Shown {
            size,
            len,
            background,
            written: Vec::new(),
        }
    }

    /// The columns per row that a buffer holding `held` has outside the background, when
    /// its words can stand where this readout writes the background: the same size, length
    /// and known background word. `None`: every background word is written.
    pub(crate) fn kept<'a>(&self, held: Option<&'a Shown>) -> Option<&'a [(u32, u32)]> {
        held.filter(|h| {
            h.size == self.size
                && h.len == self.len
                && h.background.is_some()
                && h.background == self.background
        })
        .map(|h| &h.written[..])
    }
}

/// A window's buffer for a frame to fill with softbuffer's `0x00RRGGBB` words
/// ([`crate::Frame::show_in`], [`crate::render_into`]): the words
/// [`Framebuffer::write_0rgb_over`] would write after the frame, read out band by band by
/// the frame's last draw while each band's rows are still in cache.
#[derive(Debug)]
pub struct WindowBuffer<'a> {
    /// The buffer: a word per pixel of the image, row-major from the top. A length other
    /// than the image's is filled at the frame's end, as `write_0rgb_over` fills it.
    pub words: &'a mut [u32],
    /// What the buffer holds: `write_0rgb_over`'s or an earlier frame's [`Shown`] while the
    /// buffer still holds those words (a surface whose buffer age is 1), else `None`. The
    /// frame's end sets it to what the buffer holds then, for the next frame.
    pub shown: &'a mut Option<Shown>,
}

/// The word of the clear colour `clean`, if known.
pub(crate) fn background_word(clean: Option<Vec3>) -> Option<u32> {
    clean.map(|c| {
        let mut word = [0];
        pack_0rgb(Encoder::new(Encoding::Srgb), &[c], &mut word);
        word[0]
    })
}

/// The columns of a row `width` long that are not the background: its dirty columns while
/// the background is known, else all of them.
pub(crate) fn written_row(
    background: Option<u32>,
    dirty: Option<(u32, u32)>,
    width: u32,
) -> (u32, u32) {
    match (background, dirty) {
        (Some(_), Some((lo, hi))) => {
            let hi = hi.min(width);
            (lo.min(hi), hi)
        }
        _ => (0, width),
    }
}

/// One row of the readout: `src`'s columns `written` packed into `dst`, and the background
/// (when known) outside them: the whole rest of the row, or, where the buffer holds a
/// row whose columns `before` were not the background, only those.
pub(crate) fn word_row(
    enc: Encoder,
    (src, dst): (&[Vec3], &mut [u32]),
    (written, background): ((u32, u32), Option<u32>),
    before: Option<(u32, u32)>,
) {
    let end = dst.len().min(src.len());
    let dst = &mut dst[..end];
    // `lo <= hi` in `written` and in a held `Shown`, and so after the clamp to `end`.
    let (lo, hi) = ((written.0 as usize).min(end), (written.1 as usize).min(end));
    if let Some(bg) = background {
        match before {
            Some((a, b)) => {
                let (a, b) = ((a as usize).min(end), (b as usize).min(end));
                if lo >= hi {
                    dst[a..b].fill(bg);
                } else {
                    dst[a.min(lo)..lo].fill(bg);
                    dst[hi..b.max(hi)].fill(bg);
                }
            }
            None => {
                dst[..lo].fill(bg);
                dst[hi..].fill(bg);
            }
        }
    }
    pack_0rgb(enc, &src[lo..hi], &mut dst[lo..hi]);
}

/// `src` packed as `0x00RRGGBB` through `enc` into `dst` (as many pixels as both hold): four
/// pixels' twelve channels as three four-lane steps of [`Encoder::encode4`], the rest one
/// channel at a time; the same codes as [`Encoder::encode`] per channel.
fn pack_0rgb(enc: Encoder, src: &[Vec3], dst: &mut [u32]) {
    let word = |r: u8, g: u8, b: u8| (u32::from(r) << 16) | (u32::from(g) << 8) | u32::from(b);
    let n = src.len().min(dst.len());
    let (src, dst) = (&src[..n], &mut dst[..n]);
    let mut quads = dst.chunks_exact_mut(4);
    for (d, s) in (&mut quads).zip(src.chunks_exact(4)) {
        let a = enc.encode4([s[0].x, s[0].y, s[0].z, s[1].x]);
        let b = enc.encode4([s[1].y, s[1].z, s[2].x, s[2].y]);
        let c = enc.encode4([s[2].z, s[3].x, s[3].y, s[3].z]);
        d[0] = word(a[0], a[1], a[2]);
        d[1] = word(a[3], b[0], b[1]);
        d[2] = word(b[2], b[3], c[0]);
        d[3] = word(c[1], c[2], c[3]);
    }
    let done = n - quads.into_remainder().len();
    for (d, c) in dst[done..].iter_mut().zip(&src[done..]) {
        *d = word(enc.encode(c.x), enc.encode(c.y), enc.encode(c.z));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A buffer kept from frame to frame ends every frame with the words a fresh full readout
    /// writes: objects that move, appear and vanish, overlapping or not, rows that go clean,
    /// a change of clear colour, a colour unknown to be clear everywhere, a size change and
    /// a buffer not held (age 0), each on one and on several threads.
    #[test]
    fn a_held_buffer_matches_a_full_readout_frame_after_frame() {
        let (w, h) = (53, 37);
        let mut fb = Framebuffer::new(w, h).unwrap();
        let mut small = Framebuffer::new(20, 10).unwrap();
        let mut seed = 12345u32;
        let mut next = |m: u32| {
            seed ^= seed << 13;
            seed ^= seed >> 17;
            seed ^= seed << 5;
            seed % m
        };
        for threads in [1, 0] {
            let mut out = vec![0u32; (w * h) as usize];
            let mut held: Option<Shown> = None;
            for frame in 0..60 {
                let (fb, out) = if frame % 17 == 16 {
                    // Another size in between: the held state must not be trusted after it.
                    let mut other = vec![0u32; 200];
                    small.clear(Vec3::ZERO);
                    held = Some(small.write_0rgb_over(&mut other, threads, held.as_ref()));
                    continue;
                } else {
                    (&mut fb, &mut out)
                };
                let bg = if frame % 11 == 5 {
                    Vec3::splat(0.25)
                } else {
                    Vec3::new(0.1, 0.2, 0.3)
                };
                fb.clear(bg);
                for _ in 0..next(4) {
                    // A rectangle of colour, widening the written columns as drawing does.
                    let (x0, y0) = (next(w), next(h));
                    let (x1, y1) = ((x0 + 1 + next(20)).min(w), (y0 + 1 + next(12)).min(h));
                    let c = Vec3::new(next(100) as f32 / 99.0, 0.5, frame as f32 / 60.0);
                    for y in y0..y1 {
                        for x in x0..x1 {
                            fb.color[(y * w + x) as usize] = c;
                        }
                        let d = &mut fb.dirty[y as usize];
                        *d = (d.0.min(x0), d.1.max(x1));
                    }
                }
                if frame % 13 == 7 {
                    // Written behind the renderer's back: no colour is known to be clear.
                    fb.clean = None;
                }
                let kept = if frame % 7 == 3 { None } else { held.as_ref() };
                held = Some(fb.write_0rgb_over(out, threads, kept));
                let mut full = vec![0u32; out.len()];
                fb.write_0rgb_threads(&mut full, threads);
                assert_eq!(*out, full, "frame {frame}, {threads} threads");
            }
        }
    }

    /// The four-lane packing gives each channel [`Encoder::encode`]'s code, for the values
    /// where a lane operation could part from the scalar one: NaN, signed zeros and
    /// infinities, the clamp's ends, values just either side of a table index's half-way
    /// point, and a sweep of `[0, 1.2]`; for every run length (the scalar tail included).
    #[test]
    fn packed_words_match_the_scalar_encoding() {
        let step = 0.5 / (LUT_SIZE - 1) as f32;
        let mut values = vec![
            f32::NAN,
            -f32::NAN,
            0.0,
            -0.0,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -1.0,
            1.0,
            1.0 + f32::EPSILON,
            f32::MIN_POSITIVE,
            crate::framebuffer::HDR_MAX,
        ];
        for k in 0..LUT_SIZE as u32 {
            let half = (2 * k + 1) as f32 * step;
            values.extend([
                half,
                f32::from_bits(half.to_bits() - 1),
                f32::from_bits(half.to_bits() + 1),
            ]);
        }
        values.extend((0..5000).map(|i| i as f32 * 1.2 / 5000.0));
        for encoding in [Encoding::Srgb, Encoding::Linear] {
            let enc = Encoder::new(encoding);
            let pixels: Vec<Vec3> = values
                .chunks(3)
                .map(|c| {
                    Vec3::new(
                        c[0],
                        c.get(1).copied().unwrap_or(0.3),
                        c.get(2).copied().unwrap_or(0.7),
                    )
                })
                .collect();
            for len in [0, 1, 2, 3, 4, 5, 7, 8, 9, pixels.len()] {
                let mut out = vec![0xDEAD_BEEF; len];
                pack_0rgb(enc, &pixels[..len], &mut out);
                for (c, &w) in pixels.iter().zip(&out) {
                    let want = (u32::from(enc.encode(c.x)) << 16)
                        | (u32::from(enc.encode(c.y)) << 8)
                        | u32::from(enc.encode(c.z));
                    assert_eq!(w, want, "{c:?} ({encoding:?})");
                }
            }
        }
    }
}
