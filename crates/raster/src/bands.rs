//! The parallel split: horizontal bands of [`BAND_ROWS`] scan lines. Triangles are accepted
//! (culled, rejected when empty) and binned to the bands they touch in parallel chunks, each
//! chunk's records grouped by band in submission order; every band then sets up and draws its
//! triangles chunk after chunk, so the picture is bit-identical for any thread count (bands
//! depend on the image, not on the threads). Bands are sized by work: a 1080-row image has 68
//! of them, many more than cores.

use std::cell::RefCell;
use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::{Arc, Mutex, OnceLock};

use rayon::prelude::*;

use crate::framebuffer::{Framebuffer, clear_rows, mark_dirty, same_color};
use crate::scanline::{BandTarget, ByPixel, Pass, Planes, depth_only};
use crate::setup::{RasterTri, ScreenPos, ScreenVertex};
use crate::shade::Mode;

/// Scan lines per band. A multiple of every multisampling block side (2 and 4), so that a
/// band holds whole rows of pixels' samples.
pub const BAND_ROWS: u32 = 16;
const _: () = assert!(BAND_ROWS.is_multiple_of(4));

/// Marks a [`TriRec`] vertex that lives in its chunk's [`Binned::extra`] (made by clipping).
pub const EXTRA_VERTEX: u32 = 1 << 31;

/// One triangle to draw: its screen vertices (indices into the draw's per-vertex array, or
/// with [`EXTRA_VERTEX`] into the chunk's clipped vertices) and the index of its mode data.
#[derive(Debug, Clone, Copy, Default)]
pub struct TriRec {
    /// Vertex references.
    pub v: [u32; 3],
    /// Index into [`Binned::tris`].
    pub tri: u32,
}

/// The accepted triangles of one chunk, grouped by band.
#[derive(Debug, Clone, Default)]
pub struct Binned<T> {
    /// Records, band by band, in submission order within each band.
    pub recs: Vec<TriRec>,
    /// Band `b`'s records are `recs[starts[b]..starts[b + 1]]`.
    pub starts: Vec<u32>,
    /// Mode data per accepted triangle.
    pub tris: Vec<T>,
    /// Screen vertices made by clipping.
    pub extra: Vec<ScreenVertex>,
}

impl<T> Binned<T> {
    /// Groups `staged` (record, first band, last band) by band, keeping their order.
    #[must_use]
    pub fn new(
        staged: &[(TriRec, u32, u32)],
        bands: usize,
        tris: Vec<T>,
        extra: Vec<ScreenVertex>,
    ) -> Binned<T> {
        let mut starts = vec![0u32; bands + 1];
        for &(_, b0, b1) in staged {
            for b in b0..=b1 {
                starts[b as usize + 1] += 1;
            }
        }
        for b in 0..bands {
            starts[b + 1] += starts[b];
        }
        let mut at: Vec<u32> = starts[..bands].to_vec();
        let mut recs = vec![TriRec::default(); starts[bands] as usize];
        for &(rec, b0, b1) in staged {
            for b in b0..=b1 {
                recs[at[b as usize] as usize] = rec;
                at[b as usize] += 1;
            }
        }
        Binned {
            recs,
            starts,
            tris,
            extra,
        }
    }

    fn band(&self, b: usize) -> &[TriRec] {
        match (self.starts.get(b), self.starts.get(b + 1)) {
            (Some(&lo), Some(&hi)) => &self.recs[lo as usize..hi as usize],
            _ => &[],
        }
    }
}

/// The bands `[first, last]` that rows `[lo, hi)` touch in an image `height` rows tall, or
/// `None` when no row is inside it.
#[must_use]
pub fn band_range(lo: i64, hi: i64, height: u32) -> Option<(u32, u32)> {
    let lo = lo.max(0);
    let hi = hi.min(height as i64);
    (lo < hi).then(|| {
        (
            (lo / BAND_ROWS as i64) as u32,
            ((hi - 1) / BAND_ROWS as i64) as u32,
        )
    })
}

