//! Stage 2, BIN: each triangle, in parallel chunks of the mesh's triangles and in submission
//! order within each, is clipped where a vertex lies outside the clip volume, accepted (not
//! degenerate, not culled, covering a pixel row inside the image), given its per-triangle
//! data as the shader's [`Face`] declares (a colour, several triangles per call in lanes; or a
//! stepped triangle), and recorded in every band it touches. The chunks are joined in order,
//! so the records of a band and the picture do not depend on the thread count.

use glam::{Vec3, Vec4};
use phosphor_lighting::Lanes;

use crate::batch::Wide;
use crate::clip::{MAX_POLY, clip_triangle};
use crate::parallel::map_chunks;
use crate::setup::{ScreenPos, ScreenVertex, row_range, screen_area2};
use crate::shader::{
    Face, MAX_VARYINGS, ScreenCorner, ScreenTriangle, Shader, Stepped, TriangleLanes,
};
use crate::vertex::{DrawVertices, Used, VertexIn, gather, varyings_one};
use crate::viewport::Viewport;

/// Marks a [`TriRec`] vertex that lives in its chunk's [`Binned::extra`] (made by clipping).
pub const EXTRA_VERTEX: u32 = 1 << 31;

/// One triangle to draw: its screen vertices (indices into the draw's per-vertex array, or
/// with [`EXTRA_VERTEX`] into the chunk's clipped vertices) and the index of its per-triangle
/// data ([`Binned::colors`] or [`Binned::stepped`], as the shader's face says).
#[derive(Debug, Clone, Copy, Default)]
pub struct TriRec {
    /// Vertex references.
    pub v: [u32; 3],
    /// Index of the triangle's data.
    pub tri: u32,
}

/// The accepted triangles of one chunk, grouped by band.
pub(crate) struct Binned<T> {
    /// Records, band by band, in submission order within each band.
    pub recs: Vec<TriRec>,
    /// Band `b`'s records are `recs[starts[b]..starts[b + 1]]`.
    pub starts: Vec<u32>,
    /// [`Face::Constant`]: each triangle's colour.
    pub colors: Vec<Vec3>,
    /// [`Face::Stepped`]: each triangle's stepped data, or `None` to interpolate it.
    pub stepped: Vec<Option<Box<Stepped<T>>>>,
    /// Screen vertices made by clipping.
    pub extra: Vec<ScreenVertex>,
}

impl<T> Binned<T> {
    /// Groups `staged` (record, first band, last band) by band, keeping their order.
    fn new(staged: &[(TriRec, u32, u32)], bands: usize, data: TriData<T>) -> Binned<T> {
        // Most triangles lie in one band: that case takes no loop.
        let mut starts = vec![0u32; bands + 1];
        for &(_, b0, b1) in staged {
            if b0 == b1 {
                if let Some(c) = starts.get_mut(b0 as usize + 1) {
                    *c += 1;
                }
                continue;
            }
            for b in b0..=b1 {
                if let Some(c) = starts.get_mut(b as usize + 1) {
                    *c += 1;
                }
            }
        }
        for b in 0..bands {
            starts[b + 1] += starts[b];
        }
        let mut at: Vec<u32> = starts[..bands].to_vec();
        let mut recs = vec![TriRec::default(); starts[bands] as usize];
        let mut put = |b: u32, rec: TriRec| {
            if let Some(a) = at.get_mut(b as usize) {
                if let Some(r) = recs.get_mut(*a as usize) {
                    *r = rec;
                }
                *a += 1;
            }
        };
        for &(rec, b0, b1) in staged {
            if b0 == b1 {
                put(b0, rec);
                continue;
            }
            for b in b0..=b1 {
                put(b, rec);
            }
        }
        Binned {
            recs,
            starts,
            colors: data.colors,
            stepped: data.stepped,
            extra: data.extra,
        }
    }

    /// Band `b`'s records, in submission order.
    pub fn band(&self, b: usize) -> &[TriRec] {
        match (self.starts.get(b), self.starts.get(b + 1)) {
            (Some(&lo), Some(&hi)) => &self.recs[lo as usize..hi as usize],
            _ => &[],
        }
    }

    /// The stepped data of record `r`, if it has some.
    #[inline(always)]
    pub fn stepped_of(&self, r: &TriRec) -> Option<&Stepped<T>> {
        self.stepped.get(r.tri as usize).and_then(|s| s.as_deref())
    }
}

/// The per-triangle data a chunk builds.
struct TriData<T> {
    colors: Vec<Vec3>,
    stepped: Vec<Option<Box<Stepped<T>>>>,
    extra: Vec<ScreenVertex>,
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
    /// Triangles [`Shader::stepped`] refused (drawn interpolated instead).
    pub fallbacks: u64,
}

