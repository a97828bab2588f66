//! `fast-phong` by Bishop and Weimer 1986's Taylor expansion ([`crate::FastPhongMethod::Taylor`]).
//!
//! Over a screen triangle the interpolated normal is affine, `N(x, y) = A x + B y + C` (with
//! perspective, `N/w` is affine and has the same direction), so one light's diffuse term is
//!
//! `(L.N)/|N| = (ax + by + c) / (dx^2 + exy + fy^2 + gx + hy + i)^(1/2)`
//!
//! with `a, b, c = L.A, L.B, L.C` and `d, e, f, g, h, i = A.A, 2A.B, B.B, 2A.C, 2B.C, C.C`. With
//! `x, y` measured from the triangle's centroid, `(1 + t)^(-1/2)` of the denominator is expanded
//! to second degree (`1 - t/2 + 3t^2/8`) and multiplied out, giving
//! `T5 x^2 + T4 xy + T3 y^2 + T2 x + T1 y + T0` ([`taylor2`]). The lights' diffuse terms add
//! up to one such quadratic per colour channel (their `L` weighted by `kd Il f(d)`). The
//! specular term is expanded the same way per light, as Bishop and Weimer extend it: Blinn's
//! `N.H/|N|` directly, Phong's `V.R = 2 (N.L)(N.V)/|N|^2 - L.V` as the product of two such
//! expansions truncated to second degree; the quadratic is raised to the shininess per pixel.
//!
//! The light directions, the attenuated intensities, the spot factors, `V` (hence `H`) and the
//! Fresnel factor are taken at the centroid: exact for directional lights and a distant
//! viewer, Bishop and Weimer's setting. Every triangle is then checked against the exact model
//! at its corners, its edge midpoints, its centroid and the centroids of its corner
//! sub-triangles, and refused (exact `phong` for that triangle, counted in
//! `RenderStats::fallbacks`) when the clamped total is off by more than
//! [`crate::FAST_PHONG_TOLERANCE`] anywhere, when a light's `N.L` changes sign inside it (the
//! diffuse clamp is not a polynomial), when more than [`MAX_TAYLOR_LIGHTS`] lights shine on it,
//! or when a highlight narrower than the triangle could hide between the checks (the same
//! bound as the six-point fit). Along a span the quadratics are stepped by forward differences
//! in `f64` (two adds per polynomial per pixel); at each span start they are evaluated
//! directly, so nothing accumulates from one scan line to the next.

use glam::{DVec2, DVec3, Vec3};
use phosphor_lighting::attenuation::factor_from_coefficients;
use phosphor_lighting::lightset::spot_cone;
use phosphor_lighting::{
    Effects, Material, PreparedPoint, SpecularModel, shade_split, specular_lobe,
};

use super::Lit;
use super::check::{FAST_PHONG_TOLERANCE, highlight_is_sampled};
use crate::framebuffer::clamp_color;
use crate::shader::ScreenCorner;

/// The most lights with a specular polynomial of their own on one triangle; a triangle lit by
/// more falls back to `phong` (each light costs one power per pixel, and the triangle data
/// holds their polynomials inline).
pub const MAX_TAYLOR_LIGHTS: usize = 4;

/// A quadratic in local `(x, y)`: coefficients `[T0, T2 (x), T1 (y), T5 (x^2), T4 (xy),
/// T3 (y^2)]`.
pub type Quad = [f64; 6];

/// The second-degree Taylor expansion about `(0, 0)` of
/// `(ax + by + c) / (dx^2 + exy + fy^2 + gx + hy + i)^(1/2)` (Bishop and Weimer 1986), as
/// `[T0, T2, T1, T5, T4, T3]`; `None` when `i <= 0` or a coefficient is not finite.
#[must_use]
pub fn taylor2([a, b, c]: [f64; 3], [d, e, f, g, h, i]: [f64; 6]) -> Option<Quad> {
    if i.is_nan() || i <= 0.0 {
        return None;
    }
    let k = i.sqrt().recip();
    // (1 + t)^(-1/2) ~ 1 - t/2 + 3 t^2 / 8, t = (g x + h y + d x^2 + e xy + f y^2) / i.
    let (px, py) = (-g / (2.0 * i), -h / (2.0 * i));
    let i2 = i * i;
    let pxx = -d / (2.0 * i) + 3.0 * g * g / (8.0 * i2);
    let pxy = -e / (2.0 * i) + 3.0 * g * h / (4.0 * i2);
    let pyy = -f / (2.0 * i) + 3.0 * h * h / (8.0 * i2);
    let t = [
        k * c,
        k * (a + c * px),
        k * (b + c * py),
        k * (a * px + c * pxx),
        k * (a * py + b * px + c * pxy),
        k * (b * py + c * pyy),
    ];
    t.iter().all(|x| x.is_finite()).then_some(t)
}

