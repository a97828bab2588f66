//! Multisampled by-pixel shading: a band of samples, `K x K` per output pixel, shaded once
//! per block and triangle. A block whose samples all show one triangle is shaded at its
//! centre (runs of such blocks stepped by `K dA/dx`); a block on an edge once for each
//! triangle it shows, at the centroid of that triangle's samples, and each colour written to
//! every sample of its triangle in the block. With a pixel layer
//! ([`crate::framebuffer::layer`]) a whole block's colour is written once, to its pixel.

use glam::Vec3;

use crate::batch::{Pending, RowShader};
use crate::bypixel::ByPixel;
use crate::clip::MAX_ATTRS;
use crate::coverage::lanes;
use crate::framebuffer::layer::{LayerRows, SPLIT, WHOLE, fill_block};
use crate::traverse::planes_at;

impl ByPixel<'_> {
    /// [`ByPixel::shade`] of a multisampled band, `K x K` samples per pixel (`S` = `K * K`).
    pub(crate) fn shade_blocks<const N: usize, const K: usize, const S: usize>(
        &self,
        color: &mut [Vec3],
        layer: Option<&mut LayerRows<'_>>,
        shade: &RowShader<'_, N>,
    ) -> u64 {
        let mut out = BlockOut {
            samples: color,
            layer,
            width: self.width as usize,
        };
        let out = &mut out;
        match (self.perspective, lanes(self.n)) {
            (true, 0) => self.run_blocks::<N, true, 0, K, S>(out, shade),
            (true, 4) => self.run_blocks::<N, true, 4, K, S>(out, shade),
            (true, 8) => self.run_blocks::<N, true, 8, K, S>(out, shade),
            (true, _) => self.run_blocks::<N, true, MAX_ATTRS, K, S>(out, shade),
            (false, 0) => self.run_blocks::<N, false, 0, K, S>(out, shade),
            (false, 4) => self.run_blocks::<N, false, 4, K, S>(out, shade),
            (false, 8) => self.run_blocks::<N, false, 8, K, S>(out, shade),
            (false, _) => self.run_blocks::<N, false, MAX_ATTRS, K, S>(out, shade),
        }
    }

    /// The columns of blocks in block row `by` that the depth pass wrote in any of its rows.
    fn block_columns<const K: usize>(&self, by: usize) -> std::ops::Range<usize> {
        block_columns::<K>(self.extents, self.width as usize, by)
    }

    /// [`ByPixel::shade`] once per `K x K` block and triangle: a block whose samples all show
    /// one triangle is shaded at its centre, and a run of such blocks is stepped by
    /// `K * dA/dx`; a block on an edge is shaded once for each triangle it shows, at the
    /// centroid of that triangle's samples. Each colour is written to every sample of its
    /// triangle in the block.
    #[inline(always)]
    fn run_blocks<
        const N: usize,
        const PERSPECTIVE: bool,
        const L: usize,
        const K: usize,
        const S: usize,
    >(
        &self,
        out: &mut BlockOut,
        shade4: &RowShader<'_, N>,
    ) -> u64 {
        let kf = K as f64;
        let width = self.width as usize;
        let pixels = width / K;
        let all = block_mask::<K>();
        let mut shaded = 0;
        let mut pending = Pending::<BlockSamples, N>::new(self.ceiling);
        for by in 0..self.extents.len() / K {
            let top = (self.y0 + (by * K) as i64) as f64;
            // The run of whole blocks being stepped, as in `run`, by K pixels a block.
            let (mut run, mut next) = (u64::MAX, usize::MAX);
            let (mut inv_w, mut attrs) = (1.0f64, [0.0f32; MAX_ATTRS]);
            let (mut step_w, mut step) = (0.0f64, [0.0f32; MAX_ATTRS]);
            // The ids of the block being walked, where `whole` does not give one for all.
            let mut ids = [u64::MAX; S];
            for bx in self.block_columns::<K>(by) {
                let base = by * K * width + bx * K;
                let pixel = by * pixels + bx;
                // The id every sample of the block shows (`whole`'s, or the samples'), or
                // none, and then the samples' ids are in `ids`.
                let shared = match self.whole.get(pixel) {
                    Some(&id) if id != SPLIT_BLOCK => Some(id),
                    _ => {
                        let Some(read) = self.block_ids::<K, S>(base) else {
                            continue;
                        };
                        ids = read;
                        ids[1..].iter().all(|&id| id == ids[0]).then_some(ids[0])
                    }
                };
                if let Some(id) = shared {
                    if id == run && bx == next {
                        if PERSPECTIVE {
                            inv_w += step_w;
                        }
                        for j in 0..L {
                            attrs[j] += step[j];
                        }
                    } else {
                        let Some(p) = self.planes_of(id) else {
                            continue;
                        };
                        let o = (
                            (bx * K) as f64 + kf * 0.5 - p.origin.0,
                            top + kf * 0.5 - p.origin.1,
                        );
                        (inv_w, attrs) =
                            planes_at(&p.inv_w, [&p.attr0, &p.attr_dx, &p.attr_dy], o, L);
                        step_w = kf * p.inv_w[1];
                        for j in 0..L {
                            step[j] = (kf * f64::from(p.attr_dx[j])) as f32;
                        }
                        run = id;
                    }
                    next = bx + 1;
                    let w = if PERSPECTIVE {
                        (1.0 / inv_w) as f32
                    } else {
                        1.0
                    };
                    if pending.queue((base, pixel, all), (&attrs, w, L)) {
                        pending.flush_into(shade4, |at, c| out.write::<K>(at, c));
                    }
                    shaded += 1;
                    continue;
                }
                // An edge: once per triangle shown, at the centroid of its samples.
                run = u64::MAX;
                // The samples this pass leaves as they were: other draws', or the clear.
                let mut keep = 0u16;
                let mut left = all;
                while left != 0 {
                    let first = left.trailing_zeros() as usize;
                    let id = ids[first];
                    // Every sample of `id` is still left (an earlier id took only its own),
                    // so all of them are compared, without a branch per sample.
                    let mask = ids
                        .iter()
                        .enumerate()
                        .fold(0u16, |m, (j, &other)| m | u16::from(other == id) << j);
                    left &= !mask;
                    let Some(p) = self.planes_of(id) else {
                        keep |= mask;
                        continue;
                    };
                    let (cx, cy) = centroid::<K>(mask);
                    let o = ((bx * K) as f64 + cx - p.origin.0, top + cy - p.origin.1);
                    let (iw, a) = planes_at(&p.inv_w, [&p.attr0, &p.attr_dx, &p.attr_dy], o, L);
                    let w = if PERSPECTIVE { (1.0 / iw) as f32 } else { 1.0 };
                    if pending.queue((base, pixel, mask), (&a, w, L)) {
                        pending.flush_into(shade4, |at, c| out.write::<K>(at, c));
                    }
                    shaded += 1;
                }
                out.split::<K>(base, pixel, keep);
            }
        }
        pending.flush_into(shade4, |at, c| out.write::<K>(at, c));
        shaded
    }

    /// The ids of the `K x K` samples of the block whose first sample is `base` (rows, then
    /// columns); `None` past the band's ids.
    #[inline(always)]
    fn block_ids<const K: usize, const S: usize>(&self, base: usize) -> Option<[u64; S]> {
        let mut ids = [u64::MAX; S];
        for sy in 0..K {
            let row = base + sy * self.width as usize;
            ids[sy * K..(sy + 1) * K].copy_from_slice(self.ids.get(row..row + K)?);
        }
        Some(ids)
    }
}

