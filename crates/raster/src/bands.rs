//! The parallel split: horizontal bands of [`BAND_ROWS`] scan lines. Triangles are set up once,
//! binned to the bands they touch, and every band draws its triangles in submission order, so
//! the picture is bit-identical for any thread count (bands depend on the image, not on the
//! threads). Bands are sized by work: a 1080-row image has 68 of them, many more than cores.

use std::sync::{Arc, Mutex, OnceLock};

use rayon::prelude::*;

use crate::framebuffer::Framebuffer;
use crate::scanline::BandTarget;
use crate::setup::TriGeom;
use crate::shade::Mode;

/// Scan lines per band.
pub const BAND_ROWS: u32 = 16;

/// A set-up triangle: geometry for the traversal and the mode's data.
#[derive(Debug, Clone, Copy)]
pub struct Prepared<T> {
    /// Screen triangle.
    pub geom: TriGeom,
    /// Mode data.
    pub tri: T,
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

/// Draws the set-up triangles `tris` (in submission order, chunk after chunk, as set-up
/// produced them: they are not copied into one Vec) with `mode` into `fb` over bands;
/// returns the pixels shaded.
pub fn draw_bands<M: Mode>(
    fb: &mut Framebuffer,
    mode: &M,
    tris: &[Vec<Prepared<M::Tri>>],
    threads: usize,
    count: bool,
) -> u64 {
    let (width, height) = (fb.width(), fb.height());
    let band_count = height.div_ceil(BAND_ROWS) as usize;
    let mut bins: Vec<Vec<&Prepared<M::Tri>>> = vec![Vec::new(); band_count];
    for t in tris.iter().flatten() {
        let lo = t.geom.row_start.max(0);
        let hi = t.geom.row_end.min(height as i64);
        if lo >= hi {
            continue;
        }
        let (b0, b1) = (
            lo as usize / BAND_ROWS as usize,
            (hi as usize - 1) / BAND_ROWS as usize,
        );
        for bin in &mut bins[b0..=b1] {
            bin.push(t);
        }
    }
    let chunk = (BAND_ROWS * width) as usize;
    let (color, depth) = (&mut fb.color, &mut fb.depth);
    let run = |(b, (color, depth)): (usize, (&mut [glam::Vec3], &mut [f32]))| -> u64 {
        let y0 = b as i64 * BAND_ROWS as i64;
        let mut target = BandTarget {
            y1: y0 + (color.len() / width as usize) as i64,
            color,
            depth,
            width,
            y0,
            count,
        };
        bins[b]
            .iter()
            .map(|t| mode.draw(&t.geom, &t.tri, &mut target))
            .sum()
    };
    let threads = effective_threads(threads);
    match (threads > 1).then(|| pool(threads)).flatten() {
        Some(p) => p.install(|| {
            let jobs = color.par_chunks_mut(chunk).zip(depth.par_chunks_mut(chunk));
            jobs.enumerate().map(run).sum()
        }),
        None => {
            let jobs = color.chunks_mut(chunk).zip(depth.chunks_mut(chunk));
            jobs.enumerate().map(run).sum()
        }
    }
}
