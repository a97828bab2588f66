//! Triangle setup (once per triangle): perspective divide, viewport, sub-pixel snapping,
//! orientation and culling, row range, and the screen-space gradients `dA/dx` of depth, `1/w`
//! and every attribute (the plane equations the traversal steps along).

use phosphor_math::fixed::{SUBPIXEL_ONE, to_fixed};

use crate::clip::{Attrs, ClipVertex, MAX_ATTRS};

const HALF: i64 = SUBPIXEL_ONE / 2;
const INV_ONE: f64 = 1.0 / SUBPIXEL_ONE as f64;

/// A vertex after the divide and the viewport, snapped to 1/256 pixel.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScreenVertex {
    /// Snapped x in fixed point (pixels << `phosphor_math::fixed::SUBPIXEL_BITS`).
    pub fx: i64,
    /// Snapped y in fixed point, row 0 at the top.
    pub fy: i64,
    /// The snapped x in pixels (what coverage and attributes both use).
    pub x: f64,
    /// The snapped y in pixels.
    pub y: f64,
    /// Depth in `[0, 1]` (NDC z mapped), linear in screen space.
    pub depth: f64,
    /// `1/w` (perspective) or 1 (screen-space linear attributes): what the traversal steps.
    pub inv_w: f64,
    /// The true `1/w` of the vertex, whatever the interpolation.
    pub rhw: f64,
    /// Attributes, divided by `w` when perspective-correct.
    pub attrs: Attrs,
}

/// Everything the traversal needs about one triangle, vertices sorted top to bottom.
#[derive(Debug, Clone, Copy)]
pub struct TriGeom {
    /// Vertices sorted by `fy` (then `fx`).
    pub v: [ScreenVertex; 3],
    /// Attributes in use.
    pub n: usize,
    /// Whether attributes are divided by `w` (perspective-correct).
    pub perspective: bool,
    /// True when the long edge `v0 -> v2` is the left edge.
    pub long_left: bool,
    /// `d depth / dx`.
    pub ddepth_dx: f64,
    /// `d (1/w) / dx`.
    pub dinv_w_dx: f64,
    /// `d attr / dx` for each attribute.
    pub dattr_dx: Attrs,
    /// First row whose pixel centre is at or below `v0` (`ceil(y0 - 0.5)`).
    pub row_start: i64,
    /// First row whose centre is at or below `v1` (top half ends here).
    pub row_mid: i64,
    /// One past the last row (`ceil(y2 - 0.5)`).
    pub row_end: i64,
}

/// `ceil(a / b)` for `b > 0`, exact in integers.
#[inline]
#[must_use]
pub fn ceil_div(a: i64, b: i64) -> i64 {
    let q = a.div_euclid(b);
    if a.rem_euclid(b) == 0 { q } else { q + 1 }
}

/// First row whose centre `(j + 0.5)` lies at or below fixed-point `fy`: `ceil(y - 0.5)`.
#[inline]
#[must_use]
pub fn first_row_at_or_below(fy: i64) -> i64 {
    ceil_div(fy - HALF, SUBPIXEL_ONE)
}

/// Divide and viewport for a clip-space vertex; `None` when a coordinate is non-finite or
/// outside the fixed-point range (clipping keeps this from happening for finite input).
#[must_use]
pub fn to_screen(
    v: &ClipVertex,
    width: u32,
    height: u32,
    n: usize,
    perspective: bool,
) -> Option<ScreenVertex> {
    let w = v.pos.w as f64;
    if w.is_nan() || w <= 0.0 || !w.is_finite() {
        return None;
    }
    let inv_w = 1.0 / w;
    let sx = (v.pos.x as f64 * inv_w + 1.0) * 0.5 * width as f64;
    let sy = (1.0 - v.pos.y as f64 * inv_w) * 0.5 * height as f64;
    let depth = (v.pos.z as f64 * inv_w) * 0.5 + 0.5;
    let fx = to_fixed(sx as f32)?;
    let fy = to_fixed(sy as f32)?;
    if !depth.is_finite() {
        return None;
    }
    let mut attrs = [0.0; MAX_ATTRS];
    let scale = if perspective { inv_w as f32 } else { 1.0 };
    for j in 0..n {
        attrs[j] = v.attrs[j] * scale;
    }
    Some(ScreenVertex {
        fx,
        fy,
        x: fx as f64 * INV_ONE,
        y: fy as f64 * INV_ONE,
        depth,
        inv_w: if perspective { inv_w } else { 1.0 },
        rhw: inv_w,
        attrs,
    })
}

