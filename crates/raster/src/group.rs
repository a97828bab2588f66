//! Small triangles eight at a time: the set-up of a band's records in lanes ([`Group::set`]:
//! positions gathered once, then area, orientation, edges, pixel box and depth plane as one
//! operation per lane), then each small triangle's box tested a row at a time as a coverage
//! mask of eight columns, with the depths of those eight pixels computed, tested and written
//! as vectors ([`Group::draw`]). Most triangles of a real mesh cover a few pixels, and for
//! them the one-triangle path's set-up and per-span book-keeping cost more than the pixels.
//!
//! A triangle is *small* when its vertices lie less than [`MAX_DX`] apart across and
//! [`MAX_DY`] down: then its box spans at most eight columns, and every edge value over that
//! box and the eight columns from its first (edges taken relative to their own vertices) fits
//! in `i32`. Other records (larger, or with vertices made by clipping) are left to
//! [`crate::setup::RasterTri`] and [`crate::coverage::for_each_span`], in the same order.
//!
//! A pixel stage run per pixel as it passes (`gouraud`'s) draws from the lanes too: the
//! basis its attribute planes need (edges from the first vertex, inverse area, vertex order)
//! is the depth plane's, kept per lane ([`Group::set_planes`]), so each small triangle's
//! planes cost only their own arithmetic ([`Group::planes`]), and each row's passing pixels
//! are shaded from its first covered pixel as a span is ([`Group::draw_shaded`]).
//!
//! Nothing changes in the picture: the edge values are the same integers as
//! [`crate::setup::RasterTri`]'s (`a X + b Y + c` with `c = -(a px + b py) - bias`, here
//! `a (X - px) + b (Y - py) - bias`), with its top-left rule; the depth plane is computed with
//! its operations in its vertex order; and a pixel's depth is [`crate::coverage::depth_at`]'s
//! formula, tested and stored as [`crate::coverage::depth_passes`] and
//! [`crate::coverage::depth_stored`] do. Every lane operation is the IEEE or integer one, so the
//! baseline and AVX2 builds of these loops agree bit for bit too.

use glam::Vec3;
use phosphor_math::fixed::SUBPIXEL_ONE;

use crate::bin::{EXTRA_VERTEX, TriRec};
use crate::clip::MAX_ATTRS;
use crate::setup::{ScreenPos, plane_through};
use crate::traverse::{Planes, SpanShade, shade_passed};

/// Records set up per call: one vector of eight lanes.
pub(crate) const LANES: usize = 8;

/// A small triangle's vertices lie less than this far apart across (fixed point): fewer than
/// sixteen pixel centres fit between them, so the box has at most two vectors of columns.
const MAX_DX: i32 = 16 * SUBPIXEL_ONE as i32;
/// ... and less than this far apart down. Over the box and up to 32 columns from a vertex,
/// `|a dX| < 2^14 2^13` and `|b dY| < 2^12 2^15`: every edge value fits in `i32`.
const MAX_DY: i32 = 64 * SUBPIXEL_ONE as i32;

const HALF: i32 = SUBPIXEL_ONE as i32 / 2;
const INV_ONE: f64 = 1.0 / SUBPIXEL_ONE as f64;

/// What happens to a record of a group.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kind {
    /// Small, with pixels in the band: drawn by [`Group::draw`].
    Small,
    /// Nothing to draw in this band: no area, or its box misses the band or the image.
    Empty,
    /// Drawn by the one-triangle path.
    Other,
}

/// Up to [`LANES`] records of a band set up together: per lane the box inside the band, the
/// edge values at its first pixel and their steps, and the depth plane.
pub(crate) struct Group {
    /// Per record.
    pub kind: [Kind; LANES],
    /// First column of the box inside the image.
    lo: [i32; LANES],
    /// One past its last column inside the image.
    hi: [i32; LANES],
    /// Bit `j` set where column `lo + j` is inside the box and the image.
    cols: [u32; LANES],
    /// Rows `[ylo, yhi)` of the box inside the band.
    ylo: [i32; LANES],
    yhi: [i32; LANES],
    /// Edge `i` at the centre of pixel `(lo, ylo)`, with the fill-rule bias.
    e: [[i32; LANES]; 3],
    /// Edge `i`'s step per column and per row (`a`, `b` times a pixel).
    col: [[i32; LANES]; 3],
    row: [[i32; LANES]; 3],
    /// The depth plane: origin, depth there, d/dx, d/dy.
    origin: [[f64; LANES]; 2],
    z: [[f64; LANES]; 3],
}

/// The basis of a group's attribute planes ([`Group::set_planes`]), per record: the edges
/// from the first vertex to the second and third (x, y, x, y, in pixels) in the set-up's
/// vertex order, the inverse of twice the area, and whether vertices 1 and 2 were swapped
/// into that order (a negative area). Kept apart from [`Group`], whose other users do not
/// need it. The two-pass depth pass keeps one per group for the by-pixel pass, with the
/// group's plane origins and which records were small ([`Basis::keep`]).
#[derive(Clone, Copy)]
pub(crate) struct Basis {
    edges: [[f64; LANES]; 5],
    swap: [bool; LANES],
    small: [bool; LANES],
    origin: [[f64; LANES]; 2],
}

