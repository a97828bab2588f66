//! Stage 3, BANDS: the image is split into horizontal bands of [`crate::bin::BAND_ROWS`]
//! pixel rows (of samples, when multisampled), drawn in parallel. Each band clears its rows,
//! then sets up and draws the triangles the bin stage recorded for it, chunk after chunk in
//! submission order, so the picture is bit-identical for any thread count (bands depend on the
//! image, not on the threads). Bands are sized by work: a 1080-row image has 68 of them, many
//! more than cores.
//!
//! How a band is drawn is the mode's [`Passes`], chosen once per draw: one pass
//! ([`draw_single`]), or a depth pass ([`depth_pass`]) that leaves the nearest triangle's id per
//! pixel followed by shading from the ids ([`by_pixel_pass`]) and/or a second traversal of
//! the visible triangles ([`visible_pass`]).

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};

use glam::Vec3;
use rayon::prelude::*;

use crate::bin::{Binned, EXTRA_VERTEX, TriRec, band_rows};
use crate::framebuffer::{Framebuffer, clear_rows, mark_dirty, same_color};
use crate::parallel::{effective_threads, pool};
use crate::scanline::{BandTarget, ByPixel, Pass, Planes, depth_only};
use crate::setup::{RasterTri, ScreenPos};
use crate::shade::{Mode, Passes};

/// A thread's buffers for two-pass bands, reused from band to band.
struct Scratch {
    /// The nearest triangle's id per band pixel.
    ids: Vec<u64>,
    /// Per record of the band: whether it is the nearest anywhere after the depth pass (only
    /// such records are visible).
    owns: Vec<bool>,
    /// Per row of the band: the columns the depth pass wrote.
    extents: Vec<(u32, u32)>,
    /// Per record: its index in `planes` (by-pixel shading).
    slot: Vec<u32>,
    /// Attribute planes of the records that were nearest somewhere.
    planes: Vec<Planes>,
}

/// One draw as every band reads it: the mode, the vertex stage's screen positions `pos`
/// ([`ScreenPos::NONE`] where a vertex has none) and attributes `attrs` (`M::ATTRS` per
/// vertex), and the bin stage's chunks.
pub(crate) struct BandInput<'a, M: Mode> {
    /// The draw's mode.
    pub mode: &'a M,
    /// Screen position per mesh vertex.
    pub pos: &'a [ScreenPos],
    /// Attributes per mesh vertex.
    pub attrs: &'a [f32],
    /// Binned triangles, in submission order.
    pub chunks: &'a [Binned<M::Tri>],
    /// Perspective-correct attributes.
    pub perspective: bool,
}

impl<M: Mode> BandInput<'_, M> {
    /// The screen positions and first `n` attributes of record `r`'s vertices: from `c`'s
    /// clipped vertices, or from the draw's per-vertex arrays; `None` when a vertex is
    /// missing or has no screen position.
    #[inline(always)]
    fn vertices_of<'c>(
        &'c self,
        r: &TriRec,
        c: &'c Binned<M::Tri>,
        n: usize,
    ) -> Option<([ScreenPos; 3], [&'c [f32]; 3])> {
        if r.v.iter().any(|&i| i & EXTRA_VERTEX != 0) {
            let v = r.v.map(|i| c.extra.get((i & !EXTRA_VERTEX) as usize));
            let [Some(a), Some(b), Some(d)] = v else {
                return None;
            };
            return Some(([a.pos(), b.pos(), d.pos()], [&a.attrs, &b.attrs, &d.attrs]));
        }
        let p =
            r.v.map(|i| self.pos.get(i as usize).copied().unwrap_or(ScreenPos::NONE));
        if p.iter().any(ScreenPos::is_none) {
            return None;
        }
        let stride = M::ATTRS;
        let a = r.v.map(|i| {
            let i = i as usize;
            self.attrs.get(i * stride..(i + 1) * stride).unwrap_or(&[])
        });
        a.iter().all(|a| a.len() >= n).then_some((p, a))
    }

    /// Set-up of record `r` of chunk `c` into `t` with `n` attributes; false when it has no
    /// vertices or no area.
    #[inline(always)]
    fn setup(&self, t: &mut RasterTri, c: &Binned<M::Tri>, r: &TriRec, n: usize) -> bool {
        self.vertices_of(r, c, n)
            .is_some_and(|(p, a)| t.set(p, a, n, self.perspective))
    }

    /// Reads the first vertex data set-up will need of record `r` (one [`AHEAD`] places on),
    /// so that the cache misses of fetching it (vertices are scattered over the mesh) overlap
    /// the work on the records before it: a prefetch in safe code. The value is folded into a
    /// sink so that the loads are kept.
    #[inline(always)]
    fn touch(&self, r: Option<&TriRec>, n: usize) -> u32 {
        let Some(r) = r else { return 0 };
        let mut sink = 0u32;
        for &i in &r.v {
            if i & EXTRA_VERTEX == 0 {
                sink ^= self.pos.get(i as usize).map_or(0, |p| p.fx as u32);
                if n > 0 {
                    sink ^= self
                        .attrs
                        .get(i as usize * M::ATTRS)
                        .map_or(0, |a| a.to_bits());
                }
            }
        }
        sink
    }

    /// Band `b`'s records, chunk after chunk, with the chunk each belongs to.
    fn records(&self, b: usize) -> impl Iterator<Item = (&Binned<M::Tri>, &[TriRec])> {
        self.chunks.iter().map(move |c| (c, c.band(b)))
    }
}

