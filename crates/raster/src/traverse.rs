//! Traversal of one set-up triangle inside a band, span by span, shading as it goes.
//!
//! Attributes are planes `A(x, y)`: at each span start every plane is evaluated afresh, then
//! stepped along the span by the triangle's constant `dA/dx` per pixel (Gouraud 1971's
//! `(I5 - I4)/(x5 - x4)`). Unlike the classic scan-line algorithm, nothing is stepped from one
//! scan line to the next, so no rounding error accumulates down a tall triangle. The classic
//! form, edge values stepped per scan line in f32, is [`crate::incremental`], with the same
//! coverage and depth. With perspective the stepped values are `A/w` and `1/w`, divided per
//! pixel.
//!
//! What a covered pixel gets is a [`SpanShade`]: one colour ([`Solid`]), the shader's pixel
//! stage one pixel at a time ([`OnePixel`]) or four at a time across triangles ([`Batched`]),
//! or a stepped triangle's quadratics ([`crate::stepped::SteppedSpan`]).

use glam::Vec3;
use phosphor_lighting::F32x1;

use crate::batch::{Pending, shade4};
use crate::clip::{Attrs, MAX_ATTRS};
use crate::coverage::{
    BandTarget, Pass, depth_col_at, depth_row, depth_stored, for_each_span, lanes, pixel_drawn,
};
use crate::framebuffer::clamp_color_to;
use crate::setup::{PlaneBasis, RasterTri, ScreenPos, append_gradients};
use crate::shader::{Shader, Varyings, interpolated};
pub(crate) use crate::span::SpanShade;
use crate::stepped::StepQueue;

/// One colour for every pixel, clamped once.
pub(crate) struct Solid(pub Vec3);

impl SpanShade for Solid {
    const ATTRS: usize = 0;
    type Span = ();
    #[inline(always)]
    fn span(&self, _: f64, _: f64) {}
    #[inline(always)]
    fn pixel(&mut self, _: &(), idx: usize, _: (&Attrs, f32), _: (i64, i64), color: &mut [Vec3]) {
        color[idx] = self.0;
    }
    #[inline(always)]
    fn step(_: &mut ()) {}
}

/// No colour at all: the depth test and write alone (a shadow map's casters).
pub(crate) struct DepthOnly;

impl SpanShade for DepthOnly {
    const ATTRS: usize = 0;
    type Span = ();
    #[inline(always)]
    fn span(&self, _: f64, _: f64) {}
    #[inline(always)]
    fn pixel(&mut self, _: &(), _: usize, _: (&Attrs, f32), _: (i64, i64), _: &mut [Vec3]) {}
    #[inline(always)]
    fn step(_: &mut ()) {}
}

impl Solid {
    /// The colour `c`, clamped to `[0, ceiling]` as every colour written is.
    #[inline]
    #[must_use]
    pub fn of(c: Vec3, ceiling: f32) -> Solid {
        debug_assert!(c.is_finite(), "non-finite colour {c}");
        Solid(clamp_color_to(c, ceiling))
    }
}

/// `attrs[..n] * w` as one-lane varyings (lanes past `n` zero).
#[inline(always)]
fn one_lane(attrs: &Attrs, w: f32, n: usize) -> Varyings<F32x1> {
    let mut v = [F32x1(0.0); MAX_ATTRS];
    for k in 0..n {
        v[k] = F32x1(attrs[k] * w);
    }
    v
}

/// The first lane of `c` as a colour clamped to `[0, ceiling]`.
#[inline(always)]
fn first(c: phosphor_lighting::Vec3s<F32x1>, ceiling: f32) -> Vec3 {
    let c = Vec3::new(c.x.0, c.y.0, c.z.0);
    debug_assert!(c.is_finite(), "non-finite colour {c}");
    clamp_color_to(c, ceiling)
}

/// The shader's pixel stage, one pixel per call, and the framebuffer's largest intensity.
pub(crate) struct OnePixel<'s, S>(pub &'s S, pub f32);

impl<S: Shader> SpanShade for OnePixel<'_, S> {
    const ATTRS: usize = interpolated::<S>();
    type Span = ();
    #[inline(always)]
    fn span(&self, _: f64, _: f64) {}
    #[inline(always)]
    fn pixel(&mut self, _: &(), idx: usize, (a, w): (&Attrs, f32), _: (i64, i64), c: &mut [Vec3]) {
        c[idx] = first(
            self.0.pixel(&one_lane(a, w, lanes(interpolated::<S>()))),
            self.1,
        );
    }
    #[inline(always)]
    fn step(_: &mut ()) {}
}