impl Basis {
    /// A basis to set groups into.
    pub(crate) fn new() -> Basis {
        Basis {
            edges: [[0.0; LANES]; 5],
            swap: [false; LANES],
            small: [false; LANES],
            origin: [[0.0; LANES]; 2],
        }
    }

    /// Keeps what [`Basis::planes`] needs of `g` besides the basis it was set with: which
    /// records are small, and their plane origins. Apart from [`Group::set_planes`], whose
    /// own loop it slowed.
    #[inline(always)]
    pub(crate) fn keep(&mut self, g: &Group) {
        for k in 0..LANES {
            self.small[k] = g.kind[k] == Kind::Small;
        }
        self.origin = g.origin;
    }

    /// Whether record `k` of the kept group was small (its basis set).
    #[inline(always)]
    pub(crate) fn small(&self, k: usize) -> bool {
        self.small.get(k) == Some(&true)
    }

    /// [`Group::planes`] of small record `k` of the kept group ([`Basis::keep`]), over `L`
    /// lanes.
    #[inline(always)]
    pub(crate) fn planes<const L: usize>(
        &self,
        k: usize,
        inv_w: ([f64; 3], bool),
        a: [[f32; L]; 3],
    ) -> Planes {
        let origin = (self.origin[0][k], self.origin[1][k]);
        lane_planes(origin, self.lane(k), inv_w, a)
    }

    /// Lane `k`'s basis, as [`plane`] takes it.
    #[inline(always)]
    fn lane(&self, k: usize) -> ([f64; 4], f64, bool) {
        let b = &self.edges;
        ([b[0][k], b[1][k], b[2][k], b[3][k]], b[4][k], self.swap[k])
    }
}

/// The planes from `origin` with `basis` ([`Basis::lane`]): `1/w` through `inv_w` with
/// `perspective`, else `1/w = 1`, and the `L` attribute planes through `a`.
#[inline(always)]
fn lane_planes<const L: usize>(
    origin: (f64, f64),
    basis: ([f64; 4], f64, bool),
    (inv_w, perspective): ([f64; 3], bool),
    a: [[f32; L]; 3],
) -> Planes {
    let mut p = Planes {
        origin,
        inv_w: [1.0, 0.0, 0.0],
        attr0: [0.0; MAX_ATTRS],
        attr_dx: [0.0; MAX_ATTRS],
        attr_dy: [0.0; MAX_ATTRS],
    };
    if perspective {
        p.inv_w = plane(basis, inv_w);
    }
    for i in 0..L.min(MAX_ATTRS) {
        let v = [f64::from(a[0][i]), f64::from(a[1][i]), f64::from(a[2][i])];
        let [a0, gx, gy] = plane(basis, v);
        p.attr0[i] = a0 as f32;
        p.attr_dx[i] = gx as f32;
        p.attr_dy[i] = gy as f32;
    }
    p
}

impl Group {
    /// Sets up `recs` (at most [`LANES`]) for the band of rows `[y0, y1)` of an image `width`
    /// pixels wide, from the draw's screen positions `pos`.
    #[inline(always)]
    pub(crate) fn set(recs: &[TriRec], pos: &[ScreenPos], width: u32, band: (i64, i64)) -> Group {
        Group::set_impl(recs, pos, width, band, None)
    }

    /// [`Group::set`], keeping the basis of the records' planes in `basis` for
    /// [`Group::planes`] (what a constant colour or the depth pass do not pay for).
    #[inline(always)]
    pub(crate) fn set_planes(
        recs: &[TriRec],
        pos: &[ScreenPos],
        width: u32,
        band: (i64, i64),
        basis: &mut Basis,
    ) -> Group {
        Group::set_impl(recs, pos, width, band, Some(basis))
    }

