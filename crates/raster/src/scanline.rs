//! Traversal per scan line and span, over a triangle's bounding box.
//!
//! Coverage is exact: three integer edge functions at the fixed-point pixel centres with a
//! top-left rule ([`RasterTri`]), stepped by one add per pixel. A row's covered pixels are
//! contiguous (the triangle is convex), so each row is one span: found by stepping the edges
//! across a narrow box, or by one exact division per edge on a wide one. Two triangles sharing
//! an edge evaluate it from the same two integer endpoints, so they split its pixels without gap
//! or overlap.
//!
//! Attributes are planes `A(x, y)`: at each span start every plane is evaluated afresh, then
//! stepped along the span by the triangle's constant `dA/dx` per pixel (Gouraud 1971's
//! `(I5 - I4)/(x5 - x4)`). Unlike the classic scan-line algorithm, nothing is stepped from one
//! scan line to the next, so no rounding error accumulates down a tall triangle. The classic
//! form, edge values stepped per scan line in f32, is [`traverse_incremental`]
//! ([`crate::Interpolation::Incremental`]), with the same coverage and depth. With
//! perspective the stepped values are `A/w` and `1/w`, divided per pixel.
//!
//! A band can be drawn in two passes ([`Pass`]): depth only, recording which triangle is
//! nearest at each pixel, then shading only those pixels. The picture is the same as one pass
//! (the nearest triangle, the first of equals in submission order) with each pixel shaded once.

use glam::Vec3;

use crate::clip::{Attrs, MAX_ATTRS};
use crate::framebuffer::clamp_color;
use crate::setup::RasterTri;

/// Small boxes at most this wide find their spans by testing the edges at every pixel, four at
/// a time; others solve each edge for the span ends (one division per edge and row).
const STEP_WIDTH: i64 = 16;

/// Per-pixel shading stage of a mode (see `shade/`): what to compute at a span start, at a
/// pixel that passed the depth test, and when stepping one pixel right.
pub trait Kernel: Sync {
    /// Attributes the kernel reads (a prefix of [`Attrs`]).
    const ATTRS: usize;
    /// Per-triangle data built by the mode's setup.
    type Tri: Sync + Send;
    /// Per-span state (forward differences for fast Phong; `()` for most).
    type Span;
    /// State at the first pixel of a span whose centre is `(x, y)` in pixels.
    fn span(&self, tri: &Self::Tri, x: f32, y: f32) -> Self::Span;
    /// Colour at pixel `(px, py)` with the interpolated (already perspective-divided) `attrs`.
    fn shade(&self, tri: &Self::Tri, span: &Self::Span, attrs: &Attrs, px: u32, py: u32) -> Vec3;
    /// Moves the span state one pixel to the right.
    fn step(span: &mut Self::Span);
    /// Pixels shaded per call of [`Kernel::shade_lanes`]: 1 (every pixel through
    /// [`Kernel::shade`]) or 4 (pixels of a triangle gathered and shaded four at a time).
    const LANES: usize = 1;
    /// The colours of the first `count` of four pixels with attributes `attrs` (only called
    /// when `LANES` is 4, for kernels with no per-span or per-pixel-position state); lanes past
    /// `count` hold copies of lane 0 and their colours are ignored. Must equal
    /// [`Kernel::shade`] per lane.
    fn shade_lanes(&self, tri: &Self::Tri, attrs: &[Attrs; 4], count: usize) -> [Vec3; 4] {
        let _ = (tri, attrs, count);
        [Vec3::ZERO; 4]
    }
    /// True when [`Kernel::shade_lanes`] does not read the triangle data, so that in the
    /// visible pass (each pixel written by one triangle) pixels of successive triangles can
    /// share a group of four; the mode then flushes the last group (`Mode::finish`).
    const ACROSS_TRIANGLES: bool = false;
}

/// Pixels waiting to be shaded `N` at a time (four for [`Kernel::LANES`]; eight for the
/// by-pixel pass on AVX2), each with where its colour goes: a pixel index of the band
/// (`usize`), or a multisampled block's samples.
#[derive(Debug, Clone)]
pub struct Pending<T = usize, const N: usize = 4> {
    idx: [T; N],
    attrs: [Attrs; N],
    len: usize,
}

impl Default for Pending {
    fn default() -> Pending {
        Pending::new()
    }
}

impl<T: Copy + Default, const N: usize> Pending<T, N> {
    /// No pixel waiting.
    #[must_use]
    pub fn new() -> Pending<T, N> {
        Pending {
            idx: [T::default(); N],
            attrs: [[0.0; MAX_ATTRS]; N],
            len: 0,
        }
    }

