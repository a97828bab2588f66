//! Upper bounds of the model over a whole triangle, from its three corners.
//!
//! Fast Phong fits a quadratic through six exact samples and checks it at four more; a
//! specular lobe narrower than the triangle whose peak falls between those points is invisible
//! to both (measured: a flat 2x2 square under a directional light, `n_s = 1000`, highlight off
//! centre: the fit passed every check and missed a peak of 0.5, 126 codes). The bound here
//! sees it: if the largest specular any point of the triangle can show is well above what the
//! samples saw, the fit cannot be trusted.
//!
//! The argument: inside the triangle the interpolated unit normal stays within the spherical
//! triangle of the corner normals, so within `spread_n` (the largest angle between two corner
//! normals, bounded from above through the chord without a transcendental call) of each
//! corner's normal; likewise the directions to the viewer (`spread_v`) and to
//! a point light (`spread_l`; 0 for a directional one). Reflection turns a normal rotated by
//! `a` into an `R` rotated by at most `2a`, and an `L` rotated by `b` into an `R` rotated by
//! `b`. So at every interior point the angle between `R` and `V` is at least
//! `max_corners(angle(R_i, V_i)) - (2 spread_n + spread_l + spread_v)`, and the lobe at most
//! `cos(that)^n_s`. (Blinn: `N.H` with `H` between `L` and `V`:
//! `spread_n + spread_l + spread_v`.) Attenuation is bounded by its value at the smallest
//! distance any point of the triangle can have to the light, spot cones and `N.L > 0` by 1.
//!
//! The bound is loose by the slack, so a caller first asks [`lobe_sharpness`] (`n_s` times
//! the slack squared): a lobe wider than the triangle (sharpness up to about 1) varies
//! smoothly across it and cannot hide between samples.

use std::f32::consts::PI;

use glam::Vec3;
use phosphor_math::{reflect, safe_normalize};

use crate::attenuation::factor_from_coefficients;
use crate::effects::Effects;
use crate::lightset::{LightSet, PreparedPoint};
use crate::lobe::specular_lobe;
use crate::material::{Material, SpecularModel};
use crate::shade::finite_intensity;

/// Angle between two unit vectors in `[0, pi]`, rounding-safe.
#[inline]
fn angle(a: Vec3, b: Vec3) -> f32 {
    a.dot(b).clamp(-1.0, 1.0).acos()
}

/// An upper bound of the angle between two unit vectors, from their chord `c = |a - b|`
/// without a transcendental call: `angle = 2 asin(c/2) <= c / sqrt(1 - c^2/4)`, tight for
/// small angles; `pi` when either is zero (unknown direction).
#[inline]
fn angle_at_most(a: Vec3, b: Vec3) -> f32 {
    if a == Vec3::ZERO || b == Vec3::ZERO {
        return PI;
    }
    let c2 = (a - b).length_squared();
    let rest = 1.0 - 0.25 * c2;
    if rest <= 0.0 {
        PI
    } else {
        (c2 / rest).sqrt().min(PI)
    }
}

/// At least the largest angle between two of three unit vectors.
#[inline]
fn spread(v: [Vec3; 3]) -> f32 {
    angle_at_most(v[0], v[1])
        .max(angle_at_most(v[1], v[2]))
        .max(angle_at_most(v[2], v[0]))
}

/// The corners of a triangle as the bounds see them.
struct Corners<'a> {
    set: &'a LightSet,
    mat: &'a Material,
    p: [Vec3; 3],
    n: [Vec3; 3],
    v: [Vec3; 3],
    /// `2 spread_n + spread_v` (Phong) or `spread_n + spread_v` (Blinn): the slack of the
    /// lobe argument before the light's own spread.
    slack: f32,
}

impl<'a> Corners<'a> {
    fn new(set: &'a LightSet, mat: &'a Material, p: [Vec3; 3], n: [Vec3; 3], eye: Vec3) -> Self {
        let n = n.map(|x| safe_normalize(x, Vec3::ZERO));
        let v: [Vec3; 3] = std::array::from_fn(|i| safe_normalize(eye - p[i], n[i]));
        let normal_factor = match mat.specular {
            SpecularModel::Phong => 2.0,
            SpecularModel::Blinn => 1.0,
        };
        let slack = normal_factor * spread(n) + spread(v);
        Corners {
            set,
            mat,
            p,
            n,
            v,
            slack,
        }
    }

    /// Point lights, spot lights (as points) and, with DISTRIBUTED, the samples.
    fn positional<const FX: u32>(&self) -> impl Iterator<Item = &'a PreparedPoint> + use<'a, FX> {
        let set: &'a LightSet = self.set;
        let spots = set.spots().iter().map(|s| &s.point);
        let samples = if FX & Effects::DISTRIBUTED.bits() != 0 {
            set.distributed_samples()
        } else {
            &[]
        };
        set.points().iter().chain(spots).chain(samples)
    }

