//! Ground truth: the model in `f64`, all effects, no shortcuts (the `reference` shading mode).

use glam::{DVec3, Vec3};
use phosphor_math::{reflect_f64, safe_normalize_f64};

use crate::attenuation::factor_from_coefficients_f64;
use crate::lightset::{LightSet, PreparedPoint, spot_cone_f64};
use crate::lobe::specular_lobe_f64;
use crate::material::{Material, SpecularModel};

/// Ground truth in f64, all effects, no shortcuts. Same conventions as [`crate::shade()`]
/// (a zero or non-finite normal gives `emission + ka Ia`); the light geometry is the f32 data
/// prepared by [`LightSet`], every operation on it is in f64. Each channel of the result is
/// in `[0, f64::MAX]`, NaN mapped to 0.
#[must_use]
pub fn shade_reference(set: &LightSet, mat: &Material, p: DVec3, n: DVec3, eye: DVec3) -> DVec3 {
    shade_reference_tinted(set, mat, p, n, eye, DVec3::ONE)
}

/// [`shade_reference`] with the ambient and diffuse light scaled by the surface colour `tint`
/// (a texture, a vertex colour) and the specular highlight added untinted ("modulate with
/// separate specular"); a `tint` of one is [`shade_reference`] bit for bit.
#[must_use]
pub fn shade_reference_tinted(
    set: &LightSet,
    mat: &Material,
    p: DVec3,
    n: DVec3,
    eye: DVec3,
    tint: DVec3,
) -> DVec3 {
    let d = |v: Vec3| v.as_dvec3();
    let ambient = (d(mat.emission) + d(mat.ka) * d(set.ambient())) * tint;
    let n = safe_normalize_f64(n, DVec3::ZERO);
    if n == DVec3::ZERO {
        return finite_f64(ambient);
    }
    let v = safe_normalize_f64(eye - p, n);
    let mut sum = ambient;
    let mut add = |l: DVec3, f: f64, il: Vec3, il_s: Vec3| {
        let n_dot_l = n.dot(l);
        if n_dot_l <= 0.0 {
            return;
        }
        let lobe = match mat.specular {
            SpecularModel::Phong => {
                specular_lobe_f64(reflect_f64(n, l).dot(v), mat.shininess.into())
            }
            SpecularModel::Blinn => {
                let h = safe_normalize_f64(l + v, n);
                specular_lobe_f64(n.dot(h), mat.shininess.into())
            }
        };
        let w = mat.fresnel.w_f64(n_dot_l);
        sum += f * (d(mat.kd) * n_dot_l * d(il) * tint + d(mat.ks) * (w * lobe) * d(il_s));
    };
    for light in set.directional() {
        let l = safe_normalize_f64(d(light.to_light), n);
        add(l, 1.0, light.il, light.il_specular);
    }
    let towards = |light: &PreparedPoint| {
        let delta = d(light.position) - p;
        let l = safe_normalize_f64(delta, n);
        (
            l,
            factor_from_coefficients_f64(light.attenuation, delta.length()),
        )
    };
    for light in set.points().iter().chain(set.distributed_samples()) {
        let (l, f) = towards(light);
        add(l, f, light.il, light.il_specular);
    }
    for spot in set.spots() {
        let (l, f) = towards(&spot.point);
        let axis = safe_normalize_f64(d(spot.axis), DVec3::ZERO);
        let cone = spot_cone_f64(
            -l.dot(axis),
            spot.cos_outer.into(),
            spot.inv_cos_width.into(),
        );
        add(l, f * cone, spot.point.il, spot.point.il_specular);
    }
    finite_f64(sum)
}

#[allow(
    clippy::manual_clamp,
    reason = "max/min map NaN to 0, clamp() keeps it"
)]
fn finite_f64(v: DVec3) -> DVec3 {
    DVec3::from_array(v.to_array().map(|c| c.max(0.0).min(f64::MAX)))
}