    /// Queues `at` with the first `l` of `attrs` times `w` (the perspective divide); true when
    /// the group holds `N`. `l` is a whole number of vector widths ([`lanes`]) known when this
    /// is inlined: kernels read only their own attributes, and a fixed width compiles to a few
    /// vector multiplies where a loop to the kernel's count did one lane at a time.
    #[inline(always)]
    fn queue(&mut self, at: T, (attrs, w, l): (&Attrs, f32, usize)) -> bool {
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
    /// attribute sets; the others repeat the first) and hands each clamped colour to `write`.
    #[inline(always)]
    fn flush_into(
        &mut self,
        shade: impl FnOnce(&[Attrs; N], usize) -> [Vec3; N],
        mut write: impl FnMut(T, Vec3),
    ) {
        if self.len == 0 {
            return;
        }
        for k in self.len..N {
            self.attrs[k] = self.attrs[0];
        }
        let c = shade(&self.attrs, self.len);
        for k in 0..self.len {
            debug_assert!(c[k].is_finite(), "non-finite colour {}", c[k]);
            write(self.idx[k], clamp_color(c[k]));
        }
        self.len = 0;
    }
}

impl Pending {
    /// Shades the waiting pixels with `kernel` and writes their colours.
    #[inline(always)]
    pub fn flush<K: Kernel>(&mut self, kernel: &K, tri: &K::Tri, color: &mut [Vec3]) {
        self.flush_with(|a, count| kernel.shade_lanes(tri, a, count), color);
    }
}

impl<const N: usize> Pending<usize, N> {
    /// Queues pixel `idx` of the band ([`Pending::queue`]), shading the group with `shade`
    /// once it holds `N`.
    #[inline(always)]
    fn push(
        &mut self,
        idx: usize,
        attrs: (&Attrs, f32, usize),
        shade: impl FnOnce(&[Attrs; N], usize) -> [Vec3; N],
        color: &mut [Vec3],
    ) {
        if self.queue(idx, attrs) {
            self.flush_with(shade, color);
        }
    }

    /// Shades the waiting pixels with `shade` and writes their colours.
    #[inline(always)]
    fn flush_with(
        &mut self,
        shade: impl FnOnce(&[Attrs; N], usize) -> [Vec3; N],
        color: &mut [Vec3],
    ) {
        self.flush_into(shade, |i, c| color[i] = c);
    }
}

/// What a traversal does at a covered pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Pass {
    /// Depth test, then shade and write colour and depth.
    Full,
    /// Shade only where the depth pass recorded this triangle (`ids[pixel] == id`); depth was
    /// written by that pass.
    Visible(u64),
}

/// The rows of the framebuffer one band owns.
pub struct BandTarget<'a> {
    /// Colours of rows `y0..y1`.
    pub color: &'a mut [Vec3],
    /// Depths of rows `y0..y1`.
    pub depth: &'a mut [f32],
    /// Image width.
    pub width: u32,
    /// First row of the band.
    pub y0: i64,
    /// One past the last row.
    pub y1: i64,
    /// Debug hook: count coverage in the red channel (no depth test, no clamp) instead of shading.
    pub count: bool,
    /// The pass being drawn.
    pub pass: Pass,
    /// The nearest triangle's id per pixel of the band, from the depth pass (empty for
    /// [`Pass::Full`]).
    pub ids: &'a [u64],
    /// Pixels waiting for a four-pixel kernel.
    pub pending: Pending,
}

impl<'a> BandTarget<'a> {
    /// The band of rows `y0..` held in `color` and `depth` (`width` pixels a row), drawn in
    /// one full pass.
    #[must_use]
    pub fn new(
        color: &'a mut [Vec3],
        depth: &'a mut [f32],
        width: u32,
        y0: i64,
        count: bool,
    ) -> BandTarget<'a> {
        let rows = color.len() / width.max(1) as usize;
        BandTarget {
            color,
            depth,
            width,
            y0,
            y1: y0 + rows as i64,
            count,
            pass: Pass::Full,
            ids: &[],
            pending: Pending::new(),
        }
    }
}

/// The depth test and the depth written by every pass (one definition, so the depth pass and
/// a single full pass agree bit for bit).
#[inline(always)]
fn depth_passes(depth: f64, stored: f32) -> bool {
    (depth as f32) < stored
}

/// Whether a span draws pixel `idx`: in a visible-only pass, where the id buffer holds this
/// triangle's `id`; in the coverage-count hook never (it counts the pixel instead); otherwise
/// where the depth test passes. One definition for the plane and the incremental spans.
#[inline(always)]
fn pixel_drawn<const VISIBLE: bool>(
    target: &mut BandTarget,
    idx: usize,
    id: u64,
    depth: f64,
) -> bool {
    if VISIBLE {
        target.ids[idx] == id
    } else if target.count {
        target.color[idx].x += 1.0;
        false
    } else {
        depth_passes(depth, target.depth[idx])
    }
}

#[inline(always)]
fn depth_stored(depth: f64) -> f32 {
    depth.max(0.0) as f32
}