/// The columns of `K x K` blocks in block row `by` that the depth pass wrote in any of its
/// rows (`extents` per sample row, rows `width` samples long).
fn block_columns<const K: usize>(
    extents: &[(u32, u32)],
    width: usize,
    by: usize,
) -> std::ops::Range<usize> {
    let rows = extents.get(by * K..((by + 1) * K).min(extents.len()));
    let (lo, hi) = rows
        .unwrap_or(&[])
        .iter()
        .fold((usize::MAX, 0), |(lo, hi), &(l, h)| {
            let h = (h as usize).min(width);
            if (l as usize) < h {
                (lo.min(l as usize), hi.max(h))
            } else {
                (lo, hi)
            }
        });
    if lo >= hi {
        0..0
    } else {
        lo / K..hi.div_ceil(K)
    }
}

/// In [`mark_blocks`]' `whole`: the block's four samples do not all show one id (or all show
/// this one, which no triangle has; the walk then reads them again).
pub(crate) const SPLIT_BLOCK: u64 = u64::MAX;

/// The ids of a band of `2 x 2` blocks read once, after the depth pass: `owns[k]` is set for
/// every record `k` (id `epoch + k`) that some sample shows, as `mark_owners` does for any
/// band, and `whole[by * (width / 2) + bx]` is the id all four samples of block `(bx, by)`
/// show, or [`SPLIT_BLOCK`]. Written only for the blocks that the walk visits (those of
/// `block_columns`); the rest of `whole` keeps what it held. The walk then reads one id
/// for a block inside a triangle, most of them, and its four samples' ids only on an edge.
/// Two blocks are compared at a time, in lanes where the CPU has AVX2; either way the same.
///
/// A block's columns may reach past what the depth pass wrote in one of its two rows: the ids
/// there were left by earlier bands, below the epoch, so no record is marked for them.
pub(crate) fn mark_blocks(
    ids: &[u64],
    (extents, width): (&[(u32, u32)], usize),
    epoch: u64,
    owns: &mut [bool],
    (whole, avx2): (&mut Vec<u64>, Option<crate::simd::Avx2>),
) {
    let pixels = width / 2;
    let rows = extents.len() / 2;
    if whole.len() < rows * pixels {
        whole.resize(rows * pixels, SPLIT_BLOCK);
    }
    let band = BlockIds {
        ids,
        extents,
        width,
        epoch,
    };
    #[cfg(target_arch = "x86_64")]
    if let Some(avx2) = avx2 {
        return avx2.run(MarkBlocksRun { band, owns, whole });
    }
    let _ = avx2;
    band.mark(owns, whole, same_pairs);
}

