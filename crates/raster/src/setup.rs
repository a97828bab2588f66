//! Triangle set-up: perspective divide, viewport and sub-pixel snapping per vertex
//! ([`to_screen`]), then per triangle and band ([`RasterTri`]) orientation, the pixel box, the
//! integer edge functions and the screen-space planes of depth, `1/w` and every attribute (what
//! the traversal steps along).

use phosphor_math::fixed::{SUBPIXEL_BITS, SUBPIXEL_ONE, to_fixed};

use crate::clip::{Attrs, ClipVertex, MAX_ATTRS};
use crate::shader::GRADIENT_SLOTS;

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

impl ScreenVertex {
    /// The part of the vertex that band set-up reads besides the attributes.
    #[inline]
    #[must_use]
    pub fn pos(&self) -> ScreenPos {
        // |fx|, |fy| <= MAX_FIXED_COORD << SUBPIXEL_BITS = 2^28 (see `to_fixed`).
        ScreenPos {
            fx: self.fx as i32,
            fy: self.fy as i32,
            depth: self.depth,
            inv_w: self.inv_w,
        }
    }
}

/// What band set-up reads of a vertex besides its attributes, in 24 bytes: a band's triangles
/// fetch their vertices from all over the mesh, so the fewer cache lines a vertex spans the
/// less the set-up waits on memory (a whole [`ScreenVertex`] spans two).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScreenPos {
    /// Snapped x in fixed point ([`ScreenVertex::fx`]; [`i32::MIN`] for no vertex).
    pub fx: i32,
    /// Snapped y in fixed point.
    pub fy: i32,
    /// Depth in `[0, 1]`.
    pub depth: f64,
    /// `1/w` (perspective) or 1.
    pub inv_w: f64,
}

impl ScreenPos {
    /// No vertex (outside the clip volume or not finite): a triangle using it is not drawn.
    pub const NONE: ScreenPos = ScreenPos {
        fx: i32::MIN,
        fy: i32::MIN,
        depth: 0.0,
        inv_w: 0.0,
    };

    /// Whether this is [`ScreenPos::NONE`].
    #[inline]
    #[must_use]
    pub fn is_none(&self) -> bool {
        self.fx == i32::MIN
    }
}

/// `ceil(a / b)` for `b > 0`, exact in integers (the tests' reference for the row rounding).
#[cfg(test)]
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
    // ceil(a / 2^k) = floor((a + 2^k - 1) / 2^k), and an arithmetic shift floors: the same
    // value as `ceil_div(fy - HALF, SUBPIXEL_ONE)` without the remainder test (it runs four
    // times per set-up). |fy| <= 2^28, so nothing overflows.
    (fy - HALF + SUBPIXEL_ONE - 1) >> SUBPIXEL_BITS
}

/// Divide and viewport for a clip-space vertex; `None` when a coordinate is non-finite or
/// outside the fixed-point range (clipping keeps this from happening for finite input).
#[inline]
#[must_use]
pub fn to_screen(
    v: &ClipVertex,
    width: u32,
    height: u32,
    n: usize,
    perspective: bool,
) -> Option<ScreenVertex> {
    let (p, rhw) = project(v.pos, width, height, perspective)?;
    let mut attrs = [0.0; MAX_ATTRS];
    let scale = attr_scale(rhw, perspective);
    for j in 0..n {
        attrs[j] = v.attrs[j] * scale;
    }
    Some(ScreenVertex {
        fx: i64::from(p.fx),
        fy: i64::from(p.fy),
        x: f64::from(p.fx) * INV_ONE,
        y: f64::from(p.fy) * INV_ONE,
        depth: p.depth,
        inv_w: p.inv_w,
        rhw,
        attrs,
    })
}

/// What [`to_screen`] multiplies a vertex's attributes by: its `1/w` (from [`project`]) when
/// perspective-correct, else 1.
#[inline]
#[must_use]
pub fn attr_scale(rhw: f64, perspective: bool) -> f32 {
    if perspective { rhw as f32 } else { 1.0 }
}