    #[inline(always)]
    fn set_impl(
        recs: &[TriRec],
        pos: &[ScreenPos],
        width: u32,
        (y0, y1): (i64, i64),
        mut basis: Option<&mut Basis>,
    ) -> Group {
        // Gathered: each vertex's fixed-point position and depth. A record with a vertex made
        // by clipping, or without a screen position, is left to the one-triangle path.
        let mut fx = [[0i32; LANES]; 3];
        let mut fy = [[0i32; LANES]; 3];
        let mut zv = [[0f64; LANES]; 3];
        let mut gathered = [false; LANES];
        for (k, r) in recs.iter().take(LANES).enumerate() {
            // A clipped vertex's index (with `EXTRA_VERTEX`) is past the end of `pos`.
            let p =
                r.v.map(|i| pos.get(i as usize).copied().unwrap_or(ScreenPos::NONE));
            for j in 0..3 {
                fx[j][k] = p[j].fx;
                fy[j][k] = p[j].fy;
                zv[j][k] = p[j].depth;
            }
            gathered[k] =
                !p.iter().any(ScreenPos::is_none) && (r.v[0] | r.v[1] | r.v[2]) & EXTRA_VERTEX == 0;
        }
        let mut g = Group {
            kind: [Kind::Other; LANES],
            lo: [0; LANES],
            hi: [0; LANES],
            cols: [0; LANES],
            ylo: [0; LANES],
            yhi: [0; LANES],
            e: [[0; LANES]; 3],
            col: [[0; LANES]; 3],
            row: [[0; LANES]; 3],
            origin: [[0.0; LANES]; 2],
            z: [[0.0; LANES]; 3],
        };
        let (width, by0, by1) = (width as i32, y0 as i32, y1 as i32);
        // Each loop below is one operation per lane (wrapping where a lane that is not small
        // could overflow; its values are then unused).
        for k in 0..LANES {
            let (x, y) = (
                [fx[0][k], fx[1][k], fx[2][k]],
                [fy[0][k], fy[1][k], fy[2][k]],
            );
            let (xmin, xmax) = (x[0].min(x[1]).min(x[2]), x[0].max(x[1]).max(x[2]));
            let (ymin, ymax) = (y[0].min(y[1]).min(y[2]), y[0].max(y[1]).max(y[2]));
            let small = xmax.wrapping_sub(xmin) < MAX_DX && ymax.wrapping_sub(ymin) < MAX_DY;
            // Twice the signed area (`setup::screen_area2`), exact in i32 for a small one.
            let area = area2(x, y);
            // The box (`setup::row_range`), clipped to the image's columns and the band.
            let lo = first_centre(xmin).max(0);
            let hi = first_centre(xmax).min(width);
            let ylo = first_centre(ymin).max(by0);
            let yhi = first_centre(ymax).min(by1);
            let kind = if !(gathered[k] && small) {
                Kind::Other
            } else if area == 0 || lo >= hi || ylo >= yhi {
                Kind::Empty
            } else {
                Kind::Small
            };
            g.kind[k] = kind;
            g.lo[k] = lo;
            g.hi[k] = hi;
            g.cols[k] = (1u32 << (hi - lo).clamp(0, 31)) - 1;
            g.ylo[k] = ylo;
            g.yhi[k] = yhi;
        }
        for k in 0..LANES {
            // Interior on the positive side of every edge: vertices 1 and 2 swapped for a
            // negative area, as `RasterTri::set` orders them.
            let area = area2(
                [fx[0][k], fx[1][k], fx[2][k]],
                [fy[0][k], fy[1][k], fy[2][k]],
            );
            let swap = area < 0;
            let pick = |v: &[[i32; LANES]; 3], j: usize| match (j, swap) {
                (1, true) => v[2][k],
                (2, true) => v[1][k],
                _ => v[j][k],
            };
            let x = [pick(&fx, 0), pick(&fx, 1), pick(&fx, 2)];
            let y = [pick(&fy, 0), pick(&fy, 1), pick(&fy, 2)];
            let cx = g.lo[k].wrapping_mul(SUBPIXEL_ONE as i32).wrapping_add(HALF);
            let cy = g.ylo[k]
                .wrapping_mul(SUBPIXEL_ONE as i32)
                .wrapping_add(HALF);
            for i in 0..3 {
                let (px, py, qx, qy) = (x[i], y[i], x[(i + 1) % 3], y[(i + 1) % 3]);
                let a = py.wrapping_sub(qy);
                let b = qx.wrapping_sub(px);
                let bias = i32::from(!(a > 0 || (a == 0 && b > 0)));
                g.e[i][k] = a
                    .wrapping_mul(cx.wrapping_sub(px))
                    .wrapping_add(b.wrapping_mul(cy.wrapping_sub(py)))
                    .wrapping_sub(bias);
                g.col[i][k] = a.wrapping_mul(SUBPIXEL_ONE as i32);
                g.row[i][k] = b.wrapping_mul(SUBPIXEL_ONE as i32);
            }
            // The depth plane, with `RasterTri::set`'s operations in its vertex order.
            let (z1, z2) = if swap {
                (zv[2][k], zv[1][k])
            } else {
                (zv[1][k], zv[2][k])
            };
            let xy = [0, 1, 2].map(|j| (f64::from(x[j]) * INV_ONE, f64::from(y[j]) * INV_ONE));
            let (dx1, dy1) = (xy[1].0 - xy[0].0, xy[1].1 - xy[0].1);
            let (dx2, dy2) = (xy[2].0 - xy[0].0, xy[2].1 - xy[0].1);
            let inv_area =
                (SUBPIXEL_ONE * SUBPIXEL_ONE) as f64 / f64::from(area.wrapping_abs()).max(1.0);
            let edges = ((dx1, dy1), (dx2, dy2));
            let [z0, zx, zy] = plane_through(edges, inv_area, [zv[0][k], z1, z2]);
            g.z[0][k] = z0;
            g.z[1][k] = zx;
            g.z[2][k] = zy;
            g.origin[0][k] = xy[0].0;
            g.origin[1][k] = xy[0].1;
            if let Some(b) = &mut basis {
                b.edges[0][k] = dx1;
                b.edges[1][k] = dy1;
                b.edges[2][k] = dx2;
                b.edges[3][k] = dy2;
                b.edges[4][k] = inv_area;
                b.swap[k] = swap;
            }
        }
        g
    }