/// Twice the signed area in fixed point, screen frame (y down): negative for a triangle that is
/// counter-clockwise in NDC, i.e. front-facing.
#[inline]
#[must_use]
pub fn screen_area2(a: &ScreenVertex, b: &ScreenVertex, c: &ScreenVertex) -> i64 {
    (b.fx - a.fx) * (c.fy - a.fy) - (c.fx - a.fx) * (b.fy - a.fy)
}

/// Sets up a triangle; `None` when it has zero area, is culled, or covers no pixel centre row.
#[must_use]
pub fn setup(
    verts: [ScreenVertex; 3],
    n: usize,
    perspective: bool,
    cull_backfaces: bool,
) -> Option<TriGeom> {
    let area = screen_area2(&verts[0], &verts[1], &verts[2]);
    if area == 0 || (cull_backfaces && area > 0) {
        return None;
    }
    // Sort three keys, then move each ~100-byte vertex once (sorting the vertices themselves
    // was a visible share of set-up's memcpy).
    let key = |i: usize| (verts[i].fy, verts[i].fx);
    let mut order = [0, 1, 2];
    order.sort_by_key(|&i| key(i));
    let v = order.map(|i| verts[i]);
    let row_start = first_row_at_or_below(v[0].fy);
    let row_mid = first_row_at_or_below(v[1].fy);
    let row_end = first_row_at_or_below(v[2].fy);
    if row_start >= row_end {
        return None;
    }
    // v1 left of the long edge (screen frame) <=> area(v0, v1, v2) > 0 ... exactly:
    // x_long(y1) < x1  <=>  (y1 - y0)(x2 - x0) < (x1 - x0)(y2 - y0).
    let cross =
        (v[1].fy - v[0].fy) * (v[2].fx - v[0].fx) - (v[1].fx - v[0].fx) * (v[2].fy - v[0].fy);
    let long_left = cross < 0;
    // Plane gradients in x: dA/dx = ((A1-A0)(y2-y0) - (A2-A0)(y1-y0)) / area.
    let (dx1, dy1) = (v[1].x - v[0].x, v[1].y - v[0].y);
    let (dx2, dy2) = (v[2].x - v[0].x, v[2].y - v[0].y);
    let area_f = dx1 * dy2 - dx2 * dy1;
    let inv_area = 1.0 / area_f;
    let grad = |a0: f64, a1: f64, a2: f64| ((a1 - a0) * dy2 - (a2 - a0) * dy1) * inv_area;
    let mut dattr_dx = [0.0; MAX_ATTRS];
    for j in 0..n {
        dattr_dx[j] = grad(
            v[0].attrs[j] as f64,
            v[1].attrs[j] as f64,
            v[2].attrs[j] as f64,
        ) as f32;
    }
    let geom = TriGeom {
        v,
        n,
        perspective,
        long_left,
        ddepth_dx: grad(v[0].depth, v[1].depth, v[2].depth),
        dinv_w_dx: grad(v[0].inv_w, v[1].inv_w, v[2].inv_w),
        dattr_dx,
        row_start,
        row_mid,
        row_end,
    };
    Some(geom)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn first_row_follows_ceil_y_minus_half() {
        // y = 0.5 exactly on the centre of row 0: included (top edge).
        assert_eq!(first_row_at_or_below(128), 0);
        assert_eq!(first_row_at_or_below(129), 1);
        assert_eq!(first_row_at_or_below(0), 0);
        assert_eq!(first_row_at_or_below(-300), -1);
        assert_eq!(ceil_div(-5, 2), -2);
        assert_eq!(ceil_div(5, 2), 3);
    }
}
