//! Pixels batched into lanes for a shader's pixel stage: each pixel's interpolated attributes
//! are queued one pixel after another ([`Pending`]) and transposed into lanes on loading, or
//! built straight into lanes ([`AttrLanes`]); either layout ([`Batch`]) goes through
//! [`shade`], one pixel per lane, and the colours are written back. The lane width is the
//! frame's SIMD level: four lanes, or eight inside an AVX2 function ([`Wide`]).

use glam::Vec3;
use phosphor_lighting::Lanes;

use crate::clip::{Attrs, MAX_ATTRS};
use crate::shader::{MAX_VARYINGS, Shader, Varyings, interpolated};

/// A shader's pixel stage over `N` pixels' attribute rows, as the by-pixel and multisampled
/// passes call it: the colours of the first `count` rows (the others repeat the first),
/// clamped to `[0, ceiling]`. The passes take it as a trait object, called once per `N`
/// pixels, so that their traversal of the id buffer is compiled once per lane width instead
/// of once per shader: the per-shader copies made most of the binary's machine code.
pub(crate) type RowShader<'a, const N: usize> = dyn Fn(&[Attrs; N], usize, f32) -> [Vec3; N] + 'a;

/// `N <= 8` pixels' attributes already in lanes: `[k][i]` is attribute `k` of pixel `i`
/// (lanes past `N` unused). What the by-pixel pass builds a run of pixels into directly, so
/// that its pixels reach the pixel stage with no transpose.
pub(crate) type AttrLanes = [[f32; 8]; MAX_ATTRS];

/// A shader's pixel stage over `N` pixels' attributes in lanes ([`AttrLanes`]): the colours
/// of the first `count`, clamped to `[0, ceiling]`, as [`RowShader`]'s. The lanes past
/// `count` must hold finite attributes of some pixel (their colours are dropped).
pub(crate) type LaneShader<'a, const N: usize> = dyn Fn(&AttrLanes, usize, f32) -> [Vec3; N] + 'a;

/// Pixels waiting to be shaded `N` at a time, each with where its colour goes: a pixel index
/// of the band (`usize`), or a multisampled block's samples.
#[derive(Debug, Clone)]
pub(crate) struct Pending<T, const N: usize> {
    idx: [T; N],
    attrs: [Attrs; N],
    len: usize,
    /// The framebuffer's largest intensity, that colours are clamped to.
    ceiling: f32,
}

impl<T: Copy + Default, const N: usize> Pending<T, N> {
    /// No pixel waiting; colours will be clamped to `[0, ceiling]`.
    #[must_use]
    pub fn new(ceiling: f32) -> Pending<T, N> {
        Pending {
            idx: [T::default(); N],
            attrs: [[0.0; MAX_ATTRS]; N],
            len: 0,
            ceiling,
        }
    }

    /// Queues `at` with the first `l` of `attrs` times `w` (the perspective divide); true when
    /// the group holds `N`. `l` is a whole number of vector widths
    /// ([`crate::coverage::lanes`]) known when this is inlined: a fixed width compiles to a few
    /// vector multiplies where a loop to the shader's count did one lane at a time.
    #[inline(always)]
    pub fn queue(&mut self, at: T, (attrs, w, l): (&Attrs, f32, usize)) -> bool {
        // `len < N` always; masked (N is a power of two) so that no bounds check is compiled.
        let at_slot = if N.is_power_of_two() {
            self.len & (N - 1)
        } else {
            self.len
        };
        let slot = &mut self.attrs[at_slot];
        for k in 0..l {
            slot[k] = attrs[k] * w;
        }
        self.idx[at_slot] = at;
        self.len += 1;
        self.len == N
    }

    /// Shades the waiting entries with `shade` (the colours of the first `count` of `N`
    /// attribute sets, the others repeating the first, clamped to `[0, ceiling]`: see
    /// [`shade`]) and hands each colour to `write`.
    #[inline(always)]
    pub fn flush_into(
        &mut self,
        shade: impl FnOnce(&[Attrs; N], usize, f32) -> [Vec3; N],
        mut write: impl FnMut(T, Vec3),
    ) {
        if self.len == 0 {
            return;
        }
        for k in self.len..N {
            self.attrs[k] = self.attrs[0];
        }
        let c = shade(&self.attrs, self.len, self.ceiling);
        for k in 0..self.len {
            write(self.idx[k], c[k]);
        }
        self.len = 0;
    }
}

impl<const N: usize> Pending<usize, N> {
    /// Queues pixel `idx` of the band ([`Pending::queue`]), shading the group with `shade`
    /// once it holds `N`.
    #[inline(always)]
    pub fn push(
        &mut self,
        idx: usize,
        attrs: (&Attrs, f32, usize),
        shade: impl FnOnce(&[Attrs; N], usize, f32) -> [Vec3; N],
        color: &mut [Vec3],
    ) {
        if self.queue(idx, attrs) {
            self.flush_with(shade, color);
        }
    }

