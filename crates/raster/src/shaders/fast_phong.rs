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

use glam::{DVec2, DVec3, Vec3};
use phosphor_lighting::{Lanes, ShadeTerms, Vec3s, shade_split, specular_lobe};

use super::Lit;
use super::check::{FAST_PHONG_TOLERANCE, highlight_is_sampled};
use super::phong::{Phong, surface_varyings};
use super::taylor::{MAX_TAYLOR_LIGHTS, TaylorTri};
use crate::FastPhongMethod;
use crate::framebuffer::clamp_color;
use crate::shader::{
    Face, MAX_QUADRATICS, Pixels, Quadratic, ScreenCorner, ScreenTriangle, Shader, Stepped,
    Varyings, VertexLanes,
};

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
struct Lagrange {
    /// Values at vertices 0, 1, 2.
    vertex: [Vec3; 3],
    /// Values at the midpoints of edges 01, 12, 20.
    mid: [Vec3; 3],
}

impl Lagrange {
    #[inline]
    fn eval(&self, l: [f64; 3]) -> Vec3 {
        let mut acc = DVec3::ZERO;
        for i in 0..3 {
            acc += self.vertex[i].as_dvec3() * (l[i] * (2.0 * l[i] - 1.0));
        }
        acc += self.mid[0].as_dvec3() * (4.0 * l[0] * l[1]);
        acc += self.mid[1].as_dvec3() * (4.0 * l[1] * l[2]);
        acc += self.mid[2].as_dvec3() * (4.0 * l[2] * l[0]);
        acc.as_vec3()
    }

    /// Channel `ch` as a quadratic in pixels about the origin of the affine barycentrics
    /// `bary` (`l_i = c + gx u + gy v`).
    fn quadratic(&self, bary: &[[f64; 3]; 3], ch: usize) -> Quadratic {
        // The product of two affine functions, as a quadratic.
        let mul = |a: &[f64; 3], b: &[f64; 3]| {
            [
                a[0] * b[0],
                a[0] * b[1] + a[1] * b[0],
                a[0] * b[2] + a[2] * b[0],
                a[1] * b[1],
                a[1] * b[2] + a[2] * b[1],
                a[2] * b[2],
            ]
        };
        let mut q = [0.0; 6];
        let mut add = |k: f64, t: [f64; 6]| {
            for (q, t) in q.iter_mut().zip(t) {
                *q += k * t;
            }
        };
        let [vx, mx] = [self.vertex, self.mid].map(|v| v.map(|v| f64::from(v[ch])));
        for i in 0..3 {
            // l (2 l - 1) = 2 l^2 - l.
            let l = bary[i];
            let mut t = mul(&l, &l).map(|c| 2.0 * c);
            t[0] -= l[0];
            t[1] -= l[1];
            t[2] -= l[2];
            add(vx[i], t);
        }
        for (m, (i, j)) in [(0, 1), (1, 2), (2, 0)].into_iter().enumerate() {
            add(4.0 * mx[m], mul(&bary[i], &bary[j]));
        }
        Quadratic(q)
    }
}

/// A fitted triangle: constant ambient, diffuse and specular quadratics, and the affine
/// screen barycentrics `l_i = c_i + gx_i x + gy_i y` (about the pixel origin).
#[derive(Debug, Clone, Copy)]
struct Fit {
    ambient: Vec3,
    diffuse: Lagrange,
    specular: Lagrange,
    bary: [[f64; 3]; 3],
}

impl Fit {
    fn total(&self, l: [f64; 3]) -> Vec3 {
        self.ambient + self.diffuse.eval(l).max(Vec3::ZERO) + self.specular.eval(l).max(Vec3::ZERO)
    }

    /// The stepped form: diffuse in quadratics 0..3, specular in 3..6, about the origin.
    fn stepped(&self) -> Stepped<FastTri> {
        let mut s = Stepped::constant(FastTri::Fit {
            ambient: self.ambient,
        });
        for ch in 0..3 {
            s.quadratics[ch] = self.diffuse.quadratic(&self.bary, ch);
            s.quadratics[3 + ch] = self.specular.quadratic(&self.bary, ch);
        }
        s.count = 6;
        s
    }
}