/// A band's sample ids, as [`mark_blocks`] reads them.
#[derive(Clone, Copy)]
struct BlockIds<'a> {
    ids: &'a [u64],
    extents: &'a [(u32, u32)],
    width: usize,
    epoch: u64,
}

impl BlockIds<'_> {
    /// [`mark_blocks`] with `same(top, bottom)`: for two blocks side by side, their top and
    /// bottom sample rows, bit `j` set where block `j`'s four samples show one id.
    #[inline(always)]
    fn mark(self, owns: &mut [bool], whole: &mut [u64], same: impl Fn([u64; 4], [u64; 4]) -> u32) {
        let (width, epoch) = (self.width, self.epoch);
        let mut mark = |id: u64| crate::two_pass::mark(owns, id, epoch);
        let pixels = width / 2;
        for by in 0..self.extents.len() / 2 {
            let cols = block_columns::<2>(self.extents, width, by);
            let Some(out) = whole.get_mut(by * pixels + cols.start..by * pixels + cols.end) else {
                continue;
            };
            let top = 2 * by * width + 2 * cols.start;
            let samples = 2 * out.len();
            let (Some(r0), Some(r1)) = (
                self.ids.get(top..top + samples),
                self.ids.get(top + width..top + width + samples),
            ) else {
                out.fill(SPLIT_BLOCK);
                continue;
            };
            let mut last = SPLIT_BLOCK;
            let mut pair = |a: [u64; 4], b: [u64; 4], w: &mut [u64], bits: u32| {
                for (j, w) in w.iter_mut().enumerate() {
                    if bits >> j & 1 != 0 {
                        let id = a[2 * j];
                        *w = id;
                        if id != last {
                            mark(id);
                            last = id;
                        }
                    } else {
                        *w = SPLIT_BLOCK;
                        for id in [a[2 * j], a[2 * j + 1], b[2 * j], b[2 * j + 1]] {
                            mark(id);
                        }
                        last = SPLIT_BLOCK;
                    }
                }
            };
            let (mut r0s, mut r1s) = (r0.chunks_exact(4), r1.chunks_exact(4));
            let mut outs = out.chunks_exact_mut(2);
            for ((a, b), w) in r0s.by_ref().zip(r1s.by_ref()).zip(outs.by_ref()) {
                let (a, b) = (four(a), four(b));
                pair(a, b, w, same(a, b));
            }
            // An odd block at the end, compared beside a copy of itself.
            if let ([a0, a1], [b0, b1], w) =
                (r0s.remainder(), r1s.remainder(), outs.into_remainder())
            {
                let (a, b) = ([*a0, *a1, *a0, *a1], [*b0, *b1, *b0, *b1]);
                pair(a, b, w, same(a, b));
            }
        }
    }
}