/// The shader's pixel stage four pixels per call, the pixels of successive triangles sharing
/// a call (each pixel is written by one triangle in a visible pass); flushed at the band's end.
pub(crate) struct Batched<'s, S> {
    pub shader: &'s S,
    pub pending: Pending<usize, 4>,
    /// The queue of stepped triangles' pixels ([`crate::stepped`]), kept with the band.
    pub stepped: StepQueue,
}

impl<S: Shader> SpanShade for Batched<'_, S> {
    const ATTRS: usize = interpolated::<S>();
    type Span = ();
    #[inline(always)]
    fn span(&self, _: f64, _: f64) {}
    #[inline(always)]
    fn pixel(&mut self, _: &(), idx: usize, a: (&Attrs, f32), _: (i64, i64), c: &mut [Vec3]) {
        let shader = self.shader;
        let shade = |rows: &[Attrs; 4], count, ceiling| shade4(shader, rows, count, ceiling);
        self.pending
            .push(idx, (a.0, a.1, lanes(interpolated::<S>())), shade, c);
    }
    #[inline(always)]
    fn step(_: &mut ()) {}
    #[inline(always)]
    fn flush(&mut self, c: &mut [Vec3]) {
        let shader = self.shader;
        let shade = |rows: &[Attrs; 4], count, ceiling| shade4(shader, rows, count, ceiling);
        self.pending.flush_with(shade, c);
    }
}

/// Draws the part of triangle `t` inside the band, shading with `shade`; returns the number
/// of pixels shaded.
pub(crate) fn traverse<T: SpanShade>(t: &RasterTri, shade: &mut T, target: &mut BandTarget) -> u64 {
    traverse_inline(t, shade, target)
}

/// [`traverse`] inlined into its caller: for a caller compiled for AVX2, whose callees run
/// at the baseline unless inlined.
#[inline(always)]
pub(crate) fn traverse_inline<T: SpanShade>(
    t: &RasterTri,
    shade: &mut T,
    target: &mut BandTarget,
) -> u64 {
    if t.n < T::ATTRS {
        // Set up with fewer attributes than the shade reads: the missing ones are zero. (The
        // traversal steps the lanes whole, see `lanes`, whatever the plane holds past its
        // own count.)
        let mut padded = *t;
        for k in t.n..MAX_ATTRS {
            padded.attr0[k] = 0.0;
            padded.attr_dx[k] = 0.0;
            padded.attr_dy[k] = 0.0;
        }
        padded.n = T::ATTRS;
        return traverse(&padded, shade, target);
    }
    match (t.perspective, target.pass) {
        (true, Pass::Full) => traverse_impl::<T, true, false>(t, shade, target),
        (false, Pass::Full) => traverse_impl::<T, false, false>(t, shade, target),
        (true, Pass::Visible(_)) => traverse_impl::<T, true, true>(t, shade, target),
        (false, Pass::Visible(_)) => traverse_impl::<T, false, true>(t, shade, target),
    }
}

#[inline(always)]
fn traverse_impl<T: SpanShade, const PERSPECTIVE: bool, const VISIBLE: bool>(
    t: &RasterTri,
    shade: &mut T,
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
            target.mark_span(y, xs, xe);
            shaded += span::<T, PERSPECTIVE, VISIBLE>(t, shade, target, y, xs, xe);
        },
    );
    shaded
}

/// One span of `t`: the attribute lanes are stepped whole ([`lanes`]).
#[inline(always)]
fn span<T: SpanShade, const PERSPECTIVE: bool, const VISIBLE: bool>(
    t: &RasterTri,
    shade: &mut T,
    target: &mut BandTarget,
    y: i64,
    x_start: i64,
    x_end: i64,
) -> u64 {
    let n = lanes(T::ATTRS);
    // Span start: every plane evaluated once at the first pixel centre.
    let (x0c, yc) = (x_start as f64 + 0.5, y as f64 + 0.5);
    let (ox, oy) = (x0c - t.origin.0, yc - t.origin.1);
    let base = depth_row(t, y);
    let (mut inv_w, mut attrs) =
        planes_at(&t.inv_w, [&t.attr0, &t.attr_dx, &t.attr_dy], (ox, oy), n);
    let mut state = shade.span(x0c, yc);
    let mut xc = x0c;
    let row = ((y - target.y0) as usize) * target.width as usize;
    let id = match target.pass {
        Pass::Visible(id) => id,
        Pass::Full => 0,
    };
    let mut shaded = 0;
    for x in x_start..x_end {
        let idx = row + x as usize;
        // The visible pass reads no depth: the depth pass left the ids.
        let depth = if VISIBLE {
            0.0
        } else {
            base + depth_col_at(t, xc)
        };
        xc += 1.0;
        if pixel_drawn::<VISIBLE>(target, idx, id, depth) {
            let w = if PERSPECTIVE && n > 0 {
                (1.0 / inv_w) as f32
            } else {
                1.0
            };
            shade.pixel(&state, idx, (&attrs, w), (x, y), target.color);
            if !VISIBLE {
                target.depth[idx] = depth_stored(depth);
            }
            shaded += 1;
        }
        if PERSPECTIVE && n > 0 {
            inv_w += t.inv_w[1];
        }
        for k in 0..n {
            attrs[k] += t.attr_dx[k];
        }
        T::step(&mut state);
    }
    shaded
}