/// The iteration every pass shares: the rows of `t` inside band rows `[y0, y1)`, its columns
/// inside `[0, width)`, the edges stepped from the first of those pixels. Calls
/// `row(y, xs, xe)` for each row with a non-empty span `[xs, xe)`.
#[inline(always)]
fn for_each_span(t: &RasterTri, width: u32, y0: i64, y1: i64, mut row: impl FnMut(i64, i64, i64)) {
    let (lo, hi) = (t.x0.max(0), t.x1.min(width as i64));
    let (ylo, yhi) = (t.y0.max(y0), t.y1.min(y1));
    if lo >= hi || ylo >= yhi {
        return;
    }
    let one = phosphor_math::fixed::SUBPIXEL_ONE;
    let e = t.edges_at(lo, ylo);
    if hi - lo <= STEP_WIDTH && t.x1 - t.x0 <= SMALL_SIDE && t.y1 - t.y0 <= SMALL_SIDE {
        // A small triangle: every edge value inside its box (and up to 16 columns right of
        // it) fits in i32 (see SMALL_SIDE). Each row tests four pixels per step with no branch
        // per pixel: a bit per covered pixel, and the span is the run of set bits.
        let lanes = wide::i32x4::new([0, 1, 2, 3]);
        let col: [i32; 3] = t.edge_a.map(|a| (a * one) as i32);
        let down: [i32; 3] = t.edge_b.map(|b| (b * one) as i32);
        let ramp = col.map(|c| lanes * wide::i32x4::splat(c));
        let four = col.map(|c| wide::i32x4::splat(4 * c));
        let steps = (hi - lo + 3) / 4;
        let valid = (1u32 << (hi - lo)) - 1;
        let mut e_row = e.map(|v| v as i32);
        for y in ylo..yhi {
            let mut v = [0, 1, 2].map(|i| wide::i32x4::splat(e_row[i]) + ramp[i]);
            let mut outside = 0u32;
            for k in 0..steps {
                // Sign bits: 1 where some edge is negative (outside).
                outside |= ((v[0] | v[1] | v[2]).move_mask() as u32) << (4 * k);
                for i in 0..3 {
                    v[i] += four[i];
                }
            }
            let inside = !outside & valid;
            if inside != 0 {
                let xs = lo + i64::from(inside.trailing_zeros());
                let xe = lo + 32 - i64::from(inside.leading_zeros());
                row(y, xs, xe);
            }
            for i in 0..3 {
                e_row[i] += down[i];
            }
        }
        return;
    }
    let col = t.edge_a.map(|a| a * one);
    let down = t.edge_b.map(|b| b * one);
    let mut e_row = e;
    for y in ylo..yhi {
        let (xs, xe) = row_span(e_row, col, lo, hi);
        if xs < xe {
            row(y, xs, xe);
        }
        for i in 0..3 {
            e_row[i] += down[i];
        }
    }
}

/// The attribute lanes a kernel reading `n` attributes steps: `n` rounded up to whole
/// four-lane vectors. Lanes past `n` hold values no kernel reads (from a plane set up for
/// more attributes, or stale); stepping them costs nothing where a loop to `n` stepped one lane
/// at a time. A compile-time constant per kernel.
#[must_use]
pub const fn lanes(n: usize) -> usize {
    let l = n.div_ceil(4) * 4;
    if l > MAX_ATTRS { MAX_ATTRS } else { l }
}

/// Largest box side (pixels) of a small triangle. Within its box and 16 columns beyond, an
/// edge value is at most `|a| dx + |b| dy <= 2 ((SMALL_SIDE + STEP_WIDTH + 1) 256)^2 < 2^31`.
const SMALL_SIDE: i64 = 64;

/// The covered span `[xs, xe)` within columns `[lo, hi)` of a row whose edge values at `lo`
/// are `e`, each edge stepping by `step` per pixel (`xs >= xe` when empty): one exact division
/// per edge.
#[inline(always)]
fn row_span(e: [i64; 3], step: [i64; 3], lo: i64, hi: i64) -> (i64, i64) {
    // Edge i holds at lo + k iff e_i + k step_i >= 0.
    let (mut ks, mut ke) = (0, hi - lo);
    for i in 0..3 {
        let (ei, si) = (e[i], step[i]);
        if si > 0 {
            if ei < 0 {
                ks = ks.max((-ei + si - 1) / si);
            }
        } else if si < 0 {
            if ei < 0 {
                return (0, 0);
            }
            ke = ke.min(ei / -si + 1);
        } else if ei < 0 {
            return (0, 0);
        }
    }
    (lo + ks, lo + ke)
}

/// Draws the part of triangle `t` inside the band with kernel `K`; returns the number of
/// pixels shaded.
pub fn traverse<K: Kernel>(
    t: &RasterTri,
    kernel: &K,
    tri: &K::Tri,
    target: &mut BandTarget,
) -> u64 {
    if t.n < K::ATTRS {
        // Set up with fewer attributes than the kernel reads: the missing ones are zero. (The
        // traversal steps the kernel's lanes whole, see `lanes`, whatever the plane holds past
        // its own count.)
        let mut padded = *t;
        for k in t.n..MAX_ATTRS {
            padded.attr0[k] = 0.0;
            padded.attr_dx[k] = 0.0;
            padded.attr_dy[k] = 0.0;
        }
        padded.n = K::ATTRS;
        return traverse(&padded, kernel, tri, target);
    }
    match (t.perspective, target.pass) {
        (true, Pass::Full) => traverse_impl::<K, true, false>(t, kernel, tri, target),
        (false, Pass::Full) => traverse_impl::<K, false, false>(t, kernel, tri, target),
        (true, Pass::Visible(_)) => traverse_impl::<K, true, true>(t, kernel, tri, target),
        (false, Pass::Visible(_)) => traverse_impl::<K, false, true>(t, kernel, tri, target),
    }
}

