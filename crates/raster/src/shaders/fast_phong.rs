//! `fast-phong`: per triangle, the diffuse and the specular sums each become a quadratic
//! polynomial in screen x and y, evaluated along the span by forward differences (two adds
//! per channel per polynomial). Two ways to make the quadratic ([`FastPhongMethod`]): Bishop
//! and Weimer 1986's Taylor expansion (see [`super::taylor`]), or the six-point fit of this
//! module (the default). For the fit, as in Barrera, Hast & Bengtsson 2006 ("Fast near
//! Phong-quality software shading"), the quadratic interpolates the exact terms (`shade_split`, perspective-correct point and
//! normal) at the three vertices and the three edge midpoints. The fit is then checked
//! against exact shading at the centroid and at the centroids of the three corner
//! sub-triangles; when the largest error of the clamped total exceeds
//! [`FAST_PHONG_TOLERANCE`], the triangle falls back to `phong` (counted in
//! `RenderStats::fallbacks`), so a large triangle with spread normals never shows the
//! polynomial's blow-up. Ten samples cannot see a highlight narrower than the triangle that
//! peaks between them, so the fit is also refused when
//! [`phosphor_lighting::specular_upper_bound`] says the specular could rise more than the
//! tolerance above the largest sampled value.

use glam::{DVec2, Vec3};
use phosphor_lighting::{ShadeTerms, lobe_sharpness, shade_split, specular_upper_bound};

use super::phong::Phong;
use super::taylor::{TaylorKernel, TaylorTri};
use super::{Lit, Mode, Passes, TriInput, TriVertices, VertexIn, surface_attrs};
use crate::FastPhongMethod;
use crate::clip::Attrs;
use crate::framebuffer::clamp_color;
use crate::scanline::{BandTarget, Kernel, traverse};
use crate::setup::{RasterTri, ScreenPos, ScreenVertex, screen_area2};
use phosphor_math::fixed::SUBPIXEL_ONE;

/// Largest error (per channel, on the `[0, 1]` intensity) the fit may show at the check
/// points before the triangle falls back to `phong`: one 8-bit code.
pub const FAST_PHONG_TOLERANCE: f32 = 1.0 / 255.0;

/// Lobes up to this [`phosphor_lighting::lobe_sharpness`] (`n_s` times the squared
/// angular extent of the triangle) are at least as wide as the triangle: they vary smoothly
/// across the ten samples, whose checks see any misfit. Sharper ones are checked against the
/// bound.
pub const MAX_SMOOTH_LOBE_SHARPNESS: f32 = 1.0;

/// Triangles covering less screen area than this (in pixels) are shaded per pixel with `phong`
/// without trying a fit: the fit evaluates the exact model at ten points plus its bound checks
/// (about 12 800 instructions on S1), while `phong`'s by-pixel pass shades four pixels at a
/// time for about 250 instructions a pixel, and only the visible part of a triangle is shaded.
/// Measured with callgrind (one thread, instructions for two frames, `fast-phong` with this
/// limit at 32 / 64 / 96 / 128 / 192 / 256 pixels): the S1 sphere at 1920x1080 647 / 592 / 551
/// / 497 / 513 / 538 M (never fitting: 686 M; `phong` 671 M), the S1 bunny 621 / 587 / - / 585
/// M, the default scene at 1280x720 488 M at 32 and 463 M at 128. Exact Phong is the more
/// accurate of the two, so this only trades speed, and it is not counted as a fallback.
pub const MIN_FIT_AREA_PX: f64 = 128.0;

/// Whether a triangle's specular highlight cannot peak between the points a method checked:
/// its lobes are smooth over the triangle, or their upper bound stays within
/// [`FAST_PHONG_TOLERANCE`] of `seen`, the largest specular the checks saw. `nodes` are the
/// surface points and normals at the corners (0, 1, 2) and at the midpoints of edges 01, 12,
/// 20 (3, 4, 5). The bound is loose on a large triangle, so where it fails it is retried on
/// the four half-size triangles of the nodes (spreads halve).
pub(crate) fn highlight_is_sampled<const FX: u32>(
    lit: &Lit,
    nodes: &[(Vec3, Vec3); 6],
    seen: Vec3,
) -> bool {
    let (set, mat, eye) = (lit.set, &lit.mat, lit.eye);
    let fits = |corners: [usize; 3]| {
        let p = corners.map(|i| nodes[i].0);
        let n = corners.map(|i| nodes[i].1);
        lobe_sharpness::<FX>(set, mat, p, n, eye) <= MAX_SMOOTH_LOBE_SHARPNESS
            || (specular_upper_bound::<FX>(set, mat, p, n, eye) - seen).max_element()
                <= FAST_PHONG_TOLERANCE
    };
    fits([0, 1, 2])
        || [[0, 3, 5], [3, 1, 4], [5, 4, 2], [3, 4, 5]]
            .into_iter()
            .all(fits)
}