/// The position part of [`to_screen`] (the same bits): the snapped position, depth and
/// stepped `1/w`, with the true `1/w` (attributes are multiplied by it, as `f32`, when
/// `perspective`). The vertex stage calls this alone and scales only the attributes its mode
/// reads, rather than building a whole [`ScreenVertex`] per mesh vertex.
#[inline]
#[must_use]
pub fn project(
    pos: glam::Vec4,
    width: u32,
    height: u32,
    perspective: bool,
) -> Option<(ScreenPos, f64)> {
    let w = pos.w as f64;
    // NaN, zero, negative and infinite `w` all fail this one test.
    if !(w > 0.0 && w < f64::INFINITY) {
        return None;
    }
    let inv_w = 1.0 / w;
    let sx = (pos.x as f64 * inv_w + 1.0) * 0.5 * width as f64;
    let sy = (1.0 - pos.y as f64 * inv_w) * 0.5 * height as f64;
    let depth = (pos.z as f64 * inv_w) * 0.5 + 0.5;
    let fx = to_fixed(sx as f32)?;
    let fy = to_fixed(sy as f32)?;
    if !depth.is_finite() {
        return None;
    }
    // |fx|, |fy| <= MAX_FIXED_COORD << SUBPIXEL_BITS = 2^28 (see `to_fixed`).
    let p = ScreenPos {
        fx: fx as i32,
        fy: fy as i32,
        depth,
        inv_w: if perspective { inv_w } else { 1.0 },
    };
    Some((p, inv_w))
}

/// Twice the signed area in fixed point, screen frame (y down): negative for a triangle that is
/// counter-clockwise in NDC, i.e. front-facing.
#[inline]
#[must_use]
pub fn screen_area2(p: &[ScreenPos; 3]) -> i64 {
    let (x, y) = (p.map(|p| i64::from(p.fx)), p.map(|p| i64::from(p.fy)));
    (x[1] - x[0]) * (y[2] - y[0]) - (x[2] - x[0]) * (y[1] - y[0])
}

/// The pixel rows `[lo, hi)` whose centres a triangle with these fixed-point `y` can cover:
/// `ceil(y_top - 0.5) .. ceil(y_bottom - 0.5)` (also used for columns with `x`).
#[inline]
#[must_use]
pub fn row_range(fy: [i64; 3]) -> (i64, i64) {
    let lo = fy[0].min(fy[1]).min(fy[2]);
    let hi = fy[0].max(fy[1]).max(fy[2]);
    (first_row_at_or_below(lo), first_row_at_or_below(hi))
}

/// A triangle ready for the bounding-box traversal: three integer edge functions, the pixel
/// bounds, and the plane equations of depth, `1/w` and the attributes.
///
/// Edge `i` is `E_i(X, Y) = a_i X + b_i Y + c_i` at fixed-point pixel centres, `c_i` holding
/// `-(a_i px_i + b_i py_i)` for a point `p_i` of the edge plus a bias; a pixel is covered when all three are `>= 0`. The bias is 0 on a left edge
/// (interior to its right) or a top edge (horizontal, interior below) and -1 elsewhere, so a
/// centre exactly on an edge belongs to the triangle to its right or below: the top-left rule.
/// Rows then run `ceil(y_top - 0.5) .. ceil(y_bottom - 0.5)` and spans
/// `[ceil(x_left - 0.5), ceil(x_right - 0.5))`, evaluated exactly in integers, so two
/// triangles sharing an edge split its pixels without gap or overlap.
#[derive(Debug, Clone, Copy)]
pub struct RasterTri {
    /// `dE/dX` per edge.
    pub edge_a: [i64; 3],
    /// `dE/dY` per edge.
    pub edge_b: [i64; 3],
    /// The constant term of each edge function, with the fill-rule bias.
    pub edge_c: [i64; 3],
    /// Pixel columns `[x0, x1)` the triangle can cover (not clipped to the image).
    pub x0: i64,
    /// One past the last column.
    pub x1: i64,
    /// Pixel rows `[y0, y1)` the triangle can cover (not clipped to the image).
    pub y0: i64,
    /// One past the last row.
    pub y1: i64,
    /// Plane origin in pixels (the first vertex).
    pub origin: (f64, f64),
    /// Depth at the origin, `d/dx`, `d/dy`.
    pub depth: [f64; 3],
    /// `1/w` at the origin, `d/dx`, `d/dy` (perspective only; else 1, 0, 0).
    pub inv_w: [f64; 3],
    /// Attributes at the origin (divided by `w` when perspective-correct).
    pub attr0: Attrs,
    /// `d attr / dx`.
    pub attr_dx: Attrs,
    /// `d attr / dy`.
    pub attr_dy: Attrs,
    /// Attributes in use.
    pub n: usize,
    /// Whether attributes are divided by `w`.
    pub perspective: bool,
}