    /// Shades the waiting pixels with `shade` and writes their colours.
    #[inline(always)]
    pub fn flush_with(
        &mut self,
        shade: impl FnOnce(&[Attrs; N], usize, f32) -> [Vec3; N],
        color: &mut [Vec3],
    ) {
        self.flush_into(shade, |i, c| color[i] = c);
    }

    /// [`Pending::flush_with`] for a pass that queues pixels in row order: `N` pixels side
    /// by side (the by-pixel pass's short runs, in the interior of a fine mesh) are written
    /// as one copy rather than one by one. The test costs more than it saves where few
    /// groups are side by side (a triangle's spans of two or three pixels), so only that
    /// pass uses it.
    #[inline(always)]
    pub fn flush_side_by_side(
        &mut self,
        shade: impl FnOnce(&[Attrs; N], usize, f32) -> [Vec3; N],
        color: &mut [Vec3],
    ) {
        let first = self.idx[0];
        // A plain loop: `fold` over the range was left out of line, a call per group.
        let mut side_by_side = self.len == N;
        for i in 1..N {
            side_by_side &= self.idx[i] == first + i;
        }
        if side_by_side {
            if let Some(dst) = color.get_mut(first..first + N) {
                dst.copy_from_slice(&shade(&self.attrs, N, self.ceiling));
                self.len = 0;
                return;
            }
        }
        self.flush_into(shade, |i, c| color[i] = c);
    }
}

/// The rows of `N` pixels' attributes as one-pixel-per-lane varyings of the kind of `like`
/// (`L::N == N`): one transpose per eight attributes the shader reads.
#[inline(always)]
pub(crate) fn varyings_of_rows<S: Shader, L: Lanes, const N: usize>(
    like: L,
    rows: &[Attrs; N],
) -> Varyings<L> {
    let zero = like.splat(0.0);
    let mut v = [zero; MAX_VARYINGS];
    let block = |at: usize| -> [[f32; 8]; 8] {
        std::array::from_fn(|i| {
            let r = &rows[i.min(N - 1)];
            std::array::from_fn(|j| r[at + j])
        })
    };
    let lo = like.columns(&block(0));
    v[..8].copy_from_slice(&lo);
    if interpolated::<S>() > 8 {
        let hi = like.columns(&block(8));
        v[8..].copy_from_slice(&hi);
    }
    v
}

/// Attributes in lanes as varyings of the kind of `like`: one load per attribute the shader
/// reads.
#[inline(always)]
pub(crate) fn varyings_of_lanes<S: Shader, L: Lanes>(like: L, a: &AttrLanes) -> Varyings<L> {
    let zero = like.splat(0.0);
    let mut v = [zero; MAX_VARYINGS];
    let n = crate::coverage::lanes(interpolated::<S>());
    for k in 0..n {
        v[k] = like.with_lanes(a[k]);
    }
    v
}

/// Pixels' attributes in one of the two layouts the pixel stage reads: rows, one pixel after
/// another (`[Attrs; N]`, transposed on loading), or already in lanes ([`AttrLanes`]). The
/// pixel stage and its wrappers are written once over this, so that the two layouts share
/// every line but the load.
pub(crate) trait Batch {
    /// This batch's pixels as one-pixel-per-lane varyings of the kind of `like`.
    fn varyings<S: Shader, L: Lanes>(&self, like: L) -> Varyings<L>;
}

impl<const N: usize> Batch for [Attrs; N] {
    #[inline(always)]
    fn varyings<S: Shader, L: Lanes>(&self, like: L) -> Varyings<L> {
        varyings_of_rows::<S, L, N>(like, self)
    }
}

impl Batch for AttrLanes {
    #[inline(always)]
    fn varyings<S: Shader, L: Lanes>(&self, like: L) -> Varyings<L> {
        varyings_of_lanes::<S, L>(like, self)
    }
}

/// A batch of eight pixels, which four-lane frames shade as two halves of four.
pub(crate) trait Batch8: Batch {
    /// Four pixels of this batch, in the layout four-lane calls read.
    type Half: Batch;
    /// `f` of the first four pixels and of the last four.
    fn halves<R>(&self, f: impl FnOnce(&Self::Half, &Self::Half) -> R) -> R;
}

impl Batch8 for [Attrs; 8] {
    type Half = [Attrs; 4];
    #[inline(always)]
    fn halves<R>(&self, f: impl FnOnce(&[Attrs; 4], &[Attrs; 4]) -> R) -> R {
        let half = |at: usize| -> [Attrs; 4] { std::array::from_fn(|i| self[at + i]) };
        f(&half(0), &half(4))
    }
}