/// The depth pass: depth test and write, and `ids[pixel] = id` where this triangle is now the
/// nearest. `extents[row]` (rows of the band) is widened to the columns `[lo, hi)` written.
/// Returns the pixels written.
pub fn depth_only(
    t: &RasterTri,
    target: &mut BandTarget,
    ids: &mut [u64],
    extents: &mut [(u32, u32)],
    id: u64,
) -> u64 {
    let mut written = 0;
    let width = target.width as usize;
    let (y0, y1, stored) = (target.y0, target.y1, &mut *target.depth);
    // Inlined: called once per row, and most triangles have only a few.
    for_each_span(
        t,
        target.width,
        y0,
        y1,
        #[inline(always)]
        |y, xs, xe| {
            let (ox, oy) = (xs as f64 + 0.5 - t.origin.0, y as f64 + 0.5 - t.origin.1);
            let mut depth = t.depth[0] + ox * t.depth[1] + oy * t.depth[2];
            let before = written;
            let row = ((y - y0) as usize) * width;
            for idx in row + xs as usize..row + xe as usize {
                if depth_passes(depth, stored[idx]) {
                    stored[idx] = depth_stored(depth);
                    ids[idx] = id;
                    written += 1;
                }
                depth += t.depth[1];
            }
            if written > before {
                if let Some(e) = extents.get_mut((y - y0) as usize) {
                    *e = (e.0.min(xs as u32), e.1.max(xe as u32));
                }
            }
        },
    );
    written
}

/// The attribute planes of a set-up triangle: what [`ByPixel`] evaluates.
#[derive(Debug, Clone, Copy)]
pub struct Planes {
    /// Plane origin in pixels.
    pub origin: (f64, f64),
    /// `1/w` at the origin, `d/dx`, `d/dy`.
    pub inv_w: [f64; 3],
    /// Attributes at the origin.
    pub attr0: Attrs,
    /// `d attr / dx`.
    pub attr_dx: Attrs,
    /// `d attr / dy`.
    pub attr_dy: Attrs,
}

impl Planes {
    /// The planes of `t`.
    #[inline]
    #[must_use]
    pub fn of(t: &RasterTri) -> Planes {
        Planes {
            origin: t.origin,
            inv_w: t.inv_w,
            attr0: t.attr0,
            attr_dx: t.attr_dx,
            attr_dy: t.attr_dy,
        }
    }
}

/// `1/w` and attributes `0..n` at offset `(ox, oy)` from the planes' origin: each plane
/// (`inv_w`, and `attr0`, `attr_dx`, `attr_dy` in `a`) evaluated once, as at a span start;
/// stepping by `dA/dx` then continues along the row. `1/w` is evaluated in f64, as the depth
/// pass's depth; the attributes in f32 from the origin (a vertex of the triangle, so the
/// offsets are at most the triangle's size), which is whole f32 vectors and as exact as the
/// f32 stepping that follows.
#[inline(always)]
fn planes_at(inv_w: &[f64; 3], a: [&Attrs; 3], (ox, oy): (f64, f64), n: usize) -> (f64, Attrs) {
    let inv_w = inv_w[0] + ox * inv_w[1] + oy * inv_w[2];
    let (fx, fy) = (ox as f32, oy as f32);
    let mut attrs: Attrs = [0.0; MAX_ATTRS];
    for k in 0..n {
        attrs[k] = a[0][k] + fx * a[1][k] + fy * a[2][k];
    }
    (inv_w, attrs)
}

/// The shading pass of a band from its id buffer alone, for kernels that read nothing but the
/// interpolated attributes: every pixel whose id (from [`depth_only`], `epoch + k`) names
/// record `k` of the band gets the colour of that triangle's `planes[slot[k]]`, four pixels per
/// call, with no second traversal of the triangles. Along a row, a run of pixels of one
/// triangle is evaluated once at its first pixel and then stepped by `dA/dx` (the incremental
/// form along a span, as in the traversal's spans). Only columns `extents[row]` are read.
#[derive(Debug, Clone, Copy)]
pub struct ByPixel<'a> {
    /// Per record of the band: its index in `planes`, or `u32::MAX` when it has none.
    pub slot: &'a [u32],
    /// Attribute planes of the records that can be visible.
    pub planes: &'a [Planes],
    /// The nearest record's id per band pixel.
    pub ids: &'a [u64],
    /// The id of the band's record 0.
    pub epoch: u64,
    /// Per row of the band: the columns `[lo, hi)` the depth pass wrote.
    pub extents: &'a [(u32, u32)],
    /// Image width.
    pub width: u32,
    /// First row of the band.
    pub y0: i64,
    /// Attributes in use.
    pub n: usize,
    /// Whether attributes are divided by `w`.
    pub perspective: bool,
    /// Multisampling: the band holds samples, `block x block` of them per output pixel
    /// (aligned to the band's first row), and each triangle is shaded once per block at the
    /// centroid of the samples it owns there, and the colour written to each of them. 2 or
    /// 4; any other value shades every sample.
    pub block: usize,
}