/// `p q` truncated to second degree.
fn product2(p: &Quad, q: &Quad) -> Quad {
    [
        p[0] * q[0],
        p[0] * q[1] + p[1] * q[0],
        p[0] * q[2] + p[2] * q[0],
        p[0] * q[3] + p[1] * q[1] + p[3] * q[0],
        p[0] * q[4] + p[1] * q[2] + p[2] * q[1] + p[4] * q[0],
        p[0] * q[5] + p[2] * q[2] + p[5] * q[0],
    ]
}

/// `q` at local `(x, y)`.
#[inline]
#[must_use]
pub fn eval(q: &Quad, x: f64, y: f64) -> f64 {
    q[0] + x * (q[1] + q[3] * x + q[4] * y) + y * (q[2] + q[5] * y)
}

/// A triangle whose shading is the Taylor quadratics.
#[derive(Debug, Clone, Copy)]
pub struct TaylorTri {
    /// The expansion point (the centroid) in pixels.
    pub origin: (f64, f64),
    /// `emission + ka Ia`.
    pub ambient: Vec3,
    /// The diffuse sum, one quadratic per channel.
    pub diffuse: [Quad; 3],
    /// Per light, the quadratic of its specular cosine.
    pub cosine: [Quad; MAX_TAYLOR_LIGHTS],
    /// Per light, `ks W Il_spec f(d)` (zero past `lights`).
    pub specular: [Vec3; MAX_TAYLOR_LIGHTS],
    /// Lights with a specular polynomial.
    pub lights: usize,
    /// The material's `n_s`.
    pub shininess: f32,
}

impl TaylorTri {
    /// The colour (unclamped) at pixel position `(x, y)`, by direct evaluation.
    #[must_use]
    pub fn total_at(&self, x: f64, y: f64) -> Vec3 {
        let (u, v) = (x - self.origin.0, y - self.origin.1);
        let d = DVec3::from_array(self.diffuse.map(|q| eval(&q, u, v)));
        let mut c = self.ambient + d.max(DVec3::ZERO).as_vec3();
        for j in 0..self.lights {
            c += self.specular[j]
                * specular_lobe(eval(&self.cosine[j], u, v) as f32, self.shininess);
        }
        c
    }
}

/// Screen barycentric nodes of the checks: corners, edge midpoints, centroid and the centroids
/// of the corner sub-triangles.
const CHECKS: [[f64; 3]; 10] = {
    let (t, s) = (1.0 / 3.0, 1.0 / 6.0);
    [
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
        [0.5, 0.5, 0.0],
        [0.0, 0.5, 0.5],
        [0.5, 0.0, 0.5],
        [t, t, t],
        [2.0 * t, s, s],
        [s, 2.0 * t, s],
        [s, s, 2.0 * t],
    ]
};

/// One light as the expansion sees it: direction and attenuated intensities at the centroid.
struct FrozenLight {
    to_light: DVec3,
    il: Vec3,
    il_specular: Vec3,
}

fn frozen_lights<const FX: u32>(lit: &Lit, p: Vec3, n: Vec3) -> Vec<FrozenLight> {
    let has = |e: Effects| FX & e.bits() != 0;
    let mut out: Vec<FrozenLight> = lit
        .set
        .directional()
        .iter()
        .map(|l| FrozenLight {
            to_light: l.to_light.as_dvec3(),
            il: l.il,
            il_specular: l.il_specular,
        })
        .collect();
    let towards = |light: &PreparedPoint| {
        let delta = light.position - p;
        let d = delta.length();
        let l = phosphor_math::safe_normalize(delta, n);
        let f = if has(Effects::ATTENUATION) {
            factor_from_coefficients(light.attenuation, d)
        } else {
            1.0
        };
        (l, f)
    };
    for light in lit.set.points() {
        let (l, f) = towards(light);
        out.push(FrozenLight {
            to_light: l.as_dvec3(),
            il: light.il * f,
            il_specular: light.il_specular * f,
        });
    }
    if has(Effects::SPOT) {
        for spot in lit.set.spots() {
            let (l, f) = towards(&spot.point);
            let f = f * spot_cone(-l.dot(spot.axis), spot.cos_outer, spot.inv_cos_width);
            out.push(FrozenLight {
                to_light: l.as_dvec3(),
                il: spot.point.il * f,
                il_specular: spot.point.il_specular * f,
            });
        }
    }
    if has(Effects::DISTRIBUTED) {
        for light in lit.set.distributed_samples() {
            let (l, f) = towards(light);
            out.push(FrozenLight {
                to_light: l.as_dvec3(),
                il: light.il * f,
                il_specular: light.il_specular * f,
            });
        }
    }
    out
}