    /// Unit directions from the corners towards a positional light.
    fn towards(&self, light: &PreparedPoint) -> [Vec3; 3] {
        self.p
            .map(|q| safe_normalize(light.position - q, Vec3::ZERO))
    }

    /// The largest lobe for corner directions `l` with angular spread `spread_l`.
    fn lobe(&self, l: [Vec3; 3], spread_l: f32) -> f32 {
        let (n, v) = (&self.n, &self.v);
        let worst = (0..3)
            .map(|i| match self.mat.specular {
                SpecularModel::Phong => angle(reflect(n[i], l[i]), v[i]),
                SpecularModel::Blinn => angle(n[i], safe_normalize(l[i] + v[i], n[i])),
            })
            .fold(0.0, f32::max);
        let closest = worst - (self.slack + spread_l);
        if closest.is_nan() || closest <= 0.0 {
            1.0
        } else {
            // The lobe is monotonic in the cosine, so the closest angle gives the largest.
            specular_lobe(closest.cos(), self.mat.shininess)
        }
    }
}

fn has_specular<const FX: u32>(mat: &Material) -> bool {
    FX & Effects::SPECULAR.bits() != 0 && mat.ks != Vec3::ZERO
}

/// How sharp the specular lobe is over the triangle with corners `p` and normals `n` seen
/// from `eye`: `n_s` times the square of the largest angular extent (radians, an upper
/// bound) of the lobe's argument over the triangle, largest over the lights; 0 without
/// specular. The lobe's width is about `1/sqrt(n_s)`, so above about 1 a lobe can be narrower
/// than the triangle and hide between samples; below, it varies smoothly across it.
///
/// Cheap (square roots, no transcendental calls): the test to run before
/// [`specular_upper_bound`]. Finite and non-negative.
#[must_use]
pub fn lobe_sharpness<const FX: u32>(
    set: &LightSet,
    mat: &Material,
    p: [Vec3; 3],
    n: [Vec3; 3],
    eye: Vec3,
) -> f32 {
    if !has_specular::<FX>(mat) {
        return 0.0;
    }
    let c = Corners::new(set, mat, p, n, eye);
    let spread_l = c
        .positional::<FX>()
        .map(|light| spread(c.towards(light)))
        .fold(0.0, f32::max);
    let slack = c.slack + spread_l;
    let sharpness = mat.shininess * slack * slack;
    if sharpness.is_nan() {
        f32::MAX
    } else {
        sharpness.min(f32::MAX)
    }
}