    /// The attribute planes of small record `k` of a group set by [`Group::set_planes`] with
    /// `basis`, bit for bit those [`Planes::set`] computes with up to `L` attributes (4 or 8,
    /// [`crate::coverage::lanes`] of the attributes in use; none when there are none): from
    /// the values `a` at its vertices (in the record's order; zeros past the attributes in
    /// use) and, with `perspective`, the plane of the vertices' `1/w` values `inv_w`, else
    /// `1/w = 1`. The basis is the one the depth plane was set up with, so a small
    /// triangle's planes cost the attributes' arithmetic alone.
    #[inline(always)]
    pub(crate) fn planes<const L: usize>(
        &self,
        (basis, k): (&Basis, usize),
        inv_w: ([f64; 3], bool),
        a: [[f32; L]; 3],
    ) -> Planes {
        let origin = (self.origin[0][k], self.origin[1][k]);
        lane_planes(origin, basis.lane(k), inv_w, a)
    }

    /// Draws small record `k` into a band whose first row is `band_y0`, rows `width` pixels
    /// wide in `depth`, with lanes `r`: each pixel that passes the depth test gets its depth
    /// written, and, with `fill = Some((buffer, v))`, `v` at its index in `buffer` (laid out
    /// as `depth`), eight columns at a time ([`fill_in`]); `row(at, [inside, passed], (x,
    /// y))` is told, per row with such pixels, the band index `at` of the row's first column
    /// `x` (image row `y`) and the bits `j` (below 16) of the columns `at + j` that the
    /// triangle covers and that passed. The fill is
    /// done here, not by `row`, so that its lane operations are compiled in the caller's
    /// instruction set (a closure is compiled in the baseline's). Returns the pixels that
    /// passed.
    #[inline(always)]
    pub(crate) fn draw<R: RowLanes, T: Fill>(
        &self,
        r: R,
        k: usize,
        band: (&mut [f32], usize, i64),
        fill: Option<(&mut [T], T)>,
        row: impl FnMut(usize, [u32; 2], (i64, i64)),
    ) -> u32 {
        if self.cols[k] >> LANES == 0 {
            self.draw_rows::<R, T, 1>(r, k, band, fill, row)
        } else {
            self.draw_rows::<R, T, 2>(r, k, band, fill, row)
        }
    }

    /// [`Group::draw`] for a pixel stage run per pixel as it passes: small record `k`, whose
    /// planes are `p` ([`Group::planes`]), drawn with `shade` into `color` (laid out as the
    /// band's depths), each row's passing pixels shaded as the one-triangle traversal's span
    /// from the row's first covered pixel shades them ([`shade_passed`]). Returns the pixels
    /// that passed.
    #[inline(always)]
    pub(crate) fn draw_shaded<R: RowLanes, T: SpanShade>(
        &self,
        r: R,
        k: usize,
        band: (&mut [f32], usize, i64),
        (p, shade): (&Planes, &mut T),
        color: &mut [Vec3],
    ) -> u32 {
        self.draw(
            r,
            k,
            band,
            None::<(&mut [Vec3], Vec3)>,
            #[inline(always)]
            |at, [inside, passed], (lo, y)| {
                let s = inside.trailing_zeros();
                let first = (at + s as usize, lo + i64::from(s), y);
                shade_passed(p, shade, color, first, passed >> s);
            },
        )
    }