/// What the bin stage of one draw reads.
pub(crate) struct BinInput<'a, S> {
    pub shader: &'a S,
    pub indices: &'a [[u32; 3]],
    pub verts: &'a DrawVertices,
    pub view: &'a Viewport,
    pub cull: bool,
    pub wide: Wide,
    /// Where the vertices of the triangles recorded unclipped are marked (their varyings are
    /// computed after this stage).
    pub used: &'a Used,
}

/// Runs the bin stage of one draw on `threads`.
pub(crate) fn bin_draw<S: Shader>(input: &BinInput<S>, threads: usize) -> BinnedDraw<S::Stepped> {
    let chunks = map_chunks(threads, input.indices, CHUNK, |indices| {
        bin_chunk(input, indices)
    });
    let mut out = BinnedDraw {
        chunks: Vec::with_capacity(chunks.len()),
        drawn: 0,
        fallbacks: 0,
    };
    for (binned, drawn, fallbacks) in chunks {
        out.drawn += drawn;
        out.fallbacks += fallbacks;
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

/// Bins one chunk of triangles; returns them with the counts accepted and refused stepping.
fn bin_chunk<S: Shader>(
    input: &BinInput<S>,
    indices: &[[u32; 3]],
) -> (Binned<S::Stepped>, u64, u64) {
    let (shader, verts, view) = (input.shader, input.verts, input.view);
    let marks = input.used.marks(verts.clip.len());
    let persp = view.perspective;
    let bands = view.height.div_ceil(view.band_rows) as usize;
    let mut staged: Vec<(TriRec, u32, u32)> = Vec::with_capacity(indices.len());
    let mut data = TriData {
        colors: Vec::new(),
        stepped: Vec::new(),
        extra: Vec::new(),
    };
    let mut batch = Batch::new(input);
    let (mut drawn, mut fallbacks) = (0, 0);
    let mut stepped = |data: &mut TriData<S::Stepped>,
                       p: &[ScreenPos; 3],
                       corners: &dyn Fn() -> [ScreenCorner; 3]| {
        let area = screen_area2(p).unsigned_abs() as f64 / 131_072.0; // 2 * 256^2
        let s = if area < shader.min_stepped_area() {
            None
        } else {
            let t = ScreenTriangle {
                corners: corners(),
                perspective: persp,
            };
            let s = shader.stepped(&t).map(Box::new);
            fallbacks += u64::from(s.is_none());
            s
        };
        data.stepped.push(s);
        (data.stepped.len() - 1) as u32
    };
    // The per-vertex arrays as slices held in registers, with one bound for both, so that
    // neither is read again nor bounds-checked per triangle (the loop's pushes could
    // otherwise alias them).
    let (clip, pos) = (verts.clip.as_slice(), verts.pos.as_slice());
    let bound = clip.len().min(pos.len());
    for idx in indices {
        if idx.iter().any(|&i| i as usize >= bound) {
            continue;
        }
        let i = idx.map(|i| i as usize);
        let p = i.map(|i| pos[i]);
        if !p.iter().any(ScreenPos::is_none) {
            // The common case: no clipping, screen vertices from the vertex stage.
            let Some(rows) = accept(p, input.cull) else {
                continue;
            };
            drawn += 1;
            let Some((b0, b1)) = on_screen(p, rows, view) else {
                continue;
            };
            let tri = match S::FACE {
                Face::Interpolated => 0,
                Face::Constant => batch.queue(*idx, &mut data.colors),
                Face::Stepped => {
                    let corners = || {
                        std::array::from_fn(|k| {
                            let (c, v) = &clip[i[k]];
                            let a = varyings_one(shader, v);
                            ScreenCorner {
                                x: f64::from(p[k].fx) / 256.0,
                                y: f64::from(p[k].fy) / 256.0,
                                rhw: 1.0 / f64::from(c.w),
                                varyings: std::array::from_fn(|j| f64::from(a[j])),
                            }
                        })
                    };
                    stepped(&mut data, &p, &corners)
                }
            };
            if S::VARYINGS > 0 {
                let [a, b, c] = i;
                Used::mark(marks, a);
                Used::mark(marks, b);
                Used::mark(marks, c);
            }
            staged.push((TriRec { v: *idx, tri }, b0, b1));
            continue;
        }
        let tri = i.map(|i| verts.clip_vertex(shader, i));
        if !tri.iter().all(|v| v.pos.is_finite()) {
            continue;
        }
        let poly = clip_triangle(&tri, S::VARYINGS, view.guard);
        let pv = poly.vertices();
        let mut sv = [None; MAX_POLY];
        for (s, v) in sv.iter_mut().zip(pv) {
            *s = view.project(v, S::VARYINGS);
        }
        let mut any = false;
        // The clipped polygon is convex: a fan keeps the winding.
        for k in 1..pv.len().saturating_sub(1) {
            let (Some(a), Some(b), Some(c)) = (&sv[0], &sv[k], &sv[k + 1]) else {
                continue;
            };
            let p = [a.pos(), b.pos(), c.pos()];
            let Some(rows) = accept(p, input.cull) else {
                continue;
            };
            any = true;
            let Some((b0, b1)) = on_screen(p, rows, view) else {
                continue;
            };
            let tri = match S::FACE {
                Face::Interpolated => 0,
                // The whole triangle's corners: the same plane.
                Face::Constant => batch.queue(*idx, &mut data.colors),
                Face::Stepped => {
                    let corners = || [a, b, c].map(|s| corner_of(s, persp));
                    stepped(&mut data, &p, &corners)
                }
            };
            let base = data.extra.len() as u32;
            data.extra.extend([*a, *b, *c]);
            let rec = TriRec {
                v: [base, base + 1, base + 2].map(|i| i | EXTRA_VERTEX),
                tri,
            };
            staged.push((rec, b0, b1));
        }
        drawn += u64::from(any);
    }
    batch.flush(&mut data.colors);
    (Binned::new(&staged, bands, data), drawn, fallbacks)
}

/// The stepped stage's view of a corner made by clipping (its varyings divided by `w` back).
fn corner_of(s: &ScreenVertex, perspective: bool) -> ScreenCorner {
    let scale = if perspective { 1.0 / s.rhw } else { 1.0 };
    ScreenCorner {
        x: s.x,
        y: s.y,
        rhw: s.rhw,
        varyings: std::array::from_fn(|k| {
            if k < MAX_VARYINGS {
                f64::from(s.attrs[k]) * scale
            } else {
                0.0
            }
        }),
    }
}

/// Triangles of a [`Face::Constant`] shader waiting for their colours, computed eight at a
/// time with AVX2 (else four) by [`Shader::constant`]; they wait as the indices of their
/// vertices in the draw's `verts.clip` (checked by the bin), and only what the shader reads
/// is gathered.
struct Batch<'a, S> {
    input: &'a BinInput<'a, S>,
    queued: [[u32; 3]; 8],
    len: usize,
    width: usize,
}

impl<'a, S: Shader> Batch<'a, S> {
    fn new(input: &'a BinInput<'a, S>) -> Batch<'a, S> {
        Batch {
            input,
            queued: [[0; 3]; 8],
            len: 0,
            width: if input.wide.avx2.is_some() { 8 } else { 4 },
        }
    }

    /// Queues the triangle of vertices `v`; returns the index its colour will have in
    /// `colors`.
    fn queue(&mut self, v: [u32; 3], colors: &mut Vec<Vec3>) -> u32 {
        let at = (colors.len() + self.len) as u32;
        self.queued[self.len] = v;
        self.len += 1;
        if self.len == self.width {
            self.flush(colors);
        }
        at
    }

    /// Computes the queued triangles' colours into `colors`.
    fn flush(&mut self, colors: &mut Vec<Vec3>) {
        let len = std::mem::take(&mut self.len);
        if len == 0 {
            return;
        }
        // Lanes past `len` repeat the first triangle; their results are dropped. A full
        // batch is read in place.
        let first = self.queued[0];
        for q in self.queued.iter_mut().skip(len) {
            *q = first;
        }
        let task = Colors {
            shader: self.input.shader,
            clip: &self.input.verts.clip,
            tris: &self.queued,
        };
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.input.wide.avx2 {
            let c = avx2.run(task);
            colors.extend_from_slice(&c[..len]);
            return;
        }
        let c = task.colors(phosphor_lighting::f32x4::ZERO);
        colors.extend_from_slice(&c[..len]);
    }
}

/// [`Shader::constant`] of up to eight triangles.
struct Colors<'a, 'v, S> {
    shader: &'a S,
    clip: &'v [(Vec4, VertexIn)],
    tris: &'a [[u32; 3]; 8],
}

impl<S: Shader> Colors<'_, '_, S> {
    #[inline(always)]
    fn colors<L: Lanes>(&self, like: L) -> [Vec3; 8] {
        // One corner of every triangle as lanes (a macro: inlined, so what the shader does
        // not read is never gathered).
        macro_rules! corner {
            ($c:expr) => {{
                let v: [&VertexIn; 8] =
                    std::array::from_fn(|k| &self.clip[self.tris[k][$c] as usize].1);
                gather(like, &v[..L::N])
            }};
        }
        let t = TriangleLanes {
            corners: [corner!(0), corner!(1), corner!(2)],
        };
        self.shader.constant(&t).to_vecs()
    }
}

#[cfg(target_arch = "x86_64")]
impl<S: Shader> phosphor_lighting::Avx2Task for Colors<'_, '_, S> {
    type Output = [Vec3; 8];
    #[inline(always)]
    fn run(self, s: phosphor_lighting::Avx2) -> [Vec3; 8] {
        self.colors(s.splat(0.0))
    }
}