impl RasterTri {
    /// An empty triangle (covers nothing) to [`RasterTri::set`] later.
    #[must_use]
    pub fn empty() -> RasterTri {
        RasterTri {
            edge_a: [0; 3],
            edge_b: [0; 3],
            edge_c: [-1; 3],
            x0: 0,
            x1: 0,
            y0: 0,
            y1: 0,
            origin: (0.0, 0.0),
            depth: [0.0; 3],
            inv_w: [1.0, 0.0, 0.0],
            attr0: [0.0; MAX_ATTRS],
            attr_dx: [0.0; MAX_ATTRS],
            attr_dy: [0.0; MAX_ATTRS],
            n: 0,
            perspective: false,
        }
    }

    /// The triangle through `v` with the first `n` attributes; `None` for zero area. The
    /// winding does not matter (culling is the caller's). The tests' constructor; the
    /// renderer reuses one triangle ([`RasterTri::set`]).
    #[cfg(test)]
    #[must_use]
    pub fn new(v: [&ScreenVertex; 3], n: usize, perspective: bool) -> Option<RasterTri> {
        let mut t = RasterTri::empty();
        let attrs = v.map(|v| &v.attrs[..]);
        t.set(v.map(ScreenVertex::pos), attrs, n, perspective)
            .then_some(t)
    }

    /// [`RasterTri::new`] in place from the vertices' positions `p` and attributes `attrs`
    /// (at least `n` each): set-up runs per band and triangle, and this avoids moving the
    /// record around. Returns false, leaving `self` unspecified, for zero area.
    #[inline]
    pub fn set(
        &mut self,
        p: [ScreenPos; 3],
        attrs: [&[f32]; 3],
        n: usize,
        perspective: bool,
    ) -> bool {
        self.set_impl(p, attrs, n, perspective)
    }

    #[inline(always)]
    fn set_impl(
        &mut self,
        p: [ScreenPos; 3],
        attrs: [&[f32]; 3],
        n: usize,
        perspective: bool,
    ) -> bool {
        let Some(basis) = PlaneBasis::of(p, attrs) else {
            return false;
        };
        let f = basis.f;
        for i in 0..3 {
            let (p, q) = (f[i], f[(i + 1) % 3]);
            // E(S) = (q - p) x (S - p) = (qx - px)(Sy - py) - (qy - py)(Sx - px).
            let a = -(q.1 - p.1);
            let b = q.0 - p.0;
            let top_left = a > 0 || (a == 0 && b > 0);
            self.edge_a[i] = a;
            self.edge_b[i] = b;
            self.edge_c[i] = -(a * p.0 + b * p.1) - i64::from(!top_left);
        }
        (self.x0, self.x1) = row_range([f[0].0, f[1].0, f[2].0]);
        (self.y0, self.y1) = row_range([f[0].1, f[1].1, f[2].1]);
        basis.attrs_each(n, [&mut self.attr0, &mut self.attr_dx, &mut self.attr_dy]);
        self.origin = basis.origin;
        let p = &basis.p;
        self.depth = basis.plane(p[0].depth, p[1].depth, p[2].depth);
        self.inv_w = basis.inv_w(n, perspective);
        self.n = n;
        self.perspective = perspective && n > 0;
        true
    }

    /// Appends the gradient slots of [`crate::shader::Shader::GRADIENTS`] after the first
    /// `self.n` attributes: the screen gradients of attributes `k` and `k + 1` and of `1/w`
    /// (`U_x, V_x, U_y, V_y, R_x, R_y`) as constant planes, so that the traversal's `* w`
    /// turns them into what [`crate::shader::uv_derivatives`] reads.
    #[inline(always)]
    pub fn add_gradients(&mut self, k: usize) {
        let planes = [&mut self.attr0, &mut self.attr_dx, &mut self.attr_dy];
        let r = (self.inv_w, self.perspective);
        self.n = append_gradients(planes, r, self.n, k);
    }

