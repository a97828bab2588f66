//! Parallel helpers every stage shares: rayon pools cached per thread count (not the global
//! pool, so a caller's thread count is exact), and maps over chunks that return their results
//! in input order, so that what runs in parallel never changes a result.

use std::sync::{Arc, Mutex, OnceLock};

use rayon::prelude::*;

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
pub(crate) fn pool(threads: usize) -> Option<Arc<rayon::ThreadPool>> {
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