/// An upper bound, per channel, of the specular sum `sum f(d) Il_s ks W lobe` of
/// [`crate::shade_split`] over every point of the triangle with corners `p` and normals `n`
/// (interpolated and renormalized between them), seen from `eye`, for the effects `FX`.
///
/// Finite and non-negative; 0 without SPECULAR in `FX` or with `ks = 0`. Not the maximum: it
/// may exceed it (by the loose angle argument in the module docs), never fall below it.
/// Zero normals count as pointing anywhere.
#[must_use]
pub fn specular_upper_bound<const FX: u32>(
    set: &LightSet,
    mat: &Material,
    p: [Vec3; 3],
    n: [Vec3; 3],
    eye: Vec3,
) -> Vec3 {
    if !has_specular::<FX>(mat) {
        return Vec3::ZERO;
    }
    let c = Corners::new(set, mat, p, n, eye);
    let longest_edge = (p[0] - p[1])
        .length()
        .max((p[1] - p[2]).length())
        .max((p[2] - p[0]).length());
    let w = if FX & Effects::FRESNEL.bits() != 0 {
        mat.fresnel.max_w()
    } else {
        1.0
    };
    let mut sum = Vec3::ZERO;
    for light in set.directional() {
        sum += light.il_specular * c.lobe([light.to_light; 3], 0.0);
    }
    for light in c.positional::<FX>() {
        let l = c.towards(light);
        let nearest = p
            .iter()
            .map(|q| (light.position - *q).length())
            .fold(f32::INFINITY, f32::min);
        let f = if FX & Effects::ATTENUATION.bits() != 0 {
            factor_from_coefficients(light.attenuation, (nearest - longest_edge).max(0.0))
        } else {
            1.0
        };
        sum += light.il_specular * (f * c.lobe(l, spread(l)));
    }
    finite_intensity(mat.ks * w * sum)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{Light, shade_split};

    const ALL: u32 = Effects::ALL.bits();

    #[test]
    fn a_narrow_highlight_inside_a_flat_triangle_is_bounded_by_its_peak() {
        // Flat square corner triangle, light and eye above its interior: the corners see
        // almost no specular (n_s = 1000), the interior peak is ks Il = 0.5.
        let set = LightSet::new(
            Vec3::ZERO,
            &[Light::directional(-Vec3::new(0.1, 0.02, 1.0), Vec3::ONE).unwrap()],
        );
        let mat = Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::splat(0.5), 1000.0).unwrap();
        let p = [
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
        ];
        let eye = Vec3::new(0.0, 0.0, 3.0);
        let corners = p.map(|q| shade_split::<ALL>(&set, &mat, q, Vec3::Z, eye).specular);
        assert!(
            corners.iter().all(|c| c.max_element() < 1e-3),
            "{corners:?}"
        );
        let bound = specular_upper_bound::<ALL>(&set, &mat, p, [Vec3::Z; 3], eye);
        assert!(bound.min_element() > 0.49, "{bound}");
        let sharpness = lobe_sharpness::<ALL>(&set, &mat, p, [Vec3::Z; 3], eye);
        assert!(sharpness > 100.0, "{sharpness}");
    }

    #[test]
    fn the_bound_is_never_below_the_specular_inside_the_triangle() {
        // Curved corner normals, a point light and a directional one, Phong and Blinn:
        // sample the interior densely.
        let set = LightSet::new(
            Vec3::ZERO,
            &[
                Light::point(Vec3::new(0.3, 0.5, 2.0), Vec3::splat(2.0)).unwrap(),
                Light::directional(-Vec3::new(-0.4, 0.1, 1.0), Vec3::ONE).unwrap(),
            ],
        );
        let p = [
            Vec3::new(-1.0, -0.8, 0.0),
            Vec3::new(1.2, -1.0, 0.1),
            Vec3::new(0.1, 1.0, -0.2),
        ];
        let n = [
            Vec3::new(-0.3, -0.2, 1.0).normalize(),
            Vec3::new(0.4, -0.1, 1.0).normalize(),
            Vec3::new(0.0, 0.35, 1.0).normalize(),
        ];
        let eye = Vec3::new(0.2, -0.1, 3.0);
        for model in [SpecularModel::Phong, SpecularModel::Blinn] {
            for shininess in [1.0, 32.0, 500.0] {
                let mat = Material::new(Vec3::ZERO, Vec3::ZERO, Vec3::ONE, shininess)
                    .unwrap()
                    .with_specular(model);
                let bound = specular_upper_bound::<ALL>(&set, &mat, p, n, eye);
                for i in 0..=40 {
                    for j in 0..=40 - i {
                        let (a, b) = (i as f32 / 40.0, j as f32 / 40.0);
                        let c = 1.0 - a - b;
                        let q = p[0] * a + p[1] * b + p[2] * c;
                        let m = (n[0] * a + n[1] * b + n[2] * c).normalize();
                        let s = shade_split::<ALL>(&set, &mat, q, m, eye).specular;
                        assert!(
                            s.cmple(bound + Vec3::splat(1e-5)).all(),
                            "{model:?} n_s {shininess}: {s} above {bound}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn no_specular_effect_or_ks_gives_zero() {
        let set = LightSet::s1();
        let p = [Vec3::ZERO, Vec3::X, Vec3::Y];
        let eye = Vec3::new(0.0, 0.0, 3.0);
        const NO_SPEC: u32 = Effects::ALL.bits() & !Effects::SPECULAR.bits();
        let b = specular_upper_bound::<NO_SPEC>(&set, &Material::s1(), p, [Vec3::Z; 3], eye);
        assert_eq!(b, Vec3::ZERO);
        let b = specular_upper_bound::<ALL>(&set, &Material::default(), p, [Vec3::Z; 3], eye);
        assert_eq!(b, Vec3::ZERO);
        assert_eq!(
            lobe_sharpness::<ALL>(&set, &Material::default(), p, [Vec3::Z; 3], eye),
            0.0
        );
        // Zero normals: anything goes, still finite.
        let b = specular_upper_bound::<ALL>(&set, &Material::s1(), p, [Vec3::ZERO; 3], eye);
        assert!(b.is_finite() && b.min_element() > 0.0);
        let s = lobe_sharpness::<ALL>(&set, &Material::s1(), p, [Vec3::ZERO; 3], eye);
        assert!(s.is_finite() && s > 1.0);
    }

    #[test]
    fn the_chord_bound_is_never_below_the_angle() {
        for k in 0..=100 {
            let t = std::f32::consts::PI * k as f32 / 100.0;
            let a = Vec3::new(t.cos(), t.sin(), 0.0);
            assert!(angle_at_most(Vec3::X, a) >= angle(Vec3::X, a) - 1e-6, "{t}");
            assert!(
                angle_at_most(Vec3::X, a) <= angle(Vec3::X, a) * 1.6 + 1e-6,
                "{t}"
            );
        }
    }
}
