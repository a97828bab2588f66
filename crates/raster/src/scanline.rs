//! Scan-line traversal (per scan line and span): the seeds' incremental interpolation.
//!
//! Coverage is exact: the left and right edge positions at each row centre are rational numbers
//! evaluated in integers from the fixed-point vertices, and a span covers the pixels
//! `[ceil(xl - 0.5), ceil(xr - 0.5))` of rows `ceil(y0 - 0.5) .. ceil(y2 - 0.5)` (a top-left
//! rule for spans). Two triangles sharing an edge evaluate it from the same two integer
//! endpoints in the same top-to-bottom order, so they split its pixels without gap or overlap.
//!
//! Attributes follow the seeds: along the left edge each value steps by
//! `(A_bottom - A_top) / (y_bottom - y_top)` per scan line (`I' = I + (I2 - I1)/(y1 - y2)`),
//! and along the span by the triangle's constant `dA/dx` (`(I5 - I4)/(x5 - x4)`), never
//! re-solved per pixel. With perspective the stepped values are `A/w` and `1/w`, divided per pixel.

use glam::Vec3;

use crate::clip::{Attrs, MAX_ATTRS};
use crate::framebuffer::clamp_color;
use crate::setup::{ScreenVertex, TriGeom, ceil_div};
use phosphor_math::fixed::SUBPIXEL_ONE;

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
}

/// One edge walked down the rows: exact integer pixel position, float position and attributes.
struct EdgeWalk {
    num: i64,
    num_step: i64,
    den: i64,
    x: f64,
    dx: f64,
    depth: f64,
    ddepth: f64,
    inv_w: f64,
    dinv_w: f64,
    attrs: [f64; MAX_ATTRS],
    dattrs: [f64; MAX_ATTRS],
}

impl EdgeWalk {
    /// The edge `a -> b` (a above b) positioned at row `j`; attributes for the first `n`.
    fn new(a: &ScreenVertex, b: &ScreenVertex, j: i64, n: usize) -> EdgeWalk {
        let half = SUBPIXEL_ONE / 2;
        let dy = b.fy - a.fy;
        let yc = j * SUBPIXEL_ONE + half;
        // first covered pixel i: i + 0.5 >= x(yc)  <=>  i = ceil((x(yc) - 0.5)), with
        // x(yc) = xa + (yc - ya)(xb - xa)/dy, all in fixed point.
        let num = a.fx * dy + (yc - a.fy) * (b.fx - a.fx) - half * dy;
        let den = SUBPIXEL_ONE * dy;
        let inv_dy = 1.0 / (b.y - a.y);
        let t = (j as f64 + 0.5) - a.y;
        let slope = |va: f64, vb: f64| (vb - va) * inv_dy;
        let dx = slope(a.x, b.x);
        let ddepth = slope(a.depth, b.depth);
        let dinv_w = slope(a.inv_w, b.inv_w);
        let mut attrs = [0.0; MAX_ATTRS];
        let mut dattrs = [0.0; MAX_ATTRS];
        for k in 0..n {
            dattrs[k] = slope(a.attrs[k] as f64, b.attrs[k] as f64);
            attrs[k] = a.attrs[k] as f64 + t * dattrs[k];
        }
        EdgeWalk {
            num,
            num_step: SUBPIXEL_ONE * (b.fx - a.fx),
            den,
            x: a.x + t * dx,
            dx,
            depth: a.depth + t * ddepth,
            ddepth,
            inv_w: a.inv_w + t * dinv_w,
            dinv_w,
            attrs,
            dattrs,
        }
    }

    #[inline]
    fn pixel(&self) -> i64 {
        ceil_div(self.num, self.den)
    }

    /// Next scan line: every value by its per-row increment (seeds: `I' = I + dI`).
    #[inline]
    fn advance(&mut self, n: usize) {
        self.num += self.num_step;
        self.x += self.dx;
        self.depth += self.ddepth;
        self.inv_w += self.dinv_w;
        for k in 0..n {
            self.attrs[k] += self.dattrs[k];
        }
    }
}