/// The fast Phong mode for effect set `FX`.
#[derive(Debug, Clone, Copy)]
pub struct FastPhong<'a, const FX: u32> {
    /// Lights, material, viewer.
    pub lit: Lit<'a>,
    /// Taylor expansion or six-point fit.
    pub method: FastPhongMethod,
}

/// A quadratic in the screen barycentrics: values at the vertices and the edge midpoints
/// (the P2 Lagrange form), one per term.
#[derive(Debug, Clone, Copy)]
pub struct Quadratic {
    /// Values at vertices 0, 1, 2.
    vertex: [Vec3; 3],
    /// Values at the midpoints of edges 01, 12, 20.
    mid: [Vec3; 3],
}

impl Quadratic {
    #[inline]
    fn eval(&self, l: [f64; 3]) -> Vec3 {
        let mut acc = glam::DVec3::ZERO;
        for i in 0..3 {
            acc += self.vertex[i].as_dvec3() * (l[i] * (2.0 * l[i] - 1.0));
        }
        acc += self.mid[0].as_dvec3() * (4.0 * l[0] * l[1]);
        acc += self.mid[1].as_dvec3() * (4.0 * l[1] * l[2]);
        acc += self.mid[2].as_dvec3() * (4.0 * l[2] * l[0]);
        acc.as_vec3()
    }
}

/// A fitted triangle: constant ambient, diffuse and specular quadratics, and the affine
/// screen barycentrics `l_i = c_i + gx_i x + gy_i y`.
#[derive(Debug, Clone, Copy)]
pub struct PolyTri {
    ambient: Vec3,
    diffuse: Quadratic,
    specular: Quadratic,
    bary: [[f64; 3]; 3],
}

impl PolyTri {
    fn bary_at(&self, x: f64, y: f64) -> [f64; 3] {
        self.bary.map(|[c, gx, gy]| c + gx * x + gy * y)
    }

    fn total(&self, l: [f64; 3]) -> Vec3 {
        self.ambient + self.diffuse.eval(l).max(Vec3::ZERO) + self.specular.eval(l).max(Vec3::ZERO)
    }
}

/// Fast Phong's per-triangle choice. A fit is boxed: every accepted triangle gets one of these
/// (72k per S1 frame, most of them too small to fit), and an inline fit made each 240 bytes,
/// 17 MB a frame to write and read back; a box is allocated only for a triangle of at least
/// [`MIN_FIT_AREA_PX`] whose fit holds, and each such triangle has as many pixels to pay for it.
#[derive(Debug, Clone)]
pub enum FastTri {
    /// The polynomial fits: forward differences.
    Poly(Box<PolyTri>),
    /// The Taylor expansion holds: forward differences.
    Taylor(Box<TaylorTri>),
    /// It does not: exact per-pixel Phong for this triangle.
    Phong,
    /// Too small to be worth a fit ([`MIN_FIT_AREA_PX`]): exact per-pixel Phong.
    Small,
}

/// Forward-difference state of one span: value, first and second difference per polynomial.
#[derive(Debug, Clone, Copy)]
pub struct FastSpan {
    ambient: Vec3,
    d: [Vec3; 3],
    s: [Vec3; 3],
}

/// The per-pixel kernel of a fitted triangle.
#[derive(Debug, Clone, Copy)]
pub struct PolyKernel;

impl Kernel for PolyKernel {
    const ATTRS: usize = 0;
    type Tri = PolyTri;
    type Span = FastSpan;
    fn span(&self, t: &PolyTri, x: f32, y: f32) -> FastSpan {
        let (x, y) = (x as f64, y as f64);
        let l = [
            t.bary_at(x, y),
            t.bary_at(x + 1.0, y),
            t.bary_at(x + 2.0, y),
        ];
        let diffs = |q: &Quadratic| {
            let (a, b, c) = (q.eval(l[0]), q.eval(l[1]), q.eval(l[2]));
            [a, b - a, c - 2.0 * b + a]
        };
        FastSpan {
            ambient: t.ambient,
            d: diffs(&t.diffuse),
            s: diffs(&t.specular),
        }
    }
    #[inline]
    fn shade(&self, _: &PolyTri, s: &FastSpan, _: &Attrs, _: u32, _: u32) -> Vec3 {
        // Each term clamped on its own: a specular lobe's polynomial may dip below zero.
        s.ambient + s.d[0].max(Vec3::ZERO) + s.s[0].max(Vec3::ZERO)
    }
    #[inline]
    fn step(s: &mut FastSpan) {
        s.d[0] += s.d[1];
        s.d[1] += s.d[2];
        s.s[0] += s.s[1];
        s.s[1] += s.s[2];
    }
}

