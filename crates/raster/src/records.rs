//! One draw as every band reads it ([`BandInput`]): the records' vertices and set-up, and
//! the drawing of one record in a pass, the shading it gets picked from the shader's
//! declarations.

use glam::Vec3;

use crate::batch::{Pending, Wide};
use crate::bin::{Binned, EXTRA_VERTEX, TriRec};
use crate::coverage::{BandTarget, Pass};
use crate::incremental::{IncrementalTri, traverse_incremental};
use crate::setup::{RasterTri, ScreenPos};
use crate::shader::{Face, Shader};
use crate::stepped::{StepQueue, SteppedSpan};
use crate::traverse::{Batched, DepthOnly, OnePixel, Solid, SpanShade, traverse, traverse_inline};

/// How many records ahead the band loops touch vertex data ([`BandInput::touch`]).
pub(crate) const AHEAD: usize = 4;

/// One draw as every band reads it: the shader, the vertex stage's screen positions `pos`
/// ([`ScreenPos::NONE`] where a vertex has none) and varyings `attrs` (`S::VARYINGS` per
/// vertex), and the bin stage's chunks.
pub(crate) struct BandInput<'a, S: Shader> {
    /// The draw's shader.
    pub shader: &'a S,
    /// Screen position per mesh vertex.
    pub pos: &'a [ScreenPos],
    /// Varyings per mesh vertex.
    pub attrs: &'a [f32],
    /// Binned triangles, in submission order.
    pub chunks: &'a [Binned<S::Stepped>],
    /// Perspective-correct attributes.
    pub perspective: bool,
    /// The classic incremental scan line for interpolated triangles.
    pub incremental: bool,
    /// The frame's lane width.
    pub wide: Wide,
    /// The framebuffer's largest intensity, that every colour is clamped to.
    pub ceiling: f32,
    /// Only depth is written (a constant-colour shader drawing a shadow map): the colour
    /// buffer is left as it was, uncleared.
    pub depth_only: bool,
}