/// The plane `N(x, y) = A x + B y + C` through the vertex normals `n` at screen points `xy`,
/// with `(x, y)` measured from the triangle's centroid (so `C` is the mean of the normals),
/// `area` the parallelogram's signed area (non-zero): Bishop and Weimer's `N = Ax + By + C`.
fn normal_plane(xy: [DVec2; 3], n: [DVec3; 3], area: f64) -> [DVec3; 3] {
    let (d1, d2) = (xy[1] - xy[0], xy[2] - xy[0]);
    let (e1, e2) = (n[1] - n[0], n[2] - n[0]);
    [
        (e1 * d2.y - e2 * d1.y) / area,
        (e2 * d1.x - e1 * d2.x) / area,
        (n[0] + n[1] + n[2]) / 3.0,
    ]
}

/// Builds the Taylor quadratics of the screen triangle `v` (attributes: world position 0..3,
/// normal 3..6, divided by `w` when `perspective`), or `None` when it must fall back to
/// `phong` (see the module docs). `exact` gives the model's terms at screen barycentrics and
/// `surface` the perspective-correct point and normal there.
pub(crate) fn build<const FX: u32>(
    lit: &Lit,
    (v, perspective): (&[ScreenCorner; 3], bool),
    surface: impl Fn([f64; 3]) -> (Vec3, Vec3),
) -> Option<TaylorTri> {
    let xy = v.map(|v| DVec2::new(v.x, v.y));
    let area = (xy[1] - xy[0]).perp_dot(xy[2] - xy[0]);
    if area == 0.0 || !area.is_finite() {
        return None;
    }
    let centroid = (xy[0] + xy[1] + xy[2]) / 3.0;
    // N(x, y) = A x + B y + C about the centroid, from the vertices' (N/w or N).
    // N/w is affine in screen space with perspective (and has N's direction).
    let nv = v.map(|v| {
        let a = &v.varyings;
        DVec3::new(a[3], a[4], a[5]) * if perspective { v.rhw } else { 1.0 }
    });
    let [a_vec, b_vec, c_vec] = normal_plane(xy, nv, area);
    let denominator = [
        a_vec.dot(a_vec),
        2.0 * a_vec.dot(b_vec),
        b_vec.dot(b_vec),
        2.0 * a_vec.dot(c_vec),
        2.0 * b_vec.dot(c_vec),
        c_vec.dot(c_vec),
    ];
    let expand = |l: DVec3| taylor2([l.dot(a_vec), l.dot(b_vec), l.dot(c_vec)], denominator);
    let third = 1.0 / 3.0;
    let (p_c, n_c) = surface([third, third, third]);
    let n_unit = n_c.normalize_or_zero();
    if n_unit == Vec3::ZERO {
        return None;
    }
    let mat: &Material = &lit.mat;
    let lights = frozen_lights::<FX>(lit, p_c, n_unit);
    let view = phosphor_math::safe_normalize(lit.eye - p_c, n_unit).as_dvec3();
    let local = xy.map(|p| p - centroid);
    let mut diffuse_dir = [DVec3::ZERO; 3];
    let mut cosine = [[0.0; 6]; MAX_TAYLOR_LIGHTS];
    let mut specular = [Vec3::ZERO; MAX_TAYLOR_LIGHTS];
    let mut count = 0;
    let specular_on = FX & Effects::SPECULAR.bits() != 0 && mat.ks != Vec3::ZERO;
    for light in &lights {
        if light.il == Vec3::ZERO && light.il_specular == Vec3::ZERO {
            continue;
        }
        // N.L is affine: its sign at the corners is its sign everywhere.
        let n_dot_l = local.map(|q| light.to_light.dot(a_vec * q.x + b_vec * q.y + c_vec));
        if n_dot_l.iter().all(|&d| d <= 0.0) {
            continue;
        }
        if n_dot_l.iter().any(|&d| d <= 0.0) {
            return None;
        }
        let kd_il = (mat.kd * light.il).as_dvec3();
        for ch in 0..3 {
            diffuse_dir[ch] += light.to_light * kd_il[ch];
        }
        if specular_on {
            if count == MAX_TAYLOR_LIGHTS {
                return None;
            }
            let lobe_cos = match mat.specular {
                SpecularModel::Blinn => {
                    let h = (light.to_light + view).try_normalize()?;
                    expand(h)?
                }
                SpecularModel::Phong => {
                    // V.R = 2 (N.L)(N.V)/|N|^2 - L.V.
                    let mut r = product2(&expand(light.to_light)?, &expand(view)?);
                    for c in &mut r {
                        *c *= 2.0;
                    }
                    r[0] -= light.to_light.dot(view);
                    r
                }
            };
            let w = if FX & Effects::FRESNEL.bits() != 0 {
                mat.fresnel.w(n_unit.dot(light.to_light.as_vec3()))
            } else {
                1.0
            };
            cosine[count] = lobe_cos;
            specular[count] = (mat.ks * w) * light.il_specular;
            count += 1;
        }
    }
    let mut diffuse = [[0.0; 6]; 3];
    for ch in 0..3 {
        if diffuse_dir[ch] != DVec3::ZERO {
            diffuse[ch] = expand(diffuse_dir[ch])?;
        }
    }
    let exact0 = shade_split::<FX>(lit.set, mat, p_c, n_c, lit.eye);
    let tri = TaylorTri {
        origin: (centroid.x, centroid.y),
        ambient: exact0.ambient,
        diffuse,
        cosine,
        specular,
        lights: count,
        shininess: mat.shininess,
    };
    // The remainder, bounded at the check points.
    let mut seen = Vec3::ZERO;
    let mut nodes = [(Vec3::ZERO, Vec3::ZERO); 6];
    for (k, l) in CHECKS.into_iter().enumerate() {
        let (p, n) = surface(l);
        if k < 6 {
            nodes[k] = (p, n);
        }
        let exact = shade_split::<FX>(lit.set, mat, p, n, lit.eye);
        let at = xy[0] * l[0] + xy[1] * l[1] + xy[2] * l[2];
        let err = (clamp_color(tri.total_at(at.x, at.y)) - clamp_color(exact.total())).abs();
        let worst = err.max_element();
        if worst.is_nan() || worst > FAST_PHONG_TOLERANCE {
            return None;
        }
        seen = seen.max(exact.specular);
    }
    // A highlight narrower than the triangle can peak between the checks: the same refusal as
    // the six-point fit's (retried on the four half-size triangles when the bound is loose).
    if specular_on && !highlight_is_sampled::<FX>(lit, &nodes, seen) {
        return None;
    }
    Some(tri)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::shader::Quadratic;

    /// The exact function the expansion approximates.
    fn exact(abc: [f64; 3], den: [f64; 6], x: f64, y: f64) -> f64 {
        let [a, b, c] = abc;
        let [d, e, f, g, h, i] = den;
        (a * x + b * y + c) / (d * x * x + e * x * y + f * y * y + g * x + h * y + i).sqrt()
    }

    /// `(L.N)/|N|` coefficients for `N = A x + B y + C`.
    fn coefficients(l: DVec3, a: DVec3, b: DVec3, c: DVec3) -> ([f64; 3], [f64; 6]) {
        (
            [l.dot(a), l.dot(b), l.dot(c)],
            [
                a.dot(a),
                2.0 * a.dot(b),
                b.dot(b),
                2.0 * a.dot(c),
                2.0 * b.dot(c),
                c.dot(c),
            ],
        )
    }

    #[test]
    fn taylor_expansion_is_exact_to_second_degree() {
        let l = DVec3::new(0.3, 0.4, 0.87).normalize();
        let (abc, den) = coefficients(
            l,
            DVec3::new(0.02, -0.01, 0.005),
            DVec3::new(-0.004, 0.03, 0.01),
            DVec3::new(0.1, 0.2, 0.97),
        );
        let q = taylor2(abc, den).unwrap();
        // The remainder is third order: halving the distance divides it by about 8.
        let remainder = |h: f64| (eval(&q, h, 0.7 * h) - exact(abc, den, h, 0.7 * h)).abs();
        let (r1, r2) = (remainder(1.0), remainder(0.5));
        assert!(r1 > 0.0 && r2 > 0.0);
        let ratio = r1 / r2;
        assert!((6.0..=10.0).contains(&ratio), "ratio {ratio}");
        assert!((eval(&q, 0.0, 0.0) - exact(abc, den, 0.0, 0.0)).abs() < 1e-15);
    }

    #[test]
    fn forward_differences_equal_direct_evaluation_over_4096_steps() {
        // A triangle about 4096 pixels wide whose normals turn by about 0.2 across it.
        let l = DVec3::new(0.3, 0.4, 0.87).normalize();
        let (a, b, c) = (
            DVec3::new(4e-5, -1e-5, 0.0),
            DVec3::new(-1e-5, 3e-5, 0.0),
            DVec3::new(0.1, 0.2, 0.97),
        );
        let (abc, den) = coefficients(l, a, b, c);
        let q = taylor2(abc, den).unwrap();
        let h = DVec3::new(0.2, 0.3, 1.0).normalize();
        let (habc, hden) = coefficients(h, a, b, c);
        let cosine = taylor2(habc, hden).unwrap();
        let origin = (2048.0, 600.0);
        let (x0, y) = (0.5, 123.5);
        let (u0, v) = (x0 - origin.0, y - origin.1);
        let (mut d, mut s) = (
            Quadratic(q).differences(u0, v),
            Quadratic(cosine).differences(u0, v),
        );
        let mut worst = 0.0f64;
        for k in 0..4096 {
            let u = u0 + f64::from(k);
            worst = worst.max((d[0] - eval(&q, u, v)).abs());
            worst = worst.max((s[0] - eval(&cosine, u, v)).abs());
            for f in [&mut d, &mut s] {
                f[0] += f[1];
                f[1] += f[2];
            }
        }
        assert!(worst <= 1e-5, "forward differences drift {worst}");
    }

    #[test]
    fn normal_plane_passes_through_the_three_vertex_normals() {
        // A long, thin, clockwise triangle far from the origin, normals in every direction.
        let xy = [
            DVec2::new(1500.25, 20.5),
            DVec2::new(1.75, 31.0),
            DVec2::new(1499.0, 23.125),
        ];
        let n = [
            DVec3::new(0.0, 0.0, 1.0),
            DVec3::new(0.6, -0.8, 0.0),
            DVec3::new(-0.3, 0.1, 2.5),
        ];
        let area = (xy[1] - xy[0]).perp_dot(xy[2] - xy[0]);
        let centroid = (xy[0] + xy[1] + xy[2]) / 3.0;
        let [a, b, c] = normal_plane(xy, n, area);
        let at = |p: DVec2| a * (p.x - centroid.x) + b * (p.y - centroid.y) + c;
        for k in 0..3 {
            let miss = (at(xy[k]) - n[k]).abs().max_element();
            assert!(miss < 1e-12, "vertex {k}: {} against {}", at(xy[k]), n[k]);
        }
        // Affine: the midpoint of an edge has the mean of its normals, and a point outside
        // the triangle continues the plane.
        let mid = at((xy[0] + xy[1]) / 2.0) - (n[0] + n[1]) / 2.0;
        assert!(mid.abs().max_element() < 1e-12, "edge midpoint {mid}");
        let beyond = at(xy[2] * 2.0 - xy[0]) - (n[2] * 2.0 - n[0]);
        assert!(beyond.abs().max_element() < 1e-9, "extrapolated {beyond}");
    }

    #[test]
    fn product_truncates_to_second_degree() {
        let p = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
        let q = [0.5, -1.0, 0.25, 2.0, -3.0, 1.5];
        let r = product2(&p, &q);
        // Near the origin the product agrees with the truncation to third order.
        let (x, y) = (1e-3, -2e-3);
        let full = eval(&p, x, y) * eval(&q, x, y);
        assert!((full - eval(&r, x, y)).abs() < 1e-7);
    }
}