/// The pixels of one row of a small triangle drawn from the lanes ([`crate::group`]), after
/// their depth test: bit `j` of `passed` for the pixel `j` columns right of the row's first
/// covered pixel, column `x` of row `y`, at band index `at`. What [`span`] does for them:
/// the planes `p` evaluated at the first covered pixel and stepped pixel by pixel, so each
/// passing pixel gets the attributes the one-triangle traversal gives it.
#[inline(always)]
pub(crate) fn shade_passed<T: SpanShade>(
    p: &Planes,
    shade: &mut T,
    color: &mut [Vec3],
    (at, x, y): (usize, i64, i64),
    mut passed: u32,
) {
    let n = lanes(T::ATTRS);
    let (x0c, yc) = (x as f64 + 0.5, y as f64 + 0.5);
    let (ox, oy) = (x0c - p.origin.0, yc - p.origin.1);
    let (mut inv_w, mut attrs) =
        planes_at(&p.inv_w, [&p.attr0, &p.attr_dx, &p.attr_dy], (ox, oy), n);
    let mut state = shade.span(x0c, yc);
    let mut j = 0;
    loop {
        if passed & 1 != 0 {
            // Without perspective the plane of `1/w` is 1 everywhere, and so is `w`.
            let w = (1.0 / inv_w) as f32;
            shade.pixel(&state, at + j, (&attrs, w), (x + j as i64, y), color);
        }
        passed >>= 1;
        if passed == 0 {
            break;
        }
        inv_w += p.inv_w[1];
        for k in 0..n {
            attrs[k] += p.attr_dx[k];
        }
        T::step(&mut state);
        j += 1;
    }
}

/// The attribute planes of a set-up triangle: what the by-pixel pass evaluates.
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
    #[cfg(test)]
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

    /// The planes of the triangle `p` with vertex attributes `attrs` (at least `n` each),
    /// bit for bit those [`RasterTri::set`] computes, without its edges, depth and pixel box:
    /// for the by-pixel pass, which knows the triangle's pixels already. `None` for no area.
    #[inline(always)]
    pub(crate) fn set(
        p: [ScreenPos; 3],
        attrs: [&[f32]; 3],
        n: usize,
        perspective: bool,
    ) -> Option<Planes> {
        let basis = PlaneBasis::of(p, attrs)?;
        let mut planes = Planes {
            origin: basis.origin,
            inv_w: basis.inv_w(n, perspective),
            attr0: [0.0; MAX_ATTRS],
            attr_dx: [0.0; MAX_ATTRS],
            attr_dy: [0.0; MAX_ATTRS],
        };
        basis.attrs(
            n,
            [&mut planes.attr0, &mut planes.attr_dx, &mut planes.attr_dy],
        );
        Some(planes)
    }

    /// [`RasterTri::add_gradients`] on planes set with `n` attributes.
    #[inline(always)]
    pub(crate) fn add_gradients(&mut self, n: usize, perspective: bool, k: usize) {
        let planes = [&mut self.attr0, &mut self.attr_dx, &mut self.attr_dy];
        append_gradients(planes, (self.inv_w, perspective && n > 0), n, k);
    }
}

/// `1/w` and attributes `0..n` at offset `(ox, oy)` from the planes' origin: each plane
/// (`inv_w`, and `attr0`, `attr_dx`, `attr_dy` in `a`) evaluated once, as at a span start;
/// stepping by `dA/dx` then continues along the row. `1/w` is evaluated in f64, as the depth
/// pass's depth; the attributes in f32 from the origin (a vertex of the triangle, so the
/// offsets are at most the triangle's size), which is whole f32 vectors and as exact as the
/// f32 stepping that follows.
#[inline(always)]
pub(crate) fn planes_at(
    inv_w: &[f64; 3],
    a: [&Attrs; 3],
    (ox, oy): (f64, f64),
    n: usize,
) -> (f64, Attrs) {
    let inv_w = inv_w[0] + ox * inv_w[1] + oy * inv_w[2];
    let (fx, fy) = (ox as f32, oy as f32);
    let mut attrs: Attrs = [0.0; MAX_ATTRS];
    for k in 0..n {
        attrs[k] = a[0][k] + fx * a[1][k] + fy * a[2][k];
    }
    (inv_w, attrs)
}