impl<S: Shader> BandInput<'_, S> {
    /// The screen positions and first `n` attributes of record `r`'s vertices: from `c`'s
    /// clipped vertices, or from the draw's per-vertex arrays; `None` when a vertex is
    /// missing or has no screen position.
    #[inline(always)]
    pub(crate) fn vertices_of<'c>(
        &'c self,
        r: &TriRec,
        c: &'c Binned<S::Stepped>,
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
        let stride = S::VARYINGS;
        let a = r.v.map(|i| {
            let i = i as usize;
            self.attrs.get(i * stride..(i + 1) * stride).unwrap_or(&[])
        });
        a.iter().all(|a| a.len() >= n).then_some((p, a))
    }

    /// What the planes of record `r` (with no clipped vertex) are set through
    /// ([`crate::group::Group::planes`]): its vertices' `1/w` and whether attributes are
    /// divided by `w`, and their first `S::VARYINGS` varyings (at most `L`) with zeros past
    /// them, as [`crate::traverse::Planes::set`] pads them.
    #[inline(always)]
    pub(crate) fn plane_values<const L: usize>(
        &self,
        r: &TriRec,
    ) -> (([f64; 3], bool), [[f32; L]; 3]) {
        let stride = S::VARYINGS;
        let (mut a, mut inv_w) = ([[0.0f32; L]; 3], [0.0f64; 3]);
        for j in 0..3 {
            let i = r.v[j] as usize;
            inv_w[j] = self.pos.get(i).map_or(0.0, |p| p.inv_w);
            if let Some(v) = self.attrs.get(i * stride..i * stride + stride) {
                let m = stride.min(L);
                a[j][..m].copy_from_slice(&v[..m]);
            }
        }
        ((inv_w, self.perspective && stride > 0), a)
    }

    /// Set-up of record `r` of chunk `c` into `t` with `n` attributes; false when it has no
    /// vertices or no area.
    #[inline(always)]
    pub(crate) fn setup(
        &self,
        t: &mut RasterTri,
        c: &Binned<S::Stepped>,
        r: &TriRec,
        n: usize,
    ) -> bool {
        let set = self
            .vertices_of(r, c, n)
            .is_some_and(|(p, a)| t.set(p, a, n, self.perspective));
        if let (true, Some(k)) = (set && n > 0, S::GRADIENTS) {
            t.add_gradients(k);
        }
        set
    }

    /// [`BandInput::setup`] out of line, for the depth pass that draws most records from lanes
    /// and sets up only the few large ones alone: inlined there, this set-up took registers
    /// from the lanes' rows (1.6 M instructions in a 1080p S1 phong frame). The one-pass
    /// loop keeps it inlined: out of line cost it 0.37 M.
    #[inline(never)]
    pub(crate) fn setup_apart(
        &self,
        t: &mut RasterTri,
        c: &Binned<S::Stepped>,
        r: &TriRec,
        n: usize,
    ) -> bool {
        self.setup(t, c, r, n)
    }

    /// Reads the first vertex data set-up will need of record `r` (one [`AHEAD`] places on),
    /// so that the cache misses of fetching it (vertices are scattered over the mesh) overlap
    /// the work on the records before it: a prefetch in safe code. The value is folded into a
    /// sink so that the loads are kept.
    #[inline(always)]
    pub(crate) fn touch(&self, r: Option<&TriRec>, n: usize) -> u32 {
        let Some(r) = r else { return 0 };
        let mut sink = 0u32;
        for &i in &r.v {
            if i & EXTRA_VERTEX == 0 {
                sink ^= self.pos.get(i as usize).map_or(0, |p| p.fx as u32);
                if n > 0 {
                    sink ^= self
                        .attrs
                        .get(i as usize * S::VARYINGS)
                        .map_or(0, |a| a.to_bits());
                }
            }
        }
        sink
    }

    /// Band `b`'s records, chunk after chunk, with the chunk each belongs to.
    pub(crate) fn records(
        &self,
        b: usize,
    ) -> impl Iterator<Item = (&Binned<S::Stepped>, &[TriRec])> {
        self.chunks.iter().map(move |c| (c, c.band(b)))
    }

    /// Whether record `r` is drawn by its stepped data (else it is interpolated).
    #[inline(always)]
    pub(crate) fn is_stepped(c: &Binned<S::Stepped>, r: &TriRec) -> bool {
        S::FACE == Face::Stepped && c.stepped_of(r).is_some()
    }

    /// Draws record `r` of chunk `c`, set up in `t` with the shader's varyings, into
    /// `target`'s pass; interpolated pixels of a shade-once shader go through `batched`.
    /// `INLINE`: a constant colour's or a per-pixel stage's traversal is inlined into the
    /// caller (the one-pass band loop compiled for AVX2). Returns the pixels shaded.
    #[inline(always)]
    pub(crate) fn draw<const INLINE: bool>(
        &self,
        t: &RasterTri,
        (c, r): (&Binned<S::Stepped>, &TriRec),
        target: &mut BandTarget,
        batched: &mut Batched<S>,
    ) -> u64 {
        match S::FACE {
            Face::Constant => {
                if self.depth_only {
                    return walk::<_, INLINE>(t, &mut DepthOnly, target);
                }
                let color = c.colors.get(r.tri as usize).copied().unwrap_or(Vec3::ZERO);
                return walk::<_, INLINE>(t, &mut Solid::of(color, self.ceiling), target);
            }
            Face::Stepped => {
                if let Some(tri) = c.stepped_of(r) {
                    let mut shade = SteppedSpan {
                        shader: self.shader,
                        tri,
                        ceiling: self.ceiling,
                        wide: self.wide,
                        queue: &mut batched.stepped,
                    };
                    let shaded = traverse(t, &mut shade, target);
                    // The queue holds this triangle's data: shade it before the next.
                    shade.flush(target.color);
                    return shaded;
                }
            }
            Face::Interpolated => {}
        }
        let full = target.pass == Pass::Full;
        let shaded = match (self.incremental, S::SHADE_ONCE) {
            (false, false) => {
                walk::<_, INLINE>(t, &mut OnePixel(self.shader, self.ceiling), target)
            }
            (false, true) => traverse(t, batched, target),
            (true, once) => {
                let Some((p, a)) = self.vertices_of(r, c, S::VARYINGS) else {
                    return 0;
                };
                let walk = IncrementalTri::new(p, a, S::VARYINGS);
                if once {
                    traverse_incremental(t, batched, &walk, target)
                } else {
                    traverse_incremental(t, &mut OnePixel(self.shader, self.ceiling), &walk, target)
                }
            }
        };
        // In a full pass a later triangle may draw over a waiting pixel: shade it now.
        if full {
            batched.flush(target.color);
        }
        shaded
    }

    /// The batching state of a band.
    pub(crate) fn batched(&self) -> Batched<'_, S> {
        Batched {
            shader: self.shader,
            pending: Pending::new(self.ceiling),
            stepped: StepQueue::new(),
        }
    }
}

/// [`traverse`], or with `INLINE` [`traverse_inline`].
#[inline(always)]
fn walk<T: SpanShade, const INLINE: bool>(
    t: &RasterTri,
    shade: &mut T,
    target: &mut BandTarget,
) -> u64 {
    if INLINE {
        traverse_inline(t, shade, target)
    } else {
        traverse(t, shade, target)
    }
}

/// The incremental walk's start of a record: its screen positions and varyings as the
/// set-up reads them.
impl IncrementalTri {
    /// From the three vertices' positions `p` and first `n` varyings `a` (divided by `w`).
    pub(crate) fn new(p: [ScreenPos; 3], a: [&[f32]; 3], n: usize) -> IncrementalTri {
        let inv_one = 1.0 / phosphor_math::fixed::SUBPIXEL_ONE as f64;
        IncrementalTri {
            xy: p.map(|p| (f64::from(p.fx) * inv_one, f64::from(p.fy) * inv_one)),
            inv_w: p.map(|p| p.inv_w as f32),
            attrs: a.map(|a| {
                let mut out = [0.0; crate::clip::MAX_ATTRS];
                for (o, v) in out.iter_mut().zip(a).take(n) {
                    *o = *v;
                }
                out
            }),
        }
    }
}
