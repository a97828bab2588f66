//! Stage 2, BIN: each triangle, in parallel chunks of the mesh's triangles and in submission
//! order within each, is clipped where a vertex lies outside the clip volume, accepted (not
//! degenerate, not culled, covering a pixel row inside the image), handed to the mode's
//! triangle set-up ([`Mode::triangle`], four at a time where the mode batches), and recorded in
//! every band it touches. The chunks are joined in order, so the records of a band and the
//! picture do not depend on the thread count.

use crate::DrawItem;
use crate::clip::{MAX_POLY, clip_triangle};
use crate::parallel::map_chunks;
use crate::setup::{ScreenPos, ScreenVertex, row_range, screen_area2};
use crate::shade::{Mode, TriInput, TriVertices, VertexIn};
use crate::vertex::{DrawVertices, Viewport};

/// Pixel rows per band. A multisampled image's bands hold this many rows of pixels, `block`
/// sample rows each ([`band_rows`]): bands of the same pixel rows keep the same split of the
/// work over threads, and a triangle is set up in no more bands than without multisampling.
pub const BAND_ROWS: u32 = 16;

/// Scan lines per band of an image with `block x block` samples per pixel (1: none).
#[must_use]
pub const fn band_rows(block: u32) -> u32 {
    BAND_ROWS * block
}

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

    /// Band `b`'s records, in submission order.
    pub fn band(&self, b: usize) -> &[TriRec] {
        match (self.starts.get(b), self.starts.get(b + 1)) {
            (Some(&lo), Some(&hi)) => &self.recs[lo as usize..hi as usize],
            _ => &[],
        }
    }
}

/// The bands `[first, last]` of `rows` scan lines each that rows `[lo, hi)` touch in an
/// image `height` rows tall, or `None` when no row is inside it.
#[must_use]
pub fn band_range(lo: i64, hi: i64, height: u32, rows: u32) -> Option<(u32, u32)> {
    let lo = lo.max(0);
    let hi = hi.min(height as i64);
    (lo < hi).then(|| ((lo / rows as i64) as u32, ((hi - 1) / rows as i64) as u32))
}

/// Triangles per parallel chunk of the bin stage.
const CHUNK: usize = 1024;

/// The bin stage's result for one draw.
pub(crate) struct BinnedDraw<T> {
    /// Per chunk, in submission order.
    pub chunks: Vec<Binned<T>>,
    /// Triangles that passed acceptance (on screen or not).
    pub drawn: u64,
    /// Triangles whose set-up fell back to a costlier kernel ([`Mode::is_fallback`]).
    pub fallbacks: u64,
}

/// Runs the bin stage of draw `d` (its vertices `verts`) for `mode` on `threads`; back faces
/// are dropped when `cull`.
pub(crate) fn bin_draw<M: Mode>(
    d: &DrawItem,
    mode: &M,
    verts: &DrawVertices,
    view: &Viewport,
    cull: bool,
    threads: usize,
) -> BinnedDraw<M::Tri> {
    let chunks = map_chunks(threads, d.mesh.indices, CHUNK, |indices| {
        bin_chunk(indices, mode, verts, view, cull)
    });
    let mut out = BinnedDraw {
        chunks: Vec::with_capacity(chunks.len()),
        drawn: 0,
        fallbacks: 0,
    };
    for (binned, drawn) in chunks {
        out.drawn += drawn;
        out.fallbacks += binned
            .tris
            .iter()
            .map(|t| u64::from(M::is_fallback(t)))
            .sum::<u64>();
        out.chunks.push(binned);
    }
    out
}

/// Accepts a screen triangle: not degenerate, not culled, covering at least one row of pixel
/// centres. Returns its rows (not clipped to the image).
#[inline]
fn accept(v: [ScreenPos; 3], cull_backfaces: bool) -> Option<(i64, i64)> {
    let area = screen_area2(&v);
    if area == 0 || (cull_backfaces && area > 0) {
        return None;
    }
    let rows = row_range(v.map(|v| i64::from(v.fy)));
    (rows.0 < rows.1).then_some(rows)
}

/// The bands of an accepted triangle with rows `rows`, when some column of it is inside the
/// image too.
#[inline]
fn on_screen(v: [ScreenPos; 3], rows: (i64, i64), view: &Viewport) -> Option<(u32, u32)> {
    let (x0, x1) = row_range(v.map(|v| i64::from(v.fx)));
    let cols = x0.max(0) < x1.min(view.width as i64);
    band_range(rows.0, rows.1, view.height, view.band_rows).filter(|_| cols)
}