/// Four ids from a slice of exactly four.
#[inline(always)]
fn four(ids: &[u64]) -> [u64; 4] {
    std::array::from_fn(|j| ids[j])
}

/// [`BlockIds::mark`]'s comparison one id at a time.
#[inline(always)]
fn same_pairs(a: [u64; 4], b: [u64; 4]) -> u32 {
    let one = |j: usize| a[j] == a[j + 1] && a[j] == b[j] && a[j + 1] == b[j + 1];
    u32::from(one(0)) | u32::from(one(2)) << 1
}

/// [`mark_blocks`]' loop as one AVX2 task, the ids compared four at a time.
#[cfg(target_arch = "x86_64")]
struct MarkBlocksRun<'a> {
    band: BlockIds<'a>,
    owns: &'a mut [bool],
    whole: &'a mut [u64],
}

#[cfg(target_arch = "x86_64")]
impl phosphor_lighting::Avx2Task for MarkBlocksRun<'_> {
    type Output = ();
    #[inline(always)]
    fn run(self, avx2: phosphor_lighting::Avx2) {
        let v = avx2.v3();
        self.band.mark(self.owns, self.whole, |a, b| {
            let a: std::arch::x86_64::__m256i = pulp::cast(a);
            // Each sample against the one below it and the one beside it.
            let below = v.avx2._mm256_cmpeq_epi64(a, pulp::cast(b));
            let beside = v.avx._mm256_permute_pd::<0b0101>(pulp::cast(a));
            let beside = v.avx2._mm256_cmpeq_epi64(a, pulp::cast(beside));
            let both = v.avx2._mm256_and_si256(below, beside);
            let m = v.avx._mm256_movemask_pd(pulp::cast(both)) as u32;
            u32::from(m & 3 == 3) | u32::from(m >> 2 == 3) << 1
        });
    }
}

/// The mask of every sample of a `K x K` block (bit `sy * K + sx`).
#[inline(always)]
const fn block_mask<const K: usize>() -> u16 {
    if K * K >= 16 {
        u16::MAX
    } else {
        (1 << (K * K)) - 1
    }
}

/// The centroid, in samples from the block's corner, of the samples in `mask` (bit
/// `sy * K + sx`; not empty) of a `K x K` block, each sample counted at its centre: looked up
/// for 2 x 2 blocks, whose 16 masks make a small table.
#[inline(always)]
fn centroid<const K: usize>(mask: u16) -> (f64, f64) {
    if K == 2 {
        CENTROIDS_2X2[usize::from(mask) & 15]
    } else {
        centroid_of(mask, K)
    }
}

/// [`centroid`] of every mask of a 2 x 2 block.
const CENTROIDS_2X2: [(f64, f64); 16] = {
    let mut table = [(0.0, 0.0); 16];
    let mut mask = 1;
    while mask < 16 {
        table[mask] = centroid_of(mask as u16, 2);
        mask += 1;
    }
    table
};