/// A stepped fast-Phong triangle: which method made its quadratics, and its constants.
#[derive(Debug, Clone, Copy)]
pub enum FastTri {
    /// The six-point fit: `ambient + max(diffuse, 0) + max(specular, 0)`, diffuse in
    /// quadratics 0..3 and specular in 3..6.
    Fit {
        /// `emission + ka Ia`.
        ambient: Vec3,
    },
    /// Bishop and Weimer's expansion ([`TaylorTri`]): `ambient + max(diffuse, 0) + sum
    /// specular_j lobe(cosine_j)`, diffuse in quadratics 0..3 and each light's cosine after.
    Taylor {
        /// `emission + ka Ia`.
        ambient: Vec3,
        /// Per light, `ks W Il_spec f(d)`.
        specular: [Vec3; MAX_TAYLOR_LIGHTS],
        /// Lights with a cosine quadratic.
        lights: usize,
        /// The material's `n_s`.
        shininess: f32,
    },
}

/// The screen triangle a fit is made on: corners sorted top to bottom (by `y`, then `x`), so
/// that the fit does not depend on the mesh's vertex order.
pub(crate) struct FitTri {
    pub v: [ScreenCorner; 3],
    pub perspective: bool,
}

impl FitTri {
    pub(crate) fn new(t: &ScreenTriangle) -> FitTri {
        let mut order = [0, 1, 2];
        order.sort_by(|&a, &b| {
            let (p, q) = (&t.corners[a], &t.corners[b]);
            p.y.total_cmp(&q.y).then(p.x.total_cmp(&q.x))
        });
        FitTri {
            v: order.map(|i| t.corners[i]),
            perspective: t.perspective,
        }
    }
}