/// Bins one chunk of triangles; returns them with the count accepted.
fn bin_chunk<M: Mode>(
    indices: &[[u32; 3]],
    mode: &M,
    verts: &DrawVertices,
    view: &Viewport,
    cull: bool,
) -> (Binned<M::Tri>, u64) {
    let persp = view.perspective;
    let bands = view.height.div_ceil(view.band_rows) as usize;
    let mut staged: Vec<(TriRec, u32, u32)> = Vec::with_capacity(indices.len());
    let mut tris = Vec::with_capacity(indices.len());
    let mut extra = Vec::new();
    let mut batch = Batch::new(mode, persp);
    let mut drawn = 0;
    for idx in indices {
        if idx.iter().any(|&i| i as usize >= verts.clip.len()) {
            continue;
        }
        let i = idx.map(|i| i as usize);
        let p = i.map(|i| verts.pos[i]);
        if !p.iter().any(ScreenPos::is_none) {
            // The common case: no clipping, screen vertices from the vertex stage.
            let Some(rows) = accept(p, cull) else {
                continue;
            };
            drawn += 1;
            let Some((b0, b1)) = on_screen(p, rows, view) else {
                continue;
            };
            let tri = if let Some(tri) = mode.triangle_from_positions(&p) {
                batch.push(tri, &mut tris)
            } else {
                match M::INPUT {
                    TriInput::Positions => {
                        batch.push(mode.triangle(TriVertices::Positions, persp), &mut tris)
                    }
                    TriInput::World => batch.queue(i.map(|i| &verts.clip[i].1), &mut tris),
                    TriInput::Screen => {
                        let [Some(a), Some(b), Some(c)] = i.map(|i| verts.screen.get(i)?.as_ref())
                        else {
                            continue;
                        };
                        batch.push(
                            mode.triangle(TriVertices::Screen([a, b, c]), persp),
                            &mut tris,
                        )
                    }
                    TriInput::ScreenPerTriangle => {
                        let s = i.map(|i| view.screen(&verts.clip_vertex(mode, i), M::ATTRS));
                        let [Some(a), Some(b), Some(c)] = &s else {
                            continue;
                        };
                        batch.push(
                            mode.triangle(TriVertices::Screen([a, b, c]), persp),
                            &mut tris,
                        )
                    }
                }
            };
            staged.push((TriRec { v: *idx, tri }, b0, b1));
            continue;
        }
        let tri = i.map(|i| verts.clip_vertex(mode, i));
        if !tri.iter().all(|v| v.pos.is_finite()) {
            continue;
        }
        let src = i.map(|i| &verts.clip[i].1);
        let poly = clip_triangle(&tri, M::ATTRS, view.guard);
        let pv = poly.vertices();
        let mut sv = [None; MAX_POLY];
        for (s, v) in sv.iter_mut().zip(pv) {
            *s = view.project(v, M::ATTRS);
        }
        let mut any = false;
        // The clipped polygon is convex: a fan keeps the winding.
        for k in 1..pv.len().saturating_sub(1) {
            let (Some(a), Some(b), Some(c)) = (&sv[0], &sv[k], &sv[k + 1]) else {
                continue;
            };
            let p = [a.pos(), b.pos(), c.pos()];
            let Some(rows) = accept(p, cull) else {
                continue;
            };
            any = true;
            let Some((b0, b1)) = on_screen(p, rows, view) else {
                continue;
            };
            let input = match M::INPUT {
                TriInput::Positions => TriVertices::Positions,
                TriInput::World => TriVertices::World(src),
                TriInput::Screen | TriInput::ScreenPerTriangle => TriVertices::Screen([a, b, c]),
            };
            let base = extra.len() as u32;
            extra.extend([*a, *b, *c]);
            let rec = TriRec {
                v: [base, base + 1, base + 2].map(|i| i | EXTRA_VERTEX),
                tri: batch.push(mode.triangle(input, persp), &mut tris),
            };
            staged.push((rec, b0, b1));
        }
        drawn += u64::from(any);
    }
    batch.flush(&mut tris);
    (Binned::new(&staged, bands, tris, extra), drawn)
}

/// Triangles of a [`TriInput::World`] mode waiting for their data, computed four at a time
/// ([`Mode::triangle4`]); they wait as references to their vertices, not copies.
struct Batch<'m, 'v, M> {
    mode: &'m M,
    perspective: bool,
    queued: [Option<[&'v VertexIn; 3]>; 4],
    len: usize,
}

impl<'m, 'v, M: Mode> Batch<'m, 'v, M> {
    fn new(mode: &'m M, perspective: bool) -> Batch<'m, 'v, M> {
        Batch {
            mode,
            perspective,
            queued: [None; 4],
            len: 0,
        }
    }

    /// Queues a triangle; returns the index its data will have in `tris`.
    fn queue(&mut self, v: [&'v VertexIn; 3], tris: &mut Vec<M::Tri>) -> u32 {
        let at = (tris.len() + self.len) as u32;
        self.queued[self.len] = Some(v);
        self.len += 1;
        if self.len == 4 {
            self.flush(tris);
        }
        at
    }

    /// Adds data already computed, after the queued triangles; returns its index in `tris`.
    fn push(&mut self, tri: M::Tri, tris: &mut Vec<M::Tri>) -> u32 {
        self.flush(tris);
        tris.push(tri);
        (tris.len() - 1) as u32
    }

    /// Computes the queued triangles' data into `tris`.
    fn flush(&mut self, tris: &mut Vec<M::Tri>) {
        let len = std::mem::take(&mut self.len);
        let Some(first) = self.queued[0] else {
            return;
        };
        // Lanes past `len` repeat the first triangle; their results are dropped.
        let lane = |k: usize| self.queued[k].filter(|_| k < len).unwrap_or(first);
        let out = self
            .mode
            .triangle4(std::array::from_fn(lane), self.perspective);
        tris.extend(out.into_iter().take(len));
        self.queued = [None; 4];
    }
}