    /// Edge values at the centre of pixel `(x, y)`.
    #[inline]
    #[must_use]
    pub fn edges_at(&self, x: i64, y: i64) -> [i64; 3] {
        let cx = x * SUBPIXEL_ONE + HALF;
        let cy = y * SUBPIXEL_ONE + HALF;
        let (a, b, c) = (&self.edge_a, &self.edge_b, &self.edge_c);
        [
            a[0] * cx + b[0] * cy + c[0],
            a[1] * cx + b[1] * cy + c[1],
            a[2] * cx + b[2] * cy + c[2],
        ]
    }
}

/// The first `n` of `a` followed by zeros (all zeros if `a` is shorter).
#[inline(always)]
fn padded<const L: usize>(a: &[f32], n: usize) -> [f32; L] {
    let mut v = [0.0f32; L];
    if let Some(a) = a.get(..n) {
        v[..n].copy_from_slice(a);
    }
    v
}

/// The gradient slots of [`RasterTri::add_gradients`] appended after attribute `at` of the
/// planes `[attr0, attr_dx, attr_dy]`, `1/w`'s gradients taken from `inv_w` when
/// `perspective`; returns the attributes then in use (`at` when they do not fit).
#[inline(always)]
pub(crate) fn append_gradients(
    [attr0, attr_dx, attr_dy]: [&mut Attrs; 3],
    (inv_w, perspective): ([f64; 3], bool),
    at: usize,
    k: usize,
) -> usize {
    if k + 1 >= at || at + GRADIENT_SLOTS > MAX_ATTRS {
        return at;
    }
    let (rx, ry) = if perspective {
        (inv_w[1] as f32, inv_w[2] as f32)
    } else {
        (0.0, 0.0)
    };
    let g = [
        attr_dx[k],
        attr_dx[k + 1],
        attr_dy[k],
        attr_dy[k + 1],
        rx,
        ry,
    ];
    for (j, g) in g.into_iter().enumerate() {
        attr0[at + j] = g;
        attr_dx[at + j] = 0.0;
        attr_dy[at + j] = 0.0;
    }
    at + GRADIENT_SLOTS
}

/// What a triangle's planes are computed from: its vertices in the winding of the set-up
/// (interior on the positive side of every edge), their fixed-point coordinates, and the
/// basis of the gradients. [`RasterTri::set`] and [`crate::traverse::Planes::set`] both go
/// through it, so that the by-pixel pass evaluates the planes the traversal would.
pub(crate) struct PlaneBasis<'a> {
    /// The vertices, reordered.
    pub p: [ScreenPos; 3],
    /// Their attributes, reordered alike.
    pub attrs: [&'a [f32]; 3],
    /// Their fixed-point coordinates.
    pub f: [(i64, i64); 3],
    /// The first vertex in pixels: where each plane is anchored.
    pub origin: (f64, f64),
    /// The edges from the first vertex to the others, in pixels.
    d1: (f64, f64),
    d2: (f64, f64),
    /// The inverse of twice the area, in pixels.
    inv_area: f64,
}