impl Batch8 for AttrLanes {
    type Half = AttrLanes;
    /// The first half is this batch itself (a four-lane load reads lanes 0 to 3); the second
    /// is lanes 4 to 7 moved down, repeated so that every lane stays finite.
    #[inline(always)]
    fn halves<R>(&self, f: impl FnOnce(&AttrLanes, &AttrLanes) -> R) -> R {
        let hi: AttrLanes = std::array::from_fn(|k| {
            let r = &self[k];
            [r[4], r[5], r[6], r[7], r[4], r[5], r[6], r[7]]
        });
        f(self, &hi)
    }
}

/// [`shade`] in four lanes: the one copy of a shader's four-lane pixel stage per layout, which
/// every pass shading four pixels at a time calls. Not inlined, so that the pixel stage, the
/// largest code of a shader, is compiled once per shader and layout rather than once per call
/// site.
#[inline(never)]
pub(crate) fn shade4<S: Shader, B: Batch>(
    shader: &S,
    batch: &B,
    count: usize,
    ceiling: f32,
) -> [Vec3; 4] {
    shade(
        shader,
        phosphor_lighting::f32x4::ZERO,
        batch,
        count,
        ceiling,
    )
}

/// The colours of `N` pixels from their attributes through [`Shader::pixel`] in lanes of the
/// kind of `like` (`L::N == N`), clamped to `[0, ceiling]` with NaN and `-0.0` as `+0.0`: the
/// values of [`crate::framebuffer::clamp_color_to`], computed for all lanes at once rather
/// than for each pixel as it is written.
#[inline(always)]
pub(crate) fn shade<S: Shader, L: Lanes, B: Batch, const N: usize>(
    shader: &S,
    like: L,
    batch: &B,
    count: usize,
    ceiling: f32,
) -> [Vec3; N] {
    let c = shader.pixel(&batch.varyings::<S, L>(like));
    clamped_colors(c, count, ceiling)
}

/// The first `N` lanes of `c` as colours clamped to `[0, ceiling]` with NaN and `-0.0` as
/// `+0.0` (in debug builds, the first `count` checked finite).
#[inline(always)]
pub(crate) fn clamped_colors<L: Lanes, const N: usize>(
    c: phosphor_lighting::Vec3s<L>,
    count: usize,
    ceiling: f32,
) -> [Vec3; N] {
    if cfg!(debug_assertions) {
        let v = c.to_vecs();
        for (k, v) in v.iter().enumerate().take(count.min(N)) {
            assert!(v.is_finite(), "non-finite colour {v} in lane {k}");
        }
    }
    // `max_c` and `min_c` are the scalar selects `x > 0 ? x : 0` and `x < c ? x : c`.
    let (zero, top) = (c.x.splat(0.0), c.x.splat(ceiling));
    let clamp = |x: L| x.max_c(zero).min_c(top);
    let c = phosphor_lighting::Vec3s::new(clamp(c.x), clamp(c.y), clamp(c.z)).to_vecs();
    std::array::from_fn(|i| c[i])
}

/// The frame's lane width: eight lanes inside an AVX2 function when the frame runs them,
/// else four.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Wide {
    /// The AVX2 token when the frame runs eight lanes.
    pub avx2: Option<crate::simd::Avx2>,
}

impl Wide {
    /// The colours of eight pixels: one AVX2 call, or two of four lanes.
    #[inline(always)]
    pub fn shade8<S: Shader, B: Batch8>(
        self,
        shader: &S,
        batch: &B,
        count: usize,
        ceiling: f32,
    ) -> [Vec3; 8] {
        #[cfg(target_arch = "x86_64")]
        if let Some(avx2) = self.avx2 {
            return avx2.run(Shade8 {
                shader,
                batch,
                count,
                ceiling,
            });
        }
        let (lo, hi) = batch.halves(|lo, hi| {
            (
                shade4(shader, lo, count.min(4), ceiling),
                shade4(shader, hi, count.saturating_sub(4), ceiling),
            )
        });
        std::array::from_fn(|i| if i < 4 { lo[i] } else { hi[i - 4] })
    }
}

/// Eight pixels of a shader's pixel stage as one AVX2 task.
#[cfg(target_arch = "x86_64")]
struct Shade8<'a, S, B> {
    shader: &'a S,
    batch: &'a B,
    count: usize,
    ceiling: f32,
}

#[cfg(target_arch = "x86_64")]
impl<S: Shader, B: Batch> phosphor_lighting::Avx2Task for Shade8<'_, S, B> {
    type Output = [Vec3; 8];
    #[inline(always)]
    fn run(self, s: phosphor_lighting::Avx2) -> [Vec3; 8] {
        shade(
            self.shader,
            s.splat(0.0),
            self.batch,
            self.count,
            self.ceiling,
        )
    }
}