/// Draws the part of triangle `geom` inside the band with kernel `K`; returns the number of
/// pixels that passed the depth test (were shaded).
pub fn traverse<K: Kernel>(
    geom: &TriGeom,
    kernel: &K,
    tri: &K::Tri,
    target: &mut BandTarget,
) -> u64 {
    if geom.perspective {
        traverse_impl::<K, true>(geom, kernel, tri, target)
    } else {
        traverse_impl::<K, false>(geom, kernel, tri, target)
    }
}

fn traverse_impl<K: Kernel, const PERSPECTIVE: bool>(
    geom: &TriGeom,
    kernel: &K,
    tri: &K::Tri,
    target: &mut BandTarget,
) -> u64 {
    let n = K::ATTRS.min(geom.n);
    let [v0, v1, v2] = &geom.v;
    let mut shaded = 0;
    // Two halves: rows above v1 use the short edge v0->v1, rows below it v1->v2.
    for (short_a, short_b, lo, hi) in [
        (v0, v1, geom.row_start, geom.row_mid),
        (v1, v2, geom.row_mid, geom.row_end),
    ] {
        let lo = lo.max(target.y0);
        let hi = hi.min(target.y1);
        if lo >= hi {
            continue;
        }
        let mut long = EdgeWalk::new(v0, v2, lo, n);
        let mut short = EdgeWalk::new(short_a, short_b, lo, n);
        for j in lo..hi {
            let (left, right) = if geom.long_left {
                (&long, &short)
            } else {
                (&short, &long)
            };
            let x_start = left.pixel().max(0);
            let x_end = right.pixel().min(target.width as i64);
            if x_start < x_end {
                shaded +=
                    span::<K, PERSPECTIVE>(geom, kernel, tri, target, left, j, x_start, x_end, n);
            }
            if geom.long_left {
                long.advance(n);
                short.advance(0);
            } else {
                long.advance(0);
                short.advance(n);
            }
        }
    }
    shaded
}

#[allow(
    clippy::too_many_arguments,
    reason = "the hot loop's state, kept in registers"
)]
#[inline(always)]
fn span<K: Kernel, const PERSPECTIVE: bool>(
    geom: &TriGeom,
    kernel: &K,
    tri: &K::Tri,
    target: &mut BandTarget,
    left: &EdgeWalk,
    j: i64,
    x_start: i64,
    x_end: i64,
    n: usize,
) -> u64 {
    // Span start: the edge values moved from the edge to the first pixel centre.
    let xc = x_start as f64 + 0.5;
    let off = xc - left.x;
    let mut depth = left.depth + off * geom.ddepth_dx;
    let mut inv_w = left.inv_w + off * geom.dinv_w_dx;
    let mut attrs: Attrs = [0.0; MAX_ATTRS];
    for k in 0..n {
        attrs[k] = (left.attrs[k] + off * geom.dattr_dx[k] as f64) as f32;
    }
    let mut state = kernel.span(tri, xc as f32, j as f32 + 0.5);
    let row = ((j - target.y0) as usize) * target.width as usize;
    let mut shaded = 0;
    let mut out: Attrs = [0.0; MAX_ATTRS];
    for x in x_start..x_end {
        let idx = row + x as usize;
        if target.count {
            target.color[idx].x += 1.0;
        } else if (depth as f32) < target.depth[idx] {
            let w = if PERSPECTIVE {
                (1.0 / inv_w) as f32
            } else {
                1.0
            };
            for k in 0..n {
                out[k] = attrs[k] * w;
            }
            let c = kernel.shade(tri, &state, &out, x as u32, j as u32);
            debug_assert!(c.is_finite(), "non-finite colour {c} at ({x}, {j})");
            target.color[idx] = clamp_color(c);
            target.depth[idx] = depth.max(0.0) as f32;
            shaded += 1;
        }
        depth += geom.ddepth_dx;
        if PERSPECTIVE {
            inv_w += geom.dinv_w_dx;
        }
        for k in 0..n {
            attrs[k] += geom.dattr_dx[k];
        }
        K::step(&mut state);
    }
    shaded
}