impl<'a> PlaneBasis<'a> {
    /// The basis of the triangle `p` with vertex attributes `attrs`; `None` for no area.
    #[inline(always)]
    pub fn of(p: [ScreenPos; 3], attrs: [&'a [f32]; 3]) -> Option<PlaneBasis<'a>> {
        let area = screen_area2(&p);
        if area == 0 {
            return None;
        }
        // Interior on the positive side of every edge.
        let order = if area > 0 { [0, 1, 2] } else { [0, 2, 1] };
        let (p, attrs) = (order.map(|i| p[i]), order.map(|i| attrs[i]));
        let f = p.map(|p| (i64::from(p.fx), i64::from(p.fy)));
        // Plane gradients: A = A0 + gx (x - x0) + gy (y - y0) through the three vertices.
        let xy = f.map(|(x, y)| (x as f64 * INV_ONE, y as f64 * INV_ONE));
        Some(PlaneBasis {
            p,
            attrs,
            f,
            origin: xy[0],
            d1: (xy[1].0 - xy[0].0, xy[1].1 - xy[0].1),
            d2: (xy[2].0 - xy[0].0, xy[2].1 - xy[0].1),
            inv_area: (SUBPIXEL_ONE * SUBPIXEL_ONE) as f64 / area.abs() as f64,
        })
    }

    /// The plane through the values `a0`, `a1`, `a2` at the vertices: its value at the
    /// origin, `d/dx` and `d/dy`.
    #[inline(always)]
    pub fn plane(&self, a0: f64, a1: f64, a2: f64) -> [f64; 3] {
        plane_through((self.d1, self.d2), self.inv_area, [a0, a1, a2])
    }

    /// The planes of attributes `0..n` into `[attr0, attr_dx, attr_dy]`, in f32, one by one:
    /// for a set-up inlined into a loop that needs its registers (the traversal's, where
    /// [`PlaneBasis::attrs`] cost 16 more instructions per triangle with three attributes).
    #[inline(always)]
    pub fn attrs_each(&self, n: usize, out: [&mut Attrs; 3]) {
        self.planes_into(self.attrs, n, out);
    }

    /// The planes of attributes `0..n` into `[attr0, attr_dx, attr_dy]`, in f32, and zeros
    /// (of either sign) up to the next whole vector ([`crate::coverage::lanes`]): the same
    /// bits as [`PlaneBasis::attrs_each`] in the first `n`, computed as whole vectors.
    #[inline(always)]
    pub fn attrs(&self, n: usize, out: [&mut Attrs; 3]) {
        match n {
            0 => {}
            1..=4 => self.attr_lanes::<4>(n, out),
            5..=8 => self.attr_lanes::<8>(n, out),
            _ => self.attr_lanes::<MAX_ATTRS>(n, out),
        }
    }

    /// [`PlaneBasis::attrs`] over `L` lanes: the vertices' attributes copied into arrays of
    /// `L` first, so that the planes are computed as whole vectors rather than lane by lane.
    #[inline(always)]
    fn attr_lanes<const L: usize>(&self, n: usize, out: [&mut Attrs; 3]) {
        let n = n.min(L);
        let [a0, a1, a2] = self.attrs;
        let (a0, a1, a2) = (padded::<L>(a0, n), padded::<L>(a1, n), padded::<L>(a2, n));
        // Past `n`, the plane of zeros: zeros, some of them -0. Selecting +0 there instead
        // made LLVM write the lanes with masked stores, which AMD's cores run slowly.
        self.planes_into([&a0, &a1, &a2], L, out);
    }

    /// The planes of the values `a0[k]`, `a1[k]`, `a2[k]` at the vertices for `k < n`, into
    /// `[attr0, attr_dx, attr_dy]` in f32.
    #[inline(always)]
    fn planes_into(
        &self,
        [a0, a1, a2]: [&[f32]; 3],
        n: usize,
        [attr0, attr_dx, attr_dy]: [&mut Attrs; 3],
    ) {
        for k in 0..n {
            let [a, gx, gy] = self.plane(a0[k] as f64, a1[k] as f64, a2[k] as f64);
            attr0[k] = a as f32;
            attr_dx[k] = gx as f32;
            attr_dy[k] = gy as f32;
        }
    }

    /// The plane of `1/w`: only with `perspective` and attributes to divide, else 1.
    #[inline(always)]
    pub fn inv_w(&self, n: usize, perspective: bool) -> [f64; 3] {
        let p = &self.p;
        if perspective && n > 0 {
            self.plane(p[0].inv_w, p[1].inv_w, p[2].inv_w)
        } else {
            [1.0, 0.0, 0.0]
        }
    }
}

/// The plane through the values `a0`, `a1`, `a2` at a triangle's vertices, from the edges
/// `d1`, `d2` (pixels) from its first vertex to the other two and the inverse of twice its
/// area: its value at the first vertex, `d/dx` and `d/dy`. The one formula of every plane,
/// so that the lanes' planes ([`crate::group`]) have the bits of [`PlaneBasis::plane`]'s.
#[inline(always)]
pub(crate) fn plane_through(
    ((dx1, dy1), (dx2, dy2)): ((f64, f64), (f64, f64)),
    inv_area: f64,
    [a0, a1, a2]: [f64; 3],
) -> [f64; 3] {
    let (d1, d2) = (a1 - a0, a2 - a0);
    [
        a0,
        (d1 * dy2 - d2 * dy1) * inv_area,
        (d2 * dx1 - d1 * dx2) * inv_area,
    ]
}

#[cfg(test)]
#[path = "tests/setup_unit.rs"]
mod tests;