impl ByPixel<'_> {
    /// Shades the band's pixels into `color` with `shade` (the colours of the first `count` of
    /// `N` attribute sets), `N` pixels per call; returns the pixels shaded.
    pub fn shade<const N: usize>(
        &self,
        color: &mut [Vec3],
        shade: impl Fn(&[Attrs; N], usize) -> [Vec3; N],
    ) -> u64 {
        match self.block {
            2 => return self.shade_blocks::<N, 2, 4>(color, shade),
            4 => return self.shade_blocks::<N, 4, 16>(color, shade),
            _ => {}
        }
        // The lane count as a constant: the stepping and the divide compile to whole vectors.
        match (self.perspective, lanes(self.n)) {
            (true, 0) => self.run::<N, true, 0>(color, shade),
            (true, 4) => self.run::<N, true, 4>(color, shade),
            (true, 8) => self.run::<N, true, 8>(color, shade),
            (true, _) => self.run::<N, true, MAX_ATTRS>(color, shade),
            (false, 0) => self.run::<N, false, 0>(color, shade),
            (false, 4) => self.run::<N, false, 4>(color, shade),
            (false, 8) => self.run::<N, false, 8>(color, shade),
            (false, _) => self.run::<N, false, MAX_ATTRS>(color, shade),
        }
    }

    /// [`ByPixel::shade`] of a multisampled band, `K x K` samples per pixel (`S` = `K * K`).
    fn shade_blocks<const N: usize, const K: usize, const S: usize>(
        &self,
        color: &mut [Vec3],
        shade: impl Fn(&[Attrs; N], usize) -> [Vec3; N],
    ) -> u64 {
        match (self.perspective, lanes(self.n)) {
            (true, 0) => self.run_blocks::<N, true, 0, K, S>(color, shade),
            (true, 4) => self.run_blocks::<N, true, 4, K, S>(color, shade),
            (true, 8) => self.run_blocks::<N, true, 8, K, S>(color, shade),
            (true, _) => self.run_blocks::<N, true, MAX_ATTRS, K, S>(color, shade),
            (false, 0) => self.run_blocks::<N, false, 0, K, S>(color, shade),
            (false, 4) => self.run_blocks::<N, false, 4, K, S>(color, shade),
            (false, 8) => self.run_blocks::<N, false, 8, K, S>(color, shade),
            (false, _) => self.run_blocks::<N, false, MAX_ATTRS, K, S>(color, shade),
        }
    }

    /// [`ByPixel::shade`] stepping `L` attribute lanes ([`lanes`] of `self.n`).
    #[inline(always)]
    fn run<const N: usize, const PERSPECTIVE: bool, const L: usize>(
        &self,
        color: &mut [Vec3],
        shade4: impl Fn(&[Attrs; N], usize) -> [Vec3; N],
    ) -> u64 {
        let width = self.width as usize;
        let mut shaded = 0;
        let mut pending = Pending::<usize, N>::new();
        for (row, &(lo, hi)) in self.extents.iter().enumerate() {
            let base = row * width;
            let (lo, hi) = (lo as usize, (hi as usize).min(width));
            let Some(row_ids) = self.ids.get(base + lo..base + hi) else {
                continue;
            };
            let yc = (self.y0 + row as i64) as f64 + 0.5;
            // The run being stepped: its id, the next column it would continue at, and its
            // steps per pixel (kept, so that a pixel continuing it looks nothing up).
            let (mut run, mut next) = (u64::MAX, usize::MAX);
            let (mut inv_w, mut attrs) = (1.0f64, [0.0f32; MAX_ATTRS]);
            let (mut step_w, mut step) = (0.0f64, [0.0f32; MAX_ATTRS]);
            for (i, &id) in row_ids.iter().enumerate() {
                let x = lo + i;
                if id == run && x == next {
                    if PERSPECTIVE {
                        inv_w += step_w;
                    }
                    // Whole vectors, as in `Pending::push`.
                    for k in 0..L {
                        attrs[k] += step[k];
                    }
                } else {
                    let Some(p) = self.planes_of(id) else {
                        continue;
                    };
                    let o = (x as f64 + 0.5 - p.origin.0, yc - p.origin.1);
                    (inv_w, attrs) = planes_at(&p.inv_w, [&p.attr0, &p.attr_dx, &p.attr_dy], o, L);
                    (step_w, step) = (p.inv_w[1], p.attr_dx);
                    run = id;
                }
                next = x + 1;
                let w = if PERSPECTIVE {
                    (1.0 / inv_w) as f32
                } else {
                    1.0
                };
                pending.push(base + x, (&attrs, w, L), &shade4, color);
                shaded += 1;
            }
        }
        pending.flush_with(&shade4, color);
        shaded
    }
}