/// How many records ahead the band loops touch vertex data ([`BandInput::touch`]).
const AHEAD: usize = 4;

/// Ids of the depth pass: a fresh epoch per band job in the high bits, so ids left in a
/// thread's scratch by earlier jobs never match.
static EPOCH: AtomicU64 = AtomicU64::new(1);

thread_local! {
    /// Per-thread scratch of two-pass bands.
    static SCRATCH: RefCell<Scratch> = const {
        RefCell::new(Scratch {
            ids: Vec::new(),
            owns: Vec::new(),
            extents: Vec::new(),
            slot: Vec::new(),
            planes: Vec::new(),
        })
    };
}

/// Draws `input` into `fb` over bands on `threads`. With `block > 1` the image holds samples,
/// `block x block` per pixel, and the by-pixel pass shades each triangle once per pixel
/// ([`ByPixel::block`]); `count` is the coverage-count test hook (no depth test, every band
/// one pass). Returns the pixels (or, multisampled, the pixel and triangle pairs) shaded.
pub(crate) fn draw_bands<M: Mode>(
    fb: &mut Framebuffer,
    input: &BandInput<M>,
    threads: usize,
    count: bool,
    block: u32,
) -> u64 {
    let band_rows = band_rows(block);
    let width = fb.width();
    let chunk = (band_rows * width) as usize;
    let clear = fb.pending_clear.take();
    // Outside its dirty columns a row already holds the last clear's colour and depth.
    let only_dirty = clear.is_some_and(|bg| same_color(fb.clean, bg));
    if clear.is_some() {
        fb.clean = clear;
    }
    let (color, depth, dirty) = (&mut fb.color, &mut fb.depth, &mut fb.dirty);
    type Rows<'a> = ((&'a mut [Vec3], &'a mut [f32]), &'a mut [(u32, u32)]);
    let run = |(b, ((color, depth), dirty)): (usize, Rows)| -> u64 {
        if let Some(bg) = clear {
            // The frame's clear, deferred to here: each band clears its rows in parallel,
            // just before drawing them (they stay in cache).
            clear_rows((color, depth, dirty), width, bg, only_dirty);
        }
        let y0 = b as i64 * band_rows as i64;
        let in_band: usize = input.records(b).map(|(_, r)| r.len()).sum();
        let mut target = BandTarget::new(color, depth, width, y0, count);
        if M::PASSES == Passes::Single || count || in_band < 2 {
            return draw_single(input, b, &mut target, dirty);
        }
        SCRATCH.with(|scratch| {
            let scratch = &mut *scratch.borrow_mut();
            draw_two_pass(input, b, target, dirty, scratch, block)
        })
    };
    let threads = effective_threads(threads);
    match (threads > 1).then(|| pool(threads)).flatten() {
        Some(p) => p.install(|| {
            let jobs = color.par_chunks_mut(chunk).zip(depth.par_chunks_mut(chunk));
            let jobs = jobs.zip(dirty.par_chunks_mut(band_rows as usize));
            jobs.enumerate().map(run).sum()
        }),
        None => {
            let jobs = color.chunks_mut(chunk).zip(depth.chunks_mut(chunk));
            let jobs = jobs.zip(dirty.chunks_mut(band_rows as usize));
            jobs.enumerate().map(run).sum()
        }
    }
}