    /// [`Group::draw`] with `V` vectors of eight columns per row.
    #[inline(always)]
    fn draw_rows<R: RowLanes, T: Fill, const V: usize>(
        &self,
        r: R,
        k: usize,
        (depth, width, band_y0): (&mut [f32], usize, i64),
        mut fill: Option<(&mut [T], T)>,
        mut row: impl FnMut(usize, [u32; 2], (i64, i64)),
    ) -> u32 {
        let lo = self.lo[k];
        let step = LANES as i32;
        // Plain loops, not `array::from_fn`: its closures may stay out of line, where the
        // AVX2 operations would be calls.
        let mut v = [[r.splat(0); V]; 3];
        for i in 0..3 {
            let (e, col) = (self.e[i][k], self.col[i][k]);
            for h in 0..V {
                v[i][h] = r.ramp(e.wrapping_add(col.wrapping_mul(step * h as i32)), col);
            }
        }
        let down = [
            r.splat(self.row[0][k]),
            r.splat(self.row[1][k]),
            r.splat(self.row[2][k]),
        ];
        // `depth_col` of the columns, once per triangle.
        let (ox, zx) = (self.origin[0][k], self.z[1][k]);
        let mut col_z = [r.depth_cols(lo, ox, zx); V];
        for h in 1..V {
            col_z[h] = r.depth_cols(lo + step * h as i32, ox, zx);
        }
        let (oy, z0, zy) = (self.origin[1][k], self.z[0][k], self.z[2][k]);
        let (cols, mut passed_all) = (self.cols[k], 0);
        let mut at = (i64::from(self.ylo[k]) - band_y0) as usize * width + lo as usize;
        for y in self.ylo[k]..self.yhi[k] {
            let mut outside = 0;
            for h in 0..V {
                outside |= r.outside([v[0][h], v[1][h], v[2][h]]) << (LANES * h);
                for i in 0..3 {
                    v[i][h] = r.add(v[i][h], down[i]);
                }
            }
            let inside = !outside & cols;
            let here = at;
            at += width;
            if inside == 0 {
                continue;
            }
            // `depth_row`, then `depth_at` per column, tested as `depth_passes` does and
            // stored as `depth_stored` does.
            let base = z0 + ((f64::from(y) + 0.5) - oy) * zy;
            let mut passed = 0;
            for h in 0..V {
                let (part, first) = ((inside >> (LANES * h)) & 0xff, here + LANES * h);
                if part == 0 {
                    continue;
                }
                let hit = match depth
                    .get_mut(first..first + LANES)
                    .map(<&mut [f32; LANES]>::try_from)
                {
                    Some(Ok(s)) => {
                        let (less, d) = r.less(base, col_z[h], s);
                        r.store(less & part, d, s);
                        less & part
                    }
                    // The band's last pixels: one at a time.
                    _ => {
                        let d = r.depths(base, col_z[h]);
                        let mut hit = 0;
                        for_bits(part, |j| {
                            if let Some(s) = depth.get_mut(first + j) {
                                if d[j] < *s {
                                    *s = if d[j] > 0.0 { d[j] } else { 0.0 };
                                    hit |= 1 << j;
                                }
                            }
                        });
                        hit
                    }
                };
                passed |= hit << (LANES * h);
            }
            if passed != 0 {
                if let Some((buffer, v)) = &mut fill {
                    fill_in(r, buffer, here, passed, *v);
                }
                row(here, [inside, passed], (i64::from(lo), i64::from(y)));
                passed_all += passed.count_ones();
            }
        }
        passed_all
    }

    /// The band rows `[y0, y1)` and columns `[x0, x1)` of small record `k`'s box: its
    /// spans lie inside.
    #[inline(always)]
    pub(crate) fn bounds(&self, k: usize) -> [i32; 4] {
        [self.lo[k], self.hi[k], self.ylo[k], self.yhi[k]]
    }
}

/// The union of boxes ([`Group::bounds`]) to widen a band's per-row column record by: what
/// the small triangles of a group drew, marked once per group. A box holds its triangle's
/// spans, so the union is a superset of what was written, which is what a dirty record (what
/// to clear and read out again) and the depth pass's extents (where to look for ids) may be.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Marks([i32; 4]);

impl Marks {
    /// Nothing yet.
    pub(crate) const NONE: Marks = Marks([i32::MAX, i32::MIN, i32::MAX, i32::MIN]);

    /// Adds a box.
    #[inline(always)]
    pub(crate) fn add(&mut self, b: [i32; 4]) {
        let m = &mut self.0;
        *m = [
            m[0].min(b[0]),
            m[1].max(b[1]),
            m[2].min(b[2]),
            m[3].max(b[3]),
        ];
    }

    /// Widens `marks` (one `(lo, hi)` per band row; the band's first row `band_y0`) over the
    /// union's rows to its columns.
    #[inline(always)]
    pub(crate) fn apply(self, marks: &mut [(u32, u32)], band_y0: i64) {
        let [x0, x1, y0, y1] = self.0;
        if x0 >= x1 || y0 >= y1 {
            return;
        }
        let rows = (i64::from(y0) - band_y0) as usize..(i64::from(y1) - band_y0) as usize;
        for e in marks.get_mut(rows).unwrap_or(&mut []) {
            *e = (e.0.min(x0 as u32), e.1.max(x1 as u32));
        }
    }
}

/// A value [`Group::draw`] writes to each pixel that passes: a colour, or an id.
pub(crate) trait Fill: Copy {
    /// `px[j] = v` where `passed` has bit `j` (below 8), with lanes `r`; the others written
    /// back unchanged.
    fn eight<R: RowLanes>(r: R, passed: u32, v: Self, px: &mut [Self; LANES]);
}

impl Fill for Vec3 {
    #[inline(always)]
    fn eight<R: RowLanes>(r: R, passed: u32, v: Vec3, px: &mut [Vec3; LANES]) {
        r.fill_rgb(passed, v, px);
    }
}

impl Fill for u64 {
    #[inline(always)]
    fn eight<R: RowLanes>(r: R, passed: u32, v: u64, px: &mut [u64; LANES]) {
        r.fill_id(passed, v, px);
    }
}

/// `row[at + j] = v` for each set bit `j` (below 16) of `bits`: the per-pixel writes of a
/// row [`Group::draw`] reports. Each eight columns lying inside `row` are written at once
/// with lanes `r` ([`Fill::eight`]), so a row costs a few vector operations instead of a
/// loop over its pixels; the band's last columns are written one by one.
#[inline(always)]
pub(crate) fn fill_in<R: RowLanes, T: Fill>(r: R, row: &mut [T], at: usize, bits: u32, v: T) {
    for h in 0..2 {
        let (part, first) = ((bits >> (LANES * h)) & 0xff, at + LANES * h);
        if part == 0 {
            continue;
        }
        match row
            .get_mut(first..first + LANES)
            .map(<&mut [T; LANES]>::try_from)
        {
            Some(Ok(px)) => T::eight(r, part, v, px),
            _ => for_bits(part, |j| {
                if let Some(p) = row.get_mut(first + j) {
                    *p = v;
                }
            }),
        }
    }
}