impl<const FX: u32> FastPhong<'_, FX> {
    /// Perspective-correct surface point and (unnormalized) normal at screen barycentrics `l`.
    pub(crate) fn surface(geom: &FitTri, l: [f64; 3]) -> (Vec3, Vec3) {
        let t = ScreenTriangle {
            corners: geom.v,
            perspective: geom.perspective,
        };
        let w = t.weights(l);
        let (mut p, mut n) = (DVec3::ZERO, DVec3::ZERO);
        for (i, v) in geom.v.iter().enumerate() {
            let a = &v.varyings;
            p += DVec3::new(a[0], a[1], a[2]) * w[i];
            n += DVec3::new(a[3], a[4], a[5]) * w[i];
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
    fn fit(&self, geom: &FitTri) -> Option<Stepped<FastTri>> {
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
        let quad = |f: fn(&ShadeTerms) -> Vec3| Lagrange {
            vertex: [f(&t[0]), f(&t[1]), f(&t[2])],
            mid: [f(&t[3]), f(&t[4]), f(&t[5])],
        };
        let ambient = t[0].ambient;
        // Barycentrics about the first corner: the quadratics' coefficients stay small.
        let origin = DVec2::new(geom.v[0].x, geom.v[0].y);
        let [a, b, c] = geom.v.map(|v| DVec2::new(v.x, v.y) - origin);
        let area = (b - a).perp_dot(c - a);
        if area == 0.0 || !area.is_finite() {
            return None;
        }
        // l_i(x, y) affine: l0 = area(p, b, c) / area, etc.
        let affine = |p: DVec2, q: DVec2| {
            // area2(x, p, q) = (p - x) x (q - x) = p x q - x (q.y - p.y) + y (q.x - p.x)
            [p.perp_dot(q) / area, (p.y - q.y) / area, (q.x - p.x) / area]
        };
        let fit = Fit {
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
            let err = (clamp_color(fit.total(l)) - clamp_color(exact.total())).abs();
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
        if !highlight_is_sampled::<FX>(&self.lit, &surface, seen) {
            return None;
        }
        let mut s = fit.stepped();
        s.origin = (origin.x, origin.y);
        Some(s)
    }

    fn phong(&self) -> Phong<'_, FX, false> {
        Phong {
            lit: self.lit,
            bump: None,
        }
    }
}

impl<const FX: u32> Shader for FastPhong<'_, FX> {
    const VARYINGS: usize = 6;
    const FACE: Face = Face::Stepped;
    type Stepped = FastTri;
    #[inline(always)]
    fn vertex<L: Lanes>(&self, v: &VertexLanes<L>) -> Varyings<L> {
        surface_varyings(v, false)
    }
    #[inline]
    fn min_stepped_area(&self) -> f64 {
        match self.method {
            // The fit is tried only on triangles large enough to pay for it.
            FastPhongMethod::Fit => MIN_FIT_AREA_PX,
            // The Taylor set-up is tried on every triangle.
            FastPhongMethod::Taylor => 0.0,
        }
    }
    fn stepped(&self, t: &ScreenTriangle) -> Option<Stepped<FastTri>> {
        // Sorted corners: the fit is the same whatever the mesh's vertex order.
        let geom = FitTri::new(t);
        match self.method {
            FastPhongMethod::Taylor => {
                super::taylor::build::<FX>(&self.lit, (&geom.v, geom.perspective), |l| {
                    Self::surface(&geom, l)
                })
                .map(taylor_stepped)
            }
            FastPhongMethod::Fit => self.fit(&geom),
        }
    }
    /// Triangles shaded exactly (too small to fit, or refused): `phong`.
    #[inline(always)]
    fn pixel<L: Lanes>(&self, v: &Varyings<L>) -> Vec3s<L> {
        self.phong().pixel(v)
    }
    #[inline(always)]
    fn stepped_pixel<L: Lanes>(
        &self,
        tri: &FastTri,
        q: &[L; MAX_QUADRATICS],
        _: &Varyings<L>,
        _: &Pixels<L>,
    ) -> Vec3s<L> {
        let zero = q[0].splat(0.0);
        let positive = |x: L| x.max_c(zero);
        match tri {
            FastTri::Fit { ambient } => {
                // Each term clamped on its own: a specular lobe's polynomial may dip below 0.
                let d = Vec3s::new(positive(q[0]), positive(q[1]), positive(q[2]));
                let s = Vec3s::new(positive(q[3]), positive(q[4]), positive(q[5]));
                Vec3s::broadcast(zero, *ambient) + d + s
            }
            FastTri::Taylor {
                ambient,
                specular,
                lights,
                shininess,
            } => {
                let d = Vec3s::new(positive(q[0]), positive(q[1]), positive(q[2]));
                let mut c = Vec3s::broadcast(zero, *ambient) + d;
                for (j, s) in specular.iter().enumerate().take(*lights) {
                    let cos = q[3 + j].to_lanes();
                    let lobe = zero.with_lanes(cos.map(|x| specular_lobe(x, *shininess)));
                    c = c + Vec3s::broadcast(zero, *s) * lobe;
                }
                c
            }
        }
    }
}

/// A Taylor triangle in stepped form: the diffuse channels in quadratics 0..3, each light's
/// cosine after.
fn taylor_stepped(t: TaylorTri) -> Stepped<FastTri> {
    let mut s = Stepped::constant(FastTri::Taylor {
        ambient: t.ambient,
        specular: t.specular,
        lights: t.lights,
        shininess: t.shininess,
    });
    s.origin = t.origin;
    for (ch, q) in t.diffuse.iter().enumerate() {
        s.quadratics[ch] = Quadratic(*q);
    }
    for j in 0..t.lights {
        s.quadratics[3 + j] = Quadratic(t.cosine[j]);
    }
    s.count = 3 + t.lights;
    s
}

/// Draws `d` with fast Phong shading into `frame`, specialized for its effects; a bumped,
/// textured or vertex-coloured draw is drawn with `phong` (the quadratics follow none of
/// them).
pub(crate) fn draw(frame: &mut crate::Frame, d: &crate::DrawItem) {
    if d.bump.is_some() || super::tinted::is_tinted(d) {
        return super::phong::draw(frame, d);
    }
    let lit = Lit::new(d.lights, d.material, d.effects, frame.eye());
    let method = frame.options().fast_phong;
    crate::with_fx!(d.effects, FX => frame.draw(&d.mesh, d.model, &FastPhong::<FX> { lit, method }, d.cull_backfaces));
}
