//! Coverage and depth: which pixels of a band a set-up triangle covers, and the depth pass.
//!
//! Coverage is exact: three integer edge functions at the fixed-point pixel centres with a
//! top-left rule ([`RasterTri`]), stepped by one add per pixel. A row's covered pixels are
//! contiguous (the triangle is convex), so each row is one span: found by stepping the edges
//! across a narrow box, or by one exact division per edge on a wide one. Two triangles sharing
//! an edge evaluate it from the same two integer endpoints, so they split its pixels without gap
//! or overlap.
//!
//! A band can be drawn in two passes ([`Pass`]): depth only ([`depth_only`]), recording which
//! triangle is nearest at each pixel, then shading only those pixels. The picture is the same
//! as one pass (the nearest triangle, the first of equals in submission order) with each pixel
//! shaded once.

use glam::Vec3;

use crate::clip::MAX_ATTRS;
use crate::setup::RasterTri;

/// Small boxes at most this wide find their spans by testing the edges at every pixel, eight
/// at a time; others solve each edge for the span ends (one division per edge and row).
const STEP_WIDTH: i64 = 16;
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
    /// Per row of the band, the columns `[lo, hi)` written since the last clear, widened by
    /// every span traversed ([`BandTarget::mark_span`]); empty when nothing is to be marked
    /// (the two-pass bands take it and widen it from the depth pass's extents).
    pub dirty: &'a mut [(u32, u32)],
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
            dirty: &mut [],
        }
    }

    /// The same band, its spans widening `dirty` (one entry per row of the band).
    #[must_use]
    pub fn with_dirty(self, dirty: &'a mut [(u32, u32)]) -> BandTarget<'a> {
        BandTarget { dirty, ..self }
    }

    /// Widens row `y`'s dirty columns to the span `[xs, xe)` (`0 <= xs < xe <= width`, as
    /// [`for_each_span`] gives them): a pixel is written only inside a span, so the union of
    /// the spans is what the next clear and the readout must cover. Per span rather than per
    /// triangle box, as the spans are already at hand and a box is updated row by row anyway.
    #[inline(always)]
    pub fn mark_span(&mut self, y: i64, xs: i64, xe: i64) {
        if let Some(e) = self.dirty.get_mut((y - self.y0) as usize) {
            *e = (e.0.min(xs as u32), e.1.max(xe as u32));
        }
    }
}

/// The depth test and the depth written by every pass (one definition, so the depth pass and
/// a single full pass agree bit for bit).
#[inline(always)]
pub(crate) fn depth_passes(depth: f64, stored: f32) -> bool {
    (depth as f32) < stored
}

/// Whether a span draws pixel `idx`: in a visible-only pass, where the id buffer holds this
/// triangle's `id`; in the coverage-count hook never (it counts the pixel instead); otherwise
/// where the depth test passes. One definition for the plane and the incremental spans.
#[inline(always)]
pub(crate) fn pixel_drawn<const VISIBLE: bool>(
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

/// The depth stored for a pixel that passed: `depth` as f32, with negatives (a rounding just
/// in front of the near plane), -0 and NaN stored as 0. A compare-select, so the lanes of
/// [`crate::group`] store the same bits.
#[inline(always)]
pub(crate) fn depth_stored(depth: f64) -> f32 {
    let d = depth as f32;
    if d > 0.0 { d } else { 0.0 }
}

/// The depth of triangle `t` at the centre of pixel `(x, y)`: the row's part first, then the
/// column's, `(z0 + dy zy) + dx zx` with `dx = (x + 0.5) - origin.x` and
/// `dy = (y + 0.5) - origin.y`. Every pass evaluates this one formula at every pixel (none
/// steps it along a span), so a pixel's depth is the same bits whichever pass, walker or lane
/// width computes it; the row's part ([`depth_row`]) is shared by a span's pixels.
#[cfg_attr(
    not(test),
    expect(dead_code, reason = "the formula's statement; passes use its parts")
)]
#[inline(always)]
pub(crate) fn depth_at(t: &RasterTri, x: i64, y: i64) -> f64 {
    depth_row(t, y) + depth_col(t, x)
}

/// [`depth_at`]'s row part, `z0 + ((y + 0.5) - origin.y) zy`.
#[inline(always)]
pub(crate) fn depth_row(t: &RasterTri, y: i64) -> f64 {
    t.depth[0] + ((y as f64 + 0.5) - t.origin.1) * t.depth[2]
}

/// [`depth_at`]'s column part, `((x + 0.5) - origin.x) zx`.
#[inline(always)]
pub(crate) fn depth_col(t: &RasterTri, x: i64) -> f64 {
    depth_col_at(t, x as f64 + 0.5)
}