/// [`centroid`] of `mask` in a `k x k` block, summed in integers (twice the offsets).
const fn centroid_of(mask: u16, k: usize) -> (f64, f64) {
    let (mut sx, mut sy, mut j) = (0u32, 0u32, 0);
    while j < k * k {
        if mask & (1 << j) != 0 {
            sx += 2 * (j % k) as u32 + 1;
            sy += 2 * (j / k) as u32 + 1;
        }
        j += 1;
    }
    let twice_count = 2.0 * mask.count_ones() as f64;
    (sx as f64 / twice_count, sy as f64 / twice_count)
}

/// Where a multisampled shading's colour goes: the first sample of its block, the block's
/// pixel in the band, and a mask of the block's samples (bit `sy * K + sx`) that take it.
type BlockSamples = (usize, usize, u16);

/// A multisampled band's colours: its samples (rows `width` long) and, when the image has
/// one, its pixel layer's rows ([`crate::framebuffer::layer`]).
pub(crate) struct BlockOut<'o, 'l> {
    samples: &'o mut [Vec3],
    layer: Option<&'o mut LayerRows<'l>>,
    width: usize,
}

impl BlockOut<'_, '_> {
    /// Writes colour `c` to the samples `(base, pixel, mask)` of a `K x K` block: a whole
    /// block to its pixel's colour in the pixel layer (the pixel becomes whole), or to its
    /// samples when the image has no layer; part of one to its samples, the block's pixel
    /// being split already ([`BlockOut::split`]).
    #[inline(always)]
    fn write<const K: usize>(&mut self, (base, pixel, mask): BlockSamples, c: Vec3) {
        if mask != block_mask::<K>() {
            write_masked::<K>(self.samples, self.width, base, mask, c);
        } else if let Some(layer) = &mut self.layer {
            if let (Some(color), Some(split)) =
                (layer.color.get_mut(pixel), layer.split.get_mut(pixel))
            {
                (*color, *split) = (c, WHOLE);
            }
        } else {
            fill_block(self.samples, self.width, base, K, c);
        }
    }

    /// Splits the pixel of an edge block (first sample `base`, pixel `pixel`) before or
    /// after its triangles' colours are written: when the layer holds the pixel whole, its
    /// colour goes to the samples in `keep`, the ones no triangle of this pass writes (the
    /// others take their triangles' colours whenever those are written), and the pixel is
    /// marked split.
    #[inline(always)]
    fn split<const K: usize>(&mut self, base: usize, pixel: usize, keep: u16) {
        let Some(layer) = &mut self.layer else {
            return;
        };
        let (Some(color), Some(split)) = (layer.color.get(pixel), layer.split.get_mut(pixel))
        else {
            return;
        };
        if *split == WHOLE {
            write_masked::<K>(self.samples, self.width, base, keep, *color);
            *split = SPLIT;
        }
    }
}