/// The screen triangle a fit is made on: vertices sorted top to bottom (by `y`, then `x`), so
/// that the fit does not depend on the mesh's vertex order.
struct FitTri {
    v: [ScreenVertex; 3],
    perspective: bool,
}

impl FitTri {
    fn new(screen: [&ScreenVertex; 3], perspective: bool) -> FitTri {
        let mut order = [0, 1, 2];
        order.sort_by_key(|&i| (screen[i].fy, screen[i].fx));
        FitTri {
            v: order.map(|i| *screen[i]),
            perspective,
        }
    }
}

impl<const FX: u32> FastPhong<'_, FX> {
    /// Perspective-correct surface point and (unnormalized) normal at screen barycentrics `l`.
    fn surface(geom: &FitTri, l: [f64; 3]) -> (Vec3, Vec3) {
        let q: [f64; 3] = std::array::from_fn(|i| {
            if geom.perspective {
                l[i] * geom.v[i].inv_w
            } else {
                l[i]
            }
        });
        let s = q[0] + q[1] + q[2];
        let w = if s.abs() > 1e-300 {
            q.map(|x| x / s)
        } else {
            l
        };
        let mut p = glam::DVec3::ZERO;
        let mut n = glam::DVec3::ZERO;
        for (i, v) in geom.v.iter().enumerate() {
            // Stored attributes are divided by w when perspective-correct: undo.
            let scale = w[i] * if geom.perspective { 1.0 / v.inv_w } else { 1.0 };
            p += glam::DVec3::new(v.attrs[0] as f64, v.attrs[1] as f64, v.attrs[2] as f64) * scale;
            n += glam::DVec3::new(v.attrs[3] as f64, v.attrs[4] as f64, v.attrs[5] as f64) * scale;
        }
        (p.as_vec3(), n.as_vec3())
    }

    /// Exact terms at surface point `p` with normal `n`.
    fn shade(&self, p: Vec3, n: Vec3) -> ShadeTerms {
        shade_split::<FX>(self.lit.set, &self.lit.mat, p, n, self.lit.eye)
    }

    /// Exact terms at screen barycentrics `l` (perspective-correct point and normal).
    fn exact(&self, geom: &FitTri, l: [f64; 3]) -> ShadeTerms {
        let (p, n) = Self::surface(geom, l);
        self.shade(p, n)
    }

    /// Fits the quadratics, or `None` when the check points show more than the tolerance.
    fn fit(&self, geom: &FitTri) -> Option<PolyTri> {
        let third = 1.0 / 3.0;
        let nodes = [
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
            [0.0, 0.0, 1.0],
            [0.5, 0.5, 0.0],
            [0.0, 0.5, 0.5],
            [0.5, 0.0, 0.5],
        ];
        let surface = nodes.map(|l| Self::surface(geom, l));
        let t = surface.map(|(p, n)| self.shade(p, n));
        let quad = |f: fn(&ShadeTerms) -> Vec3| Quadratic {
            vertex: [f(&t[0]), f(&t[1]), f(&t[2])],
            mid: [f(&t[3]), f(&t[4]), f(&t[5])],
        };
        let ambient = t[0].ambient;
        let [a, b, c] = geom.v.map(|v| DVec2::new(v.x, v.y));
        let area = (b - a).perp_dot(c - a);
        if area == 0.0 || !area.is_finite() {
            return None;
        }
        // l_i(x, y) affine: l0 = area(p, b, c) / area, etc.
        let affine = |p: DVec2, q: DVec2| {
            // area2(x, p, q) = (p - x) x (q - x) = p x q - x (q.y - p.y) + y (q.x - p.x)
            [p.perp_dot(q) / area, (p.y - q.y) / area, (q.x - p.x) / area]
        };
        let poly = PolyTri {
            ambient,
            diffuse: quad(|t| t.diffuse),
            specular: quad(|t| t.specular),
            bary: [affine(b, c), affine(c, a), affine(a, b)],
        };
        let checks = [
            [third, third, third],
            [2.0 * third, 1.0 / 6.0, 1.0 / 6.0],
            [1.0 / 6.0, 2.0 * third, 1.0 / 6.0],
            [1.0 / 6.0, 1.0 / 6.0, 2.0 * third],
        ];
        let mut seen = t.iter().fold(Vec3::ZERO, |m, t| m.max(t.specular));
        for l in checks {
            let exact = self.exact(geom, l);
            let err = (clamp_color(poly.total(l)) - clamp_color(exact.total())).abs();
            let worst = err.max_element();
            if worst.is_nan() || worst > FAST_PHONG_TOLERANCE {
                return None;
            }
            seen = seen.max(exact.specular);
        }
        // A highlight narrower than the triangle can peak between all ten samples, where the
        // fit shows nothing: refuse when such a lobe (sharpness above the limit) could rise
        // above what the samples saw. The bound is loose on a large triangle, so where it
        // fails it is retried on the four half-size triangles of the nodes (spreads halve).
        highlight_is_sampled::<FX>(&self.lit, &surface, seen).then_some(poly)
    }

    fn phong(&self) -> Phong<'_, FX, false> {
        Phong {
            lit: self.lit,
            bump: None,
        }
    }
}

