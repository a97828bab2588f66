//! The framebuffer read out as 8-bit pixels through an encoding table: softbuffer's
//! `0x00RRGGBB` words for a window, RGB or RGBA bytes for files and other callers, whole or a
//! row at a time.

use glam::Vec3;

use super::{Framebuffer, PixelLayout};
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
        let enc = Encoder::new(Encoding::Srgb);
        let pack = |c: &Vec3| {
            let (r, g, b) = (enc.encode(c.x), enc.encode(c.y), enc.encode(c.z));
            (u32::from(r) << 16) | (u32::from(g) << 8) | u32::from(b)
        };
        let width = self.width as usize;
        let n = out.len().min(self.color.len());
        let background = self.clean.as_ref().map(pack);
        let rows: Vec<usize> = (0..n.div_ceil(width)).collect();
        crate::parallel::for_each_chunk(threads, &mut out[..n], &rows, (16, width), |dst, rows| {
            for (dst, &y) in dst.chunks_mut(width).zip(rows) {
                let src = &self.color[y * width..y * width + dst.len()];
                let (lo, hi) = match (background, self.dirty.get(y)) {
                    (Some(bg), Some(&(lo, hi))) => {
                        let hi = (hi as usize).min(dst.len());
                        let lo = (lo as usize).min(hi);
                        dst[..lo].fill(bg);
                        dst[hi..].fill(bg);
                        (lo, hi)
                    }
                    _ => (0, dst.len()),
                };
                for (d, c) in dst[lo..hi].iter_mut().zip(&src[lo..hi]) {
                    *d = pack(c);
                }
            }
        });
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
