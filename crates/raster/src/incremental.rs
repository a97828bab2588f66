//! The classic incremental scan line ([`crate::Interpolation::Incremental`]): the same
//! pixels (the integer edge functions decide coverage) and the same depth as the plane
//! traversal, but with the attributes of Gouraud 1971's walk (Phong 1975 steps normals the
//! same way): two edge walkers step `x`, `1/w` and the attributes from one scan line to the
//! next by constant increments, `I' = I + (I2 - I1)/(y1 - y2)`, and each span takes the
//! constant increment `(I5 - I4)/(x5 - x4)` between its two edge values and steps it per
//! pixel, all in `f32`, as a 1970s implementation would hold them.

use crate::clip::{Attrs, MAX_ATTRS};
use crate::coverage::{
    BandTarget, Pass, depth_col_at, depth_row, depth_stored, for_each_span, pixel_drawn,
};
use crate::setup::RasterTri;
use crate::traverse::SpanShade;

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

/// Draws triangle `t` shading with `shade` like [`crate::traverse::traverse`], with the same pixels (the integer edge
/// functions decide coverage) and the same depth, but with the attributes of the classic
/// incremental scan line (Gouraud 1971; Phong 1975 steps normals the same way): two edge
/// walkers step `x`, `1/w` and the attributes from one scan line to the next by constant
/// increments, each span takes the constant increment `(I5 - I4)/(x5 - x4)` between its two
/// edge values and steps it per pixel, all in `f32`. The walk starts at the triangle's top
/// vertex whatever band is drawn, so the picture does not depend on the banding; its rounding
/// error accumulates down the triangle (see `docs/numerical-stability.md`). A shade reading
/// more attributes than `tri` holds is not supported (its extra attributes read as zero).
pub(crate) fn traverse_incremental<K: SpanShade>(
    t: &RasterTri,
    shade: &mut K,
    tri: &IncrementalTri,
    target: &mut BandTarget,
) -> u64 {
    match target.pass {
        Pass::Full => incremental_impl::<K, false>(t, shade, tri, target),
        Pass::Visible(_) => incremental_impl::<K, true>(t, shade, tri, target),
    }
}

fn incremental_impl<K: SpanShade, const VISIBLE: bool>(
    t: &RasterTri,
    shade: &mut K,
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
        target.mark_span(y, xs, xe);
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
        let base = depth_row(t, y);
        let mut state = shade.span(xs as f64 + 0.5, y as f64 + 0.5);
        let row = ((y - y0) as usize) * width as usize;
        let mut out: Attrs = [0.0; MAX_ATTRS];
        let mut xc = xs as f64 + 0.5;
        for x in xs..xe {
            let idx = row + x as usize;
            let depth = if VISIBLE {
                0.0
            } else {
                base + depth_col_at(t, xc)
            };
            xc += 1.0;
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
                shade.pixel(&state, idx, (&out, 1.0), (x, y), target.color);
                if !VISIBLE {
                    target.depth[idx] = depth_stored(depth);
                }
                shaded += 1;
            }
            for k in 0..=n {
                v[k] += dv[k];
            }
            K::step(&mut state);
        }
    });
    shaded
}