impl<const FX: u32> Mode for FastPhong<'_, FX> {
    const ATTRS: usize = 6;
    type Tri = FastTri;
    const PASSES: Passes = Passes::ByPixel;
    fn vertex(&self, v: &VertexIn) -> Attrs {
        surface_attrs(v)
    }
    // With the fit only triangles of MIN_FIT_AREA_PX or more get here: a few hundred on S1.
    const INPUT: TriInput = TriInput::ScreenPerTriangle;
    #[inline]
    fn triangle_from_positions(&self, p: &[ScreenPos; 3]) -> Option<FastTri> {
        if self.method == FastPhongMethod::Taylor {
            // The Taylor set-up is tried on every triangle.
            return None;
        }
        // The area first: most triangles of a dense mesh stop here, before their vertices
        // are fetched. Twice the area in 1/256 pixel units, exact in integers.
        let area2 = screen_area2(p).unsigned_abs() as f64;
        (area2 * 0.5 < MIN_FIT_AREA_PX * (SUBPIXEL_ONE * SUBPIXEL_ONE) as f64)
            .then_some(FastTri::Small)
    }
    fn triangle(&self, v: TriVertices<'_>, perspective: bool) -> FastTri {
        // The renderer hands the screen vertices (INPUT); without them, shade exactly.
        let TriVertices::Screen(screen) = v else {
            return FastTri::Phong;
        };
        if self.method == FastPhongMethod::Taylor {
            let geom = FitTri::new(screen, perspective);
            return match super::taylor::build::<FX>(&self.lit, &geom.v, |l| Self::surface(&geom, l))
            {
                Some(t) => FastTri::Taylor(Box::new(t)),
                None => FastTri::Phong,
            };
        }
        // The same test as `triangle_from_positions`, for clipped triangles.
        let [a, b, c] = screen.map(|v| DVec2::new(v.x, v.y));
        if (b - a).perp_dot(c - a).abs() * 0.5 < MIN_FIT_AREA_PX {
            return FastTri::Small;
        }
        // Sorted corners: the fit is the same whatever the mesh's vertex order.
        match self.fit(&FitTri::new(screen, perspective)) {
            Some(p) => FastTri::Poly(Box::new(p)),
            None => FastTri::Phong,
        }
    }
    fn draw(&self, t: &RasterTri, tri: &FastTri, target: &mut BandTarget) -> u64 {
        match tri {
            FastTri::Poly(p) => traverse(t, &PolyKernel, &**p, target),
            FastTri::Taylor(p) => traverse(t, &TaylorKernel, &**p, target),
            FastTri::Phong | FastTri::Small => traverse(t, &self.phong(), &(), target),
        }
    }
    fn finish(&self, target: &mut BandTarget) {
        target.pending.flush(&self.phong(), &(), target.color);
    }
    // Triangles shaded exactly (too small to fit, or refused) take phong's by-pixel pass
    // (PASSES); only fitted ones are traversed again, to step their polynomials along the
    // spans.
    #[inline]
    fn shade4(&self, attrs: &[Attrs; 4], count: usize) -> [Vec3; 4] {
        self.phong().shade4(attrs, count)
    }
    fn by_pixel(tri: &FastTri) -> bool {
        !matches!(tri, FastTri::Poly(_) | FastTri::Taylor(_))
    }
    fn is_fallback(tri: &FastTri) -> bool {
        matches!(tri, FastTri::Phong)
    }
}