/// Writes `c` to the samples in `mask` (bit `sy * K + sx`) of the `K x K` block whose first
/// sample is `base`, in rows `width` samples long: one step per sample in the mask, none for
/// an empty one.
#[inline(always)]
fn write_masked<const K: usize>(
    samples: &mut [Vec3],
    width: usize,
    base: usize,
    mask: u16,
    c: Vec3,
) {
    let mut left = mask;
    while left != 0 {
        let j = left.trailing_zeros() as usize;
        left &= left - 1;
        if let Some(p) = samples.get_mut(base + (j / K) * width + j % K) {
            *p = c;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn blocks_marked_in_one_read_agree_with_their_samples() {
        // A band of 6 sample rows, 12 wide: ids of this band (epoch + 0..5) and ones left by
        // earlier bands (below the epoch), with extents that differ between a block's rows.
        let (width, epoch) = (12usize, 7u64 << 32);
        let mut seed = 12345u32;
        let mut pick = |n: u32| {
            seed = seed.wrapping_mul(1_103_515_245).wrapping_add(12345);
            (seed >> 16) % n
        };
        // Per block one id, and one sample in four (about) another.
        let block: Vec<u32> = (0..18).map(|_| pick(5)).collect();
        let ids: Vec<u64> = (0..6 * width)
            .map(|i| {
                let b = block[(i / width / 2) * 6 + (i % width) / 2];
                let v = if pick(4) == 0 { pick(5) } else { b };
                match v {
                    0..=2 => epoch + u64::from(v),
                    3 => 3,
                    _ => u64::MAX,
                }
            })
            .collect();
        let extents = [(0, 12), (2, 9), (5, 5), (u32::MAX, 0), (1, 3), (7, 12)];
        for avx2 in [None, crate::simd::SimdLevel::Avx2.token()] {
            let mut owns = vec![false; 6];
            // Whatever `whole` held before stays outside the visited blocks.
            let mut whole = vec![42u64; 18];
            mark_blocks(
                &ids,
                (&extents, width),
                epoch,
                &mut owns,
                (&mut whole, avx2),
            );
            check_blocks(&ids, &extents, epoch, &owns, &whole);
        }
    }

    /// [`mark_blocks`]' `owns` and `whole` against the ids, one by one.
    fn check_blocks(ids: &[u64], extents: &[(u32, u32)], epoch: u64, owns: &[bool], whole: &[u64]) {
        let width = 12;
        let mut seen = vec![false; 6];
        for (row, &(lo, hi)) in extents.iter().enumerate() {
            for x in lo as usize..(hi as usize).min(width) {
                let id = ids[row * width + x];
                if id >= epoch && id - epoch < 6 {
                    seen[(id - epoch) as usize] = true;
                }
            }
        }
        assert_eq!(owns, seen);
        for by in 0..3 {
            let cols = block_columns::<2>(extents, width, by);
            for bx in 0..6 {
                let at = 2 * by * width + 2 * bx;
                let four = [ids[at], ids[at + 1], ids[at + width], ids[at + width + 1]];
                let got = whole[by * 6 + bx];
                if !cols.contains(&bx) {
                    assert_eq!(got, 42, "block ({bx}, {by}) is not visited");
                } else if four.iter().all(|&id| id == four[0]) {
                    assert_eq!(got, four[0], "block ({bx}, {by}): {four:?}");
                } else {
                    assert_eq!(got, SPLIT_BLOCK, "block ({bx}, {by}): {four:?}");
                }
            }
        }
        // Some block of each kind, so that the checks above test both.
        let shared = whole.iter().filter(|&&w| w != 42 && w != SPLIT_BLOCK);
        assert!(shared.count() > 0 && whole.contains(&SPLIT_BLOCK));
    }

    #[test]
    fn centroids_are_the_mean_of_the_sample_centres() {
        // 2 x 2 (bits: 0 top left, 1 top right, 2 bottom left, 3 bottom right).
        assert_eq!(centroid::<2>(0b0001), (0.5, 0.5));
        assert_eq!(centroid::<2>(0b1000), (1.5, 1.5));
        assert_eq!(centroid::<2>(0b0011), (1.0, 0.5));
        assert_eq!(centroid::<2>(0b0101), (0.5, 1.0));
        assert_eq!(centroid::<2>(0b1111), (1.0, 1.0));
        assert_eq!(centroid::<2>(0b0111), (2.5 / 3.0, 2.5 / 3.0));
        // 4 x 4: the whole block, one corner, the bottom row.
        assert_eq!(centroid::<4>(u16::MAX), (2.0, 2.0));
        assert_eq!(centroid::<4>(1 << 15), (3.5, 3.5));
        assert_eq!(centroid::<4>(0xF000), (2.0, 3.5));
        // The table agrees with a sum of f64 sample centres for every 2 x 2 mask.
        for mask in 1u16..16 {
            let bits: Vec<usize> = (0..4).filter(|j| mask & (1 << j) != 0).collect();
            let n = bits.len() as f64;
            let sx = bits.iter().map(|j| (j % 2) as f64 + 0.5).sum::<f64>() / n;
            let sy = bits.iter().map(|j| (j / 2) as f64 + 0.5).sum::<f64>() / n;
            assert_eq!(centroid::<2>(mask), (sx, sy), "mask {mask:04b}");
        }
    }
}