/// [`depth_col`] at the pixel centre `xc = x + 0.5`: a span steps `xc` by 1.0, which is exact
/// (a whole number and a half, far below 2^52), saving the conversion per pixel.
#[inline(always)]
pub(crate) fn depth_col_at(t: &RasterTri, xc: f64) -> f64 {
    (xc - t.origin.0) * t.depth[1]
}

/// The iteration every pass shares: the rows of `t` inside band rows `[y0, y1)`, its columns
/// inside `[0, width)`, the edges stepped from the first of those pixels. Calls
/// `row(y, xs, xe)` for each row with a non-empty span `[xs, xe)`.
#[inline(always)]
pub(crate) fn for_each_span(
    t: &RasterTri,
    width: u32,
    y0: i64,
    y1: i64,
    mut row: impl FnMut(i64, i64, i64),
) {
    let (lo, hi) = (t.x0.max(0), t.x1.min(width as i64));
    let (ylo, yhi) = (t.y0.max(y0), t.y1.min(y1));
    if lo >= hi || ylo >= yhi {
        return;
    }
    let one = phosphor_math::fixed::SUBPIXEL_ONE;
    let e = t.edges_at(lo, ylo);
    if hi - lo <= STEP_WIDTH && t.x1 - t.x0 <= SMALL_SIDE && t.y1 - t.y0 <= SMALL_SIDE {
        // A small triangle: every edge value inside its box (and up to 16 columns right of
        // it) fits in i32 (see SMALL_SIDE). Each row tests its pixels as one or two vectors of
        // eight per edge, kept in registers from row to row, with no branch per pixel: a bit
        // per covered pixel, and the span is the run of set bits.
        let e = e.map(|v| v as i32);
        let col: [i32; 3] = t.edge_a.map(|a| (a * one) as i32);
        let down: [i32; 3] = t.edge_b.map(|b| (b * one) as i32);
        if hi - lo <= 8 {
            small_rows::<1>((e, col, down), (lo, hi), (ylo, yhi), row);
        } else {
            small_rows::<2>((e, col, down), (lo, hi), (ylo, yhi), row);
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

/// [`for_each_span`]'s rows of a small triangle at most `8 * V` columns wide (`hi - lo`),
/// whose edges are `e` at `(lo, ylo)` and step by `col` per column and `down` per row, all in
/// i32: per edge `V` vectors of eight columns, stepped down a row by one add each.
#[inline(always)]
fn small_rows<const V: usize>(
    (e, col, down): ([i32; 3], [i32; 3], [i32; 3]),
    (lo, hi): (i64, i64),
    (ylo, yhi): (i64, i64),
    mut row: impl FnMut(i64, i64, i64),
) {
    use wide::i32x8;
    let lanes = i32x8::new([0, 1, 2, 3, 4, 5, 6, 7]);
    // v[i][j]: edge i at columns lo + 8 j .. lo + 8 j + 8 of the current row.
    let mut v: [[i32x8; V]; 3] = std::array::from_fn(|i| {
        std::array::from_fn(|j| i32x8::splat(e[i] + 8 * j as i32 * col[i]) + lanes * col[i])
    });
    let step = down.map(i32x8::splat);
    let valid = (1u32 << (hi - lo)) - 1;
    for y in ylo..yhi {
        // Sign bits: 1 where some edge is negative (outside).
        let mut outside = 0u32;
        for j in 0..V {
            outside |= ((v[0][j] | v[1][j] | v[2][j]).move_mask() as u32) << (8 * j);
        }
        let inside = !outside & valid;
        if inside != 0 {
            let xs = lo + i64::from(inside.trailing_zeros());
            let xe = lo + 32 - i64::from(inside.leading_zeros());
            row(y, xs, xe);
        }
        for i in 0..3 {
            for j in 0..V {
                v[i][j] += step[i];
            }
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

/// The depth pass: depth test and write, and `ids[pixel] = id` where this triangle is now the
/// nearest. `extents[row]` (rows of the band) is widened to the columns `[lo, hi)` written.
/// Returns the pixels written. Inlined into the depth pass's loop, which runs as AVX2 code
/// where the CPU has it.
#[inline(always)]
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
            let base = depth_row(t, y);
            let before = written;
            let row = ((y - y0) as usize) * width;
            let mut xc = xs as f64 + 0.5;
            for x in xs..xe {
                let (idx, depth) = (row + x as usize, base + depth_col_at(t, xc));
                xc += 1.0;
                if depth_passes(depth, stored[idx]) {
                    stored[idx] = depth_stored(depth);
                    ids[idx] = id;
                    written += 1;
                }
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