/// The thread count `threads` stands for (0 = all cores).
#[must_use]
pub fn effective_threads(threads: usize) -> usize {
    if threads == 0 {
        std::thread::available_parallelism().map_or(1, |n| n.get())
    } else {
        threads
    }
}

/// A rayon pool of `threads` workers, built once per count and cached (not the global pool).
fn pool(threads: usize) -> Option<Arc<rayon::ThreadPool>> {
    type Pools = Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>>;
    static POOLS: OnceLock<Pools> = OnceLock::new();
    let pools = POOLS.get_or_init(|| Mutex::new(Vec::new()));
    let mut pools = pools.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, p)) = pools.iter().find(|(n, _)| *n == threads) {
        return Some(p.clone());
    }
    let p = Arc::new(
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .ok()?,
    );
    pools.push((threads, p.clone()));
    Some(p)
}

/// Maps `f` over `items` in chunks of `chunk`, in parallel on the cached pool when `threads`
/// asks for more than one, and returns the results in input order (so set-up is deterministic).
pub fn map_chunks<I: Sync, T: Send>(
    threads: usize,
    items: &[I],
    chunk: usize,
    f: impl Fn(&[I]) -> T + Sync + Send,
) -> Vec<T> {
    let threads = effective_threads(threads);
    let chunk = chunk.max(1);
    match (threads > 1 && items.len() > chunk)
        .then(|| pool(threads))
        .flatten()
    {
        Some(p) => p.install(|| items.par_chunks(chunk).map(&f).collect()),
        None => items.chunks(chunk).map(f).collect(),
    }
}

/// Calls `f` on matching chunks of `out` (`chunk * per` items each) and `src` (`chunk` items
/// each: `per` outputs per source item), in parallel on the cached pool when `threads` asks for
/// more than one.
pub fn for_each_chunk<O: Send, S: Sync>(
    threads: usize,
    out: &mut [O],
    src: &[S],
    (chunk, per): (usize, usize),
    f: impl Fn(&mut [O], &[S]) + Sync + Send,
) {
    let threads = effective_threads(threads);
    let chunk = chunk.max(1);
    let out_chunk = chunk * per.max(1);
    match (threads > 1 && src.len() > chunk)
        .then(|| pool(threads))
        .flatten()
    {
        Some(p) => p.install(|| {
            out.par_chunks_mut(out_chunk)
                .zip(src.par_chunks(chunk))
                .for_each(|(o, s)| f(o, s));
        }),
        None => out
            .chunks_mut(out_chunk)
            .zip(src.chunks(chunk))
            .for_each(|(o, s)| f(o, s)),
    }
}

/// Calls `f(first, a, b)` on matching chunks of `a` (`chunk` items each, the first being item
/// `first`) and `b` (`chunk * per_b` items each; empty chunks when `per_b` is 0), in parallel
/// on the cached pool when `threads` asks for more than one: one pass writing two outputs.
pub fn for_each_chunk_pair<A: Send, B: Send>(
    threads: usize,
    a: &mut [A],
    b: &mut [B],
    (chunk, per_b): (usize, usize),
    f: impl Fn(usize, &mut [A], &mut [B]) + Sync + Send,
) {
    let threads = effective_threads(threads);
    let chunk = chunk.max(1);
    let pool = (threads > 1 && a.len() > chunk)
        .then(|| pool(threads))
        .flatten();
    match (pool, per_b) {
        (Some(p), 0) => p.install(|| {
            a.par_chunks_mut(chunk)
                .enumerate()
                .for_each(|(k, a)| f(k * chunk, a, &mut []));
        }),
        (Some(p), per) => p.install(|| {
            a.par_chunks_mut(chunk)
                .zip(b.par_chunks_mut(chunk * per))
                .enumerate()
                .for_each(|(k, (a, b))| f(k * chunk, a, b));
        }),
        (None, 0) => a
            .chunks_mut(chunk)
            .enumerate()
            .for_each(|(k, a)| f(k * chunk, a, &mut [])),
        (None, per) => a
            .chunks_mut(chunk)
            .zip(b.chunks_mut(chunk * per))
            .enumerate()
            .for_each(|(k, (a, b))| f(k * chunk, a, b)),
    }
}