impl ByPixel<'_> {
    /// The planes of the triangle with id `id`, if it is shaded here (ids below the epoch
    /// were left by earlier bands).
    #[inline(always)]
    fn planes_of(&self, id: u64) -> Option<&Planes> {
        (id >= self.epoch)
            .then(|| self.slot.get((id - self.epoch) as usize))
            .flatten()
            .and_then(|&s| self.planes.get(s as usize))
    }

    /// The columns of blocks in block row `by` that the depth pass wrote in any of its rows.
    fn block_columns<const K: usize>(&self, by: usize) -> std::ops::Range<usize> {
        let width = self.width as usize;
        let rows = self
            .extents
            .get(by * K..((by + 1) * K).min(self.extents.len()));
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
        color: &mut [Vec3],
        shade4: impl Fn(&[Attrs; N], usize) -> [Vec3; N],
    ) -> u64 {
        let kf = K as f64;
        let width = self.width as usize;
        let all = block_mask::<K>();
        let mut shaded = 0;
        let mut pending = Pending::<BlockSamples, N>::new();
        for by in 0..self.extents.len() / K {
            let top = (self.y0 + (by * K) as i64) as f64;
            // The run of whole blocks being stepped, as in `run`, by K pixels a block.
            let (mut run, mut next) = (u64::MAX, usize::MAX);
            let (mut inv_w, mut attrs) = (1.0f64, [0.0f32; MAX_ATTRS]);
            let (mut step_w, mut step) = (0.0f64, [0.0f32; MAX_ATTRS]);
            for bx in self.block_columns::<K>(by) {
                let base = by * K * width + bx * K;
                let Some(ids) = self.block_ids::<K, S>(base) else {
                    continue;
                };
                if ids[1..].iter().all(|&id| id == ids[0]) {
                    if ids[0] == run && bx == next {
                        if PERSPECTIVE {
                            inv_w += step_w;
                        }
                        for j in 0..L {
                            attrs[j] += step[j];
                        }
                    } else {
                        let Some(p) = self.planes_of(ids[0]) else {
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
                        run = ids[0];
                    }
                    next = bx + 1;
                    let w = if PERSPECTIVE {
                        (1.0 / inv_w) as f32
                    } else {
                        1.0
                    };
                    if pending.queue((base, all), (&attrs, w, L)) {
                        pending.flush_into(&shade4, |at, c| write_block::<K>(color, width, at, c));
                    }
                    shaded += 1;
                    continue;
                }
                // An edge: once per triangle shown, at the centroid of its samples.
                run = u64::MAX;
                let mut left = all;
                while left != 0 {
                    let first = left.trailing_zeros() as usize;
                    let id = ids[first];
                    let mut mask = 0u16;
                    for (j, &other) in ids.iter().enumerate().skip(first) {
                        if other == id {
                            mask |= 1 << j;
                        }
                    }
                    left &= !mask;
                    let Some(p) = self.planes_of(id) else {
                        continue;
                    };
                    let (cx, cy) = centroid::<K>(mask);
                    let o = ((bx * K) as f64 + cx - p.origin.0, top + cy - p.origin.1);
                    let (iw, a) = planes_at(&p.inv_w, [&p.attr0, &p.attr_dx, &p.attr_dy], o, L);
                    let w = if PERSPECTIVE { (1.0 / iw) as f32 } else { 1.0 };
                    if pending.queue((base, mask), (&a, w, L)) {
                        pending.flush_into(&shade4, |at, c| write_block::<K>(color, width, at, c));
                    }
                    shaded += 1;
                }
            }
        }
        pending.flush_into(&shade4, |at, c| write_block::<K>(color, width, at, c));
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

/// Where a multisampled shading's colour goes: the first sample of its block and a mask of the
/// block's samples (bit `sy * K + sx`) that take it.
type BlockSamples = (usize, u16);

/// Writes colour `c` to the samples `(base, mask)` of a `K x K` block in rows `width` long.
#[inline(always)]
fn write_block<const K: usize>(
    color: &mut [Vec3],
    width: usize,
    (base, mask): BlockSamples,
    c: Vec3,
) {
    if mask == block_mask::<K>() {
        for sy in 0..K {
            let row = base + sy * width;
            if let Some(row) = color.get_mut(row..row + K) {
                row.fill(c);
            }
        }
        return;
    }
    for sy in 0..K {
        for sx in 0..K {
            if mask & (1 << (sy * K + sx)) != 0 {
                if let Some(p) = color.get_mut(base + sy * width + sx) {
                    *p = c;
                }
            }
        }
    }
}

fn traverse_impl<K: Kernel, const PERSPECTIVE: bool, const VISIBLE: bool>(
    t: &RasterTri,
    kernel: &K,
    tri: &K::Tri,
    target: &mut BandTarget,
) -> u64 {
    let mut shaded = 0;
    let (width, y0, y1) = (target.width, target.y0, target.y1);
    for_each_span(
        t,
        width,
        y0,
        y1,
        #[inline(always)]
        |y, xs, xe| {
            shaded += span::<K, PERSPECTIVE, VISIBLE>(t, kernel, tri, target, y, xs, xe);
        },
    );
    if K::LANES == 4 && !(VISIBLE && K::ACROSS_TRIANGLES) {
        target.pending.flush(kernel, tri, target.color);
    }
    shaded
}

/// One span of `t` (set up with at least the kernel's attributes, see [`traverse`]): the
/// kernel's attribute lanes are stepped whole ([`lanes`]).
#[inline(always)]
fn span<K: Kernel, const PERSPECTIVE: bool, const VISIBLE: bool>(
    t: &RasterTri,
    kernel: &K,
    tri: &K::Tri,
    target: &mut BandTarget,
    y: i64,
    x_start: i64,
    x_end: i64,
) -> u64 {
    let n = lanes(K::ATTRS);
    // Span start: every plane evaluated once at the first pixel centre.
    let xc = x_start as f64 + 0.5;
    let yc = y as f64 + 0.5;
    let (ox, oy) = (xc - t.origin.0, yc - t.origin.1);
    let mut depth = t.depth[0] + ox * t.depth[1] + oy * t.depth[2];
    let (mut inv_w, mut attrs) =
        planes_at(&t.inv_w, [&t.attr0, &t.attr_dx, &t.attr_dy], (ox, oy), n);
    let mut state = kernel.span(tri, xc as f32, yc as f32);
    let row = ((y - target.y0) as usize) * target.width as usize;
    let id = match target.pass {
        Pass::Visible(id) => id,
        Pass::Full => 0,
    };
    let mut shaded = 0;
    let mut out: Attrs = [0.0; MAX_ATTRS];
    for x in x_start..x_end {
        let idx = row + x as usize;
        let draw = pixel_drawn::<VISIBLE>(target, idx, id, depth);
        if draw {
            let w = if PERSPECTIVE {
                (1.0 / inv_w) as f32
            } else {
                1.0
            };
            if K::LANES == 4 {
                let shade = |a: &[Attrs; 4], count| kernel.shade_lanes(tri, a, count);
                target
                    .pending
                    .push(idx, (&attrs, w, n), shade, target.color);
            } else {
                for k in 0..n {
                    out[k] = attrs[k] * w;
                }
                let c = kernel.shade(tri, &state, &out, x as u32, y as u32);
                debug_assert!(c.is_finite(), "non-finite colour {c} at ({x}, {y})");
                target.color[idx] = clamp_color(c);
            }
            if !VISIBLE {
                target.depth[idx] = depth_stored(depth);
            }
            shaded += 1;
        }
        depth += t.depth[1];
        if PERSPECTIVE {
            inv_w += t.inv_w[1];
        }
        for k in 0..n {
            attrs[k] += t.attr_dx[k];
        }
        K::step(&mut state);
    }
    shaded
}

/// What the incremental scan line ([`traverse_incremental`]) starts from: the three screen
/// vertices of a triangle, each with its position in pixels, its `1/w` (1 when attributes are
/// screen-linear) and its attributes (divided by `w` when perspective-correct), as the set-up
/// hands them over. The walk is in `f32`, as a 1970s implementation would hold it.
#[derive(Debug, Clone, Copy)]
pub struct IncrementalTri {
    /// Vertex positions in pixels (the snapped positions coverage uses).
    pub xy: [(f64, f64); 3],
    /// `1/w` per vertex (1 for screen-linear attributes).
    pub inv_w: [f32; 3],
    /// Attributes per vertex (the first `n` are walked).
    pub attrs: [Attrs; 3],
}

/// One edge of the incremental walk: its `x`, `1/w` and attributes at the current scan line's
/// centre, and their constant increments per scan line (Gouraud 1971:
/// `I' = I + (I2 - I1)/(y1 - y2)`), all in `f32`.
#[derive(Debug, Clone, Copy)]
struct EdgeWalker {
    x: f32,
    dx: f32,
    /// `1/w` in lane `n`, attributes in lanes `0..n`.
    v: [f32; MAX_ATTRS + 1],
    dv: [f32; MAX_ATTRS + 1],
}

impl EdgeWalker {
    /// The edge from `top` to `bottom` (by `y`) at the centre of row `row`.
    fn new(tri: &IncrementalTri, top: usize, bottom: usize, row: i64, n: usize) -> EdgeWalker {
        let (x0, y0) = tri.xy[top];
        let (x1, y1) = tri.xy[bottom];
        let height = (y1 - y0) as f32;
        let values = |k: usize| {
            let mut v = [0.0f32; MAX_ATTRS + 1];
            v[..n].copy_from_slice(&tri.attrs[k][..n]);
            v[n] = tri.inv_w[k];
            v
        };
        let (v0, v1) = (values(top), values(bottom));
        let mut w = EdgeWalker {
            x: x0 as f32,
            dx: 0.0,
            v: v0,
            dv: [0.0; MAX_ATTRS + 1],
        };
        if height > 0.0 {
            // The per-line increments, then the walk moved from the vertex down to the first
            // row centre it crosses.
            let to_row = (row as f64 + 0.5 - y0) as f32;
            w.dx = (x1 - x0) as f32 / height;
            w.x += to_row * w.dx;
            for k in 0..=n {
                w.dv[k] = (v1[k] - v0[k]) / height;
                w.v[k] += to_row * w.dv[k];
            }
        }
        w
    }

    #[inline]
    fn step(&mut self, n: usize) {
        self.x += self.dx;
        for k in 0..=n {
            self.v[k] += self.dv[k];
        }
    }
}

/// Draws triangle `t` with kernel `K` like [`traverse`], with the same pixels (the integer edge
/// functions decide coverage) and the same depth, but with the attributes of the classic
/// incremental scan line (Gouraud 1971; Phong 1975 steps normals the same way): two edge
/// walkers step `x`, `1/w` and the attributes from one scan line to the next by constant
/// increments, each span takes the constant increment `(I5 - I4)/(x5 - x4)` between its two
/// edge values and steps it per pixel, all in `f32`. The walk starts at the triangle's top
/// vertex whatever band is drawn, so the picture does not depend on the banding; its rounding
/// error accumulates down the triangle (see `docs/numerical-stability.md`). A kernel reading
/// more attributes than `tri` holds is not supported (its extra attributes read as zero).
pub fn traverse_incremental<K: Kernel>(
    t: &RasterTri,
    kernel: &K,
    kernel_tri: &K::Tri,
    tri: &IncrementalTri,
    target: &mut BandTarget,
) -> u64 {
    match target.pass {
        Pass::Full => incremental_impl::<K, false>(t, kernel, kernel_tri, tri, target),
        Pass::Visible(_) => incremental_impl::<K, true>(t, kernel, kernel_tri, tri, target),
    }
}

fn incremental_impl<K: Kernel, const VISIBLE: bool>(
    t: &RasterTri,
    kernel: &K,
    kernel_tri: &K::Tri,
    tri: &IncrementalTri,
    target: &mut BandTarget,
) -> u64 {
    let n = K::ATTRS.min(MAX_ATTRS);
    let perspective = t.perspective;
    // Vertices top to bottom.
    let mut order = [0usize, 1, 2];
    order.sort_by(|&a, &b| tri.xy[a].1.total_cmp(&tri.xy[b].1));
    let [top, mid, bottom] = order;
    let mid_y = tri.xy[mid].1;
    // The long edge top-bottom, and the short edge in use (top-mid, then mid-bottom).
    let mut long = EdgeWalker::new(tri, top, bottom, t.y0, n);
    let mut short = EdgeWalker::new(tri, top, mid, t.y0, n);
    let mut lower = false;
    let mut walked = t.y0;
    let (width, y0, y1) = (target.width, target.y0, target.y1);
    let id = match target.pass {
        Pass::Visible(id) => id,
        Pass::Full => 0,
    };
    let mut shaded = 0;
    for_each_span(t, width, y0, y1, |y, xs, xe| {
        // Step the walkers down to this row (rows above the band included).
        while walked < y {
            long.step(n);
            walked += 1;
            if lower {
                short.step(n);
            } else if (walked as f64 + 0.5) >= mid_y {
                short = EdgeWalker::new(tri, mid, bottom, walked, n);
                lower = true;
            } else {
                short.step(n);
            }
        }
        if !lower && (y as f64 + 0.5) >= mid_y {
            short = EdgeWalker::new(tri, mid, bottom, y, n);
            lower = true;
        }
        let (l, r) = if long.x <= short.x {
            (&long, &short)
        } else {
            (&short, &long)
        };
        // The span's constant increment per pixel, and its value at the first pixel centre
        // (the offset kept inside the span: the walked x drifts a little from the exact edge).
        let span_width = r.x - l.x;
        let mut dv = [0.0f32; MAX_ATTRS + 1];
        let mut v = l.v;
        let offset = ((xs as f32 + 0.5) - l.x).clamp(0.0, span_width.max(0.0));
        for k in 0..=n {
            let d = if span_width > 0.0 {
                (r.v[k] - l.v[k]) / span_width
            } else {
                0.0
            };
            dv[k] = if d.is_finite() { d } else { 0.0 };
            v[k] += offset * dv[k];
        }
        let (ox, oy) = (xs as f64 + 0.5 - t.origin.0, y as f64 + 0.5 - t.origin.1);
        let mut depth = t.depth[0] + ox * t.depth[1] + oy * t.depth[2];
        let mut state = kernel.span(kernel_tri, xs as f32 + 0.5, y as f32 + 0.5);
        let row = ((y - y0) as usize) * width as usize;
        let mut out: Attrs = [0.0; MAX_ATTRS];
        for x in xs..xe {
            let idx = row + x as usize;
            let draw = pixel_drawn::<VISIBLE>(target, idx, id, depth);
            if draw {
                let w = if perspective && v[n] != 0.0 {
                    1.0 / v[n]
                } else {
                    1.0
                };
                for k in 0..n {
                    let a = v[k] * w;
                    // Overflow of the walk (huge coordinates) never reaches a kernel.
                    out[k] = if a.is_finite() { a } else { 0.0 };
                }
                if K::LANES == 4 {
                    let shade = |a: &[Attrs; 4], count| kernel.shade_lanes(kernel_tri, a, count);
                    target
                        .pending
                        .push(idx, (&out, 1.0, n), shade, target.color);
                } else {
                    let c = kernel.shade(kernel_tri, &state, &out, x as u32, y as u32);
                    debug_assert!(c.is_finite(), "non-finite colour {c} at ({x}, {y})");
                    target.color[idx] = clamp_color(c);
                }
                if !VISIBLE {
                    target.depth[idx] = depth_stored(depth);
                }
                shaded += 1;
            }
            depth += t.depth[1];
            for k in 0..=n {
                v[k] += dv[k];
            }
            K::step(&mut state);
        }
    });
    if K::LANES == 4 && !(VISIBLE && K::ACROSS_TRIANGLES) {
        target.pending.flush(kernel, kernel_tri, target.color);
    }
    shaded
}

#[cfg(test)]
mod tests {
    use super::*;

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