/// Calls `f(j)` for each set bit `j` of `bits`, lowest first.
#[inline(always)]
pub(crate) fn for_bits(mut bits: u32, mut f: impl FnMut(usize)) {
    while bits != 0 {
        f(bits.trailing_zeros() as usize);
        bits &= bits - 1;
    }
}

/// The plane through the values `a` at a triangle's vertices (in its record's order) over
/// `basis` (`[dx1, dy1, dx2, dy2]`, the inverse of twice the area, whether vertices 1 and 2
/// are swapped): [`plane_through`] in the set-up's vertex order.
#[inline(always)]
fn plane(([dx1, dy1, dx2, dy2], inv_area, swap): ([f64; 4], f64, bool), a: [f64; 3]) -> [f64; 3] {
    let (a1, a2) = if swap { (a[2], a[1]) } else { (a[1], a[2]) };
    plane_through(((dx1, dy1), (dx2, dy2)), inv_area, [a[0], a1, a2])
}

/// Twice the signed area of a triangle (`setup::screen_area2`), in i32: exact for a small
/// one, wrapped (and unused) for others.
#[inline(always)]
fn area2(x: [i32; 3], y: [i32; 3]) -> i32 {
    let d = |a: i32, b: i32| a.wrapping_sub(b);
    d(x[1], x[0])
        .wrapping_mul(d(y[2], y[0]))
        .wrapping_sub(d(x[2], x[0]).wrapping_mul(d(y[1], y[0])))
}

/// The eight-column operations of [`Group::draw`]: `wide`'s portable vectors at the
/// baseline ([`Portable`]), 256-bit registers under AVX2. Both are the same integer and IEEE
/// operations, so they give the same bits.
pub(crate) trait RowLanes: Copy {
    /// Eight i32 lanes.
    type I: Copy;
    /// Eight f64 lanes.
    type D: Copy;
    /// Eight f32 lanes.
    type F: Copy;
    /// `e + j step` in lane `j`.
    fn ramp(self, e: i32, step: i32) -> Self::I;
    /// `x` in every lane.
    fn splat(self, x: i32) -> Self::I;
    /// Lane-wise wrapping sum.
    fn add(self, a: Self::I, b: Self::I) -> Self::I;
    /// Bit `j` set where some of the three is negative in lane `j`.
    fn outside(self, v: [Self::I; 3]) -> u32;
    /// `((lo + j) + 0.5 - ox) zx` in lane `j` (`depth_col`).
    fn depth_cols(self, lo: i32, ox: f64, zx: f64) -> Self::D;
    /// `(base + c[j]) as f32` per lane.
    fn depths(self, base: f64, c: Self::D) -> [f32; LANES];
    /// [`RowLanes::depths`] as lanes, and bit `j` set where lane `j`'s depth is less than
    /// `stored[j]`.
    fn less(self, base: f64, c: Self::D, stored: &[f32; LANES]) -> (u32, Self::F);
    /// `stored[j]` set to `d[j]` (negatives, -0 and NaN as 0: `depth_stored`) where `passed`
    /// has bit `j`; the other lanes are written back unchanged.
    fn store(self, passed: u32, d: Self::F, stored: &mut [f32; LANES]);
    /// `px[j] = rgb` where `passed` has bit `j` (below 8); the other pixels written back
    /// unchanged.
    fn fill_rgb(self, passed: u32, rgb: Vec3, px: &mut [Vec3; LANES]);
    /// `px[j] = id` where `passed` has bit `j` (below 8); the others written back unchanged.
    fn fill_id(self, passed: u32, id: u64, px: &mut [u64; LANES]);
}

/// [`RowLanes`] with `wide`'s vectors, for any CPU.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Portable;