/// `f(0), f(1), .., f(len - 1)`, in parallel on the cached pool when `threads` asks for more
/// than one (at least `min_len` indices per task), collected in order into one Vec written in
/// place (no per-chunk Vecs to concatenate).
pub fn map_indices<T: Send>(
    threads: usize,
    len: usize,
    min_len: usize,
    f: impl Fn(usize) -> T + Sync + Send,
) -> Vec<T> {
    let threads = effective_threads(threads);
    match (threads > 1 && len > min_len)
        .then(|| pool(threads))
        .flatten()
    {
        Some(p) => p.install(|| {
            (0..len)
                .into_par_iter()
                .with_min_len(min_len.max(1))
                .map(f)
                .collect()
        }),
        None => (0..len).map(f).collect(),
    }
}

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

/// The screen positions and first `n` attributes of record `r`'s vertices: from `c`'s
/// clipped vertices, or from the draw's per-vertex `pos` and `attrs` (`stride` per vertex);
/// `None` when a vertex is missing or has no screen position.
#[inline(always)]
fn vertices_of<'a, T>(
    r: &TriRec,
    c: &'a Binned<T>,
    (pos, attrs, stride): (&[ScreenPos], &'a [f32], usize),
    n: usize,
) -> Option<([ScreenPos; 3], [&'a [f32]; 3])> {
    if r.v.iter().any(|&i| i & EXTRA_VERTEX != 0) {
        let v = r.v.map(|i| c.extra.get((i & !EXTRA_VERTEX) as usize));
        let [Some(a), Some(b), Some(d)] = v else {
            return None;
        };
        return Some(([a.pos(), b.pos(), d.pos()], [&a.attrs, &b.attrs, &d.attrs]));
    }
    let p =
        r.v.map(|i| pos.get(i as usize).copied().unwrap_or(ScreenPos::NONE));
    if p.iter().any(ScreenPos::is_none) {
        return None;
    }
    let a = r.v.map(|i| {
        let i = i as usize;
        attrs.get(i * stride..(i + 1) * stride).unwrap_or(&[])
    });
    a.iter().all(|a| a.len() >= n).then_some((p, a))
}

/// How many records ahead the band loops touch vertex data (see `touch` in [`draw_bands`]).
const AHEAD: usize = 4;

/// Ids of the depth pass: a fresh epoch per band job in the high bits, so ids left in a
/// thread's scratch by earlier jobs never match.
static EPOCH: AtomicU64 = AtomicU64::new(1);

thread_local! {
    /// Per-thread scratch of the depth pass: the nearest triangle's id per band pixel, and
    /// per record whether it was nearest anywhere when drawn.
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

/// Draws the binned triangles `chunks` (in submission order, chunk after chunk) with `mode`
/// into `fb` over bands. The draw's per-vertex screen positions are `pos`
/// ([`ScreenPos::NONE`] where a vertex has none) and its attributes `attrs`, `M::ATTRS` per
/// vertex. With `block > 1` the image holds samples, `block x block` per pixel, and the
/// by-pixel pass shades each triangle once per pixel ([`ByPixel::block`]). Returns the pixels
/// (or, multisampled, the pixel and triangle pairs) shaded.
#[allow(
    clippy::too_many_arguments,
    reason = "one draw's inputs, passed through once"
)]
pub fn draw_bands<M: Mode>(
    fb: &mut Framebuffer,
    mode: &M,
    pos: &[ScreenPos],
    attrs: &[f32],
    chunks: &[Binned<M::Tri>],
    perspective: bool,
    threads: usize,
    count: bool,
    block: u32,
) -> u64 {
    let width = fb.width();
    let n = M::ATTRS;
    // Set-up of record `r` of chunk `c` into `t` with `n` attributes; false when it has no
    // vertices or no area.
    let setup = |t: &mut RasterTri, c: &Binned<M::Tri>, r: &TriRec, n: usize| -> bool {
        vertices_of(r, c, (pos, attrs, M::ATTRS), n)
            .is_some_and(|(p, a)| t.set(p, a, n, perspective))
    };
    // Reads the first vertex data set-up will need of a record `AHEAD` places on, so that
    // the cache misses of fetching it (vertices are scattered over the mesh) overlap the
    // work on the records before it: a prefetch in safe code. The value is folded into a
    // sink so that the loads are kept.
    let touch = |r: Option<&TriRec>, n: usize| -> u32 {
        let Some(r) = r else { return 0 };
        let mut sink = 0u32;
        for &i in &r.v {
            if i & EXTRA_VERTEX == 0 {
                sink ^= pos.get(i as usize).map_or(0, |p| p.fx as u32);
                if n > 0 {
                    sink ^= attrs.get(i as usize * M::ATTRS).map_or(0, |a| a.to_bits());
                }
            }
        }
        sink
    };
    let chunk = (BAND_ROWS * width) as usize;
    let clear = fb.pending_clear.take();
    // Outside its dirty columns a row already holds the last clear's colour and depth.
    let only_dirty = clear.is_some_and(|bg| same_color(fb.clean, bg));
    if clear.is_some() {
        fb.clean = clear;
    }
    let (color, depth, dirty) = (&mut fb.color, &mut fb.depth, &mut fb.dirty);
    type Rows<'a> = ((&'a mut [glam::Vec3], &'a mut [f32]), &'a mut [(u32, u32)]);
    let run = |(b, ((color, depth), dirty)): (usize, Rows)| -> u64 {
        if let Some(bg) = clear {
            // The frame's clear, deferred to here: each band clears its rows in parallel,
            // just before drawing them (they stay in cache).
            clear_rows((color, depth, dirty), width, bg, only_dirty);
        }
        let y0 = b as i64 * BAND_ROWS as i64;
        let in_band: usize = chunks.iter().map(|c| c.band(b).len()).sum();
        let mut t = RasterTri::empty();
        let mut target = BandTarget::new(color, depth, width, y0, count);
        if !M::EARLY_Z || count || in_band < 2 {
            let (mut shaded, mut sink) = (0, 0);
            for c in chunks {
                let recs = c.band(b);
                for (i, r) in recs.iter().enumerate() {
                    sink ^= touch(recs.get(i + AHEAD), n);
                    if let Some(tri) = c.tris.get(r.tri as usize) {
                        if setup(&mut t, c, r, n) {
                            // A mode writes only inside the triangle's pixel box.
                            mark_dirty(dirty, y0, (t.y0, t.y1), (t.x0, t.x1), width);
                            shaded += mode.draw(&t, tri, &mut target);
                        }
                    }
                }
            }
            std::hint::black_box(sink);
            return shaded;
        }
        let BandTarget { color, depth, .. } = target;
        SCRATCH.with(|scratch| {
            let mut scratch = scratch.borrow_mut();
            let Scratch {
                ids,
                owns,
                extents,
                slot,
                planes,
            } = &mut *scratch;
            if ids.len() < color.len() {
                ids.resize(color.len(), 0);
            }
            extents.clear();
            extents.resize(color.len() / width.max(1) as usize, (u32::MAX, 0));
            let mut target = BandTarget::new(color, depth, width, y0, count);
            let epoch = EPOCH.fetch_add(1, Ordering::Relaxed) << 32;
            let mut seq = epoch;
            // Depth only: set-up without attributes (same edges and depth plane).
            let mut sink = 0;
            for c in chunks {
                let recs = c.band(b);
                for (i, r) in recs.iter().enumerate() {
                    sink ^= touch(recs.get(i + AHEAD), 0);
                    if setup(&mut t, c, r, 0) {
                        depth_only(&t, &mut target, ids, extents, seq);
                    }
                    seq += 1;
                }
            }
            // The records that own a pixel now, from the ids the pass left: only they are
            // visible. (A triangle nearest somewhere when drawn is often covered later, by a
            // nearer one drawn after it: about half of them in S1.)
            owns.clear();
            owns.resize((seq - epoch) as usize, false);
            let w = width as usize;
            for (row, &(lo, hi)) in extents.iter().enumerate() {
                let (lo, hi) = (row * w + lo as usize, row * w + (hi as usize).min(w));
                for &id in ids.get(lo..hi).unwrap_or(&[]) {
                    // Ids below the epoch were left by earlier bands.
                    if let Some(o) = id.checked_sub(epoch).and_then(|k| owns.get_mut(k as usize)) {
                        *o = true;
                    }
                }
            }
            // Only the depth pass writes outside the pixels it recorded (the shading passes
            // write where it did).
            for (d, e) in dirty.iter_mut().zip(extents.iter()) {
                *d = (d.0.min(e.0), d.1.max(e.1));
            }
            // The visible pass: records that own a pixel (and, after a by-pixel pass, only
            // those it left out) traversed again, each pixel shaded where its id names them.
            let visible_pass = |target: &mut BandTarget, t: &mut RasterTri, by_pixel_done: bool| {
                let (mut shaded, mut seq) = (0, epoch);
                for c in chunks {
                    for r in c.band(b) {
                        let owner = owns.get((seq - epoch) as usize) == Some(&true);
                        if let (true, Some(tri)) = (owner, c.tris.get(r.tri as usize)) {
                            if !(by_pixel_done && M::by_pixel(tri)) && setup(t, c, r, n) {
                                target.pass = Pass::Visible(seq);
                                shaded += mode.draw(t, tri, target);
                            }
                        }
                        seq += 1;
                    }
                }
                mode.finish(target);
                shaded
            };
            if M::BY_PIXEL {
                // Planes of the visible triangles, then every pixel from its id.
                slot.clear();
                planes.clear();
                let (mut k, mut traced) = (0, false);
                for c in chunks {
                    let recs = c.band(b);
                    for (i, r) in recs.iter().enumerate() {
                        if owns.get(k + AHEAD) == Some(&true) {
                            sink ^= touch(recs.get(i + AHEAD), n);
                        }
                        let owner = owns.get(k) == Some(&true);
                        let by_pixel = owner && c.tris.get(r.tri as usize).is_some_and(M::by_pixel);
                        traced |= owner && !by_pixel;
                        // Its pixels are known: the planes alone.
                        let visible = by_pixel
                            && vertices_of(r, c, (pos, attrs, M::ATTRS), n)
                                .is_some_and(|(p, a)| t.set_planes(p, a, n, perspective));
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
                let pass = ByPixel {
                    slot,
                    planes,
                    ids,
                    epoch,
                    extents,
                    width,
                    y0,
                    n,
                    perspective: perspective && n > 0,
                    block: block as usize,
                };
                let shaded = pass.shade(target.color, |a, count| mode.shade4(a, count));
                if !traced {
                    return shaded;
                }
                target.ids = ids;
                return shaded + visible_pass(&mut target, &mut t, true);
            }
            std::hint::black_box(sink);
            target.ids = ids;
            visible_pass(&mut target, &mut t, false)
        })
    };
    let threads = effective_threads(threads);
    match (threads > 1).then(|| pool(threads)).flatten() {
        Some(p) => p.install(|| {
            let jobs = color.par_chunks_mut(chunk).zip(depth.par_chunks_mut(chunk));
            let jobs = jobs.zip(dirty.par_chunks_mut(BAND_ROWS as usize));
            jobs.enumerate().map(run).sum()
        }),
        None => {
            let jobs = color.chunks_mut(chunk).zip(depth.chunks_mut(chunk));
            let jobs = jobs.zip(dirty.chunks_mut(BAND_ROWS as usize));
            jobs.enumerate().map(run).sum()
        }
    }
}