/// Band `b` in one pass: each triangle depth-tested, shaded and written in turn. Widens the
/// band's `dirty` columns by every triangle's box. Returns the pixels shaded.
fn draw_single<M: Mode>(
    input: &BandInput<M>,
    b: usize,
    target: &mut BandTarget,
    dirty: &mut [(u32, u32)],
) -> u64 {
    let (n, width, y0) = (M::ATTRS, target.width, target.y0);
    let mut t = RasterTri::empty();
    let (mut shaded, mut sink) = (0, 0);
    for (c, recs) in input.records(b) {
        for (i, r) in recs.iter().enumerate() {
            sink ^= input.touch(recs.get(i + AHEAD), n);
            if let Some(tri) = c.tris.get(r.tri as usize) {
                if input.setup(&mut t, c, r, n) {
                    // A mode writes only inside the triangle's pixel box.
                    mark_dirty(dirty, y0, (t.y0, t.y1), (t.x0, t.x1), width);
                    shaded += input.mode.draw(&t, tri, target);
                }
            }
        }
    }
    std::hint::black_box(sink);
    shaded
}

/// Band `b` in two passes: the depth pass, then the by-pixel pass ([`Passes::ByPixel`]) and/or
/// the visible pass over the triangles that own a pixel. Returns the pixels shaded.
fn draw_two_pass<'s, M: Mode>(
    input: &BandInput<M>,
    b: usize,
    mut target: BandTarget<'s>,
    dirty: &mut [(u32, u32)],
    scratch: &'s mut Scratch,
    block: u32,
) -> u64 {
    let width = target.width as usize;
    if scratch.ids.len() < target.color.len() {
        scratch.ids.resize(target.color.len(), 0);
    }
    scratch.extents.clear();
    let rows = target.color.len() / width.max(1);
    scratch.extents.resize(rows, (u32::MAX, 0));
    let epoch = EPOCH.fetch_add(1, Ordering::Relaxed) << 32;
    let (ids, extents) = (&mut scratch.ids, &mut scratch.extents);
    let records = depth_pass(input, b, &mut target, ids, extents, epoch);
    mark_owners(ids, extents, width, epoch, records, &mut scratch.owns);
    // Only the depth pass writes outside the pixels it recorded (the shading passes write
    // where it did).
    for (d, e) in dirty.iter_mut().zip(scratch.extents.iter()) {
        *d = (d.0.min(e.0), d.1.max(e.1));
    }
    let (mut shaded, mut traced) = (0, true);
    if M::PASSES == Passes::ByPixel {
        (shaded, traced) = by_pixel_pass(input, b, &mut target, scratch, epoch, block);
    }
    if traced {
        let scratch: &'s Scratch = scratch;
        target.ids = &scratch.ids;
        shaded += visible_pass(input, b, &mut target, &scratch.owns, epoch);
    }
    shaded
}

/// The by-pixel pass of band `b` ([`Passes::ByPixel`]), after the depth pass left its ids in
/// `scratch`: the planes of the visible records ([`visible_planes`]), then every pixel whose
/// id names one of them gets [`Mode::shade4`] of its attributes, with no second traversal.
/// Returns the pixels (or pixel and triangle pairs) shaded, and whether some visible record
/// is left for [`visible_pass`].
fn by_pixel_pass<M: Mode>(
    input: &BandInput<M>,
    b: usize,
    target: &mut BandTarget,
    scratch: &mut Scratch,
    epoch: u64,
    block: u32,
) -> (u64, bool) {
    let Scratch {
        ids,
        owns,
        extents,
        slot,
        planes,
    } = scratch;
    let traced = visible_planes(input, b, owns, slot, planes);
    let pass = ByPixel {
        slot,
        planes,
        ids,
        epoch,
        extents,
        width: target.width,
        y0: target.y0,
        n: M::ATTRS,
        perspective: input.perspective && M::ATTRS > 0,
        block: block as usize,
    };
    (input.mode.shade_pixels(&pass, target.color), traced)
}