impl RowLanes for Portable {
    type I = wide::i32x8;
    type D = [f64; LANES];
    type F = [f32; LANES];
    #[inline(always)]
    fn ramp(self, e: i32, step: i32) -> wide::i32x8 {
        wide::i32x8::new(std::array::from_fn(|j| {
            e.wrapping_add(step.wrapping_mul(j as i32))
        }))
    }
    #[inline(always)]
    fn splat(self, x: i32) -> wide::i32x8 {
        wide::i32x8::splat(x)
    }
    #[inline(always)]
    fn add(self, a: wide::i32x8, b: wide::i32x8) -> wide::i32x8 {
        a + b
    }
    #[inline(always)]
    fn outside(self, v: [wide::i32x8; 3]) -> u32 {
        (v[0] | v[1] | v[2]).move_mask() as u32
    }
    #[inline(always)]
    fn depth_cols(self, lo: i32, ox: f64, zx: f64) -> [f64; LANES] {
        std::array::from_fn(|j| ((f64::from(lo + j as i32) + 0.5) - ox) * zx)
    }
    #[inline(always)]
    fn depths(self, base: f64, c: [f64; LANES]) -> [f32; LANES] {
        std::array::from_fn(|j| (base + c[j]) as f32)
    }
    #[inline(always)]
    fn less(self, base: f64, c: [f64; LANES], stored: &[f32; LANES]) -> (u32, [f32; LANES]) {
        use wide::{CmpLt, f32x8};
        let d = self.depths(base, c);
        let less = f32x8::from(d).cmp_lt(f32x8::from(*stored)).move_mask() as u32;
        (less, d)
    }
    #[inline(always)]
    fn store(self, passed: u32, d: [f32; LANES], stored: &mut [f32; LANES]) {
        for_bits(passed, |j| {
            stored[j & 7] = if d[j & 7] > 0.0 { d[j & 7] } else { 0.0 }
        });
    }
    #[inline(always)]
    fn fill_rgb(self, passed: u32, rgb: Vec3, px: &mut [Vec3; LANES]) {
        for_bits(passed, |j| px[j & 7] = rgb);
    }
    #[inline(always)]
    fn fill_id(self, passed: u32, id: u64, px: &mut [u64; LANES]) {
        for_bits(passed, |j| px[j & 7] = id);
    }
}

#[cfg(target_arch = "x86_64")]
mod avx2 {
    use std::arch::x86_64::{__m256, __m256d, __m256i};

    use pulp::x86::V3;

    use glam::Vec3;

    use super::{LANES, RowLanes};

    /// `_mm256_cmp_ps`'s ordered, quiet less-than (false with a NaN, as `<`).
    const LT_OQ: i32 = 0x11;

    /// [`RowLanes`] in AVX2 registers: `pulp`'s `V3` token, and a zero vector that LLVM cannot
    /// see through. Each store blends the new lanes into the loaded row and writes the row
    /// whole; without the zero or-ed into the loaded row, LLVM turns that load, blend and
    /// store into one masked store (`vmaskmovps`), which AMD's cores run many times slower.
    #[derive(Debug, Clone, Copy)]
    pub(crate) struct Avx2Rows {
        v: V3,
        zero: __m256,
    }

    impl Avx2Rows {
        /// The lanes of `v`.
        #[inline(always)]
        pub(crate) fn new(v: V3) -> Avx2Rows {
            let zero = std::hint::black_box(v.avx._mm256_setzero_ps());
            Avx2Rows { v, zero }
        }
    }

    impl Avx2Rows {
        /// `row[j] = value[j]` where `mask[j]`'s sign is set: the row loaded, blended and
        /// stored whole, with the hidden zero or-ed into the loaded row so that LLVM keeps the
        /// plain store (see [`Avx2Rows`]).
        #[inline(always)]
        fn blend_row(self, row: &mut [f32; LANES], value: __m256, mask: __m256) {
            let a = self.v.avx;
            let old = a._mm256_or_ps(pulp::cast(*row), self.zero);
            *row = pulp::cast(a._mm256_blendv_ps(old, value, mask));
        }
    }

