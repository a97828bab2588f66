//! Where a texture's texels live: every level of the mip chain in one array of RGBA `f32`
//! (alpha unused), row after row, each row with one more texel on either side that holds the
//! texel the `u` wrap puts there. So the two texels a bilinear lookup blends along a row are
//! always next to each other, seams included, and a lookup reads each row's pair as one run of
//! eight floats.

use glam::Vec3;

use super::Wrap;

/// One level of the chain: its size and where its rows start.
#[derive(Debug, Clone, Copy)]
pub(super) struct Level {
    pub(super) width: usize,
    pub(super) height: usize,
    /// Slot (texel position in the array) of row 0's left padding.
    pub(super) offset: usize,
}

impl Level {
    /// Slots per row: the texels and their two paddings.
    #[inline(always)]
    pub(super) fn stride(&self) -> usize {
        self.width + 2
    }
}

/// The sizes of a chain from `width x height` down to 1x1, each level's side half the one
/// above (rounded down, at least 1), with their offsets; and the slots in all.
fn layout(width: usize, height: usize) -> (Vec<Level>, usize) {
    let mut levels = Vec::new();
    let (mut w, mut h, mut offset) = (width, height, 0);
    loop {
        levels.push(Level {
            width: w,
            height: h,
            offset,
        });
        offset += (w + 2) * h;
        if w == 1 && h == 1 {
            return (levels, offset);
        }
        (w, h) = ((w / 2).max(1), (h / 2).max(1));
    }
}

/// The texels of every level, padded.
#[derive(Debug, Clone)]
pub(super) struct Chain {
    pub(super) levels: Vec<Level>,
    data: Vec<f32>,
}

impl Chain {
    /// Bytes the chain of a `width x height` image takes.
    pub(super) fn bytes_for(width: u32, height: u32) -> u64 {
        let (_, slots) = layout(width as usize, height as usize);
        slots as u64 * 16
    }

    /// The chain of `texels` (`width x height`, rows from the top, already finite and
    /// non-negative): level 0 as given, each next one the mean of the (up to) 2x2 texels above
    /// it; padded for `wrap_u`.
    pub(super) fn build(width: usize, height: usize, texels: &[Vec3], wrap_u: Wrap) -> Chain {
        let (levels, slots) = layout(width, height);
        let mut chain = Chain {
            levels,
            data: vec![0.0; slots * 4],
        };
        for j in 0..height {
            for i in 0..width {
                chain.set(0, i, j, texels[j * width + i]);
            }
        }
        for k in 1..chain.levels.len() {
            let (above, l) = (chain.levels[k - 1], chain.levels[k]);
            for j in 0..l.height {
                for i in 0..l.width {
                    let (i0, j0) = (2 * i, 2 * j);
                    let (i1, j1) = (
                        (i0 + 1).min(above.width - 1),
                        (j0 + 1).min(above.height - 1),
                    );
                    let sum = chain.at(k - 1, i0, j0)
                        + chain.at(k - 1, i1, j0)
                        + chain.at(k - 1, i0, j1)
                        + chain.at(k - 1, i1, j1);
                    chain.set(k, i, j, sum * 0.25);
                }
            }
        }
        chain.pad(wrap_u);
        chain
    }

    /// Slots in all levels.
    #[inline(always)]
    pub(super) fn slots(&self) -> usize {
        self.data.len() / 4
    }

    #[inline(always)]
    fn slot(&self, level: usize, i: usize, j: usize) -> usize {
        let l = &self.levels[level];
        l.offset + j * l.stride() + i + 1
    }

    /// Texel `(i, j)` of `level` (within its size).
    #[inline(always)]
    pub(super) fn at(&self, level: usize, i: usize, j: usize) -> Vec3 {
        let s = 4 * self.slot(level, i, j);
        match self.data.get(s..s + 3) {
            Some(c) => Vec3::new(c[0], c[1], c[2]),
            None => Vec3::ZERO,
        }
    }

    fn set(&mut self, level: usize, i: usize, j: usize, c: Vec3) {
        let s = 4 * self.slot(level, i, j);
        self.data[s..s + 3].copy_from_slice(&c.to_array());
    }

    /// Each row's paddings for `wrap`: the texel across the seam for repeat, the edge texel
    /// for clamp and mirror (whose seams repeat it).
    pub(super) fn pad(&mut self, wrap: Wrap) {
        for k in 0..self.levels.len() {
            let l = self.levels[k];
            for j in 0..l.height {
                let (first, last) = (self.at(k, 0, j), self.at(k, l.width - 1, j));
                let (left, right) = match wrap {
                    Wrap::Repeat => (last, first),
                    Wrap::Clamp | Wrap::Mirror => (first, last),
                };
                let row = 4 * (l.offset + j * l.stride());
                self.data[row..row + 3].copy_from_slice(&left.to_array());
                let end = row + 4 * (l.width + 1);
                self.data[end..end + 3].copy_from_slice(&right.to_array());
            }
        }
    }

    /// Every texel times `f`, non-finite products read as 0.
    pub(super) fn scale(&mut self, f: Vec3) {
        for t in self.data.chunks_exact_mut(4) {
            let c = Vec3::new(t[0], t[1], t[2]) * f;
            let c = Vec3::select(c.is_finite_mask(), c, Vec3::ZERO);
            t[..3].copy_from_slice(&c.to_array());
        }
    }

    /// The two texels from slot `s` on (slot `i + 1` of a row holds texel `i`), as
    /// `[r, g, b, _, r, g, b, _]`; zeros past the end.
    #[inline(always)]
    pub(super) fn pair(&self, s: usize) -> [f32; 8] {
        match self.data.get(4 * s..4 * s + 8) {
            Some(p) => {
                let mut out = [0.0; 8];
                out.copy_from_slice(p);
                out
            }
            None => [0.0; 8],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rows_are_padded_with_the_texel_across_each_seam() {
        let texels: Vec<Vec3> = (0..6).map(|k| Vec3::splat(k as f32)).collect();
        let mut c = Chain::build(3, 2, &texels, Wrap::Repeat);
        // Row 1 is texels 3, 4, 5: repeat pads 5 on the left and 3 on the right.
        let row = c.levels[0].stride();
        assert_eq!(c.pair(row)[0], 5.0);
        assert_eq!(c.pair(row)[4], 3.0);
        assert_eq!(c.pair(row + 3)[4], 3.0);
        c.pad(Wrap::Clamp);
        assert_eq!(c.pair(row)[0], 3.0);
        assert_eq!(c.pair(row + 3)[4], 5.0);
        // 3x2, 1x1: the second level is the mean of the top-left 2x2.
        assert_eq!(c.levels.len(), 2);
        assert_eq!(c.at(1, 0, 0), Vec3::splat(2.0));
        assert_eq!(Chain::bytes_for(3, 2), (5 * 2 + 3) * 16);
    }
}