/// The depth pass of band `b`: every triangle set up without attributes (the same edges and
/// depth plane), depth-tested and written, and `ids[pixel]` set to `epoch + k` where record
/// `k` of the band is now the nearest; `extents[row]` is widened to the columns written.
/// Returns the band's record count.
fn depth_pass<M: Mode>(
    input: &BandInput<M>,
    b: usize,
    target: &mut BandTarget,
    ids: &mut [u64],
    extents: &mut [(u32, u32)],
    epoch: u64,
) -> usize {
    let mut t = RasterTri::empty();
    let (mut seq, mut sink) = (epoch, 0);
    for (c, recs) in input.records(b) {
        for (i, r) in recs.iter().enumerate() {
            sink ^= input.touch(recs.get(i + AHEAD), 0);
            if input.setup(&mut t, c, r, 0) {
                depth_only(&t, target, ids, extents, seq);
            }
            seq += 1;
        }
    }
    std::hint::black_box(sink);
    (seq - epoch) as usize
}

/// `owns[k]`: whether record `k` of `records` owns a pixel after the depth pass, from the ids
/// it left inside `extents` (rows `width` pixels wide). Only those records are visible: a
/// triangle nearest somewhere when drawn is often covered later by a nearer one (about half
/// of them in S1).
fn mark_owners(
    ids: &[u64],
    extents: &[(u32, u32)],
    width: usize,
    epoch: u64,
    records: usize,
    owns: &mut Vec<bool>,
) {
    owns.clear();
    owns.resize(records, false);
    for (row, &(lo, hi)) in extents.iter().enumerate() {
        let (lo, hi) = (
            row * width + lo as usize,
            row * width + (hi as usize).min(width),
        );
        for &id in ids.get(lo..hi).unwrap_or(&[]) {
            // Ids below the epoch were left by earlier bands.
            if let Some(o) = id.checked_sub(epoch).and_then(|k| owns.get_mut(k as usize)) {
                *o = true;
            }
        }
    }
}

/// The attribute planes of band `b`'s records that own a pixel and are shaded by pixel
/// ([`Mode::by_pixel`]): `slot[k]` is record `k`'s index in `planes`, or `u32::MAX`.
/// Returns whether some owner is not shaded by pixel (and needs [`visible_pass`]).
fn visible_planes<M: Mode>(
    input: &BandInput<M>,
    b: usize,
    owns: &[bool],
    slot: &mut Vec<u32>,
    planes: &mut Vec<Planes>,
) -> bool {
    let n = M::ATTRS;
    let mut t = RasterTri::empty();
    slot.clear();
    planes.clear();
    let (mut k, mut traced, mut sink) = (0, false, 0);
    for (c, recs) in input.records(b) {
        for (i, r) in recs.iter().enumerate() {
            if owns.get(k + AHEAD) == Some(&true) {
                sink ^= input.touch(recs.get(i + AHEAD), n);
            }
            let owner = owns.get(k) == Some(&true);
            let by_pixel = owner && c.tris.get(r.tri as usize).is_some_and(M::by_pixel);
            traced |= owner && !by_pixel;
            // Its pixels are known: the planes alone.
            let visible = by_pixel
                && input
                    .vertices_of(r, c, n)
                    .is_some_and(|(p, a)| t.set_planes(p, a, n, input.perspective));
            slot.push(if visible {
                planes.len() as u32
            } else {
                u32::MAX
            });
            if visible {
                planes.push(Planes::of(&t));
            }
            k += 1;
        }
    }
    std::hint::black_box(sink);
    traced
}

/// The visible pass of band `b`: the records that own a pixel (after a by-pixel pass, only
/// those it left out) traversed again, each pixel shaded where its id (in `target.ids`)
/// names them. Returns the pixels shaded.
fn visible_pass<M: Mode>(
    input: &BandInput<M>,
    b: usize,
    target: &mut BandTarget,
    owns: &[bool],
    epoch: u64,
) -> u64 {
    let n = M::ATTRS;
    let by_pixel_done = M::PASSES == Passes::ByPixel;
    let mut t = RasterTri::empty();
    let (mut shaded, mut seq) = (0, epoch);
    for (c, recs) in input.records(b) {
        for r in recs {
            let owner = owns.get((seq - epoch) as usize) == Some(&true);
            if let (true, Some(tri)) = (owner, c.tris.get(r.tri as usize)) {
                if !(by_pixel_done && M::by_pixel(tri)) && input.setup(&mut t, c, r, n) {
                    target.pass = Pass::Visible(seq);
                    shaded += input.mode.draw(&t, tri, target);
                }
            }
            seq += 1;
        }
    }
    input.mode.finish(target);
    shaded
}