    impl RowLanes for Avx2Rows {
        type I = __m256i;
        type D = [__m256d; 2];
        type F = __m256;
        #[inline(always)]
        fn ramp(self, e: i32, step: i32) -> __m256i {
            let j = self.v.avx._mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
            let s = self
                .v
                .avx2
                ._mm256_mullo_epi32(j, self.v.avx._mm256_set1_epi32(step));
            self.v
                .avx2
                ._mm256_add_epi32(s, self.v.avx._mm256_set1_epi32(e))
        }
        #[inline(always)]
        fn splat(self, x: i32) -> __m256i {
            self.v.avx._mm256_set1_epi32(x)
        }
        #[inline(always)]
        fn add(self, a: __m256i, b: __m256i) -> __m256i {
            self.v.avx2._mm256_add_epi32(a, b)
        }
        #[inline(always)]
        fn outside(self, v: [__m256i; 3]) -> u32 {
            let any = self
                .v
                .avx2
                ._mm256_or_si256(self.v.avx2._mm256_or_si256(v[0], v[1]), v[2]);
            self.v
                .avx
                ._mm256_movemask_ps(self.v.avx._mm256_castsi256_ps(any)) as u32
        }
        #[inline(always)]
        fn depth_cols(self, lo: i32, ox: f64, zx: f64) -> [__m256d; 2] {
            let a = self.v.avx;
            let l = f64::from(lo);
            let x = [
                a._mm256_setr_pd(l, l + 1.0, l + 2.0, l + 3.0),
                a._mm256_setr_pd(l + 4.0, l + 5.0, l + 6.0, l + 7.0),
            ];
            let half = a._mm256_set1_pd(0.5);
            let (ox, zx) = (a._mm256_set1_pd(ox), a._mm256_set1_pd(zx));
            x.map(|x| a._mm256_mul_pd(a._mm256_sub_pd(a._mm256_add_pd(x, half), ox), zx))
        }
        #[inline(always)]
        fn depths(self, base: f64, c: [__m256d; 2]) -> [f32; LANES] {
            pulp::cast(cvt(self.v, base, c))
        }
        #[inline(always)]
        fn less(self, base: f64, c: [__m256d; 2], stored: &[f32; LANES]) -> (u32, __m256) {
            let d = cvt(self.v, base, c);
            let s = pulp::cast(*stored);
            let less = self
                .v
                .avx
                ._mm256_movemask_ps(self.v.avx._mm256_cmp_ps::<LT_OQ>(d, s));
            (less as u32, d)
        }
        #[inline(always)]
        fn store(self, passed: u32, d: __m256, stored: &mut [f32; LANES]) {
            let a = self.v.avx;
            let mask = sign_mask(
                self.v,
                passed,
                a._mm256_setr_epi32(31, 30, 29, 28, 27, 26, 25, 24),
            );
            // `_mm256_max_ps(d, 0)` is 0 for a NaN, -0 or negative `d` (the second operand
            // wins those), as `depth_stored`'s compare-select.
            let keep = a._mm256_max_ps(d, a._mm256_setzero_ps());
            self.blend_row(stored, keep, mask);
        }
        #[inline(always)]
        fn fill_rgb(self, passed: u32, rgb: Vec3, px: &mut [Vec3; LANES]) {
            let a = self.v.avx;
            // The 24 floats of eight pixels as three vectors: float `i` belongs to pixel
            // `i / 3` (its bit of `passed` shifted to the sign by `31 - i / 3`), and is
            // channel `i % 3` of `rgb`.
            let flat: &mut [f32; 3 * LANES] = bytemuck::cast_mut(px);
            let (r, g, b) = (rgb.x, rgb.y, rgb.z);
            let value = [
                a._mm256_setr_ps(r, g, b, r, g, b, r, g),
                a._mm256_setr_ps(b, r, g, b, r, g, b, r),
                a._mm256_setr_ps(g, b, r, g, b, r, g, b),
            ];
            let shift = [
                a._mm256_setr_epi32(31, 31, 31, 30, 30, 30, 29, 29),
                a._mm256_setr_epi32(29, 28, 28, 28, 27, 27, 27, 26),
                a._mm256_setr_epi32(26, 26, 25, 25, 25, 24, 24, 24),
            ];
            for (i, chunk) in flat.chunks_exact_mut(LANES).enumerate() {
                let Ok(chunk) = <&mut [f32; LANES]>::try_from(chunk) else {
                    continue;
                };
                self.blend_row(chunk, value[i], sign_mask(self.v, passed, shift[i]));
            }
        }
        #[inline(always)]
        fn fill_id(self, passed: u32, id: u64, px: &mut [u64; LANES]) {
            let (a, a2) = (self.v.avx, self.v.avx2);
            let value = a._mm256_castsi256_pd(a._mm256_set1_epi64x(id as i64));
            let all = a._mm256_set1_epi64x(i64::from(passed));
            let shift = [
                a._mm256_setr_epi64x(63, 62, 61, 60),
                a._mm256_setr_epi64x(59, 58, 57, 56),
            ];
            for (i, chunk) in px.chunks_exact_mut(LANES / 2).enumerate() {
                let Ok(chunk) = <&mut [u64; LANES / 2]>::try_from(chunk) else {
                    continue;
                };
                let mask = a._mm256_castsi256_pd(a2._mm256_sllv_epi64(all, shift[i]));
                let old = a._mm256_or_pd(pulp::cast(*chunk), a._mm256_castps_pd(self.zero));
                *chunk = pulp::cast(a._mm256_blendv_pd(old, value, mask));
            }
        }
    }

    /// Lane `j` with bit `31 - shift[j]` of `passed` in its sign: a blend mask
    /// (`_mm256_blendv_ps` reads only the signs), in two operations.
    #[inline(always)]
    fn sign_mask(v: V3, passed: u32, shift: __m256i) -> __m256 {
        let a = v.avx;
        let all = a._mm256_set1_epi32(passed as i32);
        a._mm256_castsi256_ps(v.avx2._mm256_sllv_epi32(all, shift))
    }

    /// `(base + c[j]) as f32` in lane `j`: the sum in f64, rounded to nearest.
    #[inline(always)]
    fn cvt(v: V3, base: f64, c: [__m256d; 2]) -> __m256 {
        let a = v.avx;
        let b = a._mm256_set1_pd(base);
        let [lo, hi] = c.map(|c| a._mm256_cvtpd_ps(a._mm256_add_pd(b, c)));
        a._mm256_set_m128(hi, lo)
    }
}

/// `setup::first_row_at_or_below` in i32: the first pixel row (or column) whose centre lies
/// at or below fixed-point `f`.
#[inline(always)]
fn first_centre(f: i32) -> i32 {
    f.wrapping_add(SUBPIXEL_ONE as i32 - 1 - HALF) >> phosphor_math::fixed::SUBPIXEL_BITS
}

#[cfg(target_arch = "x86_64")]
pub(crate) use avx2::Avx2Rows;

#[cfg(test)]
#[path = "tests/group_unit.rs"]
mod tests;
